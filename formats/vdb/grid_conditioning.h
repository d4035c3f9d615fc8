#pragma once
// Internal to firelook::vdb: making a freshly read grid safe to sample.

#include <openvdb/openvdb.h>

#include <cstdint>

#include "vdb/volume_frame.h"

namespace firelook::vdb {

struct ConditioningRule {
    bool clamp_negative = false;       // density: negative values become 0
    double scale = 1.0, offset = 0.0;  // value = scale * raw + offset, applied after cleaning
};

struct ConditioningReport {
    GridStats stats;               // over active voxels, after cleaning and mapping (name left empty)
    std::uint64_t non_finite = 0;  // active voxels (and the background) that were NaN or Inf
    std::uint64_t negative = 0;    // active voxels that were negative, when clamp_negative is set
};

// In one pass over the grid: active NaN/Inf values become 0 (and negatives 0 under
// clamp_negative), the mapping is applied to every value, inactive voxels are set to the
// (mapped) background, and the active statistics are gathered. Offending voxels are counted,
// so a caller refusing them can throw with the count.
ConditioningReport conditionGrid(openvdb::FloatGrid& grid, const ConditioningRule& rule);

}  // namespace firelook::vdb
