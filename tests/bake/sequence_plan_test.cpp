// The plan a farm's shards bake from (bake/sequence_plan.h): written and read back it is the
// plan, number for number, so a shard with a plan derives the axes, bins and camera a bake without
// one derives; the sequence's identity is its frames' content, not the path it is read from.
#include "bake/sequence_plan.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "../support/temp_dir.h"
#include "bake/bake_pipeline.h"
#include "common/error.h"
#include "tiny_sample_bake.h"

namespace firelook::bake {
namespace {

using firelook::testing::TempDir;

TEST(SequencePlan, ReadBackItIsThePlanExactly) {
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(FIRELOOK_SAMPLE_DIR);
    const SequencePlan plan = planSequence(sequence);
    ASSERT_EQ(plan.frames.size(), sequence.frames().size());
    const SequencePlan read = planFromJson(planToJson(plan, FIRELOOK_SAMPLE_DIR), "plan.json");
    // Exact equality: a shard's bytes depend on these values, and a round trip that lost the last
    // bit of one would bake another package.
    EXPECT_EQ(read.sequence_xxh3_64, plan.sequence_xxh3_64);
    EXPECT_EQ(read.read.density_grid, plan.read.density_grid);
    EXPECT_EQ(read.read.temperature_grid, plan.read.temperature_grid);
    EXPECT_EQ(read.world_bounds.min, plan.world_bounds.min);
    EXPECT_EQ(read.world_bounds.max, plan.world_bounds.max);
    EXPECT_EQ(read.survey.temperature_range, plan.survey.temperature_range);
    EXPECT_EQ(read.survey.temperatures.t_min, plan.survey.temperatures.t_min);
    EXPECT_EQ(read.survey.temperatures.t_max, plan.survey.temperatures.t_max);
    EXPECT_EQ(read.survey.density.depth, plan.survey.density.depth);
    EXPECT_EQ(read.survey.density.density_p99, plan.survey.density.density_p99);
    EXPECT_EQ(read.survey.density.dense_side, plan.survey.density.dense_side);
    ASSERT_EQ(read.frames.size(), plan.frames.size());
    for (size_t i = 0; i < plan.frames.size(); ++i) {
        EXPECT_EQ(read.frames[i].number, plan.frames[i].number);
        EXPECT_EQ(read.frames[i].file, plan.frames[i].file);
        EXPECT_EQ(read.frames[i].xxh3_64, plan.frames[i].xxh3_64);
    }
    // The same survey as the one a bake without a plan measures: the temperature range of the
    // whole sequence too (scene_setup.h), from the same single pass.
    EXPECT_EQ(plan.survey.temperature_range, sequenceTemperatureRange(sequence));
    const SequenceSurvey surveyed = surveySequence(sequence);
    EXPECT_EQ(surveyed.density.depth, plan.survey.density.depth);
    EXPECT_EQ(surveyed.temperatures.t_max, plan.survey.temperatures.t_max);
}

// With every axis derived from the data and the temperature range from it (nothing given), the
// description a bake derives from a plan read back is the one it derives from the sequence.
TEST(SequencePlan, DerivesTheDescriptionABakeWithoutAPlanDerives) {
    BakeConfig config = test::tinyConfig();
    config.t_lo.reset();
    config.t_hi.reset();
    config.axes = BakeAxes();
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(FIRELOOK_SAMPLE_DIR);
    const SceneSetup scene = resolveScene(sequence, config.scene);
    const SequencePlan read = planFromJson(planToJson(planSequence(sequence), "seq"), "plan.json");
    const DescribedBake from_plan = describeDerivedBake(sequence, config, scene, &read.survey);
    const DescribedBake measured = describeDerivedBake(sequence, config, scene);
    EXPECT_EQ(axisDerivationToJson(from_plan.derivation), axisDerivationToJson(measured.derivation));
    EXPECT_EQ(from_plan.description.bins.t_hi, measured.description.bins.t_hi);
    EXPECT_EQ(from_plan.description.axes.smoke_extinction, measured.description.axes.smoke_extinction);
    EXPECT_EQ(from_plan.description.default_look_json, measured.description.default_look_json);
}

TEST(SequencePlan, TheSameFilesAnywhereAreTheSameSequence) {
    TempDir dir;
    for (const char* folder : {"a", "b"}) {
        std::filesystem::create_directory(dir / folder);
        for (const char* name : {"fluid_data_0001.vdb", "fluid_data_0002.vdb"})
            std::filesystem::copy_file(std::filesystem::path(FIRELOOK_SAMPLE_DIR) / name,
                                       dir / folder / name);
    }
    const std::string a = planSequence(vdb::VdbSequence::open((dir / "a").string())).sequence_xxh3_64;
    EXPECT_EQ(
        planSequence(vdb::VdbSequence::open((dir / "b" / "fluid_data_####.vdb").string())).sequence_xxh3_64,
        a);
    std::filesystem::copy_file(std::filesystem::path(FIRELOOK_SAMPLE_DIR) / "fluid_data_0003.vdb",
                               dir / "b" / "fluid_data_0002.vdb",
                               std::filesystem::copy_options::overwrite_existing);
    EXPECT_NE(planSequence(vdb::VdbSequence::open((dir / "b").string())).sequence_xxh3_64, a)
        << "another frame 2";
}

// vdb::VdbSequence::openKnown, what a bake with a plan opens: the folder is listed, no file read
// until a frame is loaded, so a broken frame fails only its own load.
TEST(SequencePlan, OpeningWithAPlanReadsOnlyTheFramesLoaded) {
    TempDir dir;
    for (const char* name : {"fluid_data_0001.vdb", "fluid_data_0002.vdb"})
        std::filesystem::copy_file(std::filesystem::path(FIRELOOK_SAMPLE_DIR) / name, dir / name);
    const SequencePlan plan = planSequence(vdb::VdbSequence::open(dir.path().string()));
    std::ofstream(dir / "fluid_data_0002.vdb", std::ios::trunc) << "not a VDB file";
    EXPECT_THROW(vdb::VdbSequence::open(dir.path().string()), vdb::VdbError) << "open() reads every file";
    const vdb::VdbSequence known =
        vdb::VdbSequence::openKnown(dir.path().string(), plan.read, plan.world_bounds);
    EXPECT_EQ(known.frames().size(), 2u);
    EXPECT_EQ(known.sequenceWorldBounds().max, plan.world_bounds.max);
    EXPECT_GT(known.load(1).density_stats.active_voxels, 0u);
    EXPECT_THROW(known.load(2), vdb::VdbError);
    EXPECT_THROW(vdb::VdbSequence::openKnown(dir.path().string(), vdb::ReadOptions{}, plan.world_bounds),
                 vdb::VdbError)
        << "without the grid names";
}

// The frame a bake traces first is kept from the plan's pass (LoadedFrame), as a load of its own
// would give it: the same medium voxel for voxel and the same record of the read. (A bake from a
// plan loads every frame itself; tests/cli/shard_plan_test.cpp merges such shards into the bytes
// of one bake without a plan.)
TEST(SequencePlan, KeepsTheFrameAskedForAsItsOwnLoadGivesIt) {
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(FIRELOOK_SAMPLE_DIR);
    const int keep = sequence.frames()[1].number;
    LoadedFrame kept;
    const SequencePlan plan = planSequence(sequence, {}, keep, &kept);
    EXPECT_EQ(plan.frames.size(), sequence.frames().size());
    ASSERT_EQ(kept.number, keep);
    const LoadedFrame own = loadFrame(sequence.load(keep));
    EXPECT_EQ(kept.file, own.file);
    EXPECT_EQ(kept.active_voxels, own.active_voxels);
    EXPECT_GT(kept.active_voxels, 0u);
    EXPECT_EQ(kept.cleaned_non_finite, own.cleaned_non_finite);
    EXPECT_EQ(kept.clamped_extreme, own.clamped_extreme);
    ASSERT_EQ(kept.medium.dims(), own.medium.dims());
    EXPECT_EQ(kept.medium.origin(), own.medium.origin());
    const glm::ivec3 d = own.medium.dims();
    std::size_t differing = 0;
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const render::MediumSample a = kept.medium.voxel({x, y, z}), b = own.medium.voxel({x, y, z});
                differing += a.density != b.density || a.temperature != b.temperature;
            }
    EXPECT_EQ(differing, 0u);
    LoadedFrame none;
    planSequence(sequence, {}, -1, &none);
    EXPECT_EQ(none.number, -1) << "no frame asked for, none kept";
}

TEST(SequencePlan, RefusesWhatIsNotAPlanOfThisVersion) {
    const auto message = [](const std::string& text) {
        try {
            planFromJson(text, "p.json");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(message("[1, 2]").find("p.json: not a plan written by firelook bake --plan-only"),
              std::string::npos);
    EXPECT_NE(message(R"({"firelook_plan": 2})").find("p.json: plan version 2"), std::string::npos);
    EXPECT_NE(message(R"({"firelook_plan": 1, "sequence_xxh3_64": "0"})").find("p.json: not a complete plan"),
              std::string::npos);
}

}  // namespace
}  // namespace firelook::bake
