#include "vdb_test_files.h"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <stdexcept>

namespace firelook::vdb::testing {

openvdb::FloatGrid::Ptr makeGrid(const std::string& name, const Voxels& voxels, double voxel_size,
                                 float background) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(background);
    grid->setName(name);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel_size));
    auto accessor = grid->getAccessor();
    for (const auto& [coord, value] : voxels) accessor.setValueOn(coord, value);
    return grid;
}

void writeVdb(const std::filesystem::path& path, const openvdb::GridPtrVec& grids, bool with_stats) {
    openvdb::initialize();
    openvdb::io::File file(path.string());
    file.setGridStatsMetadataEnabled(with_stats);
    file.write(grids);
    file.close();
}

void touch(const std::filesystem::path& path) {
    std::ofstream out(path);
    if (!out) throw std::runtime_error("cannot create " + path.string());
}

}  // namespace firelook::vdb::testing
