// The camera-relative directional lights of `firelook bake --lights sphere:N`: N directions on a
// geodesic sphere (an icosahedron, N = 12, or its once-subdivided form, N = 42), for relighting from
// any direction at run time (relight.h). Light from a direction d between them is their spherical
// barycentric interpolation on the geodesic triangle that holds d (sphereWeights), which
// scripts/bench/relight.sh measured against the reference path tracer (README, "Light from any
// direction").
//
// Camera frame as six_way_lights.h (+X right, +Y up, +Z towards the viewer). The first vertex is
// "top" (the light above, travelling down), the second lies towards the camera at 26.6 degrees of
// elevation; N = 42 keeps the 12 icosahedron vertices first, then the 30 edge midpoints.
#pragma once

#include <array>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

namespace firelook::basis {

// The light counts a sphere bake may have.
inline constexpr std::array<int, 2> kSphereLightCounts = {12, 42};

struct GeodesicSphere {
    std::vector<glm::dvec3> axes;               // unit, from the volume towards each light
    std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from outside; 2N - 4 of them
};

// The sphere of `count` lights (one of kSphereLightCounts), camera frame. An InvalidArgument Error
// for another count.
GeodesicSphere geodesicSphere(int count);

// The direction each light travels (-axis), in world space, for a camera with this
// world_from_camera transform (as sixWayTravelDirections).
std::vector<glm::dvec3> sphereTravelDirections(const glm::dmat4& world_from_camera, int count);

// The weights of the lights travelling along `directions` (unit) for a light travelling along
// `direction` (any non-zero finite length): on the triangle that holds it, its barycentric
// coordinates (the coefficients of d = a t_a + b t_b + c t_c, divided by their sum); 0 elsewhere.
// They are >= 0, sum to 1, are continuous in d, and give one light alone at its own direction.
// An InvalidArgument Error when the direction is not finite or has zero length, a triangle names no
// light, or no triangle holds the direction (the triangles do not cover the sphere).
std::vector<double> sphereWeights(std::span<const glm::dvec3> directions,
                                  std::span<const std::array<int, 3>> triangles, const glm::dvec3& direction);

}  // namespace firelook::basis
