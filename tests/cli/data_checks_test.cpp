// Telling the truth about the data (issue 13 C), end to end: every command that reads a sequence
// warns on stderr about cleaned and clamped values (one line per frame and grid) and about gaps,
// refuses implausible values unless --clamp-extreme, and --strict turns each warning into the
// one-line error. Sequences are tiny VDB files written here with OpenVDB.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../support/command.h"
#include "../support/tiny_bake_config.h"
#include "../vdb/vdb_test_files.h"
#include "image/image_io.h"

namespace {

namespace fs = std::filesystem;
using namespace firelook::testing;  // runFirelook, lines, kTinyBakeConfig
using firelook::vdb::testing::makeGrid;
using firelook::vdb::testing::TempDir;
using firelook::vdb::testing::Voxels;
using firelook::vdb::testing::writeVdb;
using nlohmann::json;
using ::testing::HasSubstr;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

std::vector<std::string> warnings(const CommandResult& r) {
    std::vector<std::string> out;
    for (const std::string& line : lines(r.err))
        if (line.rfind("firelook: warning: ", 0) == 0) out.push_back(line.substr(19));
    return out;
}

void expectExitOneWithOneErrorLine(const CommandResult& r, const std::string& mentions) {
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    int error_lines = 0;
    for (const std::string& line : lines(r.err)) error_lines += line.rfind("firelook: error:", 0) == 0;
    EXPECT_EQ(error_lines, 1) << r.err;
    EXPECT_THAT(r.err, HasSubstr(mentions));
}

// A 6^3 block of density 1 whose temperature rises from 0 to 3 along x.
Voxels block(float density) {
    Voxels v;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            for (int k = 0; k < 6; ++k) v.push_back({openvdb::Coord(i, j, k), density});
    return v;
}
Voxels ramp() {
    Voxels v = block(0.0f);
    for (auto& [coord, value] : v) value = 3.0f * float(coord.x()) / 5.0f;
    return v;
}

std::string frameFile(const fs::path& seq, int frame) {
    char name[32];
    std::snprintf(name, sizeof name, "fire_%04d.vdb", frame);
    return (seq / name).string();
}

void writeFrame(const fs::path& seq, int frame, const Voxels& density, const Voxels& temperature) {
    fs::create_directories(seq);
    writeVdb(frameFile(seq, frame), {makeGrid("density", density), makeGrid("temperature", temperature)});
}

// Frame 1 of `seq` with 2 NaN, 1 Inf and 1 negative density and 1 Inf temperature.
void writeDirtyFrame(const fs::path& seq, int frame) {
    Voxels density = block(1.0f), temperature = ramp();
    density[0].second = kNaN;
    density[1].second = kNaN;
    density[2].second = kInf;
    density[3].second = -0.5f;
    temperature[10].second = kInf;
    writeFrame(seq, frame, density, temperature);
}

TEST(CliDataChecks, InfoWarnsAboutCleanedValuesAndShowsThem) {
    TempDir dir;
    writeDirtyFrame(dir / "seq", 1);
    CommandResult r = runFirelook(dir, "info seq");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(warnings(r), (std::vector<std::string>{"seq/fire_0001.vdb: density: 2 NaN, 1 Inf, 1 negative values set to 0",
                                                      "seq/fire_0001.vdb: temperature: 0 NaN, 1 Inf values set to 0"}))
        << r.err;
    EXPECT_THAT(r.out, HasSubstr("frame 1: seq/fire_0001.vdb: density: 2 NaN, 1 Inf, 1 negative values set to 0"));
    EXPECT_THAT(r.out, HasSubstr("frame 1: seq/fire_0001.vdb: temperature: 0 NaN, 1 Inf values set to 0"));

    r = runFirelook(dir, "info --json seq");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json cleaned = json::parse(r.out).at("frames")[0].at("cleaned");
    EXPECT_EQ(cleaned.at("density").at("nan"), 2);
    EXPECT_EQ(cleaned.at("density").at("inf"), 1);
    EXPECT_EQ(cleaned.at("density").at("negative"), 1);
    EXPECT_EQ(cleaned.at("temperature").at("inf"), 1);
    EXPECT_EQ(cleaned.at("non_finite"), 4);
    EXPECT_EQ(warnings(r).size(), 2u) << "the warnings go to stderr with --json too";

    r = runFirelook(dir, "info seq --strict");
    expectExitOneWithOneErrorLine(r, "seq/fire_0001.vdb: density: 2 NaN, 1 Inf, 1 negative values; temperature: 0 NaN, 1 Inf "
                          "values (refused by --strict");
}

TEST(CliDataChecks, ReferenceWarnsOncePerFrameAndGridAndStrictRefuses) {
    // No --config: the reference loads every frame for the temperature range, then frame 1 again.
    TempDir dir;
    writeDirtyFrame(dir / "seq", 1);
    writeDirtyFrame(dir / "seq", 2);
    CommandResult r = runFirelook(dir, "reference seq --frame 1 --size 8x8 --spp 1 --out a.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::vector<std::string> w = warnings(r);
    EXPECT_EQ(w.size(), 4u) << r.err;  // 2 frames x 2 grids, each once
    for (int frame : {1, 2})
        for (const char* grid : {": density: ", ": temperature: "})
            EXPECT_EQ(std::count_if(w.begin(), w.end(),
                                    [&](const std::string& line) {
                                        return line.rfind("seq/fire_000" + std::to_string(frame) + ".vdb" + grid, 0) == 0;
                                    }),
                      1)
                << "frame " << frame << grid << "\n"
                << r.err;
    EXPECT_TRUE(fs::exists(dir / "a.exr"));

    r = runFirelook(dir, "reference seq --frame 1 --size 8x8 --spp 1 --out b.exr --strict");
    expectExitOneWithOneErrorLine(r, "refused by --strict");
    EXPECT_FALSE(fs::exists(dir / "b.exr"));
}

TEST(CliDataChecks, ImplausibleValuesAreRefusedUnlessClamped) {
    TempDir dir;
    Voxels density = block(1.0f);
    density[7].second = 1e30f;  // voxel (0, 1, 1)
    writeFrame(dir / "seq", 1, density, ramp());
    CommandResult r = runFirelook(dir, "info seq");
    expectExitOneWithOneErrorLine(r, "seq/fire_0001.vdb: density: value 1e+30 at voxel (0, 1, 1) is beyond any plausible density");
    r = runFirelook(dir, "reference seq --frame 1 --size 8x8 --spp 1 --out a.exr");
    expectExitOneWithOneErrorLine(r, "density: value 1e+30");
    EXPECT_FALSE(fs::exists(dir / "a.exr"));

    r = runFirelook(dir, "reference seq --frame 1 --size 8x8 --spp 1 --out a.exr --clamp-extreme");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(warnings(r), std::vector<std::string>{"seq/fire_0001.vdb: density: 1 value above 1e+06 clamped to 1e+06"})
        << r.err;
    EXPECT_TRUE(fs::exists(dir / "a.exr"));

    // Temperatures: the bins would stretch over 1e9 and squeeze the real range into bin 0.
    TempDir hot;
    Voxels temperature = ramp();
    temperature[3].second = -2e9f;
    writeFrame(hot / "seq", 1, block(1.0f), temperature);
    r = runFirelook(hot, "info seq");
    expectExitOneWithOneErrorLine(r, "seq/fire_0001.vdb: temperature: value -2e+09 at voxel (0, 0, 3)");
    r = runFirelook(hot, "info seq --clamp-extreme");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(warnings(r),
              std::vector<std::string>{"seq/fire_0001.vdb: temperature: 1 value beyond +-1e+06 clamped to +-1e+06"});
    r = runFirelook(hot, "info seq --clamp-extreme --strict");
    expectExitOneWithOneErrorLine(r, "temperature: 1 value beyond +-1e+06 (refused by --strict");
}

TEST(CliDataChecks, ClampedExtremeDensityBakesLikeTheReference) {
    // Four voxels of density 1e30, clamped to 1e6, in a block of density 1 (issue 28). They fill
    // the density's 99th percentile, so the derived extinctions are 1e-5 and the emission stops
    // with them: the emission columns came out 1e5 times the sun's, and the SVD and the S V^T grid,
    // bounding error against the whole basis, dropped the sun's light (rendered 0 where the
    // reference has 43% of the image). The sources are balanced now (basis/source_balance.h).
    // Measured: +1.6 / +2.1 / +2.1% per channel (the sun's part alone +0.4%). Margin 5% (the
    // issue's bar): the reference's noise of the mean at 16x16 and 256 spp is about 0.5%.
    TempDir dir;
    Voxels density = block(1.0f);
    for (int v : {7, 50, 101, 180}) density[v].second = 1e30f;
    writeFrame(dir / "seq", 1, density, ramp());
    CommandResult r = runFirelook(dir, "bake seq --size 16x16 --clamp-extreme -o huge.firelook");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // bench reads the sequence as the package's provenance says, so without the flag it clamps too.
    r = runFirelook(dir, "bench seq --package huge.firelook --frames 1 --looks 1 --spp 2 --alpha-rays 1");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.err, HasSubstr("density: 4 values above 1e+06 clamped to 1e+06")) << r.err;
    r = runFirelook(dir, "render huge.firelook --frame 1 -o baked.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = runFirelook(dir, "reference seq --frame 1 --size 16x16 --spp 256 --clamp-extreme -o reference.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const firelook::image::ImageRGBA baked = firelook::image::readImage(dir / "baked.exr");
    const firelook::image::ImageRGBA reference = firelook::image::readImage(dir / "reference.exr");
    ASSERT_EQ(baked.pixels.size(), reference.pixels.size());
    for (int c = 0; c < 4; ++c) {
        double b = 0.0, ref = 0.0;
        for (size_t p = c; p < baked.pixels.size(); p += 4) {
            b += baked.pixels[p];
            ref += reference.pixels[p];
        }
        ASSERT_GT(ref, 0.0) << "channel " << c;
        EXPECT_NEAR(b / ref, 1.0, 0.05) << "channel " << c << ": baked mean " << b << ", reference " << ref;
    }
}

TEST(CliDataChecks, GapsAreReportedByEveryCommandAndRefusedUnderStrict) {
    TempDir dir;
    for (int frame : {1, 2, 4}) writeFrame(dir / "seq", frame, block(1.0f), ramp());
    std::ofstream(dir / "bake.json") << kTinyBakeConfig;

    CommandResult r = runFirelook(dir, "info seq");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(warnings(r), std::vector<std::string>{"seq: frame 3 missing"});
    EXPECT_THAT(r.out, HasSubstr("missing frames: [3]"));
    expectExitOneWithOneErrorLine(runFirelook(dir, "info seq --strict"), "seq: frame 3 missing (refused by --strict)");

    r = runFirelook(dir, "reference seq --frame 1 --size 8x8 --spp 1 --out a.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(warnings(r), std::vector<std::string>{"seq: frame 3 missing"});
    r = runFirelook(dir, "reference seq --frame 1 --size 8x8 --spp 1 --out b.exr --strict");
    expectExitOneWithOneErrorLine(r, "frame 3 missing (refused by --strict)");
    EXPECT_FALSE(fs::exists(dir / "b.exr"));

    // bake --frames 1-3 names a frame that is not there.
    r = runFirelook(dir, "bake seq -o pkg.firelook --frames 1-3 --size 8x8 --config bake.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(warnings(r), (std::vector<std::string>{"seq: frame 3 missing", "seq: --frames 1-3 skips frame 3 (no file)"}))
        << r.err;
    ASSERT_TRUE(fs::exists(dir / "pkg.firelook"));
    r = runFirelook(dir, "bake seq -o strict.firelook --frames 1-3 --size 8x8 --config bake.json --strict");
    expectExitOneWithOneErrorLine(r, "frame 3 missing (refused by --strict)");
    EXPECT_FALSE(fs::exists(dir / "strict.firelook"));

    // bench reads the sequence too.
    const std::string bench = "bench seq --package pkg.firelook --frames 1 --looks 1 --spp 2 --alpha-rays 1";
    r = runFirelook(dir, bench);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(warnings(r), std::vector<std::string>{"seq: frame 3 missing"});
    expectExitOneWithOneErrorLine(runFirelook(dir, bench + " --strict"), "frame 3 missing (refused by --strict)");
}

TEST(CliDataChecks, ASelectionPastTheEndWarnsWithoutAGap) {
    TempDir dir;
    for (int frame : {1, 2}) writeFrame(dir / "seq", frame, block(1.0f), ramp());
    std::ofstream(dir / "bake.json") << kTinyBakeConfig;
    CommandResult r =
        runFirelook(dir, "bake seq -o pkg.firelook --frames 2-5,7 --size 8x8 --config bake.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(warnings(r), std::vector<std::string>{"seq: --frames 2-5,7 skips frames 3-5, 7 (no file)"}) << r.err;
    r = runFirelook(dir, "bake seq -o strict.firelook --frames 1-2 --size 8x8 --config bake.json --strict");
    EXPECT_EQ(r.exit_code, 0) << "a clean sequence and selection pass --strict: " << r.err;
    EXPECT_TRUE(warnings(r).empty()) << r.err;
}

}  // namespace
