#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <limits>

namespace firelook::vdb {

// Axis-aligned world-space box; default constructed it is empty (min > max).
struct Aabb {
    glm::dvec3 min{std::numeric_limits<double>::infinity()};
    glm::dvec3 max{-std::numeric_limits<double>::infinity()};

    bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    void extend(const glm::dvec3& point);
    void extend(const Aabb& other);
    bool contains(const Aabb& other) const;
};

// Inclusive box of voxel indices; default constructed it is empty (min > max).
struct IndexBox {
    glm::ivec3 min{std::numeric_limits<int>::max()};
    glm::ivec3 max{std::numeric_limits<int>::min()};

    bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    void extend(const IndexBox& other);
};

// World box of the region where a field trilinearly interpolated from voxels in `active` can be
// non-zero: the index box grown by one voxel on every side, mapped by the affine index_to_world.
// Empty for an empty index box.
Aabb interpolationSupport(const IndexBox& active, const glm::dmat4& index_to_world);

}  // namespace firelook::vdb
