// Relighting a package baked with `--lights six-way` or `--lights sphere:N` from directions chosen
// at run time (`firelook render --light-dir`, fl_instance_set_light_direction[s]): light transport
// is linear in a light's irradiance, so a directional light travelling along d is a weighted sum of
// the baked light columns, and several lights the sum of theirs. A sphere package weights its
// lights by spherical barycentric interpolation (sphere_lights.h, sphereWeights); a six-way package
// weights the six-way light columns (six_way_lights.h) by
//     w_i(d) = max(0, d . t_i)^p / sum_j max(0, d . t_j)^p        (t_i: the direction light i travels)
// with p = kRelightExponent. Either kind of weights is non-negative, sums to 1 (a light's power is
// kept), is continuous in d and is one light's alone at its own direction (w_i = 1), so a baked
// direction reproduces that light's image. p was chosen by measurement against the reference path
// tracer (scripts/bench/relight.sh, README "Light from any direction").
#pragma once

#include <array>
#include <glm/vec3.hpp>
#include <span>
#include <string>
#include <vector>

#include "basis/bake_description.h"
#include "basis/six_way_lights.h"
#include "basis/sphere_lights.h"
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

// The weights of the package's run-time light columns (BasisModel::relightFirstLight(), in their
// order: six-way or sphere lights) for a light travelling along `direction`: >= 0, summing to 1.
// An InvalidArgument Error when the package has neither (the message names `package_name`) or the
// direction is not finite or has zero length.
std::vector<double> packageRelightWeights(const BakeDescription& description, const glm::dvec3& direction,
                                          const std::string& package_name);

// The run-time light columns' irradiance that stands for all of `lights` together: the sum over
// the lights of their weights times their irradiance (no lights: all zero). Errors as
// packageRelightWeights, and for a light with a negative or non-finite irradiance or a sum that
// overflows the float range.
std::vector<Rgb> relightIrradiance(const BakeDescription& description, std::span<const RunTimeLight> lights,
                                   const std::string& package_name);

// light_irradiance (one per package light) with the run-time light columns' entries replaced by
// relightIrradiance(); the scene's own lights keep theirs.
void applyRunTimeLights(const BakeDescription& description, std::span<const RunTimeLight> lights,
                        const std::string& package_name, std::span<Rgb> light_irradiance);
void applyRunTimeLight(const BakeDescription& description, const RunTimeLight& light, const std::string& package_name,
                       std::span<Rgb> light_irradiance);

}  // namespace firelook::basis
