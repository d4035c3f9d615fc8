#include "render/volume_walk.h"

#include <algorithm>
#include <numbers>

namespace firelook::render {
namespace {

// Ratio-tracking weights below this play Russian roulette: survive with probability w / threshold
// and carry the threshold on, so the expectation is unchanged.
constexpr double kRouletteWeight = 0.02;

// Past the roulette depth, paths whose throughput fell below this play Russian roulette and the
// survivors carry exactly this throughput on. Survivors then gain at most 1/0.05 in weight, not the
// 1/albedo^depth of a "survive with probability throughput" rule, which left rare survivors
// carrying a visible share of the answer (0.4% at albedo 0.5) that few pixels ever sampled.
constexpr double kRouletteThroughput = 0.05;

double rouletteWeight(double weight, Pcg32& rng) {
    if (weight >= kRouletteWeight || weight <= 0.0) return weight;
    return rng.uniform() * kRouletteWeight < weight ? kRouletteWeight : 0.0;
}

glm::dvec3 directLight(const VolumeScene& scene, const glm::dvec3& position, Pcg32& rng) {
    glm::dvec3 sum(0.0);
    for (const LightForWalk& light : scene.lights())
        sum += light.irradiance_over_4pi *
               ratioTrackingTransmittance(scene, Ray{position, light.toward_light}, rng);
    return sum;
}

}  // namespace

glm::dvec3 sampleIsotropicDirection(Pcg32& rng) {
    const double z = 1.0 - 2.0 * rng.uniform();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = 2.0 * std::numbers::pi * rng.uniform();
    return {r * std::cos(phi), r * std::sin(phi), z};
}

double ratioTrackingTransmittance(const VolumeScene& scene, const Ray& ray, Pcg32& rng) {
    const LookEvaluator& look = scene.look();
    MajorantTracker tracker(scene.majorants(), ray);
    TentativeCollision c;
    double weight = 1.0;
    while (weight > 0.0 && tracker.advance(sampleOpticalDistance(rng), c)) {
        const MediumSample& s = c.sample;
        if (s.density <= 0.0f) continue;
        const double p = std::min(look.extinction(s.density, s.temperature) / c.majorant, 1.0);
        weight = rouletteWeight(weight * (1.0 - p), rng);
    }
    return weight;
}

bool deltaTrack(const VolumeScene& scene, const Ray& ray, Pcg32& rng, double throughput, glm::dvec3& emission,
                glm::dvec3& collision) {
    const LookEvaluator& look = scene.look();
    const bool emissive = look.hasEmission();
    MajorantTracker tracker(scene.majorants(), ray);
    TentativeCollision c;
    while (tracker.advance(sampleOpticalDistance(rng), c)) {
        const MediumSample& s = c.sample;
        if (s.density <= 0.0f) continue;
        if (emissive)
            emission += (throughput * s.density / c.majorant) * look.emissionPerDensity(s.temperature);
        if (rng.uniform() * c.majorant < look.extinction(s.density, s.temperature)) {
            collision = tracker.worldPoint(c.distance);
            return true;
        }
    }
    return false;
}

PathEstimate estimateCameraPath(const VolumeScene& scene, const Ray& ray, Pcg32& rng,
                                const WalkSettings& settings) {
    const LookEvaluator& look = scene.look();
    const bool emissive = look.hasEmission();
    PathEstimate out;

    // The camera segment runs ratio tracking to the far side: its weight estimates the
    // transmittance (alpha) and weights the emission estimate there, which is less noisy than
    // delta tracking's. On the same tentative collisions an independent coin flip per collision
    // picks delta tracking's first real collision, where the walk goes on. Both estimators are
    // unbiased on their own, so their sum is.
    const bool walk =
        look.albedo() > 0.0 && settings.max_scattering_order >= 1 && (emissive || !scene.lights().empty());
    bool scattered = false;
    glm::dvec3 position(0.0);
    double weight = 1.0;
    MajorantTracker tracker(scene.majorants(), ray);
    TentativeCollision c;
    while ((weight > 0.0 || (walk && !scattered)) && tracker.advance(sampleOpticalDistance(rng), c)) {
        const MediumSample& s = c.sample;
        if (s.density <= 0.0f) continue;
        if (emissive && weight > 0.0)
            out.radiance += (weight * s.density / c.majorant) * look.emissionPerDensity(s.temperature);
        const double p = std::min(look.extinction(s.density, s.temperature) / c.majorant, 1.0);
        if (walk && !scattered && rng.uniform() < p) {
            scattered = true;
            position = tracker.worldPoint(c.distance);
        }
        weight = rouletteWeight(weight * (1.0 - p), rng);
    }
    out.transmittance = weight;
    if (!scattered) return out;

    // From here on delta tracking with analog scattering; sigma_s / sigma_t = albedo is the weight
    // of every real collision (the phase function's sample weight is 1).
    double throughput = 1.0;
    for (int order = 1;; ++order) {
        throughput *= look.albedo();
        out.radiance += throughput * directLight(scene, position, rng);
        if (order >= settings.max_scattering_events) {
            out.truncated = true;
            break;
        }
        if (order >= settings.roulette_depth && throughput < kRouletteThroughput) {
            const double survival = throughput / kRouletteThroughput;
            if (rng.uniform() >= survival) break;
            throughput = kRouletteThroughput;
        }
        // Emission gathered on the next segment has been scattered `order` times.
        const Ray next{position, sampleIsotropicDirection(rng)};
        if (!deltaTrack(scene, next, rng, throughput, out.radiance, position) ||
            order >= settings.max_scattering_order)
            break;
    }
    return out;
}

}  // namespace firelook::render
