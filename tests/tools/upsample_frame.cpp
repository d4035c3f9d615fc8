// firelook_upsample IN.vdb OUT.vdb --factor N
//
// Writes a higher-resolution version of a real VDB frame, so the baker can be measured on
// frames N^3 times bigger with the same content (issue 11). Every float grid is resampled with
// OpenVDB's quadratic sampler onto a grid whose voxel is the input's divided by N; grid names,
// classes, backgrounds and metadata are kept. OpenVDB puts voxel (i,j,k) at world point
// transform(i,j,k), so scaling the index space by 1/N before the input's map keeps the world
// placement: output voxel N*(i,j,k) sits where input voxel (i,j,k) did.
//
// After resampling, in every grid that is not a level set (OpenVDB rebuilds those itself):
//   - values are clamped from below to min(background, smallest active input value): quadratic
//     interpolation undershoots next to steep edges, which would make density (background 0)
//     negative and temperature fall below its background;
//   - voxels within 1e-6 of the background, and voxels one input voxel or more from every
//     active input voxel, become inactive background, and emptied nodes are pruned. OpenVDB's
//     sampler activates everything its 3x3x3 stencil touches, and past the data's edge the
//     products of two negative lobes are small positive values (on frame 12 at x2: up to 1.3e-4
//     density, 3e-3 temperature, 1.5 input voxels out); they are artifacts, not smoke.
// Any grid of another value type is an error: silently dropping it would break "drop nothing".
// The file is written atomically (common/atomic_file.h), so OUT is never left half-written.
#include <openvdb/openvdb.h>
#include <openvdb/tools/Count.h>
#include <openvdb/tools/GridTransformer.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "common/atomic_file.h"

namespace {

constexpr float kBackgroundTolerance = 1e-6f;

struct Usage : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Totals {
    openvdb::Index64 active = 0;
    openvdb::CoordBBox bounds;
    double voxel = 0.0;
};

int parseFactor(const std::string& text) {
    size_t used = 0;
    int factor = 0;
    try {
        factor = std::stoi(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || factor < 1 || factor > 8)
        throw Usage("--factor must be an integer from 1 to 8, got '" + text + "'");
    return factor;
}

// Mantaflow writes its own resolution and voxel-size keys; rescaled, they describe the new grid
// instead of the input's.
void rescaleMantaflowMetadata(openvdb::GridBase& grid, int factor) {
    if (auto resolution = grid.getMetadata<openvdb::Vec3IMetadata>("file_base_resolution"))
        resolution->value() *= factor;
    if (auto voxel = grid.getMetadata<openvdb::FloatMetadata>("file_voxel_size")) voxel->value() /= factor;
    if (auto voxel = grid.getMetadata<openvdb::DoubleMetadata>("file_voxel_size")) voxel->value() /= factor;
}

// Input voxels c whose cell [c, c+1)^3 has an active corner: an output voxel at input index
// position x is less than one input voxel from active data exactly when floor(x) is in this set.
openvdb::MaskGrid::Ptr cellsTouchingActive(const openvdb::FloatGrid& in) {
    openvdb::MaskGrid::Ptr cells = openvdb::MaskGrid::create();
    auto acc = cells->getAccessor();
    for (auto v = in.cbeginValueOn(); v; ++v) {
        const openvdb::CoordBBox box = v.getBoundingBox();
        for (auto c = openvdb::CoordBBox(box.min().offsetBy(-1), box.max()).beginXYZ(); c; ++c)
            acc.setValueOn(*c);
    }
    return cells;
}

void clampAndPrune(openvdb::FloatGrid& out, const openvdb::FloatGrid& in, int factor) {
    const float background = out.background();
    const float lowest = std::min(background, openvdb::tools::minMax(in.tree()).min());
    const openvdb::MaskGrid::Ptr support = cellsTouchingActive(in);
    const auto inputCell = [factor](int i) { return i >= 0 ? i / factor : -((-i + factor - 1) / factor); };
    openvdb::tree::LeafManager<openvdb::FloatTree> leaves(out.tree());
    leaves.foreach ([&](openvdb::FloatTree::LeafNodeType& leaf, size_t) {
        const auto near_data = support->getConstAccessor();
        for (auto v = leaf.beginValueOn(); v; ++v) {
            const openvdb::Coord c = v.getCoord();
            const float value = std::max(*v, lowest);
            const bool keep = std::abs(value - background) > kBackgroundTolerance &&
                              near_data.isValueOn({inputCell(c.x()), inputCell(c.y()), inputCell(c.z())});
            v.setValue(keep ? value : background);
            if (!keep) v.setValueOff();
        }
    });
    openvdb::tools::pruneInactive(out.tree());
}

openvdb::FloatGrid::Ptr upsample(const openvdb::FloatGrid& in, int factor) {
    openvdb::FloatGrid::Ptr out = in.copyWithNewTree();
    openvdb::math::Transform::Ptr transform = in.transform().copy();
    transform->preScale(1.0 / factor);
    out->setTransform(transform);
    rescaleMantaflowMetadata(*out, factor);
    openvdb::tools::resampleToMatch<openvdb::tools::QuadraticSampler>(in, *out);
    if (in.getGridClass() != openvdb::GRID_LEVEL_SET && in.activeVoxelCount() > 0)
        clampAndPrune(*out, in, factor);
    return out;
}

void add(Totals& totals, const openvdb::FloatGrid& grid) {
    totals.active += grid.activeVoxelCount();
    totals.bounds.expand(grid.evalActiveVoxelBoundingBox());
    totals.voxel = grid.voxelSize()[0];
}

std::string describe(const Totals& t) {
    const openvdb::Coord dim = t.bounds.empty() ? openvdb::Coord(0) : t.bounds.dim();
    char text[160];
    std::snprintf(text, sizeof text, "%llu active, bbox %dx%dx%d, voxel %g",
                  static_cast<unsigned long long>(t.active), dim.x(), dim.y(), dim.z(), t.voxel);
    return text;
}

void run(const std::filesystem::path& in_path, const std::filesystem::path& out_path, int factor) {
    openvdb::io::File in_file(in_path.string());
    try {
        in_file.open(/*delayLoad=*/false);
    } catch (const std::exception& error) {
        throw std::runtime_error(in_path.string() + ": not a readable VDB file (" + error.what() + ")");
    }
    openvdb::GridPtrVec out_grids;
    Totals in_totals, out_totals;
    // One input grid in memory at a time: only the output grids accumulate.
    for (auto name = in_file.beginName(); name != in_file.endName(); ++name) {
        const openvdb::GridBase::Ptr base = in_file.readGrid(name.gridName());
        const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
        if (!grid)
            throw std::runtime_error(in_path.string() + ": grid '" + name.gridName() + "' holds " +
                                     base->valueType() + " values; only float grids can be upsampled");
        openvdb::FloatGrid::Ptr out = upsample(*grid, factor);
        add(in_totals, *grid);
        add(out_totals, *out);
        out_grids.push_back(out);
    }
    if (out_grids.empty()) throw std::runtime_error(in_path.string() + ": no grids");

    try {
        firelook::writeFileAtomically(out_path, [&](const std::filesystem::path& temporary) {
            openvdb::io::File out_file(temporary.string());
            out_file.setCompression(in_file.compression());
            out_file.write(out_grids, *in_file.getMetadata());
            out_file.close();
        });
    } catch (const std::exception& error) {
        throw std::runtime_error(out_path.string() + ": cannot write (" + error.what() + ")");
    }
    std::printf("%s: %zu grids x%d: %s -> %s\n", out_path.string().c_str(), out_grids.size(), factor,
                describe(in_totals).c_str(), describe(out_totals).c_str());
}

}  // namespace

int main(int argc, char** argv) {
    try {
        std::string paths[2];
        int path_count = 0, factor = 0;
        for (int a = 1; a < argc; ++a) {
            const std::string arg = argv[a];
            if (arg == "--factor") {
                if (++a == argc) throw Usage("--factor needs a value");
                factor = parseFactor(argv[a]);
            } else if (arg.rfind("--", 0) == 0 || path_count == 2) {
                throw Usage("unexpected argument '" + arg + "'");
            } else {
                paths[path_count++] = arg;
            }
        }
        if (path_count != 2 || factor == 0) throw Usage("usage: firelook_upsample IN.vdb OUT.vdb --factor N");
        openvdb::initialize();
        run(paths[0], paths[1], factor);
        return 0;
    } catch (const Usage& error) {
        std::fprintf(stderr, "firelook_upsample: %s\n", error.what());
        return 2;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "firelook_upsample: %s\n", error.what());
        return 1;
    }
}
