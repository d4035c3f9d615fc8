#include "render/fluence_probe.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "render/random.h"

namespace firelook::render {
namespace {

// An orthonormal frame (u, v, w) around the unit vector w.
void frameAround(const glm::dvec3& w, glm::dvec3& u, glm::dvec3& v) {
    const glm::dvec3 helper = std::abs(w.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    u = glm::normalize(glm::cross(helper, w));
    v = glm::cross(w, u);
}

// The mean and standard error of `samples` values of sample(rng), per channel; non-finite values
// count 0 (a path that overflowed must not poison the estimate).
template <typename Sample>
FluenceEstimate meanOf(int samples, std::uint64_t seed, Sample&& sample) {
    Pcg32 rng(seed);
    glm::dvec3 sum(0.0), square(0.0);
    for (int s = 0; s < samples; ++s) {
        glm::dvec3 value = sample(rng);
        if (!std::isfinite(value.x) || !std::isfinite(value.y) || !std::isfinite(value.z))
            value = glm::dvec3(0.0);
        sum += value;
        square += value * value;
    }
    FluenceEstimate out;
    const double n = samples;
    out.fluence = sum / n;
    if (samples > 1)
        out.standard_error = glm::sqrt(glm::max(square / n - out.fluence * out.fluence, 0.0) / (n - 1.0));
    return out;
}

// The cone from `point` that bounds the volume's bounding sphere: its axis, cos of its half-angle
// (-1, the whole sphere, from inside) and solid angle 2 pi (1 - cos).
struct BoundingCone {
    glm::dvec3 u, v, w;
    double cos_max, solid_angle;
    bool inside;
};

BoundingCone boundingCone(const VolumeScene& scene, const glm::dvec3& point) {
    const WorldBox box = scene.medium().worldBounds();
    const glm::dvec3 centre = 0.5 * (box.min + box.max);
    const double radius = 0.5 * glm::length(box.max - box.min);
    const glm::dvec3 axis = centre - point;
    const double distance = glm::length(axis);
    BoundingCone c;
    c.inside = !(distance > radius);
    c.cos_max = c.inside ? -1.0 : std::sqrt(1.0 - (radius / distance) * (radius / distance));
    c.solid_angle = 2.0 * std::numbers::pi * (1.0 - c.cos_max);
    c.w = distance > 0.0 ? axis / distance : glm::dvec3(0.0, 0.0, 1.0);
    frameAround(c.w, c.u, c.v);
    return c;
}

glm::dvec3 inCone(const BoundingCone& c, Pcg32& rng) {
    const double cos_t = 1.0 - rng.uniform() * (1.0 - c.cos_max),
                 phi = 2.0 * std::numbers::pi * rng.uniform();
    const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
    return glm::normalize(sin_t * std::cos(phi) * c.u + sin_t * std::sin(phi) * c.v + cos_t * c.w);
}

}  // namespace

FluenceEstimate estimateFluence(const VolumeScene& scene, const glm::dvec3& point, int samples,
                                std::uint64_t seed, const WalkSettings& walk) {
    if (samples <= 0 || scene.medium().empty()) return {};
    const BoundingCone cone = boundingCone(scene, point);
    return meanOf(samples, seed, [&](Pcg32& rng) {
        const Ray ray{point, inCone(cone, rng)};
        return estimateCameraPath(scene, ray, rng, walk).radiance * cone.solid_angle;
    });
}

FluenceEstimate estimateIrradiance(const VolumeScene& scene, const glm::dvec3& point,
                                   const glm::dvec3& normal, int samples, std::uint64_t seed,
                                   const WalkSettings& walk) {
    const double length = glm::length(normal);
    if (samples <= 0 || scene.medium().empty() || !(length > 0.0)) return {};
    const glm::dvec3 n = normal / length;
    const BoundingCone cone = boundingCone(scene, point);
    if (!cone.inside)
        return meanOf(samples, seed, [&](Pcg32& rng) {
            const glm::dvec3 d = inCone(cone, rng);
            const double cosine = glm::dot(d, n);
            if (!(cosine > 0.0)) return glm::dvec3(0.0);
            return estimateCameraPath(scene, {point, d}, rng, walk).radiance * (cone.solid_angle * cosine);
        });
    // Cosine-distributed over the hemisphere (pdf cos / pi): each path weighs pi.
    glm::dvec3 u, v;
    frameAround(n, u, v);
    return meanOf(samples, seed, [&](Pcg32& rng) {
        const double r2 = rng.uniform(), phi = 2.0 * std::numbers::pi * rng.uniform();
        const double r = std::sqrt(r2), z = std::sqrt(std::max(0.0, 1.0 - r2));
        const glm::dvec3 d = glm::normalize(r * std::cos(phi) * u + r * std::sin(phi) * v + z * n);
        return estimateCameraPath(scene, {point, d}, rng, walk).radiance * std::numbers::pi;
    });
}

}  // namespace firelook::render
