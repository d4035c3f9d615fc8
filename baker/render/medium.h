// A participating medium: dense density and temperature voxels in world space.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

namespace firelook::render {

// Axis-aligned box in world space.
struct WorldBox {
    glm::dvec3 min{0.0};
    glm::dvec3 max{0.0};
};

// Interpolated values at a point.
struct MediumSample {
    float density = 0.0f;
    float temperature = 0.0f;
};

// Ranges of the voxels whose values can reach points of one brick by trilinear interpolation.
struct BrickRange {
    float max_density = 0.0f;
    float min_temperature = 0.0f;
    float max_temperature = 0.0f;
};

// Density and temperature stored on a dense index box, with OpenVDB's conventions (docs/model.md):
// voxel (i,j,k) sits at index point (i,j,k), values between voxels are interpolated
// trilinearly, and outside the stored box density is 0 and temperature is the background.
// The index-to-world map may be any invertible affine map; rays and distances are in world units.
//
// Input is sanitised on construction: NaN, Inf or negative density becomes 0 and a non-finite
// temperature becomes the background; sanitizedValues() counts both.
//
// For tracking, the index space is also cut into bricks of kBrickSize^3 voxels, each holding the
// range of every voxel its points interpolate from (so the layer of neighbouring voxels too).
class Medium {
  public:
    // 4 rather than 8: tighter majorants made the reference ~12% faster on an 80^3 synthetic
    // explosion (tests/render/reference_timing), for 8x more (still tiny) brick data.
    static constexpr int kBrickSize = 4;

    Medium() = default;  // empty: density 0 everywhere

    // density and temperature: x fastest (i + dims.x * (j + dims.y * k)), element (i,j,k) is the
    // voxel at index point origin + (i,j,k). Throws RenderError on mismatched sizes, negative dims
    // or a non-invertible or non-affine transform.
    Medium(glm::ivec3 origin, glm::ivec3 dims, std::span<const float> density,
           std::span<const float> temperature, const glm::dmat4& index_to_world,
           float background_temperature);

    // A box of uniform density and temperature centred on the world origin. The voxels are placed so
    // that any ray crossing two opposite faces away from the edges accumulates exactly
    // density * (path length inside world_size box) of density — the one-voxel interpolation ramp
    // at each face integrates to half a voxel — and temperature is the same everywhere (the
    // background equals it). Analytic tests rely on this.
    static Medium homogeneousBox(const glm::dvec3& world_size, const glm::ivec3& voxels, float density,
                                 float temperature);
    // A homogeneous slab of the given thickness along world Z, lateral_size wide in X and Y.
    static Medium slab(double thickness, double lateral_size, float density, float temperature);

    MediumSample sampleIndex(const glm::dvec3& index_point) const;
    // The eight stored values (density, temperature) at the corners of the unit index cube whose
    // low corner is `corner`, x fastest, then y, then z (the background outside the stored box):
    // what sampleIndex interpolates between inside that cube. For callers that sample one cube
    // many times (the scattered-light cells' quadrature) and interpolate themselves.
    void cubeCorners(const glm::ivec3& corner, glm::vec2 (&c)[8]) const;
    // Trilinear interpolation between those corners at f in [0, 1]^3: what sampleIndex returns.
    static MediumSample interpolate(const glm::vec2 (&c)[8], const glm::vec3& f) {
        const glm::vec2 x00 = c[0] + (c[1] - c[0]) * f.x;
        const glm::vec2 x10 = c[2] + (c[3] - c[2]) * f.x;
        const glm::vec2 x01 = c[4] + (c[5] - c[4]) * f.x;
        const glm::vec2 x11 = c[6] + (c[7] - c[6]) * f.x;
        const glm::vec2 y0 = x00 + (x10 - x00) * f.y;
        const glm::vec2 y1 = x01 + (x11 - x01) * f.y;
        const glm::vec2 v = y0 + (y1 - y0) * f.z;
        // Rounding in the differences can leave a tiny negative density next to zeros.
        return {std::max(v.x, 0.0f), v.y};
    }
    // The stored voxel at origin + relative (after sanitising), or density 0 and the background
    // temperature outside the stored box: the corners trilinear interpolation reads.
    MediumSample voxel(const glm::ivec3& relative) const {
        const glm::vec2 v = voxelOrBackground(relative.x, relative.y, relative.z);
        return {v.x, v.y};
    }
    MediumSample sampleWorld(const glm::dvec3& world_point) const;

    bool empty() const { return voxels_.empty(); }
    glm::ivec3 origin() const { return origin_; }
    glm::ivec3 dims() const { return dims_; }
    float backgroundTemperature() const { return background_temperature_; }
    const glm::dmat4& indexToWorld() const { return index_to_world_; }
    const glm::dmat4& worldToIndex() const { return world_to_index_; }
    // World-space bounds of where the interpolated density can be non-zero, and the eight corners
    // of that index box in world space (the bounds' corners where the grid is not axis-aligned).
    WorldBox worldBounds() const;
    std::array<glm::dvec3, 8> worldCorners() const;
    // Shortest world length of one voxel edge.
    double minVoxelEdge() const;
    std::uint64_t sanitizedValues() const { return sanitized_values_; }

    // Bricks: brick (0,0,0) starts at index point origin - 1 (the first point that can see a
    // stored voxel); brick b covers index points [origin - 1 + b * kBrickSize, ... + kBrickSize).
    glm::ivec3 brickCounts() const { return brick_counts_; }
    glm::dvec3 brickGridOrigin() const { return glm::dvec3(origin_) - 1.0; }
    const BrickRange& brick(const glm::ivec3& b) const { return bricks_[brickIndex(b)]; }
    // Whether brick b holds any density (brick(b).max_density > 0), from a byte a brick: the marches
    // ask it at nearly every step of a photon track, and the ranges (12 bytes a brick, 4 MB on a
    // frame upsampled 4x) missed the cache where these bytes (350 KB there) mostly do not.
    bool brickHasDensity(const glm::ivec3& b) const { return brick_has_density_[brickIndex(b)] != 0; }

  private:
    // Bricks are stored x fastest, then y, then z.
    std::size_t brickIndex(const glm::ivec3& b) const {
        return static_cast<std::size_t>(b.x) +
               static_cast<std::size_t>(brick_counts_.x) *
                   (static_cast<std::size_t>(b.y) +
                    static_cast<std::size_t>(brick_counts_.y) * static_cast<std::size_t>(b.z));
    }
    glm::vec2 voxelOrBackground(int i, int j, int k) const;
    void loadCorners(const glm::ivec3& relative, glm::vec2 (&c)[8]) const;
    void buildBricks();

    glm::ivec3 origin_{0};
    glm::ivec3 dims_{0};
    std::vector<glm::vec2> voxels_;  // (density, temperature) side by side: one cache line per lookup
    glm::dmat4 index_to_world_{1.0};
    glm::dmat4 world_to_index_{1.0};
    float background_temperature_ = 0.0f;
    std::uint64_t sanitized_values_ = 0;
    glm::ivec3 brick_counts_{0};
    std::vector<BrickRange> bricks_;
    std::vector<std::uint8_t> brick_has_density_;
};

}  // namespace firelook::render
