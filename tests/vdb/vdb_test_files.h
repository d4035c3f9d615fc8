#pragma once
// Helpers for the VDB tests: small crafted VDB files (the temporary folder is tests/support/temp_dir.h).

#include <openvdb/openvdb.h>

#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "../support/temp_dir.h"

namespace firelook::vdb {
class VdbError;  // vdb/vdb_error.h: include it where errorOf is used
}

namespace firelook::vdb::testing {

using TempDir = firelook::testing::TempDir;

using Voxels = std::vector<std::pair<openvdb::Coord, float>>;

inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
inline constexpr float kInf = std::numeric_limits<float>::infinity();

// A few voxels of plausible density and temperature, for a well-formed frame.
inline const Voxels kDensity = {{{0, 0, 0}, 0.5f}, {{3, 1, 2}, 1.0f}, {{-2, 4, 1}, 0.25f}};
inline const Voxels kTemperature = {{{0, 0, 0}, 2.0f}, {{5, 5, 5}, 3.0f}};

// The message of the VdbError that `action` throws, or "no error" (any other exception propagates).
template <typename Error = VdbError, typename F>
std::string errorOf(F&& action) {
    try {
        action();
    } catch (const Error& error) {
        return error.what();
    }
    return "no error";
}

// A float grid with the given active voxels and a uniform-scale transform.
openvdb::FloatGrid::Ptr makeGrid(const std::string& name, const Voxels& voxels, double voxel_size = 0.1,
                                 float background = 0.0f);

// Writes the grids to a VDB file; with_stats = false leaves out OpenVDB's per-grid bounding-box
// metadata, as some writers do.
void writeVdb(const std::filesystem::path& path, const openvdb::GridPtrVec& grids, bool with_stats = true);

// Creates an empty file (for tests of file discovery, which never reads the contents).
void touch(const std::filesystem::path& path);

}  // namespace firelook::vdb::testing
