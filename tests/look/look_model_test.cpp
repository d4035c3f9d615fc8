// The shared look model (look_model.h): extinction, bins and clamping.
#include "look/look_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace firelook {
namespace {

TEST(SmokeFlameSigmoid, SaturatesWithoutNaNForHugeArguments) {
    EXPECT_EQ(smokeFlameSigmoid(1e30, 0.1), 1.0);
    EXPECT_EQ(smokeFlameSigmoid(-1e30, 0.1), -1.0);
    EXPECT_EQ(smokeFlameSigmoid(1e30, 1e-300), 1.0);  // r / dT overflows to inf
    EXPECT_EQ(smokeFlameSigmoid(0.0, 1.0), 0.0);
}

TEST(SmokeFlameSigmoid, EqualsThePapersLogisticForm) {
    // f(r) = 2 / (1 + exp(-r/dT)) - 1 (paper eq. 3); the two agree to rounding.
    for (double r : {-3.0, -0.5, 0.25, 2.0})
        EXPECT_NEAR(smokeFlameSigmoid(r, 0.5), 2.0 / (1.0 + std::exp(-r / 0.5)) - 1.0, 1e-15);
}

TEST(ExtinctionPerDensity, IsSmokeFarBelowAndFlameFarAboveThreshold) {
    const TemperatureBins bins{0.0, 3.0, 16};
    const ExtinctionParams p{1.5, 6.0, 0.5};
    // 1.5 / dT = 8 bins from T_c: tanh(4) is within 7e-4 of +-1, so kappa is within
    // (6 - 0.5) / 2 * 7e-4 = 2e-3 of k_s or k_f.
    EXPECT_NEAR(extinctionPerDensity(0.0, p, bins), 6.0, 2e-3);
    EXPECT_NEAR(extinctionPerDensity(3.0, p, bins), 0.5, 2e-3);
    EXPECT_DOUBLE_EQ(extinctionPerDensity(1.5, p, bins), 0.5 * (6.0 + 0.5));
    // Outside the range the temperature is clamped first.
    EXPECT_EQ(extinctionPerDensity(-1e30, p, bins), extinctionPerDensity(0.0, p, bins));
    EXPECT_EQ(extinctionPerDensity(1e30, p, bins), extinctionPerDensity(3.0, p, bins));
}

TEST(ExtinctionPerDensity, NonFiniteTemperatureGivesFiniteExtinction) {
    const TemperatureBins bins{0.0, 3.0, 16};
    const ExtinctionParams p{1.5, 6.0, 0.5};
    for (double t : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()})
        EXPECT_TRUE(std::isfinite(extinctionPerDensity(t, p, bins))) << t;
}

TEST(TemperatureBins, CentresAndClamp) {
    const TemperatureBins one{2.0, 4.0, 1};
    EXPECT_DOUBLE_EQ(one.width(), 2.0);
    EXPECT_DOUBLE_EQ(one.center(0), 3.0);
    const TemperatureBins many{0.0, 64.0, 64};
    EXPECT_DOUBLE_EQ(many.center(63), 63.5);
    EXPECT_EQ(many.clamp(std::numeric_limits<double>::quiet_NaN()), 0.0);
    EXPECT_EQ(many.clamp(100.0), 64.0);
}

TEST(ExtinctionPerDensity, TemperatureUnitDoesNotMatter) {
    // The same look in normalised units over a tiny and a huge temperature range.
    for (double unit : {1e-3, 1e4}) {
        const TemperatureBins bins{0.0, unit, 16};
        const ExtinctionParams p{0.4 * unit, 3.0, 1.0};
        const TemperatureBins reference_bins{0.0, 1.0, 16};
        const ExtinctionParams reference{0.4, 3.0, 1.0};
        for (double u = 0.0; u <= 1.0; u += 1.0 / 64)
            // Only rounding of u * unit differs between the two.
            EXPECT_NEAR(extinctionPerDensity(u * unit, p, bins),
                        extinctionPerDensity(u, reference, reference_bins), 1e-12)
                << "unit " << unit << " u " << u;
    }
}

// docs/model.md: L_e(T) = L_e(clamp(T, T_0, T_{n-1})), so the hottest bin's emissivity holds for
// everything hotter (and the coolest for everything cooler). Exact equality: the clamp happens
// before any arithmetic. The version-1 rule (clamp to [T_lo, T_hi]) rolls off in the outer half
// bins, by 1 - exp(-(0.5 / 0.7)^2) = 40% at T_hi for a lone top-bin coefficient.
TEST(EmissionBasis, HoldsTheOuterBinsBeyondTheirCentres) {
    const TemperatureBins bins{0.0, 3.0, 8};
    EmissionFunction emission{EmissionBasis{bins, kDefaultRbfWidth}, std::vector<Rgb>(8, Rgb(0.0f))};
    emission.coefficients.front() = Rgb(0.5f, 0.25f, 0.1f);
    emission.coefficients.back() = Rgb(4.0f, 2.0f, 1.0f);
    const Rgb top = emission.evaluate(bins.center(7)), bottom = emission.evaluate(bins.center(0));
    for (double t : {bins.center(7) + 1e-9, bins.center(7) + 0.1, bins.t_hi, 10.0, 1e30})
        EXPECT_EQ(emission.evaluate(t), top) << "T = " << t;
    for (double t : {bins.center(0) - 1e-9, 0.05, bins.t_lo, -10.0, -1e30})
        EXPECT_EQ(emission.evaluate(t), bottom) << "T = " << t;
    emission.basis.clamp_to_centres = false;  // version 1
    const double u = 0.5 / kDefaultRbfWidth;
    EXPECT_NEAR(emission.evaluate(bins.t_hi).r / emission.evaluate(bins.center(7)).r, std::exp(-u * u), 1e-3);
    EXPECT_EQ(emission.evaluate(10.0), emission.evaluate(bins.t_hi));
}

}  // namespace
}  // namespace firelook
