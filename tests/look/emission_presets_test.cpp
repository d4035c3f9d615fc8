// Emission presets and the blackbody colour they are built on.
#include "look/emission_presets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/vec2.hpp>

#include "look/blackbody.h"

namespace firelook {
namespace {

// Planckian locus chromaticity by the cubic fit of Kim et al., US patent 7024034
// (valid 1667..25000 K; within 1e-4 of the tabulated locus there).
glm::dvec2 planckianLocus(double kelvin) {
    const double t = kelvin;
    const double x = kelvin <= 4000
                         ? -0.2661239e9 / (t * t * t) - 0.2343589e6 / (t * t) + 0.8776956e3 / t + 0.179910
                         : -3.0258469e9 / (t * t * t) + 2.1070379e6 / (t * t) + 0.2226347e3 / t + 0.240390;
    double y;
    if (kelvin <= 2222)
        y = -1.1063814 * x * x * x - 1.34811020 * x * x + 2.18555832 * x - 0.20219683;
    else if (kelvin <= 4000)
        y = -0.9549476 * x * x * x - 1.37418593 * x * x + 2.09137015 * x - 0.16748867;
    else
        y = 3.0817580 * x * x * x - 5.87338670 * x * x + 3.75112997 * x - 0.37001483;
    return {x, y};
}

TEST(Blackbody, ChromaticityFollowsThePlanckianLocus) {
    for (double kelvin : {2000.0, 3000.0, 4000.0, 6500.0}) {
        const glm::dvec3 xyz = blackbodyXyz(kelvin);
        const double sum = xyz.x + xyz.y + xyz.z;
        const glm::dvec2 expected = planckianLocus(kelvin);
        // The analytic colour matching functions are least accurate in the deep red,
        // which dominates cool blackbodies: measured 0.0027 at 2000 K, 0.001 at 3000 K.
        EXPECT_NEAR(xyz.x / sum, expected.x, 0.004) << kelvin;
        EXPECT_NEAR(xyz.y / sum, expected.y, 0.004) << kelvin;
    }
}

TEST(Blackbody, ColourIsRedWhenCoolAndNearWhiteAtD65) {
    const glm::dvec3 cool = blackbodyColor(1500.0);
    EXPECT_GT(cool.r, 5.0 * cool.g);
    EXPECT_GE(cool.b, 0.0);  // clipped, not negative
    const glm::dvec3 d65 = blackbodyColor(6504.0);
    // The Planckian locus passes 0.003 from D65 (which lies off it): a few % per channel.
    EXPECT_NEAR(d65.r, 1.0, 0.06);
    EXPECT_NEAR(d65.g, 1.0, 0.06);
    EXPECT_NEAR(d65.b, 1.0, 0.06);
}

TEST(EmissionPresets, AreZeroWhenColdAndBrightenWithTemperature) {
    EXPECT_EQ(presetNames(), (std::vector<std::string>{"blackbody", "fire"}));
    for (const EmissionPresetDefinition& preset : emissionPresets()) {
        EXPECT_EQ(preset.evaluate(0.0), Rgb(0.0f)) << preset.name;
        float previous_luminance = -1.0f;
        for (int step = 0; step <= 32; ++step) {
            const Rgb c = preset.evaluate(step / 32.0);
            EXPECT_TRUE(c.r >= 0.0f && c.g >= 0.0f && c.b >= 0.0f) << preset.name;
            const float luminance = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
            EXPECT_GT(luminance, previous_luminance) << preset.name << " at step " << step;
            previous_luminance = luminance;
        }
        // Documented: luminance ~1 at the hot end, so "scale" sets the brightness.
        EXPECT_NEAR(previous_luminance, 1.0f, 0.05f) << preset.name;
        // Hot end is yellow-white: red >= green >= blue > 0.
        const Rgb hot = preset.evaluate(1.0);
        EXPECT_TRUE(hot.r >= hot.g && hot.g >= hot.b && hot.b > 0.0f) << preset.name;
        // Out-of-range and NaN inputs are clamped.
        EXPECT_EQ(preset.evaluate(2.0), hot);
        EXPECT_EQ(preset.evaluate(std::nan("")), Rgb(0.0f));
    }
}

TEST(EmissionPresets, FindByName) {
    ASSERT_NE(findEmissionPreset("fire"), nullptr);
    EXPECT_EQ(findEmissionPreset("fire")->name, "fire");
    EXPECT_EQ(findEmissionPreset("Fire"), nullptr);
}

}  // namespace
}  // namespace firelook
