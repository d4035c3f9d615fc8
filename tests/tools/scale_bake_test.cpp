// Issue 11 in the suite: a 2x-resolution version of a real frame (firelook_upsample) baked with the
// command line at a small image size, and the bake's memory estimate against the peak it measured.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../support/command.h"
#include "../support/temp_dir.h"

namespace {

using firelook::testing::CommandResult;
using firelook::testing::runIn;
using firelook::testing::TempDir;

nlohmann::json readJson(const std::filesystem::path& file) { return nlohmann::json::parse(std::ifstream(file)); }

// The estimate is an upper bound by design (it counts every cell a non-empty brick touches, and
// the compression's worst case at the largest rank); measured on frames 1-12 of the sample and
// their 2x versions at 32x32-256x256 it was 1.0-1.4 times the peak. Bounds: at least 0.8 of the
// peak (an estimate much below it would let a budget be exceeded) and at most twice it (an
// estimate far above would refuse bakes that fit).
void expectEstimateNearPeak(const nlohmann::json& report) {
    const double peak = report.at("peak_memory_mib").get<double>();
    const double estimate = report.at("frames").at(0).at("estimated_peak_mib").get<double>();
    std::printf("[measured] estimated %.0f MiB, peak %.0f MiB (ratio %.2f)\n", estimate, peak, estimate / peak);
#if defined(__SANITIZE_ADDRESS__)
    // The estimate models the normal build; under AddressSanitizer its shadow memory and the
    // quarantine of freed blocks (256 MiB by default) add to the peak (measured ratio 0.58-0.70),
    // so only the upper bound is checked here.
#else
    EXPECT_GE(estimate, 0.8 * peak);
#endif
    EXPECT_LE(estimate, 2.0 * peak);
}

TEST(ScaleBake, TwiceTheResolutionBakesWithinItsEstimate) {
    TempDir dir;
    std::filesystem::create_directories(dir / "x2");
    const std::string frame = std::string(FIRELOOK_SAMPLE_DIR) + "/fluid_data_0012.vdb";
    const CommandResult upsampled = runIn(dir, std::string(FIRELOOK_UPSAMPLE_EXE) + " " + frame + " " +
                                                   (dir / "x2/fluid_data_0012.vdb").string() + " --factor 2");
    ASSERT_EQ(upsampled.exit_code, 0) << upsampled.err;
    // Few photons and a small image keep it a few seconds; the resolution is what is tested.
    std::ofstream(dir / "bake.json") << R"({"trace": {"photons_primary": 20000, "photons_per_order": 10000, "photon_noise_target": 0}})";
    for (const char* name : {"x1", "x2"}) {
        const std::string sequence = std::string(name) == "x1" ? frame : (dir / "x2").string();
        const std::filesystem::path package = dir / (std::string(name) + ".firelook");
        const std::filesystem::path report = dir / (std::string(name) + ".report.json");
        const CommandResult baked =
            runIn(dir, std::string(FIRELOOK_EXE) + " bake " + sequence + " --up z --size 32x32 --config " +
                           (dir / "bake.json").string() + " -o " + package.string() + " --report " +
                           report.string());
        ASSERT_EQ(baked.exit_code, 0) << name << ": " << baked.err;
        const nlohmann::json r = readJson(report);
        expectEstimateNearPeak(r);
        const nlohmann::json& f = r.at("frames").at(0);
        EXPECT_GT(f.at("rank").get<int>(), 0) << name;
        if (std::string(name) == "x2") {
            EXPECT_GT(f.at("active_voxels").get<double>(), 7.0 * 96410) << "about 8x the voxels of frame 12";
            // Cells follow the world extent: the 2x frame's are twice as many voxels wide (or, when
            // the medium is thick, as fine as the optical-depth rule allows).
            EXPECT_GE(f.at("cell_edge_voxels").get<int>(), 2);
        }
        const CommandResult rendered =
            runIn(dir, std::string(FIRELOOK_EXE) + " render " + package.string() + " --frame 12 --out " +
                           (dir / (std::string(name) + ".exr")).string());
        ASSERT_EQ(rendered.exit_code, 0) << name << ": " << rendered.err;
    }
}

// A budget the frame cannot meet: non-zero exit before tracing, no package, no temporary file.
TEST(ScaleBake, BudgetBelowTheFrameWritesNothing) {
    TempDir dir;
    const std::string frame = std::string(FIRELOOK_SAMPLE_DIR) + "/fluid_data_0012.vdb";
    EXPECT_NE(
        runIn(dir, std::string(FIRELOOK_EXE) + " bake " + frame +
                       " --up z --size 512x512 --memory-budget 300M -o " + (dir / "a.firelook").string())
            .exit_code,
        0);
    EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
