#include "openvdb_io.h"

#include <mutex>

#include "vdb/file_structure.h"
#include "vdb/vdb_error.h"

namespace firelook::vdb {

std::unique_ptr<openvdb::io::File> openVdbFile(const std::filesystem::path& path) {
    static std::once_flag initialized;
    std::call_once(initialized, [] { openvdb::initialize(); });
    // OpenVDB 10 trusts the sizes in the file (file_structure.h): check them all first.
    checkFileStructure(path);
    auto file = std::make_unique<openvdb::io::File>(path.string());
    try {
        // Delayed loading would keep the file mapped and load leaves on first touch; every frame
        // is read whole anyway.
        file->open(/*delayLoad=*/false);
    } catch (const std::exception& error) {
        throw VdbError(path.string() + ": not a readable VDB file (" + error.what() + ")");
    }
    return file;
}

std::vector<std::string> gridNamesIn(const openvdb::io::File& file) {
    std::vector<std::string> names;
    for (auto name = file.beginName(); name != file.endName(); ++name) names.push_back(*name);
    return names;
}

void requireFloatGrid(const openvdb::GridBase& grid, const std::filesystem::path& file) {
    if (!grid.isType<openvdb::FloatGrid>()) {
        throw VdbError(file.string() + ": grid '" + grid.getName() + "' holds " + grid.valueType() +
                       " values; a float grid is needed");
    }
}

void requireSameTransform(const openvdb::GridBase& density, const openvdb::GridBase& temperature,
                          const std::filesystem::path& file) {
    if (density.transform() != temperature.transform()) {
        throw VdbError(file.string() + ": grids '" + density.getName() + "' and '" + temperature.getName() +
                       "' have different index-to-world transforms; they must share one");
    }
}

glm::dmat4 indexToWorldMatrix(const openvdb::math::Transform& transform, const std::filesystem::path& file) {
    if (!transform.isLinear()) {
        throw VdbError(file.string() + ": grid transform is not linear (" + transform.mapType() +
                       "); only affine index-to-world maps are supported");
    }
    const openvdb::Mat4d vdb_matrix = transform.baseMap()->getAffineMap()->getMat4();
    // OpenVDB multiplies row vectors (translation in row 3); glm multiplies column vectors with
    // matrix[column][row] (translation in column 3). The two store the same numbers at [a][b].
    glm::dmat4 matrix(1.0);
    for (int a = 0; a < 4; ++a) {
        for (int b = 0; b < 4; ++b) matrix[a][b] = vdb_matrix(a, b);
    }
    return matrix;
}

IndexBox toIndexBox(const openvdb::CoordBBox& box) {
    IndexBox result;
    if (box.empty()) return result;
    result.min = {box.min().x(), box.min().y(), box.min().z()};
    result.max = {box.max().x(), box.max().y(), box.max().z()};
    return result;
}

void rethrowNamingFile(const std::filesystem::path& file) {
    try {
        throw;
    } catch (const Error&) {  // coded, and already naming its file
        throw;
    } catch (const std::exception& error) {
        throw VdbError(file.string() + ": " + error.what());
    }
}

}  // namespace firelook::vdb
