// analyseAxes (baker/bake/axis_collapse.h): which look axes cannot change an image of the data,
// the bound it gives against a brute-force evaluation of the model, and what collapsing leaves.
#include "bake/axis_collapse.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

namespace firelook::bake {
namespace {

const basis::ParameterAxes kDefaultAxes{{1.0, 1.2, 1.4, 1.6, 1.8, 2.0}, {2.0, 4.0, 8.0, 16.0}, {0.5, 1.5, 4.0}};

TemperatureBins bins(double lo, double hi, int count) { return {lo, hi, count}; }

// The largest relative change of kappa across one axis's samples, by the model itself
// (look_model.h), over a fine sweep of the data's temperatures and every grid point.
double bruteForceChange(const basis::ParameterAxes& axes, const TemperatureBins& b, double t_min, double t_max,
                        int axis) {
    double worst = 0.0;
    for (int i = 0; i <= 2000; ++i) {
        const double t = t_min + (t_max - t_min) * i / 2000.0;
        for (int p = 0; p < axes.pointCount(); ++p) {
            const ExtinctionParams base = axes.point(p);
            double lo = INFINITY, hi = 0.0;
            const std::vector<double>& samples =
                axis == 0 ? axes.temperature_threshold : axis == 1 ? axes.smoke_extinction : axes.flame_extinction;
            for (double s : samples) {
                ExtinctionParams e = base;
                (axis == 0 ? e.temperature_threshold : axis == 1 ? e.smoke_extinction : e.flame_extinction) = s;
                const double k = extinctionPerDensity(t, e, b);
                lo = std::min(lo, k);
                hi = std::max(hi, k);
            }
            worst = std::max(worst, (hi - lo) / lo);
        }
    }
    return worst;
}

// The reported case: smoke whose temperature never exceeds 0.58, bins over its own range. Every
// T_c sample gives every voxel the same flame share, and so does every k_f; k_s matters.
TEST(AxisCollapse, SmokeBelowEveryThresholdCollapsesTcAndKf) {
    const TemperatureBins b = bins(0.0, 0.58, 16);
    const AxisAnalysis a = analyseAxes(kDefaultAxes, b, {true, 0.0, 0.58}, 1e-4);
    ASSERT_EQ(a.collapsed.size(), 2u);
    EXPECT_EQ(a.collapsed[0].axis, "temperature_threshold");
    EXPECT_EQ(a.collapsed[0].kept, 1.0) << "the lowest sample";
    EXPECT_EQ(a.collapsed[0].requested, kDefaultAxes.temperature_threshold);
    EXPECT_EQ(a.collapsed[1].axis, "flame_extinction");
    EXPECT_EQ(a.collapsed[1].kept, 0.5);
    EXPECT_LE(a.relative_change[0] + a.relative_change[2], 1e-4);
    EXPECT_GT(a.relative_change[1], 1.0) << "k_s scales the smoke's extinction itself";
    // The bound holds, and is tight (within the factor its min-over-max construction allows).
    for (int axis : {0, 2}) {
        const double brute = bruteForceChange(kDefaultAxes, b, 0.0, 0.58, axis);
        EXPECT_LE(brute, a.relative_change[axis] * (1 + 1e-9)) << axis;
        EXPECT_GE(brute, 0.5 * a.relative_change[axis]) << axis;
    }
}

// Temperature crossing the axis (the bundled sample's frame 12 reaches 2.0): every axis matters.
TEST(AxisCollapse, TemperatureAcrossTheAxisKeepsEveryAxis) {
    const TemperatureBins b = bins(0.0, 3.0, 16);
    const AxisAnalysis a = analyseAxes(kDefaultAxes, b, {true, 0.0, 2.0}, 1e-4);
    EXPECT_TRUE(a.collapsed.empty());
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_GT(a.relative_change[axis], 0.1) << axis;
        EXPECT_LE(bruteForceChange(kDefaultAxes, b, 0.0, 2.0, axis), a.relative_change[axis] * (1 + 1e-9)) << axis;
    }
    // Just below the axis but with wide bins the sigmoid is soft: 0.58 is only 2.2 bins below T_c = 1,
    // where the flame share is still 0.1, so T_c changes the image and stays.
    const AxisAnalysis soft = analyseAxes(kDefaultAxes, b, {true, 0.0, 0.58}, 1e-4);
    EXPECT_TRUE(soft.collapsed.empty());
}

// All flame, far above every threshold: T_c and k_s cannot change anything, k_f can.
TEST(AxisCollapse, FlameAboveEveryThresholdCollapsesTcAndKs) {
    const TemperatureBins b = bins(0.0, 3.0, 64);
    const AxisAnalysis a = analyseAxes(kDefaultAxes, b, {true, 2.9, 3.0}, 1e-4);
    ASSERT_EQ(a.collapsed.size(), 2u);
    EXPECT_EQ(a.collapsed[0].axis, "temperature_threshold");
    EXPECT_EQ(a.collapsed[1].axis, "smoke_extinction");
    EXPECT_EQ(a.collapsed[1].kept, 2.0);
    EXPECT_LE(bruteForceChange(kDefaultAxes, b, 2.9, 3.0, 1), a.relative_change[1] * (1 + 1e-9));
}

// The bins clamp T before kappa: data above t_hi counts as t_hi.
TEST(AxisCollapse, TemperaturesAreClampedIntoTheBins) {
    const AxisAnalysis a = analyseAxes(kDefaultAxes, bins(0.0, 0.4, 16), {true, 0.0, 5.0}, 1e-4);
    EXPECT_EQ(a.collapsed.size(), 2u) << "5.0 clamps to 0.4, far below T_c = 1";
}

// The collapsed axes' changes add; the sum stays within the tolerance.
TEST(AxisCollapse, CollapsedAxesShareTheTolerance) {
    const TemperatureBins b = bins(0.0, 0.58, 16);
    const AxisAnalysis full = analyseAxes(kDefaultAxes, b, {true, 0.0, 0.58}, 1e-4);
    ASSERT_EQ(full.collapsed.size(), 2u);
    const double tc = full.relative_change[0], kf = full.relative_change[2];
    const double between = std::max(tc, kf) + 0.5 * std::min(tc, kf);  // each alone fits, both do not
    const AxisAnalysis one = analyseAxes(kDefaultAxes, b, {true, 0.0, 0.58}, between);
    ASSERT_EQ(one.collapsed.size(), 1u);
    EXPECT_EQ(one.collapsed[0].axis, tc <= between ? "temperature_threshold" : "flame_extinction");
    EXPECT_TRUE(analyseAxes(kDefaultAxes, b, {true, 0.0, 0.58}, 0.0).collapsed.empty()) << "tolerance 0";
}

// k_s = 0 leaves the smoke only the (tiny) flame share's extinction, which T_c and k_f then change
// by a large factor; k_s = k_f = 0 makes the relative change unbounded. Neither collapses.
TEST(AxisCollapse, ZeroExtinctionIsNeverCollapsedAway) {
    const basis::ParameterAxes axes{{1.0, 2.0}, {0.0, 2.0}, {0.5, 4.0}};
    const AxisAnalysis a = analyseAxes(axes, bins(0.0, 0.58, 16), {true, 0.0, 0.58}, 1e-4);
    for (int axis = 0; axis < 3; ++axis) EXPECT_GT(a.relative_change[axis], 0.5) << axis;
    EXPECT_TRUE(a.collapsed.empty());
    const AxisAnalysis zero = analyseAxes({{1.0, 2.0}, {0.0, 2.0}, {0.0, 4.0}}, bins(0.0, 0.58, 16), {true, 0.0, 0.58}, 1e-4);
    EXPECT_TRUE(std::isinf(zero.relative_change[1]));
    EXPECT_TRUE(zero.collapsed.empty());
    const nlohmann::json j = nlohmann::json::parse(axisAnalysisToJson(zero));
    EXPECT_TRUE(j.at("relative_change").at("smoke_extinction").is_null());
}

// No density in any frame: no axis can change anything; one-sample axes are never reported.
TEST(AxisCollapse, EmptyFramesCollapseEveryAxisOneSampleAxesAreLeftAlone) {
    const basis::ParameterAxes axes{{1.0, 2.0}, {4.0}, {0.5, 4.0}};
    const AxisAnalysis a = analyseAxes(axes, bins(0.0, 3.0, 16), {}, 1e-4);
    ASSERT_EQ(a.collapsed.size(), 2u);
    EXPECT_NE(describeAxisCollapse(a.collapsed[0], a).find("no frame has density"), std::string::npos);
}

TEST(AxisCollapse, ApplyLeavesOneSampleAndOneAlphaThreshold) {
    basis::BakeDescription d;
    d.bins = bins(0.0, 0.58, 16);
    d.axes = kDefaultAxes;
    for (int i = 0; i < 21; ++i) d.alpha_thresholds.push_back(1.0 + i / 20.0);
    const AxisAnalysis a = analyseAxes(d.axes, d.bins, {true, 0.0, 0.58}, 1e-4);
    applyAxisCollapse(d, a);
    EXPECT_EQ(d.axes.temperature_threshold, (std::vector<double>{1.0}));
    EXPECT_EQ(d.axes.smoke_extinction, kDefaultAxes.smoke_extinction);
    EXPECT_EQ(d.axes.flame_extinction, (std::vector<double>{0.5}));
    EXPECT_EQ(d.alpha_thresholds, (std::vector<double>{1.0}));
    EXPECT_EQ(d.axes.pointCount(), 4);
    // The line names the axis, the temperatures found, the samples and the bound.
    const std::string line = describeAxisCollapse(a.collapsed[0], a);
    for (const char* word : {"temperature_threshold", "lowest sample 1", "of 6, 1..2", "[0, 0.58]", "--keep-axes"})
        EXPECT_NE(line.find(word), std::string::npos) << word << " in: " << line;
}

TEST(AxisCollapse, ToleranceFollowsTheCodec) {
    basis::FrameCodecSettings s;
    EXPECT_DOUBLE_EQ(collapseTolerance(s), std::min(s.basis_error, s.alpha_error) / 5.0);
    EXPECT_DOUBLE_EQ(collapseTolerance(basis::FrameCodecSettings{}), 1e-4) << "documented default";
}

// A medium's range counts only where interpolated density can be non-zero.
TEST(AxisCollapse, HotAirWithoutDensityDoesNotCount) {
    // 8^3 voxels: density only in the lower half; the upper half (more than a brick away) is hot.
    std::vector<float> density(512, 0.0f), temperature(512, 0.2f);
    for (int k = 0; k < 8; ++k)
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 8; ++i) {
                const int n = i + 8 * (j + 8 * k);
                if (k < 2) density[n] = 1.0f;
                if (k == 7) temperature[n] = 5.0f;
            }
    const render::Medium m({0, 0, 0}, {8, 8, 8}, density, temperature, glm::dmat4(1.0), 0.0f);
    const DensityTemperatureRange r = densityTemperatureRange(m);
    ASSERT_TRUE(r.any_density);
    EXPECT_LT(r.t_max, 1.0) << "the hot layer holds no density";
    EXPECT_FALSE(densityTemperatureRange(render::Medium()).any_density);
}

}  // namespace
}  // namespace firelook::bake
