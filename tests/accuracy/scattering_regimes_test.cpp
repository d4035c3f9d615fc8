// The scattered-light regimes of scripts/bench/accuracy.sh as tests (issue 27): smoke lit by the
// scene's light with the emission off, dense smoke at albedo 0.95, thin late smoke with emission,
// and thick smoke around the explosion's flame. Each bakes one frame of samples/data/smoke (or of
// the explosion) at 64x64 (4 x 4 footprint rays, as advised below
// 128x128) with its look axes fixed to one point (a
// bake.json with numbers for T_c, k_s, k_f), so the package holds the basis at exactly the look
// bench draws: its image-mean bias is the tracer's (plus the codec's, ~0.01%), with no grid
// interpolation, and the bake takes seconds instead of a minute. The interpolation's own bias is
// guarded by interpolation_test.cpp and measured by scripts/bench/accuracy.sh (README, "Accuracy
// by regime").
//
// The bias this guards: the scattered light of sunlit smoke came out 1-1.7% low (the cells' sigma_s
// mass from cube centres, baker/bake/scatter_cells.cpp; and dense, high-albedo smoke lost the tail
// of its orders). Measured with the baker before the fix (bench of today's): -0.56% on the first
// case and -1.70% on the second (worst channel); with the fix -0.08%, -0.14% and +0.23% on the
// three; with stratified photons (baker/bake/photon_pass.cpp, 2026-12-06) -0.07%, -0.14%, +0.24%. Margin 0.4%: fails at half the bias the issue found; the reference's own noise of the mean
// is 0.06-0.09% at 1024 spp here (printed; the test requires below 0.13%), so the margin is 3 or
// more of its standard errors. CI time: about 165 s for the first three (2-core machine, release
// build), 6 s more for the fourth (a small frame, 4096 spp).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../support/command.h"

namespace {

using firelook::testing::runIn;
using firelook::testing::TempDir;

struct Regime {
    const char* name;
    const char* sequence;
    int frame;
    const char* bake_json;
    const char* bench_flags;
    double bias_margin = 0.004;
    int spp = 1024;
};

void checkRegime(const Regime& r) {
    TempDir dir;
    const std::string firelook = FIRELOOK_EXE;
    const std::string sequence = r.sequence;
    std::ofstream(dir / "bake.json") << r.bake_json;
    const std::string package = (dir / "p.firelook").string();
    const auto bake = runIn(dir, firelook + " bake " + sequence + " --up z --size 64x64 --frames " +
                                     std::to_string(r.frame) + " --config bake.json -o " + package);
    ASSERT_EQ(bake.exit_code, 0) << r.name << ": " << bake.err;
    const auto bench = runIn(dir, firelook + " bench " + sequence + " --package " + package + " --frames " +
                                      std::to_string(r.frame) + " --looks 2 --spp " + std::to_string(r.spp) +
                                      " " + r.bench_flags + " --json bench.json");
    ASSERT_EQ(bench.exit_code, 0) << r.name << ": " << bench.err;
    const nlohmann::json result = nlohmann::json::parse(std::ifstream(dir / "bench.json"));
    const nlohmann::json& s = result.at("summary");
    const double bias = s.at("worst_channel_image_mean_bias").get<double>();
    const double noise = s.at("median_image_mean_reference_noise").get<double>();
    const double alpha = s.at("max_alpha_error").get<double>();
    std::printf("[measured] %s: worst channel image-mean bias %+.4f (reference noise of the mean %.4f), max alpha "
                "error %.4f\n",
                r.name, bias, noise, alpha);
    EXPECT_LT(std::abs(bias), r.bias_margin) << r.name;
    EXPECT_LT(noise, r.bias_margin / 3) << r.name << ": the reference is too noisy to judge the margin";
    // Alpha: the issue's bar 0.005 (alpha is exact for any look; what is left is the codec and the
    // footprint quadrature, hence 4 x 4 rays a pixel at 64x64 as docs/bake-config.md advises: with
    // 3 x 3 the dense case measured 0.0055).
    EXPECT_LT(alpha, 0.005) << r.name;
}

TEST(ScatteringRegimes, SunlitSmokeWithoutEmission) {
    checkRegime({"sunlit smoke (frame 20, T_c 0.7, k_s 50, k_f 10, albedo 0.7, emission off)",
                 FIRELOOK_SMOKE_DIR, 20,
                 R"({"albedo": 0.7, "axes": {"temperature_threshold": 0.7, "smoke_extinction": 50,
                     "flame_extinction": 10}, "trace": {"footprint_samples_per_axis": 4}})",
                 "--emission-scale 0"});
}

TEST(ScatteringRegimes, DenseSmokeAtAlbedo095) {
    checkRegime({"dense smoke (frame 20, k_s 100, albedo 0.95, emission x0.1)", FIRELOOK_SMOKE_DIR, 20,
                 R"({"albedo": 0.95, "axes": {"temperature_threshold": 0.7, "smoke_extinction": 100,
                     "flame_extinction": 10}, "trace": {"footprint_samples_per_axis": 4}})",
                 "--emission-scale 0.1"});
}

TEST(ScatteringRegimes, ThinLateSmokeWithEmission) {
    checkRegime({"thin late smoke (frame 30, k_s 30, albedo 0.7, emission on)", FIRELOOK_SMOKE_DIR, 30,
                 R"({"albedo": 0.7, "axes": {"temperature_threshold": 0.7, "smoke_extinction": 30,
                     "flame_extinction": 10}, "trace": {"footprint_samples_per_axis": 4}})",
                 ""});
}

// The emission regime's thickest look (README, "Accuracy by regime"): the explosion's frame 3 with
// k_s 15.2 near the top of its axis. The frame is 28 voxels across: with 2-voxel cells (optical
// depth 0.79, the default until 2026-12-06) its image mean came out 0.36% low at 128x128 in
// scripts/bench/accuracy.sh. Measured here at 4096 spp (reference noise of the mean 0.05%): -0.10%
// with the default 1-voxel cells (TraceSettings::cell_voxels), -0.27% with "cell_voxels": 2.
// Margin 0.25%: within the issue's 0.3% bar, failed by the 2-voxel cells (checked), and three
// reference standard errors from the measured -0.10%. About 6 s of CI.
TEST(ScatteringRegimes, ThickSmokeAroundTheFlame) {
    checkRegime({"smoke around the flame (explosion frame 3, T_c 1.05, k_s 15.2, k_f 3.8, albedo 0.7)",
                 FIRELOOK_SAMPLE_DIR, 3,
                 R"({"axes": {"temperature_threshold": 1.05, "smoke_extinction": 15.2,
                     "flame_extinction": 3.8}, "trace": {"footprint_samples_per_axis": 4}})",
                 "", 0.0025, 4096});
}

}  // namespace
