// bakePackage (baker/bake/bake_pipeline.h) on the bundled sample, kept tiny: one frame, 16x16,
// few photons, a 2x1x1 parameter grid.
#include "bake/bake_pipeline.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <cstdio>
#include <nlohmann/json.hpp>

#include "../support/error_code.h"
#include "../support/temp_dir.h"
#include "basis/basis_package.h"
#include "basis/frame_factors.h"
#include "basis/look_renderer.h"
#include "look/look.h"
#include "package_images.h"
#include "reference/frame_medium.h"
#include "tiny_sample_bake.h"
#include "vdb/vdb_sequence.h"

namespace firelook::bake {
namespace {

using firelook::testing::TempDir;

using test::fileBytes;
using test::tinyConfig;

TEST(BakePipeline, BakesAReadablePackage) {
    TempDir dir;
    const auto out = dir / "a.firelook";
    const BakeReport report = bakePackage(FIRELOOK_SAMPLE_DIR, out, tinyConfig(), "test");
    ASSERT_EQ(report.frames.size(), 1u);
    EXPECT_EQ(report.frames[0].frame, 1);
    EXPECT_GT(report.frames[0].rank, 0);
    EXPECT_EQ(report.package_bytes, std::filesystem::file_size(out));
    const basis::BasisReader package = basis::BasisReader::open(out);
    const basis::BakeDescription& d = package.description();
    EXPECT_EQ(d.width, 16);
    EXPECT_EQ(d.height, 16);
    EXPECT_EQ(d.bins.count, 4);
    EXPECT_EQ(d.alpha_thresholds.size(), 3u);
    EXPECT_EQ(d.light_directions.size(), 1u) << "the default key light";
    ASSERT_EQ(d.frames.size(), 1u);
    EXPECT_EQ(d.frames[0].rank, report.frames[0].rank);
    const basis::FrameFactors f = package.loadFrame(1);
    EXPECT_EQ(f.columns, 2 * (4 + 1));
    const nlohmann::json meta = nlohmann::json::parse(package.metadataJson());
    EXPECT_EQ(meta.at("provenance").at("sources").size(), 1u);
    EXPECT_EQ(meta.at("camera").at("source"), "default");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"a.firelook"});
}

TEST(BakePipeline, SameSeedSameBytesOtherSeedOtherBasis) {
    TempDir dir;
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / "a.firelook", tinyConfig(1), "test");
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / "b.firelook", tinyConfig(1), "test");
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / "c.firelook", tinyConfig(2), "test");
    const std::string a = fileBytes(dir / "a.firelook");
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(a == fileBytes(dir / "b.firelook")) << "same seed, different bytes";
    EXPECT_FALSE(a == fileBytes(dir / "c.firelook"));
    // Not only the recorded seed: the photons, hence S V^T, differ too.
    const basis::FrameFactors fa = basis::BasisReader::open(dir / "a.firelook").loadFrame(1);
    const basis::FrameFactors fc = basis::BasisReader::open(dir / "c.firelook").loadFrame(1);
    EXPECT_NE(fa.svt, fc.svt);
    // Camera rays are deterministic: the exact optical depths do not depend on the seed.
    EXPECT_EQ(fa.depth_b, fc.depth_b);
}

// Photon chunks are summed in a fixed order and camera rays write only their own pixel, so the
// number of worker threads cannot change a byte.
TEST(BakePipeline, SameBytesWithOneAndTwoThreads) {
    TempDir dir;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        bakePackage(FIRELOOK_SAMPLE_DIR, dir / "one.firelook", tinyConfig(3), "test");
    }
    {
        tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
        bakePackage(FIRELOOK_SAMPLE_DIR, dir / "two.firelook", tinyConfig(3), "test");
    }
    const std::string one = fileBytes(dir / "one.firelook");
    ASSERT_FALSE(one.empty());
    EXPECT_TRUE(one == fileBytes(dir / "two.firelook")) << "1 and 2 threads gave different bytes";
}

// A budget below what the frame needs stops the bake before tracing, naming the frame, the
// estimate and the settings that lower it; nothing is written.
TEST(BakePipeline, BudgetBelowTheFrameStopsBeforeTracing) {
    TempDir dir;
    BakeConfig c = tinyConfig();
    c.scene.width = c.scene.height = 256;  // a basis of 256^2 x 2 columns: 0.5 MiB, plus the fixed share
    c.memory_budget_bytes = 64 << 20;      // below the 96 MiB fixed share alone
    double traced = 0.0;
    try {
        bakePackage(FIRELOOK_SAMPLE_DIR, dir / "a.firelook", c, "test", [&](double f, const std::string&) {
            traced = std::max(traced, f);
            return true;
        });
        FAIL() << "expected the bake to refuse";
    } catch (const std::runtime_error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("frame 1 needs an estimated"), std::string::npos) << message;
        EXPECT_NE(message.find("--memory-budget"), std::string::npos) << message;
        EXPECT_NE(message.find("--size"), std::string::npos) << message;
    }
    EXPECT_EQ(traced, 0.0) << "no tracing progress before the refusal";
    EXPECT_TRUE(dir.entries().empty());
}

// --help promises the default budget: 60% of the machine's physical memory.
TEST(BakePipeline, DefaultBudgetIsSixtyPercentOfPhysicalMemory) {
    const double physical = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
    ASSERT_GT(physical, 0.0);
    EXPECT_NEAR(static_cast<double>(defaultMemoryBudget()) / physical, 0.6, 1e-6);
    // The bake records the budget it ran under.
    TempDir dir;
    const BakeReport report = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "a.firelook", tinyConfig(), "test");
    EXPECT_EQ(report.memory_budget_bytes, defaultMemoryBudget());
    EXPECT_LE(report.frames.at(0).estimated_peak_bytes, report.memory_budget_bytes);
}

// A tighter budget coarsens the scattered-light cells instead of failing, and the plan's estimate
// never exceeds the budget it was given.
TEST(BakePipeline, TightBudgetCoarsensTheCells) {
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(FIRELOOK_SAMPLE_DIR);
    const render::Medium medium = reference::mediumFromFrame(sequence.load(6));
    const BakeConfig c = tinyConfig();
    const SceneSetup scene = resolveScene(sequence, c.scene);
    const BasisModel model = describeBake(sequence, c, scene);
    const FrameMemoryPlan free_plan = frameMemoryPlan(medium, scene.camera, model, c.trace, c.compression, 0);
    ASSERT_GT(free_plan.trace.cell_bytes, 0u);
    const uint64_t budget = free_plan.peakBytes() - free_plan.trace.cell_bytes / 2;
    const FrameMemoryPlan tight = frameMemoryPlan(medium, scene.camera, model, c.trace, c.compression, budget);
    EXPECT_TRUE(tight.fits(budget));
    EXPECT_LE(tight.peakBytes(), budget);
    EXPECT_GT(tight.trace.cell_edge_voxels, free_plan.trace.cell_edge_voxels);
}

TEST(BakePipeline, CancelledBakeLeavesNothingBehind) {
    for (int cancel_at : {1, 3}) {
        TempDir dir;
        int calls = 0;
        const auto progress = [&](double, const std::string&) { return ++calls < cancel_at; };
        EXPECT_THROW(bakePackage(FIRELOOK_SAMPLE_DIR, dir / "a.firelook", tinyConfig(), "test", progress),
                     std::runtime_error);
        EXPECT_GE(calls, cancel_at);
        EXPECT_FALSE(std::filesystem::exists(dir / "a.firelook"));
        EXPECT_TRUE(dir.entries().empty())
            << "left behind: " << (dir.entries().empty() ? "" : dir.entries()[0]);
    }
}

TEST(BakePipeline, CancelledBakeKeepsAnExistingPackage) {
    TempDir dir;
    const auto out = dir / "a.firelook";
    bakePackage(FIRELOOK_SAMPLE_DIR, out, tinyConfig(), "test");
    const std::string before = fileBytes(out);
    const auto cancel = [](double fraction, const std::string&) { return fraction < 0.5; };
    EXPECT_THROW(bakePackage(FIRELOOK_SAMPLE_DIR, out, tinyConfig(2), "test", cancel), std::runtime_error);
    EXPECT_EQ(fileBytes(out), before);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"a.firelook"});
}

TEST(BakePipeline, ProgressIsMonotonicAndEndsAtOne) {
    TempDir dir;
    std::vector<double> fractions;
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / "a.firelook", tinyConfig(), "test",
                [&](double f, const std::string& detail) {
                    fractions.push_back(f);
                    // The look axes are checked against every frame of the sequence, then frame 1 is baked.
                    EXPECT_TRUE(detail.starts_with("frame 1 (") || detail.ends_with(": checking the look axes"))
                        << detail;
                    return true;
                });
    ASSERT_FALSE(fractions.empty());
    for (size_t i = 1; i < fractions.size(); ++i) EXPECT_GE(fractions[i], fractions[i - 1]);
    EXPECT_EQ(fractions.back(), 1.0);
}

TEST(BakePipeline, BadInputsFailWithoutOutput) {
    TempDir dir;
    BakeConfig frames = tinyConfig();
    frames.frames = "40-50";
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      bakePackage(FIRELOOK_SAMPLE_DIR, dir / "a.firelook", frames, "test"));
    EXPECT_THROW(bakePackage(FIRELOOK_SAMPLE_DIR, dir / "missing" / "a.firelook", tinyConfig(), "test"),
                 std::exception);
    EXPECT_THROW(bakePackage((dir / "no-such-sequence").string(), dir / "a.firelook", tinyConfig(), "test"),
                 std::exception);
    EXPECT_TRUE(dir.entries().empty());
}

TEST(BakePipeline, DescribeBakeClampsTheDefaultLookIntoTheAxes) {
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(FIRELOOK_SAMPLE_DIR);
    BakeConfig config = tinyConfig();
    config.axes = {{2.5}, {10.0, 20.0}, {0.1}};
    const SceneSetup scene = resolveScene(sequence, config.scene);
    const basis::BakeDescription d = describeBake(sequence, config, scene);
    ASSERT_EQ(d.alpha_thresholds.size(), 1u) << "one T_c needs one alpha threshold";
    EXPECT_EQ(d.alpha_thresholds[0], 2.5);
    const Look look = parseLook(d.default_look_json, "default");
    EXPECT_EQ(look.temperature_threshold, 2.5);
    EXPECT_GE(look.smoke_extinction, 10.0);
    EXPECT_LE(look.smoke_extinction, 20.0);
    EXPECT_EQ(look.flame_extinction, 0.1);
    EXPECT_EQ(look.albedo, config.albedo);
    EXPECT_EQ(look.light_irradiance.size(), d.light_directions.size());
}

// The reported case, made from the bundled sample: temperatures scaled so the whole sequence stays
// below 0.58 (frame 12 below 0.39), bins over that range, the default look axes (reduced).
BakeConfig smokeOnlyConfig() {
    BakeConfig c = tinyConfig();
    c.frames = "12";
    // The scaled sequence's own range (given, so the bake does not load all 12 frames to find it):
    // 16 bins of 0.036, so 0.39 is 17 bins below T_c = 1.
    c.t_lo = 0.0;
    c.t_hi = 0.58;
    c.bins = 16;
    c.read.temperature_scale = 0.58 / 3.0;
    c.axes = {{1.0, 1.2, 1.4, 1.6, 1.8, 2.0}, {2.0, 8.0}, {0.5, 4.0}};
    return c;
}

// An axis that cannot change the frames is baked at one sample: 1/6 of the T_c columns (and k_f
// goes too: below every T_c the flame share is ~0), with the images of a full-axis bake of the
// same data for looks anywhere on (and off) the axes.
TEST(BakePipeline, AxisThatCannotChangeAFrameCollapses) {
    TempDir dir;
    const BakeConfig collapsed_config = smokeOnlyConfig();
    BakeConfig full_config = collapsed_config;
    full_config.collapse_unused_axes = false;
    std::vector<std::string> notices;
    const BakeReport collapsed = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "c.firelook", collapsed_config, "test", {},
                                             [&](const std::string& line) { notices.push_back(line); });
    const BakeReport full = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "f.firelook", full_config, "test");
    ASSERT_TRUE(collapsed.axes_analysed);
    EXPECT_FALSE(full.axes_analysed) << "collapse_unused_axes = false keeps the axes without looking";
    ASSERT_EQ(collapsed.axes.collapsed.size(), 2u);
    EXPECT_EQ(collapsed.axes.collapsed[0].axis, "temperature_threshold");
    EXPECT_EQ(collapsed.axes.collapsed[1].axis, "flame_extinction");
    ASSERT_EQ(notices.size(), 2u);
    EXPECT_NE(notices[0].find("temperature_threshold axis collapsed"), std::string::npos) << notices[0];
    // The whole scaled sequence's range (to 0.58), not frame 12's alone (0.39): a package's axes do
    // not depend on which frames a bake selects, so shards agree.
    EXPECT_LT(collapsed.axes.temperatures.t_max, 0.6);
    // Columns traced: (1 x 2 x 1) against (6 x 2 x 2) grid points, 16 bins + 1 light each.
    EXPECT_EQ(collapsed.frames.at(0).columns_traced, 2u * 17);
    EXPECT_EQ(full.frames.at(0).columns_traced, 24u * 17);

    const basis::BasisReader c = basis::BasisReader::open(dir / "c.firelook");
    const basis::BasisReader f = basis::BasisReader::open(dir / "f.firelook");
    EXPECT_EQ(c.description().axes.temperature_threshold, (std::vector<double>{1.0}));
    EXPECT_EQ(c.description().alpha_thresholds, (std::vector<double>{1.0}));
    EXPECT_EQ(f.description().axes.temperature_threshold.size(), 6u);
    EXPECT_EQ(c.description().default_look_json, f.description().default_look_json)
        << "the default look is the full axes' one";
    const nlohmann::json meta = nlohmann::json::parse(c.metadataJson());
    EXPECT_EQ(meta.at("axis_collapse").at("collapsed").size(), 2u);
    EXPECT_FALSE(nlohmann::json::parse(f.metadataJson()).contains("axis_collapse"));

    // Same seed: the images differ by the bound (< 1e-4 of sigma_t), the rounding of a different
    // SVD and codec, and the photon noise of the scattered light where the two bakes' photon paths
    // stop drawing the same random numbers (their grid points differ). Measured 1.5e-4 with the
    // 0.125-voxel step, 0 without scattering orders (max_orders 0), 1e-7 with the 0.25-voxel step,
    // where the paths stayed the same. Tolerance 5e-4 relative RMSE: about three times
    // that. Alpha differs by the stored depths' companding, which alpha_error bounds (1e-3; measured
    // 5e-4).
    Look look = parseLook(f.description().default_look_json, "default");
    double worst_rgb = 0.0, worst_alpha = 0.0;
    for (double tc : {0.5, 1.0, 1.5, 2.0, 3.0})
        for (double ks : {2.0, 5.0, 8.0})
            for (double kf : {0.5, 2.0, 4.0}) {
                look.temperature_threshold = tc;
                look.smoke_extinction = ks;
                look.flame_extinction = kf;
                const std::vector<float> a = test::renderFrame(c, 12, look), b = test::renderFrame(f, 12, look);
                const test::ImageDifference d = test::compareImages(a, b);
                ASSERT_GT(d.reference_norm, 0.0);
                worst_rgb = std::max(worst_rgb, d.relative_rmse);
                worst_alpha = std::max(worst_alpha, d.worst_alpha);
                EXPECT_LT(d.relative_rmse, 5e-4) << "T_c " << tc << " k_s " << ks << " k_f " << kf;
                EXPECT_LT(d.worst_alpha, 1e-3) << "T_c " << tc << " k_s " << ks << " k_f " << kf;
            }
    std::printf("collapsed vs full axes over 45 looks: worst relative RMSE %.2e, worst alpha %.2e\n", worst_rgb,
                worst_alpha);
}

// Where the temperature crosses the axis (frame 12 unscaled reaches 2.0), the full axes stay.
TEST(BakePipeline, TemperatureAcrossTheAxisKeepsTheFullAxis) {
    TempDir dir;
    BakeConfig config = smokeOnlyConfig();
    config.read.temperature_scale = 1.0;
    config.t_hi = 3.0;
    config.scene.width = config.scene.height = 8;
    const BakeReport report = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "a.firelook", config, "test");
    ASSERT_TRUE(report.axes_analysed);
    EXPECT_TRUE(report.axes.collapsed.empty());
    EXPECT_GT(report.axes.temperatures.t_max, 2.0);
    EXPECT_EQ(report.frames.at(0).columns_traced, 24u * 17);
    EXPECT_EQ(basis::BasisReader::open(dir / "a.firelook").description().axes.temperature_threshold.size(), 6u);
}

}  // namespace
}  // namespace firelook::bake
