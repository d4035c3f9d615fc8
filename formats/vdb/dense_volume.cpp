#include "vdb/dense_volume.h"

#include <openvdb/tools/Dense.h>

#include <cstdint>
#include <string>

#include "vdb/frame_grids.h"
#include "vdb/vdb_error.h"

namespace firelook::vdb {
namespace {

// Two float arrays of this many voxels take 16 GiB: far beyond any fire this tool is for, and a
// sign of a stray voxel far from the rest.
constexpr std::int64_t kMaxDenseVoxels = std::int64_t{1} << 31;

void copyGrid(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box, std::vector<float>& values) {
    openvdb::tools::Dense<float, openvdb::tools::LayoutXYZ> dense(box, values.data());
    openvdb::tools::copyToDense(grid, dense);
}

}  // namespace

DenseVolume toDense(const VolumeFrame& frame, int padding_voxels) {
    if (padding_voxels < 0) {
        throw VdbError(frame.file.string() + ": negative dense padding " + std::to_string(padding_voxels));
    }
    DenseVolume volume;
    volume.index_to_world = frame.index_to_world;
    if (frame.density_stats.active_bounds.empty()) return volume;

    const glm::i64vec3 lo = glm::i64vec3(frame.index_bounds.min) - std::int64_t{padding_voxels};
    const glm::i64vec3 hi = glm::i64vec3(frame.index_bounds.max) + std::int64_t{padding_voxels};
    const glm::i64vec3 dims = hi - lo + std::int64_t{1};
    // Each factor is below 2^33, so the product of two fits; test before forming the third.
    const std::int64_t slice = dims.x * dims.y;
    if (slice > kMaxDenseVoxels || slice * dims.z > kMaxDenseVoxels || hi.x > INT32_MAX || hi.y > INT32_MAX ||
        hi.z > INT32_MAX || lo.x < INT32_MIN || lo.y < INT32_MIN || lo.z < INT32_MIN) {
        throw VdbError(frame.file.string() + ": dense box of " + std::to_string(dims.x) + " x " +
                       std::to_string(dims.y) + " x " + std::to_string(dims.z) + " voxels is too large");
    }
    volume.origin = glm::ivec3(lo);
    volume.dims = glm::ivec3(dims);
    volume.density.resize(volume.voxelCount());
    volume.temperature.resize(volume.voxelCount());

    const openvdb::CoordBBox box(
        openvdb::Coord(volume.origin.x, volume.origin.y, volume.origin.z),
        openvdb::Coord(static_cast<int>(hi.x), static_cast<int>(hi.y), static_cast<int>(hi.z)));
    copyGrid(*frame.grids->density, box, volume.density);
    copyGrid(*frame.grids->temperature, box, volume.temperature);
    return volume;
}

}  // namespace firelook::vdb
