// Relighting a package baked with `--lights six-way` from a direction chosen at run time
// (`firelook render --light-dir`, fl_instance_set_light_direction): light transport is linear in a
// light's irradiance, so a directional light travelling along d is approximated by the six-way
// light columns (six_way_lights.h) weighted by
//     w_i(d) = max(0, d . t_i)^p / sum_j max(0, d . t_j)^p        (t_i: the direction light i travels)
// with p = kRelightExponent. The weights are non-negative, sum to 1 (a light's total power is
// kept), continuous in d, and exactly one light's at its own direction (w_i = 1), so a baked
// direction reproduces that light's image. p was chosen by measurement against the reference path
// tracer (scripts/bench/relight.sh, README "Light from any direction").
#pragma once

#include <array>
#include <span>

#include <glm/vec3.hpp>

#include "basis/bake_description.h"
#include "basis/six_way_lights.h"
#include "look/look_model.h"

namespace firelook::basis {

// The exponent of the six-way relighting weights (1: the six-way lightmap's own cosine lobes,
// normalised; 2: squared cosines, which already sum to 1).
inline constexpr double kRelightExponent = 2.0;

// A directional light chosen at run time: the direction it travels (world space, any non-zero
// finite length) and the RGB irradiance it carries (a look's light_irradiance units, >= 0).
struct RunTimeLight {
    glm::dvec3 direction{0.0, -1.0, 0.0};
    Rgb irradiance{1.0f};
};

// The light's unit direction. An InvalidArgument Error when its direction is not finite or has zero
// length, or its irradiance is not finite or is negative.
glm::dvec3 checkedUnitDirection(const RunTimeLight& light);

// The weights above for the six travel directions `six_way` (unit vectors) and d = `direction`.
// An InvalidArgument Error when the direction is not finite or has zero length, or exponent <= 0.
std::array<double, kSixWayLightCount> relightWeights(std::span<const glm::dvec3, kSixWayLightCount> six_way,
                                                     const glm::dvec3& direction,
                                                     double exponent = kRelightExponent);

// The six-way lights' irradiance that stands for `light`: w_i(d) * irradiance, in the six-way order.
// An InvalidArgument Error when the package has no six-way lights (the message names `package_name`)
// or the light is not finite, has a zero direction or a negative irradiance.
std::array<Rgb, kSixWayLightCount> relightIrradiance(const BakeDescription& description, const RunTimeLight& light,
                                                     const std::string& package_name);

// light_irradiance (one per package light) with the six-way lights' entries replaced by
// relightIrradiance(); the scene's own lights keep theirs.
void applyRunTimeLight(const BakeDescription& description, const RunTimeLight& light, const std::string& package_name,
                       std::span<Rgb> light_irradiance);

}  // namespace firelook::basis
