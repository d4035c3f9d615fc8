// Irradiance probes: the fluence rate at a point (the radiance arriving from every direction
// integrated over the sphere) and the irradiance on a surface element (the radiance integrated
// over the hemisphere of its normal, weighted by the cosine), under the model of docs/model.md
// (emission, extinction and all orders of scattering, or fewer: WalkSettings::max_scattering_order).
// A small black sphere at the point absorbs its cross-section times the fluence; a small black patch
// facing `normal` absorbs its area times the irradiance. They are the references the fire's point
// lights (runtime/basis/fire_lights.h, whose light of intensity I gives I / d^2) and probe grid
// (runtime/basis/fire_probes.h) are measured against.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>

#include "render/volume_scene.h"
#include "render/volume_walk.h"

namespace firelook::render {

struct FluenceEstimate {
    glm::dvec3 fluence{0.0};         // RGB, radiance x steradian (irradiance for estimateIrradiance)
    glm::dvec3 standard_error{0.0};  // of the mean, per channel, from the samples' spread
};

// Unbiased: `samples` directions uniform in the cone that bounds the volume's bounding sphere as
// seen from the point (the whole sphere from inside it), each followed by one path of
// estimateCameraPath. Depends only on the inputs and the seed. Lights in the scene's look add their
// scattered light too: give a look without lights to measure the fire alone.
FluenceEstimate estimateFluence(const VolumeScene& scene, const glm::dvec3& point, int samples,
                                std::uint64_t seed, const WalkSettings& walk = {});

// The irradiance on a surface at `point` facing `normal` (normalised here; a zero normal gives 0),
// in `fluence`: the surface itself neither blocks nor reflects light. Unbiased: outside the bounding
// sphere the same cone as estimateFluence weighted by max(0, cos) (directions below the surface count
// 0 without a path), inside it directions cosine-distributed over the hemisphere.
FluenceEstimate estimateIrradiance(const VolumeScene& scene, const glm::dvec3& point,
                                   const glm::dvec3& normal, int samples, std::uint64_t seed,
                                   const WalkSettings& walk = {});

}  // namespace firelook::render
