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

TEST(ParameterGrid, WeightsSumToOneAndArePositive) {
    const ParameterAxes axes = threeAxes();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> tc(0.0, 3.0), ks(0.0, 20.0), kf(0.0, 2.0);
    for (int n = 0; n < 500; ++n) {
        const GridWeights w = interpolationWeights(axes, {tc(rng), ks(rng), kf(rng)});
        ASSERT_GE(w.count, 1);
        ASSERT_LE(w.count, 8);
        EXPECT_NEAR(weightSum(w), 1.0, kWeightTolerance);
        for (int i = 0; i < w.count; ++i) {
            EXPECT_GT(w.weight[i], 0.0f);
            EXPECT_GE(w.point[i], 0);
            EXPECT_LT(w.point[i], axes.pointCount());
        }
    }
}

TEST(ParameterGrid, LinearBetweenGridPoints) {
    // Trilinear interpolation reproduces any function that is linear in each parameter.
    const ParameterAxes axes = threeAxes();
    const auto f = [](const ExtinctionParams& p) {
        return 3.0 + 2.0 * p.temperature_threshold - 0.5 * p.smoke_extinction + 7.0 * p.flame_extinction +
               0.25 * p.temperature_threshold * p.smoke_extinction * p.flame_extinction;
    };
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> tc(1.0, 2.5), ks(2.0, 16.0), kf(0.5, 1.5);
    for (int n = 0; n < 200; ++n) {
        const ExtinctionParams p{tc(rng), ks(rng), kf(rng)};
        // Values up to ~60, float weights: ~60 * 8 float ulps.
        EXPECT_NEAR(interpolate(axes, interpolationWeights(axes, p), f), f(p), 1e-4);
    }
    // One hand-checked case: halfway along T_c between 1.5 and 2.5, a quarter along k_s from 4 to 8.
    const GridWeights w = interpolationWeights(axes, {2.0, 5.0, 0.5});
    ASSERT_EQ(w.count, 4);
    double expected[4] = {0.5 * 0.75, 0.5 * 0.25, 0.5 * 0.75, 0.5 * 0.25};
    const int points[4] = {axes.pointIndex(1, 1, 0), axes.pointIndex(1, 2, 0), axes.pointIndex(2, 1, 0),
                           axes.pointIndex(2, 2, 0)};
    for (int i = 0; i < 4; ++i) {
        bool found = false;
        for (int j = 0; j < w.count; ++j)
            if (w.point[j] == points[i]) {
                EXPECT_NEAR(w.weight[j], expected[i], kWeightTolerance);
                found = true;
            }
        EXPECT_TRUE(found) << "point " << points[i];
    }
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
