#include "render/volume_scene.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

#include "render/render_error.h"

namespace firelook::render {
namespace {

// Tentative collisions per voxel edge drawn where extinction alone would draw none (pure
// emitters): emission is estimated from these points, so fewer means noisier emission.
constexpr double kEmissionCollisionsPerVoxel = 1.0;

double minimumRate(const Medium& medium, const LookEvaluator& look) {
    if (!look.hasEmission() || medium.empty()) return 0.0;
    return kEmissionCollisionsPerVoxel / medium.minVoxelEdge();
}

}  // namespace

VolumeScene::VolumeScene(const Medium& medium, const LookModel& look)
    : medium_(&medium),
      look_(look),
      majorants_(medium, look.extinction, look.bins, minimumRate(medium, look_)) {
    for (const DirectionalLight& light : look.lights) {
        const double length = glm::length(light.direction);
        if (!(std::isfinite(length) && length > 0.0))
            throw RenderError("look: a directional light has a zero or non-finite direction");
        for (int ch = 0; ch < 3; ++ch)
            if (!(std::isfinite(light.irradiance[ch]) && light.irradiance[ch] >= 0.0f))
                throw RenderError("look: a directional light's irradiance must be finite and non-negative");
        lights_.push_back(
            {-light.direction / length, glm::dvec3(light.irradiance) / (4.0 * std::numbers::pi)});
    }
}

}  // namespace firelook::render
