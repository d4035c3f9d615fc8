#include "render/volume_walk.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "look/look_model.h"
#include "render/medium.h"
#include "render/render_error.h"
#include "render/volume_scene.h"
#include "render_test_support.h"

namespace firelook::render {
namespace {

using test::makeLook;

// A unit-density box 2 units wide; rays along its z axis cross exactly 2 units of it.
const Medium& box() {
    static const Medium medium = Medium::homogeneousBox(glm::dvec3(2.0), glm::ivec3(8), 1.0f, 0.5f);
    return medium;
}
const Ray kThroughBox{glm::dvec3(0.1, -0.2, 5.0), glm::dvec3(0.0, 0.0, -1.0)};

TEST(LookEvaluator, MatchesTheLookModel) {
    LookModel look = makeLook(4.0, 0.5, 0.45, 0.7, Rgb(0.0f));
    look.emission.coefficients = {Rgb(1, 2, 3), Rgb(0, 0.5f, 0), Rgb(7, 0, 1), Rgb(0.1f, 0.2f, 0.3f)};
    const LookEvaluator evaluator(look);
    for (double t = -0.5; t <= 1.5; t += 0.01) {
        EXPECT_NEAR(evaluator.extinction(2.0, t), look.sigmaT(2.0, t), 1e-12);
        const Rgb expected = look.emission.evaluate(t);
        const glm::dvec3 got = evaluator.emissionPerDensity(t);
        // The model evaluates in float: agreement to a few float ulps of the largest term (~7).
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got[ch], expected[ch], 1e-5) << "T = " << t;
    }
}

TEST(LookEvaluator, RejectsLooksThatCannotBeEvaluated) {
    EXPECT_THROW(LookEvaluator(makeLook(-1.0, 1.0, 0.5, 0.5, Rgb(1.0f))), RenderError);
    EXPECT_THROW(LookEvaluator(makeLook(1.0, 1.0, 0.5, 1.5, Rgb(1.0f))), RenderError);
    EXPECT_THROW(LookEvaluator(makeLook(1.0, 1.0, 0.5, 0.5, Rgb(-1.0f))), RenderError);
    LookModel empty_range = makeLook(1.0, 1.0, 0.5, 0.5, Rgb(1.0f));
    empty_range.bins.t_hi = empty_range.bins.t_lo;
    EXPECT_THROW(LookEvaluator{empty_range}, RenderError);
}

TEST(VolumeWalk, IsotropicDirectionsAreUnitAndUniform) {
    Pcg32 rng(1);
    constexpr int kCount = 20000;
    glm::dvec3 mean(0.0);
    double mean_z2 = 0.0;
    for (int n = 0; n < kCount; ++n) {
        const glm::dvec3 d = sampleIsotropicDirection(rng);
        ASSERT_NEAR(glm::length(d), 1.0, 1e-12);
        mean += d / double(kCount);
        mean_z2 += d.z * d.z / kCount;
    }
    // Each component has variance 1/3 and z^2 has variance 4/45: 5 standard errors.
    const double se = std::sqrt(1.0 / 3.0 / kCount);
    for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(mean[axis], 0.0, 5.0 * se);
    EXPECT_NEAR(mean_z2, 1.0 / 3.0, 5.0 * std::sqrt(4.0 / 45.0 / kCount));
}

TEST(VolumeWalk, RatioTrackingIsUnbiasedForTransmittance) {
    // kappa varies with T: T = 0.5 with T_c = 0.3 gives kappa between k_s and k_f.
    const LookModel look = makeLook(0.2, 1.4, 0.3, 0.5, Rgb(0.0f));
    const VolumeScene scene(box(), look);
    const double expected = std::exp(-look.sigmaT(1.0, 0.5) * 2.0);
    Pcg32 rng(2);
    constexpr int kCount = 20000;
    double sum = 0.0, sum2 = 0.0;
    for (int n = 0; n < kCount; ++n) {
        const double t = ratioTrackingTransmittance(scene, kThroughBox, rng);
        ASSERT_GE(t, 0.0);
        sum += t;
        sum2 += t * t;
    }
    const double mean = sum / kCount;
    const double standard_error = std::sqrt((sum2 / kCount - mean * mean) / (kCount - 1));
    // 5 standard errors of the mean (estimated from the samples): a false failure ~ 1 in 1.7 million.
    EXPECT_NEAR(mean, expected, 5.0 * standard_error);
}

TEST(VolumeWalk, DeltaTrackingCollidesWithTheRightProbability) {
    const LookModel look = makeLook(0.7, 0.7, 0.3, 0.5, Rgb(0.0f));
    const VolumeScene scene(box(), look);
    const double p = 1.0 - std::exp(-0.7 * 2.0);
    Pcg32 rng(3);
    constexpr int kCount = 20000;
    int hits = 0;
    for (int n = 0; n < kCount; ++n) {
        glm::dvec3 emission(0.0), where(0.0);
        if (deltaTrack(scene, kThroughBox, rng, 1.0, emission, where)) {
            ++hits;
            ASSERT_LE(std::abs(where.z), 1.0 + 0.125);  // inside the box or its half-voxel ramp
        }
    }
    // Binomial standard error sqrt(p (1 - p) / N); 5 of them.
    EXPECT_NEAR(double(hits) / kCount, p, 5.0 * std::sqrt(p * (1.0 - p) / kCount));
}

TEST(VolumeWalk, DeltaTrackingEstimatesEmissionOfAPureEmitter) {
    // k_s = k_f = 0: no extinction, the majorant comes from the emission floor alone. The path
    // crosses the box; the emission estimate must average j * 2.
    const LookModel look = makeLook(0.0, 0.0, 0.3, 0.5, Rgb(1.0f, 2.0f, 0.5f));
    const VolumeScene scene(box(), look);
    const glm::dvec3 expected = 2.0 * glm::dvec3(look.emission.evaluate(0.5));
    Pcg32 rng(4);
    constexpr int kCount = 20000;
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int n = 0; n < kCount; ++n) {
        glm::dvec3 emission(0.0), where(0.0);
        ASSERT_FALSE(deltaTrack(scene, kThroughBox, rng, 1.0, emission, where));
        sum += emission;
        sum2 += emission * emission;
    }
    const glm::dvec3 mean = sum / double(kCount);
    for (int ch = 0; ch < 3; ++ch) {
        const double standard_error = std::sqrt((sum2[ch] / kCount - mean[ch] * mean[ch]) / (kCount - 1));
        EXPECT_NEAR(mean[ch], expected[ch], 5.0 * standard_error);  // 5 standard errors, as above
    }
}

TEST(VolumeWalk, AlbedoOneConservesEveryPhoton) {
    // Photons of a directional light enter a thick box (optical depth 8 across) of albedo 1: no
    // event may lose energy, so every photon must leave again with its weight intact. The walk is
    // built from the same pieces as the camera path (delta tracking + isotropic scattering).
    const LookModel look = makeLook(4.0, 4.0, 0.3, 1.0, Rgb(0.0f));
    const VolumeScene scene(box(), look);
    Pcg32 rng(5);
    constexpr int kCount = 2000;
    long scatterings = 0;
    for (int n = 0; n < kCount; ++n) {
        Ray ray = kThroughBox;
        double weight = 1.0;
        glm::dvec3 unused(0.0), where(0.0);
        int events = 0;
        while (deltaTrack(scene, ray, rng, weight, unused, where)) {
            weight *= scene.look().albedo();
            ray = Ray{where, sampleIsotropicDirection(rng)};
            ASSERT_LT(++events, 100000) << "a photon never left";
        }
        ASSERT_EQ(weight, 1.0);
        scatterings += events;
    }
    // Optical depth 8: almost every photon scatters, most many times.
    EXPECT_GT(scatterings, 5 * kCount);
}

}  // namespace
}  // namespace firelook::render
