// toDense: layout, extent, padding and the values it copies.
#include "vdb/dense_volume.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "vdb/frame_grids.h"
#include "vdb/vdb_sequence.h"
#include "vdb_test_files.h"

namespace firelook::vdb {
namespace {

using ::testing::HasSubstr;
using testing::makeGrid;
using testing::TempDir;
using testing::writeVdb;

// Density spans x -2..3, y 0..4, z 0..2; temperature (background 0.5 raw) reaches (5,6,-3).
VolumeFrame craftedFrame(const TempDir& dir, const ReadOptions& options = {}) {
    writeVdb(
        dir / "f_1.vdb",
        {makeGrid("density", {{{0, 0, 0}, 0.5f}, {{3, 1, 2}, 1.0f}, {{-2, 4, 1}, 0.25f}}),
         makeGrid("temperature", {{{0, 0, 0}, 2.0f}, {{5, 6, -3}, 3.0f}, {{1, 1, 1}, 1.5f}}, 0.1, 0.5f)});
    return VdbSequence::open(dir.path().string(), options).load(1);
}

// Every dense element equals the grid's value at its index point.
void expectDenseMatchesGrids(const DenseVolume& dense, const VolumeFrame& frame) {
    const auto density = frame.grids->density->getConstAccessor();
    const auto temperature = frame.grids->temperature->getConstAccessor();
    for (int k = 0; k < dense.dims.z; ++k) {
        for (int j = 0; j < dense.dims.y; ++j) {
            for (int i = 0; i < dense.dims.x; ++i) {
                const openvdb::Coord index(dense.origin.x + i, dense.origin.y + j, dense.origin.z + k);
                // A copy, not a computation: values must be identical.
                ASSERT_EQ(dense.density[dense.linearIndex(i, j, k)], density.getValue(index)) << index;
                ASSERT_EQ(dense.temperature[dense.linearIndex(i, j, k)], temperature.getValue(index))
                    << index;
            }
        }
    }
}

TEST(DenseVolume, CoversBothGridsPlusPaddingXFastest) {
    TempDir dir;
    const VolumeFrame frame = craftedFrame(dir);
    const DenseVolume dense = toDense(frame);
    EXPECT_EQ(dense.origin, glm::ivec3(-3, -1, -4));
    EXPECT_EQ(dense.dims, glm::ivec3(10, 9, 8));  // -3..6, -1..7, -4..3
    ASSERT_EQ(dense.density.size(), dense.voxelCount());
    ASSERT_EQ(dense.temperature.size(), dense.voxelCount());
    EXPECT_EQ(dense.index_to_world, frame.index_to_world);
    // x fastest: voxel (3,1,2) is element (6,2,6).
    EXPECT_EQ(dense.density[6 + 10 * (2 + 9 * 6)], 1.0f);
    expectDenseMatchesGrids(dense, frame);
}

TEST(DenseVolume, InactiveTemperatureReadsTheMappedBackground) {
    TempDir dir;
    const VolumeFrame frame = craftedFrame(dir, {.temperature_scale = 2.0, .temperature_offset = 1.0});
    const DenseVolume dense = toDense(frame);
    // Raw background 0.5 maps to 2.0; the padding corner is outside every active voxel.
    EXPECT_EQ(dense.temperature[0], 2.0f);
    EXPECT_EQ(dense.density[0], 0.0f);
    // Raw 3.0 at (5,6,-3) maps to 7.0.
    EXPECT_EQ(dense.temperature[dense.linearIndex(5 + 3, 6 + 1, -3 + 4)], 7.0f);
    expectDenseMatchesGrids(dense, frame);
}

TEST(DenseVolume, PaddingIsConfigurable) {
    TempDir dir;
    const VolumeFrame frame = craftedFrame(dir);
    const DenseVolume tight = toDense(frame, 0);
    EXPECT_EQ(tight.origin, glm::ivec3(-2, 0, -3));
    EXPECT_EQ(tight.dims, glm::ivec3(8, 7, 6));
    expectDenseMatchesGrids(tight, frame);
    const DenseVolume wide = toDense(frame, 3);
    EXPECT_EQ(wide.dims, glm::ivec3(14, 13, 12));
    expectDenseMatchesGrids(wide, frame);
    try {
        toDense(frame, -1);
        FAIL() << "negative padding accepted";
    } catch (const VdbError& error) {
        EXPECT_THAT(error.what(), HasSubstr("negative dense padding"));
    }
}

TEST(DenseVolume, FarApartVoxelsAreRefusedNotAllocated) {
    TempDir dir;
    writeVdb(dir / "f_1.vdb", {makeGrid("density", {{{0, 0, 0}, 1.0f}, {{4000, 4000, 4000}, 1.0f}}),
                               makeGrid("temperature", {{{0, 0, 0}, 1.0f}})});
    const VolumeFrame frame = VdbSequence::open(dir.path().string()).load(1);
    try {
        toDense(frame);
        FAIL() << "a 4003^3 dense box was accepted";
    } catch (const VdbError& error) {
        EXPECT_THAT(error.what(), HasSubstr("too large"));
    }
}

}  // namespace
}  // namespace firelook::vdb
