// A ray in world space.
#pragma once

#include <glm/vec3.hpp>

#include <algorithm>
#include <limits>

namespace firelook::render {

// origin + t * direction; direction has unit length so t is a distance in world units.
struct Ray {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};
};

// Slab test: the interval [t_enter, t_exit] of t >= 0 where origin + t * direction lies in the
// axis-aligned box [lo, hi]. False when the ray misses it (a NaN in the ray also misses).
// Works in any affine space (world, index, brick units): t keeps the caller's parameterisation.
inline bool intersectBox(const glm::dvec3& origin, const glm::dvec3& direction, const glm::dvec3& lo,
                         const glm::dvec3& hi, double& t_enter, double& t_exit) {
    t_enter = 0.0;
    t_exit = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
        if (direction[axis] == 0.0) {
            if (!(origin[axis] >= lo[axis] && origin[axis] <= hi[axis])) return false;
            continue;
        }
        double t0 = (lo[axis] - origin[axis]) / direction[axis];
        double t1 = (hi[axis] - origin[axis]) / direction[axis];
        if (t0 > t1) std::swap(t0, t1);
        t_enter = std::max(t_enter, t0);
        t_exit = std::min(t_exit, t1);
    }
    return t_enter < t_exit;
}

}  // namespace firelook::render
