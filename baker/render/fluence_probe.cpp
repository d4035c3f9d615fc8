#include "render/fluence_probe.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "render/random.h"

namespace firelook::render {

FluenceEstimate estimateFluence(const VolumeScene& scene, const glm::dvec3& point, int samples, std::uint64_t seed,
                                const WalkSettings& walk) {
    FluenceEstimate out;
    if (samples <= 0 || scene.medium().empty()) return out;
    const WorldBox box = scene.medium().worldBounds();
    const glm::dvec3 centre = 0.5 * (box.min + box.max);
    const double radius = 0.5 * glm::length(box.max - box.min);
    const glm::dvec3 axis = centre - point;
    const double distance = glm::length(axis);
    // Directions uniform in the cone of half-angle asin(radius / distance) around the axis, whose
    // solid angle 2 pi (1 - cos) is the estimator's weight; the whole sphere from inside.
    const double cos_max = distance > radius ? std::sqrt(1.0 - (radius / distance) * (radius / distance)) : -1.0;
    const double solid_angle = 2.0 * std::numbers::pi * (1.0 - cos_max);
    const glm::dvec3 w = distance > 0.0 ? axis / distance : glm::dvec3(0.0, 0.0, 1.0);
    const glm::dvec3 helper = std::abs(w.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 u = glm::normalize(glm::cross(helper, w)), v = glm::cross(w, u);
    Pcg32 rng(seed);
    glm::dvec3 sum(0.0), square(0.0);
    for (int s = 0; s < samples; ++s) {
        const double cos_t = 1.0 - rng.uniform() * (1.0 - cos_max), phi = 2.0 * std::numbers::pi * rng.uniform();
        const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
        const Ray ray{point, glm::normalize(sin_t * std::cos(phi) * u + sin_t * std::sin(phi) * v + cos_t * w)};
        glm::dvec3 value = estimateCameraPath(scene, ray, rng, walk).radiance * solid_angle;
        if (!std::isfinite(value.x) || !std::isfinite(value.y) || !std::isfinite(value.z)) value = glm::dvec3(0.0);
        sum += value;
        square += value * value;
    }
    const double n = samples;
    out.fluence = sum / n;
    if (samples > 1) out.standard_error = glm::sqrt(glm::max(square / n - out.fluence * out.fluence, 0.0) / (n - 1.0));
    return out;
}

}  // namespace firelook::render
