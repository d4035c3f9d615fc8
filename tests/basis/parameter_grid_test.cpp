// interpolationWeights and validateAxes (runtime/basis/parameter_grid.h).
#include "basis/parameter_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace firelook::basis {
namespace {

ParameterAxes threeAxes() { return {{1.0, 1.5, 2.5}, {2.0, 4.0, 8.0, 16.0}, {0.5, 1.5}}; }

double weightSum(const GridWeights& w) {
    double sum = 0.0;
    for (int i = 0; i < w.count; ++i) sum += w.weight[i];
    return sum;
}

// The interpolated value of a function known at the grid points.
template <typename F>
double interpolate(const ParameterAxes& axes, const GridWeights& w, F f) {
    double sum = 0.0;
    for (int i = 0; i < w.count; ++i) sum += w.weight[i] * f(axes.point(w.point[i]));
    return sum;
}

// Float weights (24-bit significand), products of three: a few float ulps.
constexpr double kWeightTolerance = 1e-6;

TEST(ParameterGrid, PointIndexAndPointAreInverse) {
    const ParameterAxes axes = threeAxes();
    EXPECT_EQ(axes.pointCount(), 3 * 4 * 2);
    for (int tc = 0; tc < 3; ++tc)
        for (int ks = 0; ks < 4; ++ks)
            for (int kf = 0; kf < 2; ++kf) {
                const ExtinctionParams p = axes.point(axes.pointIndex(tc, ks, kf));
                EXPECT_EQ(p.temperature_threshold, axes.temperature_threshold[tc]);
                EXPECT_EQ(p.smoke_extinction, axes.smoke_extinction[ks]);
                EXPECT_EQ(p.flame_extinction, axes.flame_extinction[kf]);
            }
    EXPECT_EQ(axes.pointIndex(0, 0, 1), 1) << "k_f varies fastest";
}

TEST(ParameterGrid, ExactAtEveryGridPoint) {
    const ParameterAxes axes = threeAxes();
    for (int g = 0; g < axes.pointCount(); ++g) {
        const GridWeights w = interpolationWeights(axes, axes.point(g));
        ASSERT_EQ(w.count, 1) << "grid point " << g;
        EXPECT_EQ(w.point[0], g);
        EXPECT_EQ(w.weight[0], 1.0f);
    }
}

TEST(ParameterGrid, WeightsSumToOneOverAtMostFiveSamplesPerAxis) {
    // T_c's 3 samples, k_s's 6 and k_f's 2: between two samples an axis blends two windows of
    // min(4, samples) neighbours, so at most 3, 5 and 2 samples.
    const ParameterAxes axes{{1.0, 1.5, 2.5}, {2.0, 4.0, 8.0, 16.0, 32.0, 64.0}, {0.5, 1.5}};
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> tc(0.0, 3.0), ks(0.0, 70.0), kf(0.0, 2.0);
    int most = 0;
    for (int n = 0; n < 1000; ++n) {
        const GridWeights w = interpolationWeights(axes, {tc(rng), ks(rng), kf(rng)});
        ASSERT_GE(w.count, 1);
        ASSERT_LE(w.count, 3 * 5 * 2);
        most = std::max(most, w.count);
        EXPECT_NEAR(weightSum(w), 1.0, kWeightTolerance);
        for (int i = 0; i < w.count; ++i) {
            EXPECT_TRUE(std::isfinite(w.weight[i]));
            EXPECT_NE(w.weight[i], 0.0f) << "zero weights are left out";
            EXPECT_GE(w.point[i], 0);
            EXPECT_LT(w.point[i], axes.pointCount());
            for (int j = 0; j < i; ++j) EXPECT_NE(w.point[i], w.point[j]) << "each grid point once";
        }
    }
    EXPECT_EQ(most, 3 * 5 * 2) << "the interior intervals of k_s blend two cubics over 5 samples";
}

TEST(ParameterGrid, ExactForCubicsInEachParameter) {
    // Each axis reproduces any polynomial of degree min(3, samples - 1) in its parameter, so the
    // tensor product reproduces this f on these axes: cubic in k_s (4 and 5 samples), quadratic in
    // T_c (3 samples), linear in k_f (2 samples).
    const auto f = [](const ExtinctionParams& p) {
        const double tc = p.temperature_threshold, ks = p.smoke_extinction, kf = p.flame_extinction;
        return 3.0 + 2.0 * tc - 1.5 * tc * tc - 0.5 * ks + 0.05 * ks * ks - 0.002 * ks * ks * ks + 7.0 * kf +
               0.02 * tc * tc * ks * ks * kf + 1e-4 * ks * ks * ks * tc;
    };
    for (const ParameterAxes& axes : {ParameterAxes{{1.0, 1.5, 2.5}, {2.0, 4.0, 8.0, 16.0}, {0.5, 1.5}},
                                      ParameterAxes{{1.0, 1.5, 2.5}, {2.0, 4.0, 8.0, 12.0, 16.0}, {0.5, 1.5}}}) {
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> tc(1.0, 2.5), ks(2.0, 16.0), kf(0.5, 1.5);
        for (int n = 0; n < 200; ++n) {
            const ExtinctionParams p{tc(rng), ks(rng), kf(rng)};
            // Terms up to ~150, weights up to ~1.4 in float: ~150 * 24 float ulps.
            EXPECT_NEAR(interpolate(axes, interpolationWeights(axes, p), f), f(p), 5e-4)
                << axes.smoke_extinction.size() << " k_s samples";
        }
    }
}

TEST(ParameterGrid, HandCheckedWeights) {
    // k_s = 5 on {2, 4, 8, 16}: a 4-sample axis has one cubic, through all four. Lagrange weights
    // at 5: (1)(-3)(-11) / ((-2)(-6)(-14)) = -11/56, 99/96 = 33/32, -33/-192 = 11/64, -9/1344 = -3/448.
    const ParameterAxes axes{{1.0}, {2.0, 4.0, 8.0, 16.0}, {0.5}};
    const GridWeights w = interpolationWeights(axes, {1.0, 5.0, 0.5});
    const double expected[4] = {-11.0 / 56.0, 33.0 / 32.0, 11.0 / 64.0, -3.0 / 448.0};
    ASSERT_EQ(w.count, 4);
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(w.point[i], i) << "k_s samples in order";
        EXPECT_NEAR(w.weight[i], expected[i], kWeightTolerance) << "k_s sample " << i;
    }
    // k_s = 10 on {2, 4, 8, 16, 32}, t = 1/4 between 8 and 16: the cubic through 2..16 and the one
    // through 4..32, blended 3/4 : 1/4. At 10: (2, 4, 8, 16) -> (3/7, -1, 3/2, 1/14) and
    // (4, 8, 16, 32) -> (-11/56, 33/32, 11/64, -3/448), the first axis's weights at 5 scaled by 2.
    const ParameterAxes five{{1.0}, {2.0, 4.0, 8.0, 16.0, 32.0}, {0.5}};
    const GridWeights b = interpolationWeights(five, {1.0, 10.0, 0.5});
    const double blended[5] = {0.75 * 3.0 / 7.0, 0.75 * -1.0 + 0.25 * -11.0 / 56.0,
                               0.75 * 1.5 + 0.25 * 33.0 / 32.0, 0.75 * 1.0 / 14.0 + 0.25 * 11.0 / 64.0,
                               0.25 * -3.0 / 448.0};
    ASSERT_EQ(b.count, 5);
    for (int i = 0; i < 5; ++i) EXPECT_NEAR(b.weight[i], blended[i], kWeightTolerance) << "k_s sample " << i;
    // T_c = 1.25 on {1, 1.5, 2.5}: three samples, so the one parabola through all three.
    const ParameterAxes tc_axes{{1.0, 1.5, 2.5}, {4.0}, {0.5}};
    const GridWeights e = interpolationWeights(tc_axes, {1.25, 4.0, 0.5});
    const double tc_expected[3] = {(1.25 - 1.5) * (1.25 - 2.5) / ((1.0 - 1.5) * (1.0 - 2.5)),
                                   (1.25 - 1.0) * (1.25 - 2.5) / ((1.5 - 1.0) * (1.5 - 2.5)),
                                   (1.25 - 1.0) * (1.25 - 1.5) / ((2.5 - 1.0) * (2.5 - 1.5))};
    ASSERT_EQ(e.count, 3);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(e.weight[i], tc_expected[i], kWeightTolerance) << "T_c sample " << i;
    // Two samples: linear.
    const GridWeights l = interpolationWeights({{1.0, 2.0}, {4.0}, {0.5}}, {1.25, 4.0, 0.5});
    ASSERT_EQ(l.count, 2);
    EXPECT_NEAR(l.weight[0], 0.75, kWeightTolerance);
    EXPECT_NEAR(l.weight[1], 0.25, kWeightTolerance);
}

TEST(ParameterGrid, ContinuousInValueAndSlopeAcrossSamples) {
    // A slider dragged across a grid sample must not kink the image: the blend's value and slope are
    // the same on both sides of every interior sample. Checked on a function no cubic reproduces.
    const ParameterAxes axes{{1.0}, {2.0, 4.0, 8.0, 16.0, 32.0}, {0.5}};
    const auto f = [](const ExtinctionParams& p) { return 1.0 - std::exp(-0.2 * p.smoke_extinction); };
    const auto at = [&](double ks) { return interpolate(axes, interpolationWeights(axes, {1.0, ks, 0.5}), f); };
    for (double sample : {4.0, 8.0, 16.0}) {
        // Value: a step across the sample smaller than float weights resolve changes nothing (a
        // jump would be of the size of the interpolation error, 1e-3 and more here).
        const double tiny = 1e-6 * sample;
        EXPECT_NEAR(at(sample - tiny), at(sample), 1e-5) << "value left of k_s = " << sample;
        EXPECT_NEAR(at(sample + tiny), at(sample), 1e-5) << "value right of k_s = " << sample;
        // Slope: one-sided differences differ by O(h f''); a kink would differ by O(1) of the slope.
        const double h = 1e-3 * sample;
        const double left = (at(sample) - at(sample - h)) / h, right = (at(sample + h) - at(sample)) / h;
        EXPECT_NEAR(left, right, 0.02 * std::abs(left) + 1e-4) << "slope at k_s = " << sample;
    }
}

// Sunlit smoke saturates as k grows: a pixel through smoke of optical depth tau per unit k has
// radiance like 1 - exp(-k tau). The worst relative error of the blend and of the chord (linear
// interpolation) per interval of the design's k_s samples (2, 4, 8, 16), over an image of such
// pixels with tau log-even over [tau_max / 100, tau_max].
struct SaturatingErrors {
    double blend[3] = {}, chord[3] = {};
};
SaturatingErrors saturatingErrors(double tau_max) {
    const ParameterAxes axes{{1.0}, {2.0, 4.0, 8.0, 16.0}, {0.5}};
    const auto image = [tau_max](const ExtinctionParams& p) {
        double sum = 0.0;
        for (int i = 0; i <= 40; ++i)
            sum += 1.0 - std::exp(-tau_max / 100.0 * std::pow(100.0, i / 40.0) * p.smoke_extinction);
        return sum / 41.0;
    };
    SaturatingErrors out;
    for (int interval = 0; interval < 3; ++interval) {
        const double lo = axes.smoke_extinction[interval], hi = axes.smoke_extinction[interval + 1];
        for (int step = 1; step < 64; ++step) {
            const double t = step / 64.0, ks = lo + t * (hi - lo);
            const double exact = image({1.0, ks, 0.5});
            const double blend = interpolate(axes, interpolationWeights(axes, {1.0, ks, 0.5}), image);
            const double chord = (1.0 - t) * image({1.0, lo, 0.5}) + t * image({1.0, hi, 0.5});
            out.blend[interval] = std::max(out.blend[interval], std::abs(blend / exact - 1.0));
            out.chord[interval] = std::max(out.chord[interval], std::abs(chord / exact - 1.0));
        }
    }
    return out;
}

TEST(ParameterGrid, FollowsSaturatingSmokeWhereLinearCutsTheCurve) {
    // Optical depths up to 4 at the top sample (the range of the sunlit and thin smoke regimes):
    // the chord lies below the curve by 1.7 / 2.4 / 2.8 % per interval; the cubic follows it to
    // 0.16 / 0.18 / 0.81 % (the parabola blend this replaced: 0.38 / 0.24 / 1.32 %).
    const SaturatingErrors e = saturatingErrors(0.25);
    EXPECT_GT(e.chord[1], 0.02) << "the case must be one where linear interpolation fails";
    EXPECT_LT(e.blend[0], 0.003);
    EXPECT_LT(e.blend[1], 0.003);
    EXPECT_LT(e.blend[2], 0.01) << "the last interval, where the samples are furthest apart";
    for (int interval = 0; interval < 3; ++interval)
        EXPECT_LT(e.blend[interval], 0.35 * e.chord[interval]) << "interval " << interval;
}

TEST(ParameterGrid, StronglySaturatingSmokeIsTheCubicsLimit) {
    // Optical depths up to 32 at the top sample: most of the image is flat over the last interval and
    // the cubic, bent by the steep start of the curve, overshoots there by 4.1 % (the chord 1.6 %,
    // the parabola blend 1.6 %); docs/model.md states this limit and its remedy, a denser top of the
    // k_s axis. The other intervals still gain: 1.0 / 1.0 % against 2.5 / 2.0 %.
    const SaturatingErrors e = saturatingErrors(2.0);
    EXPECT_LT(e.blend[0], 0.5 * e.chord[0]);
    EXPECT_LT(e.blend[1], 0.6 * e.chord[1]);
    EXPECT_LT(e.blend[2], 0.045) << "the bound docs/model.md states for the last interval";
}

TEST(ParameterGrid, ClampedOutsideTheRange) {
    const ParameterAxes axes = threeAxes();
    const GridWeights below = interpolationWeights(axes, {-100.0, 0.0, -1.0});
    ASSERT_EQ(below.count, 1);
    EXPECT_EQ(below.point[0], axes.pointIndex(0, 0, 0));
    const GridWeights above = interpolationWeights(axes, {100.0, 1e9, 50.0});
    ASSERT_EQ(above.count, 1);
    EXPECT_EQ(above.point[0], axes.pointIndex(2, 3, 1));
    const double inf = std::numeric_limits<double>::infinity();
    const GridWeights infinite = interpolationWeights(axes, {-inf, inf, inf});
    ASSERT_EQ(infinite.count, 1);
    EXPECT_EQ(infinite.point[0], axes.pointIndex(0, 3, 1));
}

TEST(ParameterGrid, NaNIsClampedNeverPropagated) {
    const ParameterAxes axes = threeAxes();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const GridWeights w = interpolationWeights(axes, {nan, nan, nan});
    ASSERT_EQ(w.count, 1);
    EXPECT_EQ(w.point[0], 0) << "NaN takes each axis's first sample";
    EXPECT_EQ(w.weight[0], 1.0f);
    const GridWeights mixed = interpolationWeights(axes, {2.0, nan, 1.0});
    EXPECT_NEAR(weightSum(mixed), 1.0, kWeightTolerance);
    for (int i = 0; i < mixed.count; ++i) EXPECT_TRUE(std::isfinite(mixed.weight[i]));
}

TEST(ParameterGrid, CollapsedAxesUseTheBakedValue) {
    const ParameterAxes all_collapsed{{1.5}, {4.0}, {1.0}};
    for (const ExtinctionParams& p : {ExtinctionParams{0.0, 0.0, 0.0}, ExtinctionParams{1.5, 4.0, 1.0},
                                      ExtinctionParams{9.0, 99.0, 0.1}}) {
        const GridWeights w = interpolationWeights(all_collapsed, p);
        ASSERT_EQ(w.count, 1);
        EXPECT_EQ(w.point[0], 0);
        EXPECT_EQ(w.weight[0], 1.0f);
    }
    // One collapsed axis among interpolated ones: only the other two blend.
    const ParameterAxes one_collapsed{{1.0, 2.0}, {4.0}, {0.5, 1.5}};
    const GridWeights w = interpolationWeights(one_collapsed, {1.5, 123.0, 1.0});
    EXPECT_EQ(w.count, 4);
    for (int i = 0; i < w.count; ++i) EXPECT_NEAR(w.weight[i], 0.25, kWeightTolerance);
}

TEST(ParameterGrid, ValidateAxesNamesTheAxis) {
    const auto message = [](const ParameterAxes& axes) -> std::string {
        try {
            validateAxes(axes);
        } catch (const firelook::Error& e) {
            EXPECT_EQ(e.code(), firelook::ErrorCode::InvalidArgument);
            return e.what();
        }
        return "";
    };
    EXPECT_NO_THROW(validateAxes(threeAxes()));
    EXPECT_NO_THROW(validateAxes({{1.0}, {1.0}, {1.0}}));

    ParameterAxes empty = threeAxes();
    empty.smoke_extinction.clear();
    EXPECT_NE(message(empty).find("smoke_extinction"), std::string::npos) << message(empty);

    ParameterAxes unsorted = threeAxes();
    unsorted.temperature_threshold = {1.0, 3.0, 2.0};
    EXPECT_NE(message(unsorted).find("temperature_threshold"), std::string::npos) << message(unsorted);

    ParameterAxes repeated = threeAxes();
    repeated.flame_extinction = {1.0, 1.0};
    EXPECT_NE(message(repeated).find("flame_extinction"), std::string::npos) << message(repeated);

    ParameterAxes not_finite = threeAxes();
    not_finite.flame_extinction = {1.0, std::numeric_limits<double>::quiet_NaN()};
    EXPECT_NE(message(not_finite).find("flame_extinction"), std::string::npos) << message(not_finite);
    not_finite.flame_extinction = {1.0, std::numeric_limits<double>::infinity()};
    EXPECT_NE(message(not_finite).find("flame_extinction"), std::string::npos) << message(not_finite);
}

}  // namespace
}  // namespace firelook::basis
