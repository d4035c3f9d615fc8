#pragma once
// Internal to firelook::vdb: making a freshly read grid safe to sample.

#include <openvdb/openvdb.h>

#include <cstdint>
#include <limits>

#include "vdb/volume_frame.h"

namespace firelook::vdb {

struct ConditioningRule {
    bool clamp_negative = false;       // density: negative values become 0
    double scale = 1.0, offset = 0.0;  // value = scale * raw + offset, applied after cleaning
    // Mapped active values with |value| > limit are extreme: counted, and clamped to +-limit when
    // clamp_extreme is set (otherwise left as they are, for the caller to refuse).
    double limit = std::numeric_limits<double>::infinity();
    bool clamp_extreme = false;
};

struct ConditioningReport {
    GridStats stats;               // over active voxels, after cleaning and mapping (name left empty)
    std::uint64_t non_finite = 0;  // active voxels (and the background) that were NaN or Inf
    std::uint64_t nan = 0, inf = 0;  // the same split (non_finite = nan + inf)
    std::uint64_t negative = 0;    // active voxels that were negative, when clamp_negative is set
    std::uint64_t extreme = 0;     // active voxels beyond the limit (counted per voxel for tiles)
    double extreme_value = 0.0;    // the mapped value of largest magnitude among them
    openvdb::Coord extreme_voxel;  // where it is (a tile's first voxel)
};

// In one pass over the grid: active NaN/Inf values become 0 (and negatives 0 under
// clamp_negative), the mapping is applied to every value, values beyond the limit are counted (and
// clamped under clamp_extreme), inactive voxels are set to the (mapped) background, and the active
// statistics are gathered. Offending voxels are counted, so a caller refusing them can throw with
// the count.
ConditioningReport conditionGrid(openvdb::FloatGrid& grid, const ConditioningRule& rule);

}  // namespace firelook::vdb
