// The tracer's arithmetic shortcuts (bake/trace_tables.h) against the library functions they stand
// in for: the vectorisable exponential and the one-exponential tanh ladder.
#include "bake/trace_tables.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

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

}  // namespace
}  // namespace firelook::bake
