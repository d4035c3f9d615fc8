// The random-walk core of the path tracers: free-flight sampling, ratio and delta tracking, and the
// estimator of one camera path. All estimators are unbiased for the model of docs/model.md.
#pragma once

#include <climits>
#include <cmath>
#include <glm/vec3.hpp>

#include "render/random.h"
#include "render/ray.h"
#include "render/volume_scene.h"

namespace firelook::render {

// An Exp(1) optical distance.
inline double sampleOpticalDistance(Pcg32& rng) { return -std::log(1.0 - rng.uniform()); }

// A direction uniform on the unit sphere (the isotropic phase function's sample, pdf 1 / (4 pi)).
glm::dvec3 sampleIsotropicDirection(Pcg32& rng);

// Ratio tracking (Novak et al. 2014): an unbiased estimate of the transmittance from the ray's
// origin to infinity. Russian roulette on small weights keeps thick media cheap and stays unbiased.
double ratioTrackingTransmittance(const VolumeScene& scene, const Ray& ray, Pcg32& rng);

// Delta tracking from the ray's origin. Adds throughput * j(x) / sigma_bar(x) to emission at every
// tentative collision up to and including the real one (unbiased for throughput times the
// integral of transmittance * j up to the real collision, even where sigma_t = 0). Returns true
// and the world position of the real collision, or false if the ray leaves the medium.
bool deltaTrack(const VolumeScene& scene, const Ray& ray, Pcg32& rng, double throughput, glm::dvec3& emission,
                glm::dvec3& collision);

struct WalkSettings {
    int roulette_depth = 8;              // scattering events before Russian roulette may end a path
    int max_scattering_order = INT_MAX;  // paths end after this many scatterings (1: single)
    int max_scattering_events = 100000;  // a guard against endless walks, see PathEstimate
};

struct PathEstimate {
    glm::dvec3 radiance{0.0};    // RGB radiance arriving along the camera ray
    double transmittance = 1.0;  // ratio-tracking estimate along the camera ray (alpha = 1 - it)
    // The walk reached max_scattering_events and was cut (biased, only possible for albedos
    // extremely close to 1 in very thick media).
    bool truncated = false;
};

// One sample of the radiance and transmittance along a camera ray: emission, single and multiple
// scattering of the directional lights and of emission, background black.
PathEstimate estimateCameraPath(const VolumeScene& scene, const Ray& ray, Pcg32& rng,
                                const WalkSettings& settings);

}  // namespace firelook::render
