#pragma once
// Internal to firelook::vdb: the OpenVDB calls shared by metadata reading and frame loading.

#include <openvdb/openvdb.h>

#include <filesystem>
#include <glm/mat4x4.hpp>
#include <memory>
#include <string>
#include <vector>

#include "vdb/bounds.h"

namespace firelook::vdb {

// Opens a VDB file for reading (OpenVDB initialised once, thread-safely). Throws VdbError naming
// the file when it cannot be opened, is not a VDB file or fails checkFileStructure (file_structure.h).
std::unique_ptr<openvdb::io::File> openVdbFile(const std::filesystem::path& path);

std::vector<std::string> gridNamesIn(const openvdb::io::File& file);

// Throws VdbError naming the file and the grid's value type unless it is a float grid.
void requireFloatGrid(const openvdb::GridBase& grid, const std::filesystem::path& file);

// Throws VdbError naming the file and both grids unless they share one index-to-world transform.
void requireSameTransform(const openvdb::GridBase& density, const openvdb::GridBase& temperature,
                          const std::filesystem::path& file);

// The transform's affine map in glm layout; throws VdbError for a non-linear (frustum) transform.
glm::dmat4 indexToWorldMatrix(const openvdb::math::Transform& transform, const std::filesystem::path& file);

IndexBox toIndexBox(const openvdb::CoordBBox& box);

// For use inside a catch block: rethrows a coded firelook::Error (VdbError among them) as is and any
// other exception (OpenVDB's) as a VdbError whose message names the file.
[[noreturn]] void rethrowNamingFile(const std::filesystem::path& file);

}  // namespace firelook::vdb
