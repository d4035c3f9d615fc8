#include "vdb/bounds.h"

#include <glm/common.hpp>
#include <glm/vector_relational.hpp>

namespace firelook::vdb {

void Aabb::extend(const glm::dvec3& point) {
    min = glm::min(min, point);
    max = glm::max(max, point);
}

void Aabb::extend(const Aabb& other) {
    if (other.empty()) return;
    extend(other.min);
    extend(other.max);
}

bool Aabb::contains(const Aabb& other) const {
    if (other.empty()) return true;
    return glm::all(glm::lessThanEqual(min, other.min)) && glm::all(glm::greaterThanEqual(max, other.max));
}

void IndexBox::extend(const IndexBox& other) {
    if (other.empty()) return;
    min = glm::min(min, other.min);
    max = glm::max(max, other.max);
}

Aabb interpolationSupport(const IndexBox& active, const glm::dmat4& index_to_world) {
    Aabb world;
    if (active.empty()) return world;
    const glm::dvec3 lo = glm::dvec3(active.min) - 1.0;
    const glm::dvec3 hi = glm::dvec3(active.max) + 1.0;
    // An affine map sends the box to a parallelepiped; its corners bound it.
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 index_point((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y,
                                     (corner & 4) ? hi.z : lo.z);
        world.extend(glm::dvec3(index_to_world * glm::dvec4(index_point, 1.0)));
    }
    return world;
}

}  // namespace firelook::vdb
