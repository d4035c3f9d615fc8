#include "grid_conditioning.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "openvdb_io.h"

namespace firelook::vdb {
namespace {

class ValueConditioner {
  public:
    explicit ValueConditioner(const ConditioningRule& rule) : rule_(rule) {}

    // Cleans and maps one active value covering `voxels` voxels at `where`, recording it in the report.
    float active(float raw, std::uint64_t voxels, const openvdb::Coord& where) {
        if (!std::isfinite(raw)) {
            report_.non_finite += voxels;
            (std::isnan(raw) ? report_.nan : report_.inf) += voxels;
            raw = 0.0f;
        } else if (rule_.clamp_negative && raw < 0.0f) {
            report_.negative += voxels;
            raw = 0.0f;
        }
        float value = map(raw);
        if (!(std::abs(static_cast<double>(value)) <= rule_.limit)) {  // also catches a mapping to Inf
            if (report_.extreme == 0 || std::abs(value) > std::abs(report_.extreme_value)) {
                report_.extreme_value = value;
                report_.extreme_voxel = where;
            }
            report_.extreme += voxels;
            if (rule_.clamp_extreme) value = static_cast<float>(std::copysign(rule_.limit, value));
        }
        min_ = std::min(min_, static_cast<double>(value));
        max_ = std::max(max_, static_cast<double>(value));
        return value;
    }

    float background(float raw) {
        if (!std::isfinite(raw)) {
            report_.non_finite += 1;
            (std::isnan(raw) ? report_.nan : report_.inf) += 1;
            raw = 0.0f;
        }
        return map(raw);
    }

    ConditioningReport finish(const openvdb::FloatGrid& grid) {
        report_.stats.active_voxels = grid.activeVoxelCount();
        if (report_.stats.active_voxels > 0) {
            report_.stats.min = min_;
            report_.stats.max = max_;
        }
        report_.stats.active_bounds = toIndexBox(grid.evalActiveVoxelBoundingBox());
        return report_;
    }

  private:
    float map(float raw) const { return static_cast<float>(rule_.scale * raw + rule_.offset); }

    ConditioningRule rule_;
    ConditioningReport report_;
    double min_ = std::numeric_limits<double>::infinity();
    double max_ = -std::numeric_limits<double>::infinity();
};

}  // namespace

ConditioningReport conditionGrid(openvdb::FloatGrid& grid, const ConditioningRule& rule) {
    using Tree = openvdb::FloatTree;
    Tree& tree = grid.tree();
    ValueConditioner conditioner(rule);
    const float background = conditioner.background(tree.background());

    // Voxels of leaf nodes, straight through the leaf buffers.
    for (auto leaf = tree.beginLeaf(); leaf; ++leaf) {
        float* values = leaf->buffer().data();
        const auto& active = leaf->getValueMask();
        for (openvdb::Index i = 0; i < Tree::LeafNodeType::SIZE; ++i) {
            values[i] = active.isOn(i) ? conditioner.active(values[i], 1, leaf->offsetToGlobalCoord(i)) : background;
        }
    }
    // Tiles of the internal and root nodes (the leaf level is done above).
    auto tile = tree.beginValueAll();
    tile.setMaxDepth(Tree::ValueAllIter::LEAF_DEPTH - 1);
    for (; tile; ++tile) {
        tile.setValue(tile.isValueOn() ? conditioner.active(*tile, tile.getVoxelCount(), tile.getCoord())
                                       : background);
    }
    tree.root().setBackground(background, /*updateChildNodes=*/false);
    return conditioner.finish(grid);
}

}  // namespace firelook::vdb
