#include "image/srgb.h"

#include <gtest/gtest.h>

namespace firelook::image {
namespace {

// Reference values computed from the IEC 61966-2-1 formulas in double precision; the tolerance only
// allows for pow() rounding differences between libraries.
constexpr double kTolerance = 1e-12;

TEST(Srgb, EncodesKnownPoints) {
    EXPECT_NEAR(linearToSrgb(0.0), 0.0, kTolerance);
    EXPECT_NEAR(linearToSrgb(1.0), 1.0, kTolerance);
    EXPECT_NEAR(linearToSrgb(0.001), 0.01292, kTolerance);  // linear toe: 12.92 * x
    EXPECT_NEAR(linearToSrgb(0.0031308), 0.040449936, kTolerance);
    EXPECT_NEAR(linearToSrgb(0.18), 0.46135612950044164, kTolerance);  // mid grey
    EXPECT_NEAR(linearToSrgb(0.5), 0.7353569830524495, kTolerance);
}

TEST(Srgb, DecodesKnownPoints) {
    EXPECT_NEAR(srgbToLinear(0.0), 0.0, kTolerance);
    EXPECT_NEAR(srgbToLinear(1.0), 1.0, kTolerance);
    EXPECT_NEAR(srgbToLinear(0.5), 0.21404114048223255, kTolerance);
    EXPECT_NEAR(srgbToLinear(0.04045), 0.0031308049535603713, kTolerance);
}

TEST(Srgb, ClampsOutOfRangeInput) {
    EXPECT_EQ(linearToSrgb(-3.0), 0.0);
    EXPECT_NEAR(linearToSrgb(7.0), 1.0, kTolerance);
    EXPECT_EQ(srgbToLinear(-0.5), 0.0);
    EXPECT_EQ(srgbToLinear(1.5), 1.0);
}

TEST(Srgb, DecodeInvertsEncode) {
    for (int i = 0; i <= 1000; ++i) {
        const double linear = i / 1000.0;
        EXPECT_NEAR(srgbToLinear(linearToSrgb(linear)), linear, kTolerance) << "at " << linear;
    }
}

}  // namespace
}  // namespace firelook::image
