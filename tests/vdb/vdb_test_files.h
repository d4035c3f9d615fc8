#pragma once
// Helpers for the VDB tests: a per-test temporary folder and small crafted VDB files.

#include <openvdb/openvdb.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace firelook::vdb::testing {

// A fresh folder under the system temp dir, removed with everything in it on destruction.
class TempDir {
  public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

  private:
    std::filesystem::path path_;
};

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
