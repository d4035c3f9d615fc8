#include "render/medium.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <limits>
#include <string>

#include "render/render_error.h"

namespace firelook::render {
namespace {

// Finite values beyond this are clamped: interpolation computes differences of neighbours, which
// must not overflow float. No physical density or temperature comes near it.
constexpr float kLargestValue = 1e30f;

bool isAffineAndInvertible(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) return false;
    const double det = glm::determinant(glm::dmat3(m));
    return std::isfinite(det) && det != 0.0;
}

}  // namespace

Medium::Medium(glm::ivec3 origin, glm::ivec3 dims, std::span<const float> density,
               std::span<const float> temperature, const glm::dmat4& index_to_world,
               float background_temperature)
    : origin_(origin), dims_(dims), index_to_world_(index_to_world) {
    if (dims.x < 0 || dims.y < 0 || dims.z < 0)
        throw RenderError("medium: negative dimensions " + std::to_string(dims.x) + "x" +
                          std::to_string(dims.y) + "x" + std::to_string(dims.z));
    const std::size_t count = static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) *
                              static_cast<std::size_t>(dims.z);
    if (density.size() != count || temperature.size() != count)
        throw RenderError("medium: expected " + std::to_string(count) + " voxels for dimensions, got " +
                          std::to_string(density.size()) + " densities and " +
                          std::to_string(temperature.size()) + " temperatures");
    if (!isAffineAndInvertible(index_to_world))
        throw RenderError("medium: the index-to-world transform is not an invertible affine map");
    if (!std::isfinite(background_temperature))
        throw RenderError("medium: the background temperature is not finite");
    world_to_index_ = glm::inverse(index_to_world);
    background_temperature_ = std::clamp(background_temperature, -kLargestValue, kLargestValue);

    if (count == 0) {
        dims_ = glm::ivec3(0);
        return;
    }
    voxels_.resize(count);
    // Slice by slice on every core (a frame upsampled 4x has 33 million voxels: 0.4 s on one); each
    // slice counts what it cleaned, summed after in slice order.
    std::vector<std::uint64_t> sanitized(static_cast<std::size_t>(dims.z), 0);
    const std::size_t slice = static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y);
    tbb::parallel_for(0, dims.z, [&](int z) {
        std::uint64_t cleaned = 0;
        for (std::size_t n = z * slice; n < (z + 1) * slice; ++n) {
            float rho = density[n];
            float t = temperature[n];
            if (!std::isfinite(rho) || rho < 0.0f) {
                rho = 0.0f;
                ++cleaned;
            }
            if (!std::isfinite(t)) {
                t = background_temperature_;
                ++cleaned;
            }
            voxels_[n] = glm::vec2(std::min(rho, kLargestValue), std::clamp(t, -kLargestValue, kLargestValue));
        }
        sanitized[static_cast<std::size_t>(z)] = cleaned;
    });
    for (std::uint64_t cleaned : sanitized) sanitized_values_ += cleaned;
    buildBricks();
}

Medium Medium::homogeneousBox(const glm::dvec3& world_size, const glm::ivec3& voxels, float density,
                              float temperature) {
    if (voxels.x < 1 || voxels.y < 1 || voxels.z < 1)
        throw RenderError("homogeneous box: needs at least one voxel per axis");
    if (!(world_size.x > 0.0 && world_size.y > 0.0 && world_size.z > 0.0))
        throw RenderError("homogeneous box: the world size must be positive");
    // Voxel i spans [i - 0.5, i + 0.5] in index space; the box spans [-0.5, n - 0.5], mapped onto
    // [-size/2, size/2]. The ramps from the first and last voxels to the zero background cover
    // [-1, 0] and [n - 1, n] and each integrates to half a voxel, so the total equals the box's.
    const glm::dvec3 voxel_size = world_size / glm::dvec3(voxels);
    glm::dmat4 index_to_world(1.0);
    for (int axis = 0; axis < 3; ++axis) {
        index_to_world[axis][axis] = voxel_size[axis];
        index_to_world[3][axis] = 0.5 * voxel_size[axis] - 0.5 * world_size[axis];
    }
    const std::size_t count = static_cast<std::size_t>(voxels.x) * static_cast<std::size_t>(voxels.y) *
                              static_cast<std::size_t>(voxels.z);
    const std::vector<float> rho(count, density);
    const std::vector<float> t(count, temperature);
    return Medium(glm::ivec3(0), voxels, rho, t, index_to_world, temperature);
}

Medium Medium::slab(double thickness, double lateral_size, float density, float temperature) {
    // Few voxels suffice: the medium is uniform, only the faces' ramps matter.
    return homogeneousBox(glm::dvec3(lateral_size, lateral_size, thickness), glm::ivec3(16, 16, 4), density,
                          temperature);
}

glm::vec2 Medium::voxelOrBackground(int i, int j, int k) const {
    if (i < 0 || j < 0 || k < 0 || i >= dims_.x || j >= dims_.y || k >= dims_.z)
        return glm::vec2(0.0f, background_temperature_);
    return voxels_[static_cast<std::size_t>(i) +
                   static_cast<std::size_t>(dims_.x) *
                       (static_cast<std::size_t>(j) +
                        static_cast<std::size_t>(dims_.y) * static_cast<std::size_t>(k))];
}

// The body of cubeCorners, relative to the stored box's first voxel. Always inlined into
// sampleIndex, the bake's most called lookup: left to itself GCC made it a call there.
[[gnu::always_inline]] inline void Medium::loadCorners(const glm::ivec3& i0, glm::vec2 (&c)[8]) const {
    if (i0.x >= 0 && i0.y >= 0 && i0.z >= 0 && i0.x + 1 < dims_.x && i0.y + 1 < dims_.y &&
        i0.z + 1 < dims_.z) {
        const std::size_t sy = static_cast<std::size_t>(dims_.x);
        const std::size_t sz = sy * static_cast<std::size_t>(dims_.y);
        const glm::vec2* p = voxels_.data() + static_cast<std::size_t>(i0.x) +
                             sy * static_cast<std::size_t>(i0.y) + sz * static_cast<std::size_t>(i0.z);
        c[0] = p[0], c[1] = p[1], c[2] = p[sy], c[3] = p[sy + 1];
        c[4] = p[sz], c[5] = p[sz + 1], c[6] = p[sz + sy], c[7] = p[sz + sy + 1];
    } else {
        for (int n = 0; n < 8; ++n)
            c[n] = voxelOrBackground(i0.x + (n & 1), i0.y + ((n >> 1) & 1), i0.z + (n >> 2));
    }
}

void Medium::cubeCorners(const glm::ivec3& corner, glm::vec2 (&c)[8]) const {
    loadCorners(corner - origin_, c);
}

MediumSample Medium::sampleIndex(const glm::dvec3& index_point) const {
    const glm::dvec3 relative = index_point - glm::dvec3(origin_);
    const glm::dvec3 base = glm::floor(relative);
    // Points whose eight neighbours all lie outside the box (NaN included) read the background.
    if (!(base.x >= -1.0 && base.y >= -1.0 && base.z >= -1.0 && base.x < dims_.x && base.y < dims_.y &&
          base.z < dims_.z))
        return {0.0f, background_temperature_};
    glm::vec2 c[8];
    loadCorners(glm::ivec3(base), c);
    return interpolate(c, glm::vec3(relative - base));
}

MediumSample Medium::sampleWorld(const glm::dvec3& world_point) const {
    return sampleIndex(glm::dvec3(world_to_index_ * glm::dvec4(world_point, 1.0)));
}

WorldBox Medium::worldBounds() const {
    if (empty()) {
        const glm::dvec3 p(index_to_world_[3]);
        return {p, p};
    }
    WorldBox box{glm::dvec3(std::numeric_limits<double>::infinity()),
                 glm::dvec3(-std::numeric_limits<double>::infinity())};
    for (const glm::dvec3& w : worldCorners()) {
        box.min = glm::min(box.min, w);
        box.max = glm::max(box.max, w);
    }
    return box;
}

std::array<glm::dvec3, 8> Medium::worldCorners() const {
    const glm::dvec3 lo = glm::dvec3(origin_) - 1.0;
    const glm::dvec3 hi = glm::dvec3(origin_ + dims_);
    std::array<glm::dvec3, 8> corners;
    for (int n = 0; n < 8; ++n) {
        const glm::dvec3 corner((n & 1) ? hi.x : lo.x, (n & 2) ? hi.y : lo.y, (n & 4) ? hi.z : lo.z);
        corners[n] = glm::dvec3(index_to_world_ * glm::dvec4(corner, 1.0));
    }
    return corners;
}

double Medium::minVoxelEdge() const {
    return std::min({glm::length(glm::dvec3(index_to_world_[0])), glm::length(glm::dvec3(index_to_world_[1])),
                     glm::length(glm::dvec3(index_to_world_[2]))});
}

void Medium::buildBricks() {
    // Index points from origin - 1 to origin + dims can see a stored voxel.
    brick_counts_ = (dims_ + 1 + (kBrickSize - 1)) / kBrickSize;
    bricks_.assign(static_cast<std::size_t>(brick_counts_.x) * static_cast<std::size_t>(brick_counts_.y) *
                       static_cast<std::size_t>(brick_counts_.z),
                   BrickRange{});
    brick_has_density_.assign(bricks_.size(), 0);
    // Each brick is written once: layers of bricks on every core.
    tbb::parallel_for(0, brick_counts_.z, [&](int bz) {
        for (int by = 0; by < brick_counts_.y; ++by)
            for (int bx = 0; bx < brick_counts_.x; ++bx) {
                // Relative voxel indices -1 + b * size ... -1 + (b + 1) * size, both ends included:
                // a point in the brick interpolates between its floor and the next voxel.
                const glm::ivec3 lo = glm::ivec3(bx, by, bz) * kBrickSize - 1;
                const glm::ivec3 hi = glm::min(lo + kBrickSize, dims_);
                BrickRange range{0.0f, std::numeric_limits<float>::max(),
                                 std::numeric_limits<float>::lowest()};
                for (int k = lo.z; k <= hi.z; ++k)
                    for (int j = lo.y; j <= hi.y; ++j)
                        for (int i = lo.x; i <= hi.x; ++i) {
                            const glm::vec2 v = voxelOrBackground(i, j, k);
                            range.max_density = std::max(range.max_density, v.x);
                            range.min_temperature = std::min(range.min_temperature, v.y);
                            range.max_temperature = std::max(range.max_temperature, v.y);
                        }
                const std::size_t at = brickIndex({bx, by, bz});
                bricks_[at] = range;
                brick_has_density_[at] = range.max_density > 0.0f;
            }
    });
}

}  // namespace firelook::render
