// Loading one frame: read both grids, check them, clean them, describe them.
#include <algorithm>
#include <cstdio>

#include "frame_reading.h"
#include "grid_conditioning.h"
#include "grid_names.h"
#include "openvdb_io.h"
#include "vdb/frame_grids.h"
#include "vdb/vdb_error.h"

namespace firelook::vdb {
namespace {

openvdb::FloatGrid::Ptr readFloatGrid(openvdb::io::File& file, const std::string& name,
                                      const std::filesystem::path& path) {
    // The type from the metadata first: the structure check walks float trees only.
    requireFloatGrid(*file.readGridMetadata(name), path);
    const openvdb::GridBase::Ptr grid = file.readGrid(name);
    requireFloatGrid(*grid, path);
    return openvdb::gridPtrCast<openvdb::FloatGrid>(grid);
}

void refuseUnderPolicy(const ReadOptions& options, std::uint64_t count, const std::string& what,
                       const std::filesystem::path& path) {
    if (options.non_finite == NonFinitePolicy::Refuse && count > 0) {
        throw VdbError(path.string() + ": " + std::to_string(count) + " " + what +
                       " (refused by NonFinitePolicy::Refuse; Clean sets them to 0)");
    }
}

CleanedValues cleanedValues(const ConditioningReport& report, bool clamped) {
    return {report.nan, report.inf, report.negative, clamped ? report.extreme : 0};
}

// Without clamp_extreme, a value beyond the plausible range stops the load (read_options.h).
void refuseExtreme(const ConditioningReport& report, const ReadOptions& options, const std::string& grid,
                   bool is_density, const std::filesystem::path& path) {
    if (report.extreme == 0 || options.clamp_extreme) return;
    const openvdb::Coord& v = report.extreme_voxel;
    char value[64];
    std::snprintf(value, sizeof value, "%g", report.extreme_value);
    char bound[96];
    if (is_density)
        std::snprintf(bound, sizeof bound, "density (above %g)", kMaxPlausibleDensity);
    else
        std::snprintf(bound, sizeof bound, "temperature (|T| above %g in the data's units)", kMaxPlausibleTemperature);
    throw VdbError(path.string() + ": " + grid + ": value " + value + " at voxel (" + std::to_string(v.x()) + ", " +
                   std::to_string(v.y()) + ", " + std::to_string(v.z()) + ") is beyond any plausible " + bound +
                   ", " + std::to_string(report.extreme) + (report.extreme == 1 ? " such voxel" : " such voxels") +
                   "; --clamp-extreme clamps such values to the bound");
}

}  // namespace

VolumeFrame loadFrame(const FrameFile& frame, const ReadOptions& resolved) {
    const std::filesystem::path& path = frame.path;
    try {
        const auto file = openVdbFile(path);
        VolumeFrame result;
        result.number = frame.number;
        result.file = path;
        result.all_grid_names = gridNamesIn(*file);
        requireGrid(result.all_grid_names, resolved.density_grid, "density", path);
        requireGrid(result.all_grid_names, resolved.temperature_grid, "temperature", path);
        const openvdb::FloatGrid::Ptr density = readFloatGrid(*file, resolved.density_grid, path);
        const openvdb::FloatGrid::Ptr temperature = readFloatGrid(*file, resolved.temperature_grid, path);
        requireSameTransform(*density, *temperature, path);
        result.index_to_world = indexToWorldMatrix(density->transform(), path);

        const ConditioningReport density_report = conditionGrid(
            *density,
            {.clamp_negative = true, .scale = resolved.density_scale, .limit = kMaxPlausibleDensity, .clamp_extreme = resolved.clamp_extreme});
        const ConditioningReport temperature_report =
            conditionGrid(*temperature, {.scale = resolved.temperature_scale,
                                         .offset = resolved.temperature_offset,
                                         .limit = kMaxPlausibleTemperature,
                                         .clamp_extreme = resolved.clamp_extreme});
        refuseExtreme(density_report, resolved, resolved.density_grid, true, path);
        refuseExtreme(temperature_report, resolved, resolved.temperature_grid, false, path);
        result.density_stats.name = resolved.density_grid;
        result.temperature_stats.name = resolved.temperature_grid;
        result.density_cleaned = cleanedValues(density_report, resolved.clamp_extreme);
        result.temperature_cleaned = cleanedValues(temperature_report, resolved.clamp_extreme);
        if (resolved.strict && (result.density_cleaned.any() || result.temperature_cleaned.any()))
            throw VdbError(path.string() + ": " + cleaningSummary(result) +
                           " (refused by --strict; without it they are set to 0 or clamped, and reported)");
        const std::uint64_t non_finite = density_report.non_finite + temperature_report.non_finite;
        refuseUnderPolicy(resolved, non_finite, "NaN/Inf values", path);
        refuseUnderPolicy(resolved, density_report.negative, "negative densities", path);
        if (density->background() != 0.0f) {
            throw VdbError(path.string() + ": density grid '" + resolved.density_grid + "' has background " +
                           std::to_string(density->background()) +
                           " instead of 0 (a fog volume is needed, not a level set)");
        }
        result.cleaned_non_finite = non_finite;
        result.cleaned_negative_density = density_report.negative;

        result.density_stats = density_report.stats;
        result.density_stats.name = resolved.density_grid;
        result.temperature_stats = temperature_report.stats;
        result.temperature_stats.name = resolved.temperature_grid;
        result.index_bounds = result.density_stats.active_bounds;
        result.index_bounds.extend(result.temperature_stats.active_bounds);
        result.world_bounds = interpolationSupport(result.density_stats.active_bounds, result.index_to_world);
        const openvdb::Vec3d voxel_size = density->voxelSize();
        result.voxel_size = std::min({voxel_size.x(), voxel_size.y(), voxel_size.z()});
        result.grids = std::make_shared<const FrameGrids>(FrameGrids{density, temperature});
        return result;
    } catch (...) {
        rethrowNamingFile(path);
    }
}

}  // namespace firelook::vdb
