// The tracer's arithmetic shortcuts (bake/trace_tables.h) against the library functions they stand
// in for: the vectorisable exponential, the one-exponential tanh ladder, the factorised
// transmittance and the depth that stands for the negligible transmittance.
#include "bake/trace_tables.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "bake_test_support.h"

namespace firelook::bake {
namespace {

// Distance in units in the last place between two positive normal floats.
std::int64_t ulps(float a, float b) {
    return std::llabs(static_cast<std::int64_t>(std::bit_cast<std::int32_t>(a)) -
                      std::bit_cast<std::int32_t>(b));
}

TEST(TraceTables, ExpNonPositiveIsWithinTwoUlpOfStdExp) {
    // Every float step would be 1e9 values: a dense sweep of [-87, 0] and the ends exactly.
    std::int64_t worst = 0;
    for (int i = 0; i <= 2000000; ++i) {
        const float x = -87.0f * static_cast<float>(i) / 2000000.0f;
        worst = std::max(worst, ulps(expNonPositive(x), std::exp(x)));
    }
    // Cephes' polynomial is within 1 ulp on the reduced range; the scaling by 2^n is exact.
    EXPECT_LE(worst, 2);
    EXPECT_EQ(expNonPositive(0.0f), 1.0f);
    EXPECT_EQ(expNonPositive(-0.0f), 1.0f);
    // Small steps' transmittance factors, where the march lives.
    for (float x : {-1e-8f, -1e-5f, -1e-3f, -0.1f}) EXPECT_LE(ulps(expNonPositive(x), std::exp(x)), 2) << x;
    // Beyond the range: 0 below -87 (exp(-87) = 1.6e-38, nothing a march can see), 1 above 0.
    EXPECT_EQ(expNonPositive(-200.0f), std::exp(-87.0f));
    EXPECT_EQ(expNonPositive(3.0f), 1.0f);
}

TEST(TraceTables, TanhLadderMatchesStdTanh) {
    // The sample's alpha thresholds (21 from 1.0 to 2.0) and its bins' 1/(2 dT) over [0, 3].
    std::vector<float> centres;
    for (int a = 0; a <= 20; ++a) centres.push_back(1.0f + 0.05f * a);
    const float k = 16.0f / (2.0f * 3.0f);
    const TanhLadder ladder(centres, k, 0.0f, 3.0f);
    double e[kMaxAxisSamples];
    double worst = 0.0;
    for (int i = 0; i <= 3000; ++i) {
        const float t = 3.0f * static_cast<float>(i) / 3000.0f;
        ladder.exponentials(t, e);
        for (std::size_t c = 0; c < centres.size(); ++c) {
            const double f = 1.0 - 2.0 / (1.0 + e[c]);
            worst = std::max(worst, std::fabs(f - std::tanh((double(t) - centres[c]) * k)));
        }
    }
    // Double rounding of one exponential, a product and a quotient: far below float's 6e-8.
    EXPECT_LT(worst, 1e-13);
}

TEST(TraceTables, TanhLadderFarOutsideItsRangeStillGivesPlusMinusOne) {
    // 256 bins over [0, 1] and centres far outside: exponents beyond +-300, each clamped on its own.
    const std::vector<float> centres{-50.0f, 0.5f, 60.0f};
    const float k = 256.0f / 2.0f;
    const TanhLadder ladder(centres, k, 0.0f, 1.0f);
    double e[3];
    ladder.exponentials(0.25f, e);
    EXPECT_DOUBLE_EQ(1.0 - 2.0 / (1.0 + e[0]), 1.0);
    EXPECT_NEAR(1.0 - 2.0 / (1.0 + e[1]), std::tanh((0.25 - 0.5) * k), 1e-15);
    EXPECT_DOUBLE_EQ(1.0 - 2.0 / (1.0 + e[2]), -1.0);
    for (double v : e) EXPECT_TRUE(std::isfinite(v));
}

// transmittance() against exp(-k_s D_s - k_f D_f) in double for every grid point: on the design's
// doubling axes (squares of one exponential) and on axes that do not double (an exponential
// each), over optical depths from 0 to far past the negligible. Relative error 4e-6 (squares add
// 2 ulp a doubling: 16 ulp, 1e-6, at the fourth sample), and where a factor is below 2^-63 it is
// held there, so the transmittance is never below 2^-126 (a normal float) and at most 2^-63 too
// high: nothing a march can see (kNegligibleTransmittance is 1e-5).
TEST(TraceTables, TransmittanceMatchesTheExponentialOnEveryAxis) {
    const basis::ParameterAxes doubling{{1.0, 1.5, 2.0}, {2.0, 4.0, 8.0, 16.0}, {0.5, 1.0, 2.0, 4.0}};
    const basis::ParameterAxes other{{1.0, 1.5, 2.0}, {2.0, 3.0, 8.0, 16.0}, {0.5, 1.7, 2.0}};
    for (const basis::ParameterAxes& axes : {doubling, other}) {
        const TraceTables tb(basisModel(4, 0.5, axes));
        std::vector<float> tau(tb.points);
        double worst = 0.0;
        for (int i = 0; i <= 400; ++i) {
            float ds[3], df[3];
            for (int a = 0; a < 3; ++a) {
                ds[a] = 0.05f * static_cast<float>(i) * (1.0f + 0.3f * a);
                df[a] = 0.07f * static_cast<float>((i * 7) % 401) / (1.0f + a);
            }
            tb.transmittance(ds, df, tau.data());
            for (int g = 0; g < tb.points; ++g) {
                const int a = g / (tb.n_ks * tb.n_kf), s = (g / tb.n_kf) % tb.n_ks, f = g % tb.n_kf;
                const double exact = std::exp(-double(tb.ks[s]) * ds[a] - double(tb.kf[f]) * df[a]);
                ASSERT_GE(tau[g], std::numeric_limits<float>::min()) << "a normal float";
                worst = std::max(worst, std::abs(tau[g] - exact) / (exact + 0x1p-63 / 4e-6));
            }
        }
        EXPECT_LT(worst, 4e-6) << "axes " << axes.smoke_extinction[1];
    }
}

// Marches that carry only depths stop where the thinnest grid point's transmittance falls below
// kNegligibleTransmittance: the depth they compare is that transmittance's.
TEST(TraceTables, NegligibleDepthIsTheNegligibleTransmittance) {
    EXPECT_NEAR(kNegligibleDepth, -std::log(double(kNegligibleTransmittance)), 1e-6);
    const TraceTables tb(basisModel(4, 0.5, {{1.0, 1.5}, {2.0, 4.0}, {0.5, 1.0}}));
    const float ds[2] = {3.0f, 9.0f}, df[2] = {10.0f, 0.0f};
    EXPECT_FLOAT_EQ(tb.minDepthOfLeastExtinction(ds, df), std::min(2.0f * 3 + 0.5f * 10, 2.0f * 9));
}

}  // namespace
}  // namespace firelook::bake
