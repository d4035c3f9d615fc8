// Rays in a medium's index space and the fixed-step march every pass of the basis tracer uses.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vector_relational.hpp>
#include <limits>
#include <utility>

#include "render/medium.h"
#include "render/ray.h"

namespace firelook::bake {

// A world ray expressed in the medium's index space, parameterised by world distance.
struct IndexRay {
    glm::dvec3 origin;
    glm::dvec3 direction;  // index-space displacement per world unit
};

inline IndexRay toIndexSpace(const render::Medium& medium, const glm::dvec3& origin, const glm::dvec3& direction) {
    const glm::dmat4& w2i = medium.worldToIndex();
    return {glm::dvec3(w2i * glm::dvec4(origin, 1.0)), glm::dmat3(w2i) * direction};
}

// An index-space box; the influence box [origin - 1, origin + dims] is where interpolated values
// can be non-zero.
struct IndexBox {
    glm::dvec3 lo, hi;
};

inline IndexBox influenceBox(const render::Medium& medium) {
    return {glm::dvec3(medium.origin()) - 1.0, glm::dvec3(medium.origin() + medium.dims())};
}

// Index points of the influence box along each axis (both ends included), and the most of any axis:
// what the cell and light-lattice sizes are counted against.
inline glm::ivec3 influencePoints(const render::Medium& medium) { return medium.dims() + 2; }
inline int longestInfluenceAxis(const render::Medium& medium) {
    const glm::ivec3 points = influencePoints(medium);
    return std::max({points.x, points.y, points.z});
}

inline bool clipToBox(const IndexRay& ray, const IndexBox& box, double& t0, double& t1) {
    return render::intersectBox(ray.origin, ray.direction, box.lo, box.hi, t0, t1);
}

// A ray in the bricks' grid (Medium::kBrickSize voxels a unit), prepared once a march: the brick
// test runs at nearly every step of a photon track (steps of a cell, bricks of 4 voxels), and
// with a division per axis it was 8% of the photon passes on a frame upsampled 4x.
struct BrickRay {
    glm::dvec3 origin, direction, inverse;  // inverse: 1 / direction per axis (0 where it is 0)
    glm::ivec3 counts;
};

inline BrickRay toBrickGrid(const render::Medium& medium, const IndexRay& ray) {
    constexpr double kBrick = render::Medium::kBrickSize;
    const glm::dvec3 direction = ray.direction / kBrick;
    glm::dvec3 inverse(0.0);
    for (int a = 0; a < 3; ++a)
        if (direction[a] != 0.0) inverse[a] = 1.0 / direction[a];
    return {(ray.origin - medium.brickGridOrigin()) / kBrick, direction, inverse, medium.brickCounts()};
}

// Whether the medium is zero throughout the brick that holds the ray's point at t, and where the
// ray leaves that brick: `exit`, a ray parameter. Outside the bricks' grid (zero everywhere) the
// empty run ends where the ray enters the grid, or never.
inline bool emptyBrickAt(const render::Medium& medium, const BrickRay& ray, double t, double& exit) {
    const glm::dvec3 g = ray.origin + t * ray.direction;
    const glm::dvec3 cell = glm::floor(g);
    const glm::ivec3 b(cell);
    exit = std::numeric_limits<double>::infinity();
    if (glm::any(glm::lessThan(b, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(b, ray.counts))) {
        double t_enter, t_leave;
        if (render::intersectBox(g, ray.direction, glm::dvec3(0.0), glm::dvec3(ray.counts), t_enter, t_leave))
            exit = t + t_enter;
        return true;
    }
    for (int a = 0; a < 3; ++a)
        if (ray.direction[a] != 0.0)
            exit = std::min(exit,
                            t + ((ray.direction[a] > 0.0 ? cell[a] + 1.0 : cell[a]) - g[a]) * ray.inverse[a]);
    return !medium.brickHasDensity(b);
}

// Marches from t_start to t_end in steps of `step` world units, calling
// visit(index_point_mid, step_length, rho, t) at each step's midpoint; visit returns false to stop.
// The first step is `phase` (in (0, 1]) times `step` long. Rays that start on a voxel face and run
// along a grid axis (the influence box's faces are whole voxels; six-way lights and views along an
// axis) would otherwise put every midpoint at the same place within its voxel, and the midpoint
// rule's error at the trilinear field's kinks would add up instead of cancelling: a phase drawn per
// ray turns it into noise (TraceSettings::step_voxels).
// Steps whose midpoints fall in a brick of zero density are not visited (every visitor returns at
// once where rho is 0): most of a camera ray's steps cross empty space (73% of them on frame 12 of
// the bundled sample at 128x128), and each cost a trilinear lookup.
template <typename Visit>
void march(const render::Medium& medium, const IndexRay& ray, double t_start, double t_end, double step,
           double phase, Visit&& visit) {
    double dt = std::min(phase * step, t_end - t_start);
    const BrickRay bricks = toBrickGrid(medium, ray);
    // Where the brick last found to hold density ends: no lookup before then.
    double brick_end = -std::numeric_limits<double>::infinity();
    for (double t = t_start; t < t_end; t += dt, dt = std::min(step, t_end - t)) {
        const double mid = t + 0.5 * dt;
        if (mid >= brick_end) {
            double exit;
            if (emptyBrickAt(medium, bricks, mid, exit)) {
                // Skip every whole step whose midpoint is still before the exit; the loop's
                // increment takes the last of them.
                if (dt == step && exit > mid) {
                    const double skipped = std::ceil((exit - mid) / step);
                    if (std::isfinite(skipped))
                        t += (skipped - 1.0) * step;
                    else
                        t = t_end;
                }
                continue;
            }
            brick_end = exit;
        }
        const glm::dvec3 p = ray.origin + mid * ray.direction;
        const render::MediumSample s = medium.sampleIndex(p);
        if (!visit(p, static_cast<float>(dt), s.density, s.temperature)) return;
    }
}

// The same with every step whole (phase 1): photon tracks start at sampled points, and the lattices'
// rays (light depths, fire lights and probes) at fixed ones.
template <typename Visit>
void march(const render::Medium& medium, const IndexRay& ray, double t_start, double t_end, double step,
           Visit&& visit) {
    march(medium, ray, t_start, t_end, step, 1.0, std::forward<Visit>(visit));
}

}  // namespace firelook::bake
