// Reading what a sequence needs from each file without loading voxel data.
#include <optional>

#include "frame_reading.h"
#include "grid_names.h"
#include "openvdb_io.h"

namespace firelook::vdb {
namespace {

// The active index box recorded in the file, or nullopt when the writer did not record it.
std::optional<IndexBox> recordedActiveBounds(const openvdb::GridBase& grid) {
    const auto min = grid.getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MIN);
    const auto max = grid.getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MAX);
    if (!min || !max) return std::nullopt;
    return toIndexBox(openvdb::CoordBBox(openvdb::Coord(min->value()), openvdb::Coord(max->value())));
}

}  // namespace

std::vector<std::string> listGridNames(const std::filesystem::path& file) {
    return gridNamesIn(*openVdbFile(file));
}

Aabb readDensitySupportBounds(const std::filesystem::path& path, const ReadOptions& resolved) {
    try {
        const auto file = openVdbFile(path);
        const std::vector<std::string> names = gridNamesIn(*file);
        requireGrid(names, resolved.density_grid, "density", path);
        requireGrid(names, resolved.temperature_grid, "temperature", path);
        const openvdb::GridBase::Ptr density = file->readGridMetadata(resolved.density_grid);
        const openvdb::GridBase::Ptr temperature = file->readGridMetadata(resolved.temperature_grid);
        requireFloatGrid(*density, path);
        requireFloatGrid(*temperature, path);
        requireSameTransform(*density, *temperature, path);
        const glm::dmat4 index_to_world = indexToWorldMatrix(density->transform(), path);
        std::optional<IndexBox> active = recordedActiveBounds(*density);
        if (!active) active = toIndexBox(file->readGrid(resolved.density_grid)->evalActiveVoxelBoundingBox());
        return interpolationSupport(*active, index_to_world);
    } catch (...) {
        rethrowNamingFile(path);
    }
}

}  // namespace firelook::vdb
