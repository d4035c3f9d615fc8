// Everything a random walk reads: the medium, the look prepared for it, majorants, lights.
#pragma once

#include <glm/vec3.hpp>
#include <vector>

#include "look/look_model.h"
#include "render/look_evaluator.h"
#include "render/majorant_grid.h"
#include "render/medium.h"

namespace firelook::render {

// A directional light as the walk uses it.
struct LightForWalk {
    glm::dvec3 toward_light{0.0, 1.0, 0.0};  // unit, opposite to the direction the light travels
    glm::dvec3 irradiance_over_4pi{0.0};     // E / (4 pi): the isotropic phase function applied
};

// Immutable once built; shared by every thread of a render. Holds a reference to the medium, which
// must outlive it.
class VolumeScene {
  public:
    // Throws RenderError for a look that cannot be evaluated (see LookEvaluator) or a light with a
    // zero or non-finite direction or a negative or non-finite irradiance.
    VolumeScene(const Medium& medium, const LookModel& look);

    const Medium& medium() const { return *medium_; }
    const LookEvaluator& look() const { return look_; }
    const MajorantGrid& majorants() const { return majorants_; }
    const std::vector<LightForWalk>& lights() const { return lights_; }

  private:
    const Medium* medium_;
    LookEvaluator look_;
    MajorantGrid majorants_;
    std::vector<LightForWalk> lights_;
};

}  // namespace firelook::render
