// The bundled Blender Mantaflow explosion (samples/data/explosion, frames 1-12).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>
#include <thread>

#include "vdb/frame_grids.h"
#include "vdb/vdb_sequence.h"

namespace firelook::vdb {
namespace {

using ::testing::Contains;

const std::string kSampleDir = FIRELOOK_SAMPLE_DIR;

TEST(SampleSequence, FramesAndGridNamesAreFound) {
    const VdbSequence sequence = VdbSequence::open(kSampleDir);
    ASSERT_EQ(sequence.frames().size(), 12u);
    for (int i = 0; i < 12; ++i) EXPECT_EQ(sequence.frames()[i].number, i + 1);
    EXPECT_TRUE(sequence.gaps().empty());
    EXPECT_EQ(sequence.options().density_grid, "density");
    EXPECT_EQ(sequence.options().temperature_grid, "temperature");
}

TEST(SampleSequence, PatternAndFolderFormsAgree) {
    const VdbSequence folder = VdbSequence::open(kSampleDir);
    for (const std::string pattern : {"/fluid_data_####.vdb", "/fluid_data_%04d.vdb"}) {
        const VdbSequence matched = VdbSequence::open(kSampleDir + pattern);
        ASSERT_EQ(matched.frames().size(), folder.frames().size()) << pattern;
        for (std::size_t i = 0; i < folder.frames().size(); ++i) {
            EXPECT_EQ(matched.frames()[i].number, folder.frames()[i].number);
            EXPECT_EQ(matched.frames()[i].path, folder.frames()[i].path);
        }
        EXPECT_EQ(matched.sequenceWorldBounds().min, folder.sequenceWorldBounds().min);
        EXPECT_EQ(matched.sequenceWorldBounds().max, folder.sequenceWorldBounds().max);
    }
}

TEST(SampleSequence, FirstFrameHasPlausibleValuesAndUniformScale) {
    const VolumeFrame frame = VdbSequence::open(kSampleDir).load(1);
    EXPECT_EQ(frame.number, 1);
    EXPECT_THAT(frame.all_grid_names, Contains("flame"));
    // Blender's smoke density is at most 1; the fireball is dense on frame 1.
    EXPECT_GT(frame.density_stats.max, 0.5);
    EXPECT_LE(frame.density_stats.max, 1.0);
    EXPECT_GE(frame.density_stats.min, 0.0);
    // Mantaflow's fire burns at up to 3.0 (1000 K units) on frames 1-6; allow float rounding.
    EXPECT_NEAR(frame.temperature_stats.max, 3.0, 0.01);
    EXPECT_GT(frame.density_stats.active_voxels, 1000u);
    // The solver's grid is 80^3 voxels starting at index 0.
    EXPECT_GE(frame.index_bounds.min.x, 0);
    EXPECT_LT(frame.index_bounds.max.z, 80);
    // voxel size 0.025 stored as a double from Blender's float: allow float rounding.
    EXPECT_NEAR(frame.voxel_size, 0.025, 1e-7);
    for (int column = 0; column < 4; ++column) {
        for (int row = 0; row < 4; ++row) {
            const double expected = column == row ? (column == 3 ? 1.0 : frame.voxel_size) : 0.0;
            EXPECT_EQ(frame.index_to_world[column][row], expected) << column << "," << row;
        }
    }
    EXPECT_FALSE(frame.world_bounds.empty());
}

TEST(SampleSequence, SequenceBoundsContainEveryFrame) {
    const VdbSequence sequence = VdbSequence::open(kSampleDir);
    for (const FrameFile& file : sequence.frames()) {
        const VolumeFrame frame = sequence.load(file.number);
        EXPECT_TRUE(sequence.sequenceWorldBounds().contains(frame.world_bounds)) << "frame " << file.number;
    }
}

TEST(SampleSequence, DenseValuesEqualGridSamples) {
    const VolumeFrame frame = VdbSequence::open(kSampleDir).load(6);
    const DenseVolume dense = toDense(frame);
    ASSERT_GT(dense.voxelCount(), 0u);
    const auto density = frame.grids->density->getConstAccessor();
    const auto temperature = frame.grids->temperature->getConstAccessor();
    std::mt19937 random(6);
    std::size_t nonzero = 0;
    for (int n = 0; n < 20000; ++n) {
        const int i = std::uniform_int_distribution<int>(0, dense.dims.x - 1)(random);
        const int j = std::uniform_int_distribution<int>(0, dense.dims.y - 1)(random);
        const int k = std::uniform_int_distribution<int>(0, dense.dims.z - 1)(random);
        const openvdb::Coord index(dense.origin.x + i, dense.origin.y + j, dense.origin.z + k);
        ASSERT_EQ(dense.density[dense.linearIndex(i, j, k)], density.getValue(index)) << index;
        ASSERT_EQ(dense.temperature[dense.linearIndex(i, j, k)], temperature.getValue(index)) << index;
        nonzero += dense.density[dense.linearIndex(i, j, k)] > 0.0f;
    }
    EXPECT_GT(nonzero, 100u) << "the samples should hit the smoke, not only empty space";
}

TEST(SampleSequence, FramesLoadConcurrently) {
    const VdbSequence sequence = VdbSequence::open(kSampleDir);
    std::vector<VolumeFrame> frames(4);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t) {
        threads.emplace_back([&, t] { frames[t] = sequence.load(t + 1); });
    }
    for (std::thread& thread : threads) thread.join();
    for (int t = 0; t < 4; ++t) {
        const VolumeFrame alone = sequence.load(t + 1);
        EXPECT_EQ(frames[t].density_stats.active_voxels, alone.density_stats.active_voxels);
        EXPECT_EQ(frames[t].density_stats.max, alone.density_stats.max);
    }
}

}  // namespace
}  // namespace firelook::vdb
