#pragma once
// Helpers for the VDB tests: small crafted VDB files (the temporary folder is tests/support/temp_dir.h).

#include <openvdb/openvdb.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "../support/temp_dir.h"

namespace firelook::vdb::testing {

using TempDir = firelook::testing::TempDir;

using Voxels = std::vector<std::pair<openvdb::Coord, float>>;

// A float grid with the given active voxels and a uniform-scale transform.
openvdb::FloatGrid::Ptr makeGrid(const std::string& name, const Voxels& voxels, double voxel_size = 0.1,
                                 float background = 0.0f);

// Writes the grids to a VDB file; with_stats = false leaves out OpenVDB's per-grid bounding-box
// metadata, as some writers do.
void writeVdb(const std::filesystem::path& path, const openvdb::GridPtrVec& grids, bool with_stats = true);

// Creates an empty file (for tests of file discovery, which never reads the contents).
void touch(const std::filesystem::path& path);

}  // namespace firelook::vdb::testing
