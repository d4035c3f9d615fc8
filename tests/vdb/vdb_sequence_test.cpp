// Reading crafted VDB files: grid choice, checks, cleaning policies, mapping and bounds.
#include "vdb/vdb_sequence.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "../support/error_code.h"
#include "vdb/frame_grids.h"
#include "vdb_test_files.h"

namespace firelook::vdb {
namespace {

using namespace testing;  // vdb_test_files.h
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::UnorderedElementsAre;

TEST(VdbSequence, MissingTemperatureGridListsTheGridsPresent) {
    TempDir dir;
    writeVdb(dir / "f_0001.vdb", {makeGrid("density", kDensity), makeGrid("velocity_x", kDensity)});
    const std::string error = errorOf([&] { VdbSequence::open(dir.path().string()); });
    EXPECT_THAT(error, HasSubstr("f_0001.vdb"));
    EXPECT_THAT(error, HasSubstr("no temperature grid"));
    EXPECT_THAT(error, HasSubstr("'density', 'velocity_x'"));
}

TEST(VdbSequence, NamedGridMissingInALaterFrameIsNamed) {
    TempDir dir;
    writeVdb(dir / "f_0001.vdb", {makeGrid("density", kDensity), makeGrid("temperature", kTemperature)});
    writeVdb(dir / "f_0002.vdb", {makeGrid("density", kDensity), makeGrid("heat", kTemperature)});
    const std::string error = errorOf([&] { VdbSequence::open(dir.path().string()); });
    EXPECT_THAT(error, HasSubstr("f_0002.vdb"));
    EXPECT_THAT(error, HasSubstr("'temperature' not found"));
    EXPECT_THAT(error, HasSubstr("'density', 'heat'"));
}

TEST(VdbSequence, TemperatureFallsBackToHeatThenFlame) {
    TempDir heat_dir, flame_dir;
    writeVdb(heat_dir / "f_1.vdb",
             {makeGrid("flame", kDensity), makeGrid("heat", kTemperature), makeGrid("density", kDensity)});
    writeVdb(flame_dir / "f_1.vdb", {makeGrid("density", kDensity), makeGrid("flame", kTemperature)});
    EXPECT_EQ(VdbSequence::open(heat_dir.path().string()).options().temperature_grid, "heat");
    const VdbSequence flame = VdbSequence::open(flame_dir.path().string());
    EXPECT_EQ(flame.options().density_grid, "density");
    EXPECT_EQ(flame.options().temperature_grid, "flame");
    EXPECT_EQ(flame.load(1).temperature_stats.name, "flame");
}

TEST(VdbSequence, ExplicitGridNamesWinOverDetection) {
    TempDir dir;
    writeVdb(dir / "f_1.vdb", {makeGrid("smoke", kDensity), makeGrid("temperature", kTemperature),
                               makeGrid("flame", {{{1, 1, 1}, 0.75f}})});
    const VdbSequence sequence =
        VdbSequence::open(dir.path().string(), {.density_grid = "smoke", .temperature_grid = "flame"});
    const VolumeFrame frame = sequence.load(1);
    EXPECT_EQ(frame.density_stats.name, "smoke");
    EXPECT_EQ(frame.temperature_stats.max, 0.75);
    EXPECT_THAT(frame.all_grid_names, UnorderedElementsAre("smoke", "temperature", "flame"));
}

TEST(VdbSequence, PartnerGridsWithDifferentTransformsAreRefused) {
    TempDir dir;
    writeVdb(dir / "f_1.vdb",
             {makeGrid("density", kDensity, 0.1), makeGrid("temperature", kTemperature, 0.2)});
    const std::string error = errorOf([&] { VdbSequence::open(dir.path().string()); });
    EXPECT_THAT(error, HasSubstr("f_1.vdb"));
    EXPECT_THAT(error, HasSubstr("different index-to-world transforms"));
}

TEST(VdbSequence, NonFloatGridIsRefused) {
    TempDir dir;
    auto velocity = openvdb::Vec3SGrid::create();
    velocity->setName("temperature");
    velocity->tree().setValueOn(openvdb::Coord(0, 0, 0), openvdb::Vec3s(1, 2, 3));
    writeVdb(dir / "f_1.vdb", {makeGrid("density", kDensity), velocity});
    const std::string error = errorOf([&] { VdbSequence::open(dir.path().string()); });
    EXPECT_THAT(error, HasSubstr("f_1.vdb"));
    EXPECT_THAT(error, HasSubstr("'temperature' holds vec3s values"));
}

TEST(VdbSequence, NonVdbFileIsRefusedByName) {
    TempDir dir;
    std::ofstream(dir / "f_0001.vdb") << "this is not a VDB file";
    const std::string error = errorOf([&] { VdbSequence::open(dir.path().string()); });
    EXPECT_THAT(error, HasSubstr((dir / "f_0001.vdb").string()));
    EXPECT_THAT(error, HasSubstr("not a readable VDB file"));
    // The code says what the plugin and the CLI act on; the type (VdbError) adds nothing to it.
    EXPECT_ERROR_CODE(ErrorCode::BadVolume, VdbSequence::open(dir.path().string()));
    EXPECT_ERROR_CODE(ErrorCode::IoError, VdbSequence::open((dir / "no-such-folder").string()));
}

TEST(VdbSequence, UnknownFrameNumberIsAnError) {
    TempDir dir;
    writeVdb(dir / "f_1.vdb", {makeGrid("density", kDensity), makeGrid("temperature", kTemperature)});
    writeVdb(dir / "f_3.vdb", {makeGrid("density", kDensity), makeGrid("temperature", kTemperature)});
    const VdbSequence sequence = VdbSequence::open(dir.path().string());
    EXPECT_THAT(sequence.gaps(), ElementsAre(2));
    EXPECT_THAT(errorOf([&] { sequence.load(2); }), HasSubstr("no frame 2 (frames 1 to 3, with gaps)"));
    EXPECT_ERROR_CODE(ErrorCode::NotFound, sequence.load(2));
}

// One density grid holding NaN, +Inf, a negative and a good voxel, and a temperature with -Inf.
void writeDirtyFrame(const std::filesystem::path& file) {
    writeVdb(file, {makeGrid("density",
                             {{{0, 0, 0}, kNaN}, {{1, 0, 0}, kInf}, {{2, 0, 0}, -0.5f}, {{3, 0, 0}, 0.5f}}),
                    makeGrid("temperature", {{{0, 0, 0}, -kInf}, {{1, 0, 0}, 2.0f}})});
}

TEST(VdbSequence, CleanPolicyZeroesAndCountsBadValues) {
    TempDir dir;
    writeDirtyFrame(dir / "f_1.vdb");
    const VolumeFrame frame = VdbSequence::open(dir.path().string()).load(1);
    EXPECT_EQ(frame.cleaned_non_finite, 3u);
    EXPECT_EQ(frame.cleaned_negative_density, 1u);
    const auto density = frame.grids->density->getConstAccessor();
    for (int x : {0, 1, 2}) {
        EXPECT_EQ(density.getValue({x, 0, 0}), 0.0f) << "x=" << x;
        EXPECT_TRUE(density.isValueOn({x, 0, 0})) << "cleaned voxels stay active, x=" << x;
    }
    EXPECT_EQ(density.getValue({3, 0, 0}), 0.5f);
    EXPECT_EQ(frame.density_stats.min, 0.0);
    EXPECT_EQ(frame.density_stats.max, 0.5);
    EXPECT_EQ(frame.density_stats.active_voxels, 4u);
    EXPECT_EQ(frame.temperature_stats.min, 0.0);
    EXPECT_EQ(frame.temperature_stats.max, 2.0);
}

TEST(VdbSequence, RefusePolicyReportsTheCounts) {
    TempDir dir;
    writeDirtyFrame(dir / "f_1.vdb");
    const VdbSequence sequence =
        VdbSequence::open(dir.path().string(), {.non_finite = NonFinitePolicy::Refuse});
    const std::string error = errorOf([&] { sequence.load(1); });
    EXPECT_THAT(error, HasSubstr("f_1.vdb"));
    EXPECT_THAT(error, HasSubstr("3 NaN/Inf values"));

    TempDir negative_dir;
    writeVdb(negative_dir / "f_1.vdb", {makeGrid("density", {{{0, 0, 0}, -1.0f}, {{0, 1, 0}, -2.0f}}),
                                        makeGrid("temperature", kTemperature)});
    const VdbSequence negative =
        VdbSequence::open(negative_dir.path().string(), {.non_finite = NonFinitePolicy::Refuse});
    EXPECT_THAT(errorOf([&] { negative.load(1); }), HasSubstr("2 negative densities"));
}

TEST(VdbSequence, ActiveTilesAreCleanedAndCountedPerVoxel) {
    TempDir dir;
    auto density = makeGrid("density", {});
    // One active tile of the lowest internal node level covers 8^3 voxels.
    density->tree().addTile(/*level=*/1, openvdb::Coord(0, 0, 0), kNaN, /*active=*/true);
    writeVdb(dir / "f_1.vdb", {density, makeGrid("temperature", kTemperature)});
    const VolumeFrame frame = VdbSequence::open(dir.path().string()).load(1);
    EXPECT_EQ(frame.cleaned_non_finite, 512u);
    EXPECT_EQ(frame.density_stats.active_voxels, 512u);
    EXPECT_EQ(frame.grids->density->tree().getValue({7, 7, 7}), 0.0f);
}

TEST(VdbSequence, TemperatureMappingAppliesToValuesBackgroundAndStats) {
    TempDir dir;
    writeVdb(dir / "f_1.vdb", {makeGrid("density", kDensity),
                               makeGrid("temperature", {{{0, 0, 0}, 1.0f}, {{1, 0, 0}, 3.0f}}, 0.1, 0.5f)});
    const VdbSequence sequence =
        VdbSequence::open(dir.path().string(), {.temperature_scale = 1000.0, .temperature_offset = 293.0});
    const VolumeFrame frame = sequence.load(1);
    const openvdb::FloatGrid& temperature = *frame.grids->temperature;
    EXPECT_EQ(temperature.tree().getValue({0, 0, 0}), 1293.0f);
    EXPECT_EQ(temperature.background(), 793.0f);
    EXPECT_EQ(temperature.tree().getValue({100, 100, 100}), 793.0f);
    EXPECT_EQ(frame.temperature_stats.min, 1293.0);
    EXPECT_EQ(frame.temperature_stats.max, 3293.0);
}

TEST(VdbSequence, InactiveVoxelsHoldTheBackground) {
    TempDir dir;
    auto density = makeGrid("density", kDensity);
    // OpenVDB lets an inactive voxel keep any value; a sampler would read it.
    density->tree().setValueOff(openvdb::Coord(1, 1, 1), kNaN);
    density->tree().setValueOff(openvdb::Coord(1, 1, 2), 7.0f);
    writeVdb(dir / "f_1.vdb", {density, makeGrid("temperature", kTemperature)});
    const VolumeFrame frame = VdbSequence::open(dir.path().string()).load(1);
    EXPECT_EQ(frame.grids->density->tree().getValue({1, 1, 1}), 0.0f);
    EXPECT_EQ(frame.grids->density->tree().getValue({1, 1, 2}), 0.0f);
    EXPECT_EQ(frame.cleaned_non_finite, 0u) << "inactive voxels carry no data and are not counted";
}

TEST(VdbSequence, LevelSetAsDensityIsRefused) {
    TempDir dir;
    writeVdb(dir / "f_1.vdb",
             {makeGrid("density", kDensity, 0.1, 0.3f), makeGrid("temperature", kTemperature)});
    EXPECT_THAT(errorOf([&] { VdbSequence::open(dir.path().string()).load(1); }),
                HasSubstr("has background 0.3"));
}

TEST(VdbSequence, FrameGeometryFollowsTheGridTransform) {
    TempDir dir;
    auto density = makeGrid("density", kDensity);
    auto transform = openvdb::math::Transform::createLinearTransform(0.5);
    transform->postRotate(0.3, openvdb::math::Z_AXIS);
    transform->postTranslate(openvdb::Vec3d(1.0, -2.0, 3.0));
    density->setTransform(transform);
    auto temperature = makeGrid("temperature", kTemperature);
    temperature->setTransform(transform->copy());
    writeVdb(dir / "f_1.vdb", {density, temperature});
    const VdbSequence sequence = VdbSequence::open(dir.path().string());
    const VolumeFrame frame = sequence.load(1);

    // OpenVDB derives the voxel size of a rotated map numerically; 1e-12 absorbs its rounding.
    EXPECT_NEAR(frame.voxel_size, 0.5, 1e-12);
    const openvdb::Vec3d index(3.0, -1.5, 2.25);
    const openvdb::Vec3d expected = transform->indexToWorld(index);
    const glm::dvec4 actual = frame.index_to_world * glm::dvec4(index.x(), index.y(), index.z(), 1.0);
    for (int axis = 0; axis < 3; ++axis) {
        // Both sides evaluate the same affine map in double; only rounding differs.
        EXPECT_NEAR(actual[axis], expected[axis], 1e-12) << "axis " << axis;
    }
    // Density voxels span x -2..3, y 0..4, z 0..2; temperature reaches (5,5,5).
    EXPECT_EQ(frame.density_stats.active_bounds.min, glm::ivec3(-2, 0, 0));
    EXPECT_EQ(frame.density_stats.active_bounds.max, glm::ivec3(3, 4, 2));
    EXPECT_EQ(frame.index_bounds.max, glm::ivec3(5, 5, 5));
    // The support of the interpolated density contains every density voxel grown by one voxel.
    for (const auto& [coord, value] : kDensity) {
        for (int corner = 0; corner < 8; ++corner) {
            const openvdb::Vec3d offset((corner & 1) ? 1 : -1, (corner & 2) ? 1 : -1, (corner & 4) ? 1 : -1);
            const openvdb::Vec3d world = transform->indexToWorld(coord.asVec3d() + offset);
            Aabb point;
            point.extend(glm::dvec3(world.x(), world.y(), world.z()));
            // The bounds are computed with the same doubles; 1e-12 absorbs rounding only.
            point.min -= 1e-12;
            point.max += 1e-12;
            Aabb grown = frame.world_bounds;
            grown.min -= 1e-12;
            grown.max += 1e-12;
            EXPECT_TRUE(grown.contains(point)) << coord << " corner " << corner;
        }
    }
    EXPECT_EQ(sequence.sequenceWorldBounds().min, frame.world_bounds.min);
    EXPECT_EQ(sequence.sequenceWorldBounds().max, frame.world_bounds.max);
}

TEST(VdbSequence, SequenceBoundsUnionFramesWithAndWithoutFileMetadata) {
    TempDir dir;
    writeVdb(dir / "f_1.vdb",
             {makeGrid("density", {{{0, 0, 0}, 1.0f}}), makeGrid("temperature", kTemperature)});
    writeVdb(dir / "f_2.vdb",
             {makeGrid("density", {{{10, -4, 2}, 1.0f}}), makeGrid("temperature", kTemperature)},
             /*with_stats=*/false);
    writeVdb(dir / "f_3.vdb", {makeGrid("density", {}), makeGrid("temperature", kTemperature)});
    const VdbSequence sequence = VdbSequence::open(dir.path().string());
    // Voxel size 0.1: support is index [-1, 11] x [-5, 1] x [-1, 3]; 1e-12 absorbs rounding of 0.1 * n.
    const Aabb& bounds = sequence.sequenceWorldBounds();
    EXPECT_NEAR(bounds.min.x, -0.1, 1e-12);
    EXPECT_NEAR(bounds.min.y, -0.5, 1e-12);
    EXPECT_NEAR(bounds.min.z, -0.1, 1e-12);
    EXPECT_NEAR(bounds.max.x, 1.1, 1e-12);
    EXPECT_NEAR(bounds.max.y, 0.1, 1e-12);
    EXPECT_NEAR(bounds.max.z, 0.3, 1e-12);
    for (const FrameFile& file : sequence.frames()) {
        EXPECT_TRUE(bounds.contains(sequence.load(file.number).world_bounds)) << "frame " << file.number;
    }
}

TEST(VdbSequence, EmptyDensityIsAValidFrame) {
    TempDir dir;
    writeVdb(dir / "f_1.vdb", {makeGrid("density", {}), makeGrid("temperature", kTemperature)});
    const VdbSequence sequence = VdbSequence::open(dir.path().string());
    EXPECT_TRUE(sequence.sequenceWorldBounds().empty());
    const VolumeFrame frame = sequence.load(1);
    EXPECT_TRUE(frame.world_bounds.empty());
    EXPECT_EQ(frame.density_stats.active_voxels, 0u);
    EXPECT_EQ(frame.density_stats.max, 0.0);
    const DenseVolume dense = toDense(frame);
    EXPECT_EQ(dense.dims, glm::ivec3(0));
    EXPECT_TRUE(dense.density.empty());
    EXPECT_TRUE(dense.temperature.empty());
}

}  // namespace
}  // namespace firelook::vdb
