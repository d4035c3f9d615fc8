#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/mat4x4.hpp>
#include <memory>
#include <string>
#include <vector>

#include "vdb/bounds.h"

namespace firelook::vdb {

// The sparse OpenVDB grids of a frame. Defined in "vdb/frame_grids.h", which includes OpenVDB;
// code that only needs the numbers below (or toDense) does not pay for OpenVDB's headers.
struct FrameGrids;

// Statistics of one grid over its active voxels (active tiles count every voxel they cover).
struct GridStats {
    std::string name;
    double min = 0.0, max = 0.0;  // both 0 when there is no active voxel
    std::uint64_t active_voxels = 0;
    IndexBox active_bounds;  // inclusive index box of the active voxels
};

// What loading changed in one grid's active voxels (and background): NaN and Inf values set to 0,
// negative densities set to 0, and values beyond the plausible range (read_options.h) clamped to it
// under ReadOptions::clamp_extreme.
struct CleanedValues {
    std::uint64_t nan = 0, inf = 0, negative = 0, clamped = 0;
    bool any() const { return nan + inf + negative + clamped > 0; }
};

// One loaded frame. Conventions (docs/model.md):
// - voxel (i,j,k) sits at index point (i,j,k) (OpenVDB's convention), values between voxels are
//   interpolated trilinearly, and outside the active voxels each grid reads its background;
// - the temperature grid already holds mapped temperatures T = scale * raw + offset (its
//   background too), so temperature_stats are in the data's temperature units;
// - inactive voxels hold exactly their grid's background, and the density background is 0.
struct VolumeFrame {
    int number = 0;  // from the file name: fluid_data_0012.vdb is frame 12
    std::filesystem::path file;
    std::shared_ptr<const FrameGrids> grids;
    GridStats density_stats, temperature_stats;
    // Union of the active voxels of both grids.
    IndexBox index_bounds;
    // Where the trilinearly interpolated density can be non-zero: the density's active index box
    // grown by one voxel on every side, mapped to world space. Empty when the density grid has no
    // active voxel (a valid frame: nothing to draw).
    Aabb world_bounds;
    // Smallest voxel edge in world units (all edges are equal for Blender's uniform scale).
    double voxel_size = 0.0;
    // Index -> world affine map, shared by both grids: world = index_to_world * (i, j, k, 1).
    // glm layout: column-major, index_to_world[3] is the translation column.
    glm::dmat4 index_to_world{1.0};
    // Voxels changed under NonFinitePolicy::Clean (NaN/Inf in either grid set to 0; negative
    // densities clamped to 0). They stay active. Always 0 under Refuse.
    std::uint64_t cleaned_non_finite = 0, cleaned_negative_density = 0;
    // The same per grid, NaN and Inf apart, with the clamped values (cleaningReport words them).
    CleanedValues density_cleaned, temperature_cleaned;
    std::vector<std::string> all_grid_names;  // every grid in the file, as OpenVDB lists them (by name)
};

// What loading changed in a frame, one line per grid that changed, naming the file and the grid:
//   "PATH: density: 12 NaN, 0 Inf, 3 negative values set to 0"
//   "PATH: temperature: 0 NaN, 2 Inf values set to 0; 5 values beyond +-1e+06 clamped to +-1e+06"
// Empty when nothing changed. VdbSequence::load passes each line to ReadOptions::warn.
std::vector<std::string> cleaningReport(const VolumeFrame& frame);
// The same counts without the file and the "set to" words, both grids on one line:
// "density: 12 NaN, 0 Inf, 3 negative values; temperature: 0 NaN, 2 Inf values". Empty if none.
std::string cleaningSummary(const VolumeFrame& frame);

}  // namespace firelook::vdb
