// End-to-end tests of the `firelook` executable (docs/cli.md). Each test runs the built
// program through the shell in its own temporary folder and checks the exit status, the output
// and the files left behind. Bakes are tiny: frame 1 of the sample, 16x16, a few thousand photons.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../support/command.h"
#include "../support/sample.h"
#include "../support/temp_dir.h"
#include "../support/tiny_bake_config.h"

#define XXH_INLINE_ALL
#include <xxhash.h>
#include "image/image_io.h"
#include "package/container_writer.h"

namespace {

using namespace firelook::testing;  // TempDir, runFirelook, readFile, lines, kTinyBakeConfig
using nlohmann::json;

// docs/cli.md: a failure is a non-zero exit with a one-line error on stderr.
void expectOneLineError(const CommandResult& r, const std::string& mentions) {
    EXPECT_NE(r.exit_code, 0) << r.out << r.err;
    const std::vector<std::string> err = lines(r.err);
    ASSERT_FALSE(err.empty()) << "no error message";
    int error_lines = 0;
    for (const std::string& line : err) error_lines += line.rfind("firelook: error:", 0) == 0;
    EXPECT_EQ(error_lines, 1) << r.err;
    EXPECT_EQ(err.back().rfind("firelook: error:", 0), 0u) << r.err;
    EXPECT_NE(err.back().find(mentions), std::string::npos) << "expected '" << mentions << "' in: " << r.err;
}

using firelook::testing::kSample;

// Tiny bake settings (../support/tiny_bake_config.h).
void writeTinyConfig(const TempDir& dir) { std::ofstream(dir / "bake.json") << kTinyBakeConfig; }

// Bakes frame 1 into dir/pkg.firelook.
void bakeTiny(const TempDir& dir) {
    writeTinyConfig(dir);
    const CommandResult r = runFirelook(
        dir, "bake '" + kSample + "' -o pkg.firelook --frames 1 --size 16x16 --up z --config bake.json");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    ASSERT_TRUE(std::filesystem::exists(dir / "pkg.firelook"));
}

TEST(Cli, HelpExitsZero) {
    TempDir dir;
    CommandResult r = runFirelook(dir, "--help");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    for (const char* command : {"info", "reference", "bake", "render", "export-cycles"})
        EXPECT_NE(r.out.find(command), std::string::npos) << command << " missing from: " << r.out;
    for (const char* command : {"bake", "render", "export-cycles"}) {
        r = runFirelook(dir, std::string(command) + " --help");
        EXPECT_EQ(r.exit_code, 0) << command << ": " << r.err;
        EXPECT_FALSE(r.out.empty()) << command;
    }
    r = runFirelook(dir, "");
    EXPECT_NE(r.exit_code, 0) << "a subcommand is required";
    EXPECT_TRUE(dir.entries().empty());
}

TEST(Cli, InfoOnSequenceListsFramesAndGrids) {
    TempDir dir;
    const CommandResult r = runFirelook(dir, "info '" + kSample + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("12 frames"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("density grid 'density'"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("temperature grid 'temperature'"), std::string::npos) << r.out;
    // One table row per frame, numbered 1..12 as in the file names.
    int rows = 0;
    for (const std::string& line : lines(r.out)) {
        std::istringstream in(line);
        int frame = 0;
        if (in >> frame && frame == rows + 1) ++rows;
    }
    EXPECT_EQ(rows, 12) << r.out;
}

TEST(Cli, InfoJsonIsValid) {
    TempDir dir;
    const CommandResult r = runFirelook(dir, "info --json '" + kSample + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json j = json::parse(r.out, nullptr, false);
    ASSERT_FALSE(j.is_discarded()) << r.out;
    EXPECT_EQ(j.at("kind"), "vdb-sequence");
    EXPECT_EQ(j.at("frame_count"), 12);
    ASSERT_EQ(j.at("frames").size(), 12u);
    EXPECT_EQ(j.at("frames")[0].at("frame"), 1);
    EXPECT_EQ(j.at("frames")[11].at("frame"), 12);
    EXPECT_EQ(j.at("density_grid"), "density");
    EXPECT_EQ(j.at("temperature_grid"), "temperature");
    const std::vector<std::string> grids = j.at("frames")[0].at("grids");
    EXPECT_NE(std::find(grids.begin(), grids.end(), "density"), grids.end());
    // Blender's voxel size for this sample.
    EXPECT_NEAR(j.at("frames")[0].at("voxel_size").get<double>(), 0.025, 1e-6);
}

TEST(Cli, BakeInfoRender) {
    TempDir dir;
    bakeTiny(dir);
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"bake.json", "pkg.firelook"})) << "nothing else left";

    CommandResult r = runFirelook(dir, "info pkg.firelook");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("image 16x16"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("frames (frame:rank): 1:"), std::string::npos) << r.out;

    r = runFirelook(dir, "info --json pkg.firelook");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json info = json::parse(r.out);
    const json& bake = info.at("metadata").at("bake");
    ASSERT_EQ(bake.at("frames").size(), 1u);
    EXPECT_EQ(bake.at("frames")[0].at("frame"), 1);
    EXPECT_GT(bake.at("frames")[0].at("rank").get<int>(), 0);
    EXPECT_EQ(bake.at("width"), 16);
    EXPECT_TRUE(bake.at("default_look").is_object());
    EXPECT_TRUE(info.at("metadata").contains("camera"));

    r = runFirelook(dir, "render pkg.firelook --frame 1 --out a.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const firelook::image::ImageRGBA image = firelook::image::readImage(dir / "a.exr");
    ASSERT_EQ(image.width, 16);
    ASSERT_EQ(image.height, 16);
    double alpha_sum = 0.0, rgb_sum = 0.0;
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        ASSERT_TRUE(std::isfinite(image.pixels[i])) << i;
        ASSERT_GE(image.pixels[i], 0.0f) << i;
        (i % 4 == 3 ? alpha_sum : rgb_sum) += image.pixels[i];
    }
    EXPECT_GT(alpha_sum, 0.0) << "the fire is in view";
    EXPECT_GT(rgb_sum, 0.0) << "and glows";

    r = runFirelook(dir, "render pkg.firelook --frame 1 --out a.png");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(firelook::image::readImage(dir / "a.png").width, 16);

    r = runFirelook(dir, "render pkg.firelook --frame 2 --out b.exr");
    expectOneLineError(r, "frame 2");
    EXPECT_FALSE(std::filesystem::exists(dir / "b.exr"));
}

// repack stores the frames again at the precision asked for (recorded in the metadata), info
// sums the stored bytes by kind and per frame, and the repacked package renders within the bound
// the codec reports; a coarser alpha error gives a package no larger.
TEST(Cli, RepackAndBytesPerFrame) {
    TempDir dir;
    bakeTiny(dir);
    CommandResult r = runFirelook(dir, "repack pkg.firelook -o coarse.firelook --alpha-error 0.004 --footprint-error 0.004");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    r = runFirelook(dir, "info --json coarse.firelook");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json coarse = json::parse(r.out);
    const json& repacked = coarse.at("metadata").at("repacked");
    EXPECT_EQ(repacked.at("from_layout"), 2);
    EXPECT_EQ(repacked.at("alpha_error"), 0.004);
    EXPECT_DOUBLE_EQ(repacked.at("frames")[0].at("alpha_storage_error_bound").get<double>(), 0.008);
    EXPECT_EQ(coarse.at("metadata").at("version"), 2);
    r = runFirelook(dir, "info --json pkg.firelook");
    const json fine = json::parse(r.out);
    ASSERT_EQ(fine.at("bytes_by_frame").size(), 1u);
    uint64_t sections = 0;
    for (const json& s : fine.at("sections"))
        if (!s.at("frame").is_null()) sections += s.at("stored_bytes").get<uint64_t>();
    EXPECT_EQ(fine.at("bytes_by_frame")[0].at("stored_bytes").get<uint64_t>(), sections);
    EXPECT_EQ(fine.at("bytes_by_kind").at("ODEP").get<uint64_t>() + fine.at("bytes_by_kind").at("UFAC").get<uint64_t>() +
                  fine.at("bytes_by_kind").at("SVTF").get<uint64_t>(),
              sections);
    EXPECT_LE(coarse.at("bytes_by_kind").at("ODEP").get<uint64_t>(), fine.at("bytes_by_kind").at("ODEP").get<uint64_t>());
    r = runFirelook(dir, "info pkg.firelook");
    EXPECT_NE(r.out.find("stored bytes per frame: mean"), std::string::npos) << r.out;

    ASSERT_EQ(runFirelook(dir, "render pkg.firelook --frame 1 --out a.exr").exit_code, 0);
    ASSERT_EQ(runFirelook(dir, "render coarse.firelook --frame 1 --out b.exr").exit_code, 0);
    const firelook::image::ImageRGBA a = firelook::image::readImage(dir / "a.exr");
    const firelook::image::ImageRGBA b = firelook::image::readImage(dir / "b.exr");
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    double worst = 0.0;
    for (size_t i = 3; i < a.pixels.size(); i += 4) worst = std::max(worst, double(std::abs(a.pixels[i] - b.pixels[i])));
    // Both stored from the same rays: the second quantisation adds at most its own bound (0.008),
    // plus the first package's (0.002) against which it was taken, and half-float rounding in EXR.
    EXPECT_LE(worst, 0.008 + 0.002 + 1e-3);

    r = runFirelook(dir, "repack missing.firelook -o x.firelook");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_FALSE(std::filesystem::exists(dir / "x.firelook"));
}

// repack --target-error / --target-size: what was chosen is recorded per frame; a target error
// below what the package already holds is said on stderr (repack cannot restore precision).
TEST(Cli, RepackToATarget) {
    TempDir dir;
    bakeTiny(dir);
    CommandResult r = runFirelook(dir, "repack pkg.firelook -o e.firelook --target-error 0.05");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    r = runFirelook(dir, "info --json e.firelook");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json repacked = json::parse(r.out).at("metadata").at("repacked");
    EXPECT_EQ(repacked.at("target_error"), 0.05);
    EXPECT_TRUE(repacked.at("frames")[0].at("met").get<bool>());
    EXPECT_LE(repacked.at("frames")[0].at("predicted_error").get<double>(), 0.05);
    // The frame's stored bytes, not the file's: the repacked package's metadata grows by the repack
    // record, which on this 16x16 frame is as large as what the looser target saves.
    const auto frameBytes = [&](const char* package) {
        const CommandResult info = runFirelook(dir, std::string("info --json ") + package);
        return json::parse(info.out).at("bytes_by_frame")[0].at("stored_bytes").get<uint64_t>();
    };
    EXPECT_LE(frameBytes("e.firelook"), frameBytes("pkg.firelook"));

    r = runFirelook(dir, "repack pkg.firelook -o t.firelook --target-error 0.00001");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("--target-error is below what the package holds"), std::string::npos) << r.err;

    const uint64_t half = std::filesystem::file_size(dir / "pkg.firelook") * 3 / 4 + 16384;
    r = runFirelook(dir, "repack pkg.firelook -o s.firelook --target-size " + std::to_string(half));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_LE(std::filesystem::file_size(dir / "s.firelook"), half);

    r = runFirelook(dir, "repack pkg.firelook -o x.firelook --target-size 1M --target-error 0.01");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_FALSE(std::filesystem::exists(dir / "x.firelook"));
}

TEST(Cli, RenderWithAnotherAlbedoFails) {
    TempDir dir;
    bakeTiny(dir);
    const CommandResult info = runFirelook(dir, "info --json pkg.firelook");
    ASSERT_EQ(info.exit_code, 0) << info.err;
    json look = json::parse(info.out).at("metadata").at("bake").at("default_look");
    look["albedo"] = look.at("albedo").get<double>() > 0.5 ? 0.2 : 0.9;
    std::ofstream(dir / "look.json") << look.dump();
    const CommandResult r = runFirelook(dir, "render pkg.firelook --frame 1 --look look.json --out a.exr");
    expectOneLineError(r, "albedo");
    EXPECT_FALSE(std::filesystem::exists(dir / "a.exr"));

    // The same look with the baked albedo renders.
    look["albedo"] = json::parse(info.out).at("metadata").at("bake").at("albedo");
    std::ofstream(dir / "look.json") << look.dump();
    EXPECT_EQ(runFirelook(dir, "render pkg.firelook --frame 1 --look look.json --out a.exr").exit_code, 0);
}

TEST(Cli, TruncatedPackageIsRefusedByName) {
    TempDir dir;
    bakeTiny(dir);
    const std::string bytes = readFile(dir / "pkg.firelook");
    std::ofstream(dir / "cut.firelook", std::ios::binary)
        .write(bytes.data(), std::streamsize(bytes.size() / 2));
    CommandResult r = runFirelook(dir, "info cut.firelook");
    expectOneLineError(r, "cut.firelook");
    r = runFirelook(dir, "render cut.firelook --frame 1 --out a.exr");
    expectOneLineError(r, "cut.firelook");
    EXPECT_FALSE(std::filesystem::exists(dir / "a.exr"));
}

// info reads a package's header, index and metadata; info --check also verifies every section's
// checksum and decodes every frame (docs/cli.md). A byte flipped inside any frame section passes info
// and fails --check with one line naming the file and the section; metadata that is not JSON fails
// info itself.
TEST(Cli, InfoCheckFindsEveryDamagedSection) {
    TempDir dir;
    bakeTiny(dir);
    CommandResult r = runFirelook(dir, "info --check pkg.firelook");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("frames decode"), std::string::npos) << r.err;
    const std::string good = readFile(dir / "pkg.firelook");
    // The index (format.h): at the header's index_offset (offset 24), 64-byte entries with the
    // section's frame at +4, offset at +16 and stored size at +24.
    const auto u32 = [&](size_t at) { uint32_t v; std::memcpy(&v, good.data() + at, 4); return v; };
    const auto u64 = [&](size_t at) { uint64_t v; std::memcpy(&v, good.data() + at, 8); return v; };
    const uint64_t index = u64(24);
    const uint32_t sections = u32(20);
    int flipped = 0;
    for (uint32_t i = 0; i < sections; ++i) {
        const size_t entry = index + 64 * size_t{i};
        if (u32(entry + 4) == 0xFFFFFFFFu || u64(entry + 24) == 0) continue;  // not a frame's, or empty
        const uint64_t offset = u64(entry + 16), size = u64(entry + 24);
        for (const uint64_t at : {offset, offset + size / 2, offset + size - 1}) {
            std::string bad = good;
            bad[at] = static_cast<char>(bad[at] ^ 0x10);
            std::ofstream(dir / "bad.firelook", std::ios::binary).write(bad.data(), std::streamsize(bad.size()));
            EXPECT_EQ(runFirelook(dir, "info bad.firelook").exit_code, 0) << "info does not read frame data";
            r = runFirelook(dir, "info --check bad.firelook");
            expectOneLineError(r, "bad.firelook");
            EXPECT_NE(r.err.find("checksum"), std::string::npos) << r.err;
            ++flipped;
        }
    }
    EXPECT_GE(flipped, 6) << "the tiny package has frame sections to damage";
    r = runFirelook(dir, "info --check '" + kSample + "'");
    expectOneLineError(r, "--check takes a package");
    // Metadata that is not JSON, with valid checksums (written by the container writer itself).
    {
        firelook::package::ContainerWriter writer(dir / "meta.firelook");
        writer.addMetadata("{\"format\": \"firelook\", truncated");
        writer.commit();
    }
    r = runFirelook(dir, "info meta.firelook");
    expectOneLineError(r, "meta.firelook: the metadata section (META) is not valid JSON");
}

// Shards baked as separate commands, with different thread counts, merge into the one-shot bake's
// bytes; an overlapping shard is one error line naming the frame, and nothing is written.
TEST(Cli, MergedShardsEqualTheOneShotBake) {
    TempDir dir;
    writeTinyConfig(dir);
    const std::string bake = "bake '" + kSample + "' --size 16x16 --up z --config bake.json";
    ASSERT_EQ(runFirelook(dir, bake + " --frames 1-3 -o one.firelook").exit_code, 0);
    ASSERT_EQ(runFirelook(dir, bake + " --frames 1 --threads 1 -o a.firelook").exit_code, 0);
    ASSERT_EQ(runFirelook(dir, bake + " --frames 2-3 --threads 2 -o b.firelook").exit_code, 0);
    CommandResult r = runFirelook(dir, "merge b.firelook a.firelook -o merged.firelook");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("wrote merged.firelook: 3 frames (1-3)"), std::string::npos) << r.out;
    EXPECT_TRUE(readFile(dir / "merged.firelook") == readFile(dir / "one.firelook"));
    r = runFirelook(dir, "merge a.firelook one.firelook -o twice.firelook");
    expectOneLineError(r, "frame 1 is also in a.firelook");
    EXPECT_FALSE(std::filesystem::exists(dir / "twice.firelook"));
    // The reverse: frames 2-3 split out of the one-shot package are the shard baked alone.
    r = runFirelook(dir, "split one.firelook --frames 2-3 -o part.firelook");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(readFile(dir / "part.firelook") == readFile(dir / "b.firelook"));
    r = runFirelook(dir, "split one.firelook --frames 7-9 -o none.firelook");
    expectOneLineError(r, "no frame of the parts");
    EXPECT_FALSE(std::filesystem::exists(dir / "none.firelook"));
}

// info --json lists each frame's input file with its XXH3-64 (the hash `xxhsum -H3` prints) and the
// settings' hash: the same for shards of one bake, another for other settings.
// A density read 4x denser (bake.json "density_scale") scales the extinctions by 1/4
// (bake/axis_derivation.h); info says so, and which axes were derived rather than given.
TEST(Cli, InfoShowsTheAxisDerivation) {
    TempDir dir;
    json config = json::parse(firelook::testing::kTinyBakeConfig);
    config["density_scale"] = 4.0;
    config["axes"].erase("smoke_extinction");
    std::ofstream(dir / "bake.json") << config.dump();
    ASSERT_EQ(runFirelook(dir, "bake '" + kSample + "' --size 16x16 --up z --frames 6 --config bake.json -o d.firelook")
                  .exit_code,
              0);
    const CommandResult r = runFirelook(dir, "info d.firelook");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("look axes from the data: temperatures x1 +0, extinctions x0.25; derived: smoke_extinction "),
              std::string::npos)
        << r.out;
}

TEST(Cli, InfoShowsWhatEachFrameWasBakedFrom) {
    TempDir dir;
    writeTinyConfig(dir);
    const std::string bake = "bake '" + kSample + "' --size 16x16 --up z --config bake.json --fire-lights";
    ASSERT_EQ(runFirelook(dir, bake + " --frames 1-2 -o a.firelook").exit_code, 0);
    ASSERT_EQ(runFirelook(dir, bake + " --frames 3 -o b.firelook").exit_code, 0);
    ASSERT_EQ(runFirelook(dir, bake + " --frames 3 --seed 7 -o c.firelook").exit_code, 0);
    const auto inputs = [&](const char* package) {
        const CommandResult r = runFirelook(dir, std::string("info --json ") + package);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return json::parse(r.out).at("inputs");
    };
    const json a = inputs("a.firelook"), b = inputs("b.firelook"), c = inputs("c.firelook");
    ASSERT_EQ(a.size(), 2u);
    EXPECT_EQ(a[1].at("frame"), 2);
    EXPECT_EQ(a[1].at("file"), "fluid_data_0002.vdb");
    const std::string data = readFile(std::filesystem::path(kSample) / "fluid_data_0002.vdb");
    char hash[17];
    std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(XXH3_64bits(data.data(), data.size())));
    EXPECT_EQ(a[1].at("xxh3_64"), hash);
    EXPECT_EQ(a[0].at("settings_xxh3_64"), b[0].at("settings_xxh3_64")) << "shards of one bake";
    EXPECT_NE(b[0].at("settings_xxh3_64"), c[0].at("settings_xxh3_64")) << "another seed";
    EXPECT_EQ(b[0].at("xxh3_64"), c[0].at("xxh3_64"));
    // The fire's point lights (docs/cli.md): per frame, for the default look, each with a finite
    // position, a non-negative intensity and radius.
    const json lights = json::parse(runFirelook(dir, "info --json a.firelook").out).at("fire_lights");
    EXPECT_EQ(lights.at("stored_per_frame"), 8);
    ASSERT_EQ(lights.at("frames").size(), 2u);
    EXPECT_EQ(lights.at("frames")[1].at("frame"), 2);
    ASSERT_EQ(lights.at("frames")[1].at("lights").size(), 8u);
    double total = 0.0;
    for (const json& l : lights.at("frames")[1].at("lights")) {
        ASSERT_EQ(l.at("position").size(), 3u);
        for (const json& c : l.at("intensity")) total += c.get<double>();
        EXPECT_GE(l.at("radius").get<double>(), 0.0);
    }
    EXPECT_GT(total, 0.0);
}

TEST(Cli, FireProbesAreBakedListedKeptByRepackAndRangeChecked) {
    TempDir dir;
    writeTinyConfig(dir);
    const std::string bake = "bake '" + kSample + "' --size 16x16 --up z --config bake.json --frames 3";
    ASSERT_EQ(runFirelook(dir, bake + " --fire-probes 3 -o p.firelook").exit_code, 0);
    // docs/cli.md: per frame, for the default look, the grid's placement and 9 RGB values a probe.
    const json probes = json::parse(runFirelook(dir, "info --json p.firelook").out).at("fire_probes");
    EXPECT_EQ(probes.at("look"), "default");
    ASSERT_EQ(probes.at("frames").size(), 1u);
    const json& frame = probes.at("frames")[0];
    EXPECT_EQ(frame.at("frame"), 3);
    EXPECT_EQ(frame.at("counts"), json::array({3, 3, 3}));
    for (const char* key : {"origin", "spacing", "falloff_centre"})
        EXPECT_EQ(frame.at(key).size(), 3u) << key;
    EXPECT_GT(frame.at("falloff_radius").get<double>(), 0.0);
    ASSERT_EQ(frame.at("probes").size(), 27u);
    double l00 = 0.0;
    for (const json& probe : frame.at("probes")) {
        ASSERT_EQ(probe.size(), 9u);
        for (const json& c : probe[0]) l00 += c.get<double>();
    }
    EXPECT_GT(l00, 0.0);  // the fluence is sqrt(4 pi) L00: the fire's light arrives somewhere
    const CommandResult text = runFirelook(dir, "info p.firelook");
    EXPECT_NE(text.out.find("fire probes: 3x3x3 per frame in 1 frames"), std::string::npos) << text.out;
    // A repack keeps them as stored; a bake without them has none, and a grid of 1 or 17 is refused.
    ASSERT_EQ(runFirelook(dir, "repack p.firelook --basis-error 0.001 -o r.firelook").exit_code, 0);
    EXPECT_EQ(json::parse(runFirelook(dir, "info --json r.firelook").out).at("fire_probes"), probes);
    ASSERT_EQ(runFirelook(dir, bake + " -o n.firelook").exit_code, 0);
    EXPECT_FALSE(json::parse(runFirelook(dir, "info --json n.firelook").out).contains("fire_probes"));
    for (const char* n : {"1", "17"}) {
        const CommandResult r = runFirelook(dir, bake + " --fire-probes " + n + " -o x.firelook");
        EXPECT_NE(r.exit_code, 0) << n;
        EXPECT_NE(r.err.find("--fire-probes"), std::string::npos) << r.err;
    }
}

TEST(Cli, BakeIntoMissingFolderLeavesNothing) {
    TempDir dir;
    writeTinyConfig(dir);
    const CommandResult r =
        runFirelook(dir, "bake '" + kSample +
                             "' -o missing/pkg.firelook --frames 1 --size 16x16 --up z --config bake.json");
    expectOneLineError(r, "missing");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"bake.json"});
}

TEST(Cli, BadArgumentsFail) {
    TempDir dir;
    writeTinyConfig(dir);
    for (const char* size : {"16", "0x16", "99999x16"}) {
        const CommandResult r = runFirelook(
            dir, "bake '" + kSample + "' -o pkg.firelook --frames 1 --size " + size + " --config bake.json");
        EXPECT_NE(r.exit_code, 0) << "--size " << size;
        EXPECT_NE(r.err.find("size"), std::string::npos) << "--size " << size << ": " << r.err;
    }
    CommandResult r = runFirelook(
        dir, "bake '" + kSample + "' -o pkg.firelook --frames 40-50 --size 16x16 --config bake.json");
    expectOneLineError(r, "40-50");
    r = runFirelook(dir, "info no-such-thing");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("no-such-thing"), std::string::npos) << r.err;
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"bake.json"});
}

// bake --quality (docs/bake-config.md, "quality"): one line says what the preset chose for the image
// size, the file's trace keys change single settings of it, the settings record it, the report
// and the table give the look error the bake predicts, and bench sets the looks it measures beside
// it. Anything but the three presets is refused before anything is written.
TEST(Cli, BakeQualityPresetIsPrintedRecordedAndPredicted) {
    TempDir dir;
    writeTinyConfig(dir);
    CommandResult r = runFirelook(dir, "bake '" + kSample +
                                           "' -o pkg.firelook --frames 1 --size 16x16 --up z --config bake.json "
                                           "--quality preview --report report.json");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.err.find("trace (preview quality): 8x8 footprint rays a pixel for alpha, 2x2 of them for radiance; "
                         "march step 0.25 voxel (toward the lights 0.25 of their lattice's spacing), or up to 16 "
                         "times it, chosen per frame: the radiance rays' where that moves radiance by at most 0.075% "
                         "and its mean by 0.05%, alpha's rays' where it moves alpha by at most 0.001, the lights' "
                         "where it moves the lit source by at most 0.075% and its mean by 0.05%"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.out.find("look err %"), std::string::npos) << r.out;
    const json frame = json::parse(readFile(dir / "report.json")).at("frames")[0];
    const double predicted = frame.at("predicted_look_error").get<double>();
    EXPECT_GT(frame.at("radiance_quadrature_error").get<double>(), 0.0) << "2x2 of 8x8 rays: measured";
    EXPECT_EQ(frame.at("radiance_rays_per_axis").get<int>(), 2);
    EXPECT_EQ(frame.at("footprint_rays_per_axis").get<int>(), 8);
    // Every n x n at 2, 4, 8 and 16 times the step, then preview's given m at the step taken,
    // measured. At this size the frame covers fewer checked pixels than kMinStepCheckPixels, so
    // both the radiance rays and alpha's keep the step (and the light, whose check points are too
    // few as well).
    const json candidates = frame.at("radiance_candidates");
    ASSERT_EQ(candidates.size(), 5u) << candidates;
    EXPECT_EQ(candidates[0].at("rays_per_axis").get<int>(), 8);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(candidates[k].at("step_scale").get<int>(), 2 << k);
    EXPECT_EQ(candidates[4].at("rays_per_axis").get<int>(), 2);
    EXPECT_EQ(candidates[4].at("step_scale").get<int>(), 1);
    EXPECT_EQ(frame.at("camera_step_voxels").get<double>(), 0.25);
    EXPECT_EQ(frame.at("depth_step_voxels").get<double>(), 0.25);
    EXPECT_EQ(candidates[4].at("quadrature_error").get<double>(),
              frame.at("radiance_quadrature_error").get<double>());
    const json light_steps = frame.at("light_steps");
    ASSERT_EQ(light_steps.size(), 1u) << "the key light";
    EXPECT_EQ(light_steps[0].at("source_error").get<double>(), 0.0);
    EXPECT_EQ(light_steps[0].at("candidates").size(), 4u) << light_steps;
    EXPECT_NE(r.out.find(" 2/8 "), std::string::npos) << "the table's rays column\n" << r.out;
    EXPECT_NEAR(predicted,
                std::sqrt(std::pow(frame.at("svd_truncation_relative_error").get<double>(), 2) +
                          std::pow(frame.at("storage_relative_error").get<double>(), 2) +
                          std::pow(frame.at("predicted_photon_noise").get<double>(), 2) +
                          std::pow(frame.at("radiance_quadrature_error").get<double>(), 2) +
                          std::pow(light_steps[0].at("source_error").get<double>(), 2)),
                1e-12);

    r = runFirelook(dir, "info pkg.firelook --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json settings = json::parse(r.out).at("metadata").at("provenance").at("settings");
    EXPECT_EQ(settings.at("quality"), "preview");
    EXPECT_EQ(settings.at("trace").at("step_voxels"), 0.25) << "the preset's";
    EXPECT_EQ(settings.at("trace").at("photons_primary"), 2000) << "the file's key over the preset";
    EXPECT_EQ(settings.at("trace").at("max_step_scale"), 16) << "the preset's";
    const json errors = json::parse(r.out).at("metadata").at("errors")[0];
    EXPECT_EQ(errors.at("camera_step_voxels"), 0.25) << "the steps taken, recorded";
    EXPECT_EQ(errors.at("depth_step_voxels"), 0.25);
    ASSERT_EQ(errors.at("light_steps").size(), 1u);
    EXPECT_EQ(errors.at("light_steps")[0].at("step_voxels"), light_steps[0].at("step_voxels"));
    EXPECT_FALSE(errors.at("light_steps")[0].contains("candidates")) << "--report only";

    r = runFirelook(dir, "bench '" + kSample +
                             "' --package pkg.firelook --frames 1 --looks 1 --spp 8 --alpha-rays 2 --json bench.json");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const json summary = json::parse(readFile(dir / "bench.json")).at("summary");
    EXPECT_EQ(summary.at("predicted_look_error").get<double>(), predicted);
    EXPECT_EQ(summary.at("within_predicted_look_error").get<bool>(),
              summary.at("worst_noise_corrected_rmse").get<double>() <= predicted);

    r = runFirelook(dir, "bake '" + kSample + "' -o other.firelook --frames 1 --size 16x16 --quality fast");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("quality"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "other.firelook"));
}

// Regression: parseSize once accepted "16x16x16", "16x16abc" and "16.5x16" as 16x16 (std::stoi
// stops at the first non-digit); each number must now use its whole part.
TEST(Cli, SizeWithTrailingGarbageFails) {
    TempDir dir;
    writeTinyConfig(dir);
    for (const char* size : {"16x16x16", "16x16abc", "16.5x16"}) {
        const CommandResult r = runFirelook(
            dir, "bake '" + kSample + "' -o pkg.firelook --frames 1 --size " + size + " --config bake.json");
        EXPECT_NE(r.exit_code, 0) << "--size " << size;
        std::filesystem::remove(dir / "pkg.firelook");
    }
}

// The speed-vs-error sweep's plumbing: `bake --report` records what the bake measured, `bench --csv`
// appends one row per run, and `--reference-cache` makes a second run reuse the path-traced
// references, giving the same figures (the package's error does not depend on the cache).
TEST(Cli, BakeReportAndBenchCsvWithReferenceCache) {
    TempDir dir;
    writeTinyConfig(dir);
    CommandResult r = runFirelook(
        dir,
        "bake '" + kSample +
            "' -o pkg.firelook --frames 1 --size 16x16 --up z --config bake.json --report bake.json.report");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const json report = json::parse(readFile(dir / "bake.json.report"));
    EXPECT_GT(report.at("seconds").get<double>(), 0.0);
    EXPECT_GT(report.at("peak_memory_mib").get<double>(), 0.0);
    EXPECT_EQ(report.at("package_bytes").get<uint64_t>(), std::filesystem::file_size(dir / "pkg.firelook"));
    ASSERT_EQ(report.at("frames").size(), 1u);
    EXPECT_GT(report.at("frames")[0].at("rank").get<int>(), 0);

    const std::string bench = "bench '" + kSample +
                              "' --package pkg.firelook --frames 1 --looks 2 --spp 8 --alpha-rays 2 "
                              "--reference-cache refs --csv sweep.csv --bake-report bake.json.report ";
    r = runFirelook(dir, bench + "--label first --json first.json");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    ASSERT_TRUE(std::filesystem::is_directory(dir / "refs"));
    size_t cached = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir / "refs")) {
        EXPECT_EQ(entry.path().extension(), ".bin") << "no temporary left: " << entry.path();
        ++cached;
    }
    EXPECT_EQ(cached, 4u) << "one reference and one exact alpha per look";
    r = runFirelook(dir, bench + "--label second --json second.json");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;

    const json first = json::parse(readFile(dir / "first.json")).at("summary");
    const json second = json::parse(readFile(dir / "second.json")).at("summary");
    for (const char* key : {"median_relative_rmse", "worst_relative_rmse", "median_reference_noise", "max_alpha_error"})
        EXPECT_EQ(first.at(key), second.at(key)) << key;
    EXPECT_EQ(first.at("bake_seconds"), report.at("seconds"));

    const std::vector<std::string> rows = lines(readFile(dir / "sweep.csv"));
    ASSERT_EQ(rows.size(), 3u) << "header and two rows";
    EXPECT_EQ(rows[0].rfind("label,looks,median_relative_rmse,", 0), 0u) << rows[0];
    EXPECT_EQ(rows[1].rfind("first,2,", 0), 0u) << rows[1];
    EXPECT_EQ(rows[2].rfind("second,2,", 0), 0u) << rows[2];
    const auto columns = [](const std::string& row) { return std::count(row.begin(), row.end(), ',') + 1; };
    EXPECT_EQ(columns(rows[1]), columns(rows[0]));
    EXPECT_EQ(columns(rows[2]), columns(rows[0]));
}

}  // namespace

// An axis that cannot change any frame: the bake says so in one line, records it in the report and
// the package, info shows it; --keep-axes bakes every sample without a word.
TEST(Cli, BakeCollapsesAnAxisThatCannotChangeAFrame) {
    TempDir dir;
    // The sample's temperatures scaled below 0.58 against T_c samples 1 and 2 (16 bins of 0.036).
    std::ofstream(dir / "bake.json") << R"({"bins": 16, "t_lo": 0, "t_hi": 0.58, "temperature_scale": 0.1933,
        "axes": {"temperature_threshold": [1.0, 2.0], "smoke_extinction": 4, "flame_extinction": 1.5},
        "trace": {"photons_primary": 2000, "photons_per_order": 1000, "photon_noise_target": 0, "max_orders": 3, "cell_voxels": 8}})";
    const std::string bake = "bake '" + kSample + "' --frames 1 --size 16x16 --up z --config bake.json";
    CommandResult r = runFirelook(dir, bake + " -o pkg.firelook --report r.json");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    int said = 0;
    for (const std::string& line : lines(r.err))
        if (line.find("temperature_threshold axis collapsed to its lowest sample 1 (of 2, 1..2)") != std::string::npos)
            ++said;
    EXPECT_EQ(said, 1) << r.err;
    const json report = json::parse(readFile(dir / "r.json"));
    ASSERT_EQ(report.at("axis_collapse").at("collapsed").size(), 1u);
    EXPECT_EQ(report.at("axis_collapse").at("collapsed")[0].at("axis"), "temperature_threshold");
    EXPECT_LE(report.at("axis_collapse").at("temperature_with_density")[1].get<double>(), 0.58);
    EXPECT_EQ(report.at("frames")[0].at("columns_traced"), 17);
    r = runFirelook(dir, "info pkg.firelook");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("temperature_threshold  [1.0]  (collapsed from 2 samples 1..2"), std::string::npos) << r.out;
    r = runFirelook(dir, "render pkg.firelook --frame 1 --out a.exr");
    EXPECT_EQ(r.exit_code, 0) << r.err;

    r = runFirelook(dir, bake + " --keep-axes -o full.firelook --report full.json");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_EQ(r.err.find("collapsed"), std::string::npos) << r.err;
    const json full = json::parse(readFile(dir / "full.json"));
    EXPECT_TRUE(full.at("axis_collapse").is_null());
    EXPECT_EQ(full.at("frames")[0].at("columns_traced"), 2 * 17);
}
