// interpolationWeights and validateAxes (runtime/basis/parameter_grid.h).
#include "basis/parameter_grid.h"

#include <gtest/gtest.h>

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

TEST(ParameterGrid, WeightsSumToOneOverAtMostFourSamplesPerAxis) {
    const ParameterAxes axes = threeAxes();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> tc(0.0, 3.0), ks(0.0, 20.0), kf(0.0, 2.0);
    for (int n = 0; n < 500; ++n) {
        const GridWeights w = interpolationWeights(axes, {tc(rng), ks(rng), kf(rng)});
        ASSERT_GE(w.count, 1);
        // T_c's 3 samples and k_s's 4 give 3 and 4 at most (a stencil of 4 needs 4); k_f's 2 give 2.
        ASSERT_LE(w.count, 3 * 4 * 2);
        EXPECT_NEAR(weightSum(w), 1.0, kWeightTolerance);
        for (int i = 0; i < w.count; ++i) {
            EXPECT_TRUE(std::isfinite(w.weight[i]));
            EXPECT_NE(w.weight[i], 0.0f) << "zero weights are left out";
            EXPECT_GE(w.point[i], 0);
            EXPECT_LT(w.point[i], axes.pointCount());
            for (int j = 0; j < i; ++j) EXPECT_NE(w.point[i], w.point[j]) << "each grid point once";
        }
    }
}

TEST(ParameterGrid, ExactForQuadraticsInEachParameter) {
    // Each axis's cubic reproduces any quadratic in its parameter (two samples: any linear one), so the
    // tensor product reproduces this f on threeAxes() (k_f has two samples: linear in k_f).
    const ParameterAxes axes = threeAxes();
    const auto f = [](const ExtinctionParams& p) {
        const double tc = p.temperature_threshold, ks = p.smoke_extinction, kf = p.flame_extinction;
        return 3.0 + 2.0 * tc - 1.5 * tc * tc - 0.5 * ks + 0.05 * ks * ks + 7.0 * kf + 0.02 * tc * tc * ks * ks * kf;
    };
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> tc(1.0, 2.5), ks(2.0, 16.0), kf(0.5, 1.5);
    for (int n = 0; n < 200; ++n) {
        const ExtinctionParams p{tc(rng), ks(rng), kf(rng)};
        // Values up to ~150, weights up to ~1.4 in float: ~150 * 24 float ulps.
        EXPECT_NEAR(interpolate(axes, interpolationWeights(axes, p), f), f(p), 5e-4);
    }
}

TEST(ParameterGrid, HandCheckedWeights) {
    // k_s = 5 on {2, 4, 8, 16}, t = 1/4 between 4 and 8: the parabola through 2, 4, 8 and the one
    // through 4, 8, 16, blended 3/4 : 1/4. Lagrange weights at 5: (2, 4, 8) -> (-1/4, 9/8, 1/8),
    // (4, 8, 16) -> (11/16, 11/32, -1/32).
    const ParameterAxes axes{{1.0}, {2.0, 4.0, 8.0, 16.0}, {0.5}};
    const GridWeights w = interpolationWeights(axes, {1.0, 5.0, 0.5});
    const double expected[4] = {0.75 * -0.25, 0.75 * 9.0 / 8.0 + 0.25 * 11.0 / 16.0,
                                0.75 * 1.0 / 8.0 + 0.25 * 11.0 / 32.0, 0.25 * -1.0 / 32.0};
    ASSERT_EQ(w.count, 4);
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(w.point[i], i) << "k_s samples in order";
        EXPECT_NEAR(w.weight[i], expected[i], kWeightTolerance) << "k_s sample " << i;
    }
    // T_c = 1.25 on {1, 1.5, 2.5}: an end interval, so the one parabola through all three.
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

TEST(ParameterGrid, FollowsSaturatingSmokeWhereLinearCutsTheCurve) {
    // Sunlit smoke saturates as k grows: a pixel through smoke of optical depth tau per unit k has
    // radiance like 1 - exp(-k tau). An image of such pixels, tau log-even over 0.02..2, on the
    // design's k_s samples (2, 4, 8, 16): linear interpolation's chord lies below the curve, 2.0% at
    // worst between 4 and 8; the cubic's two parabolas follow it to 0.7% there. The end intervals have
    // one parabola each and gain less (1.3% against 2.5% between 2 and 4, 1.6% against 1.6% between
    // 8 and 16), which is why the bound below on them is only "no worse than linear".
    const ParameterAxes axes{{1.0}, {2.0, 4.0, 8.0, 16.0}, {0.5}};
    const auto image = [](const ExtinctionParams& p) {
        double sum = 0.0;
        for (int i = 0; i <= 40; ++i) sum += 1.0 - std::exp(-0.02 * std::pow(100.0, i / 40.0) * p.smoke_extinction);
        return sum / 41.0;
    };
    double worst_cubic[3] = {}, worst_linear[3] = {};
    for (int interval = 0; interval < 3; ++interval) {
        const double lo = axes.smoke_extinction[interval], hi = axes.smoke_extinction[interval + 1];
        for (int step = 1; step < 64; ++step) {
            const double t = step / 64.0, ks = lo + t * (hi - lo);
            const double exact = image({1.0, ks, 0.5});
            const double cubic = interpolate(axes, interpolationWeights(axes, {1.0, ks, 0.5}), image);
            const double chord = (1.0 - t) * image({1.0, lo, 0.5}) + t * image({1.0, hi, 0.5});
            worst_cubic[interval] = std::max(worst_cubic[interval], std::abs(cubic / exact - 1.0));
            worst_linear[interval] = std::max(worst_linear[interval], std::abs(chord / exact - 1.0));
        }
    }
    EXPECT_GT(worst_linear[1], 0.018) << "the case must be one where linear interpolation fails";
    EXPECT_LT(worst_cubic[1], 0.008) << "interior interval";
    for (int interval = 0; interval < 3; ++interval)
        EXPECT_LE(worst_cubic[interval], worst_linear[interval] + 1e-4) << "interval " << interval;
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
        } catch (const std::invalid_argument& e) {
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
