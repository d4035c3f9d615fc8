// `firelook export-cycles` (docs/cli.md): the script it writes holds the package's camera, the
// lights the look turns on, the bins, the look's extinction, albedo and non-negative emission fit,
// and the frame's VDB file from the sequence named. Rendering it in Blender is
// tests/blender/cycles_round_trip_test.cpp; these checks need no Blender.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../support/command.h"
#include "../support/sample.h"
#include "../support/temp_dir.h"
#include "../support/tiny_bake_config.h"

namespace {

using namespace firelook::testing;
using nlohmann::json;

// The SCENE document of a written script: the JSON between json.loads(r''' and ''').
json sceneOf(const std::filesystem::path& script) {
    const std::string text = readFile(script);
    const std::string open = "json.loads(r'''";
    const size_t begin = text.find(open);
    const size_t end = text.find("''')", begin);
    if (begin == std::string::npos || end == std::string::npos) return json();
    return json::parse(text.substr(begin + open.size(), end - begin - open.size()));
}

class ExportCycles : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = new TempDir;
        std::ofstream(*dir_ / "bake.json") << kTinyBakeConfig;
        const CommandResult r = runFirelook(
            *dir_, "bake '" + kSample + "' -o pkg.firelook --frames 1,2 --size 16x12 --up z --config bake.json");
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    static void TearDownTestSuite() { delete dir_; }
    static TempDir* dir_;
};
TempDir* ExportCycles::dir_ = nullptr;

TEST_F(ExportCycles, ScriptHoldsThePackagesSceneAndTheLook) {
    std::ofstream(*dir_ / "look.json") << R"({"format": "firelook-look", "version": 1, "temperature_threshold": 1.6,
        "smoke_extinction": 5, "flame_extinction": 2, "albedo": 0.7,
        "emission": {"bins": [[0,0,0], [0,0,0], [1,0.5,0.1], [4,2,1]]}, "light_irradiance": [[1, 2, 3]]})";
    const CommandResult r = runFirelook(
        *dir_, "export-cycles pkg.firelook --frame 2 --sequence '" + kSample + "' --look look.json -o scene.py");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json scene = sceneOf(*dir_ / "scene.py");
    ASSERT_TRUE(scene.is_object()) << readFile(*dir_ / "scene.py").substr(0, 400);
    const json info = json::parse(runFirelook(*dir_, "info --json pkg.firelook").out).at("metadata");

    EXPECT_EQ(scene.at("frame"), 2);
    EXPECT_EQ(std::filesystem::path(scene.at("vdb").get<std::string>()),
              std::filesystem::absolute(std::filesystem::path(kSample) / "fluid_data_0002.vdb"));
    EXPECT_EQ(scene.at("read").at("density_grid"), "density");
    EXPECT_EQ(scene.at("read").at("temperature_grid"), "temperature");
    EXPECT_EQ(scene.at("camera").at("world_from_camera"), info.at("camera").at("world_from_camera"));
    EXPECT_EQ(scene.at("camera").at("width"), 16);
    EXPECT_EQ(scene.at("camera").at("height"), 12);
    EXPECT_EQ(scene.at("bins").at("count"), 4);  // the tiny bake's
    EXPECT_EQ(scene.at("emission_clamp"), "bin_centres");
    EXPECT_EQ(scene.at("look").at("temperature_threshold"), 1.6);
    EXPECT_EQ(scene.at("look").at("smoke_extinction"), 5.0);
    // One coefficient per bin, none negative; the cold bins' zero emissivity gives zero coefficients
    // only where the fit is non-negative (it is here: the emissivity rises).
    ASSERT_EQ(scene.at("emission_coefficients").size(), 4u);
    for (const json& c : scene.at("emission_coefficients"))
        for (const json& v : c) EXPECT_GE(v.get<double>(), 0.0);
    ASSERT_EQ(scene.at("lights").size(), 1u);
    EXPECT_EQ(scene.at("lights")[0].at("direction"), info.at("bake").at("light_directions")[0]);
    EXPECT_EQ(scene.at("lights")[0].at("irradiance"), json({1.0, 2.0, 3.0}));
    EXPECT_NE(readFile(*dir_ / "scene.py").find("def main()"), std::string::npos) << "the script's body";
}

TEST_F(ExportCycles, LightsTheLookTurnsOffAreLeftOut) {
    std::ofstream(*dir_ / "dark.json") << R"({"format": "firelook-look", "version": 1, "temperature_threshold": 1.6,
        "smoke_extinction": 5, "flame_extinction": 2, "albedo": 0.7,
        "emission": {"preset": "blackbody"}, "light_irradiance": [[0, 0, 0]]})";
    const CommandResult r = runFirelook(*dir_, "export-cycles pkg.firelook --frame 1 --sequence '" + kSample +
                                                   "' --look dark.json -o dark.py");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(sceneOf(*dir_ / "dark.py").at("lights").empty());
}

TEST_F(ExportCycles, SequenceOptionFindsTheFrameElsewhere) {
    TempDir moved;
    std::filesystem::copy_file(std::filesystem::path(kSample) / "fluid_data_0001.vdb", moved / "fire_0001.vdb");
    const CommandResult r = runFirelook(*dir_, "export-cycles pkg.firelook --frame 1 --sequence '" +
                                                   moved.path().string() + "' -o moved.py");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(std::filesystem::path(sceneOf(*dir_ / "moved.py").at("vdb").get<std::string>()), moved / "fire_0001.vdb");
}

TEST_F(ExportCycles, RefusesWithOneLineAndWritesNothing) {
    std::ofstream(*dir_ / "albedo.json") << R"({"format": "firelook-look", "version": 1, "temperature_threshold": 1.6,
        "smoke_extinction": 5, "flame_extinction": 2, "albedo": 0.5,
        "emission": {"preset": "blackbody"}, "light_irradiance": [[1, 1, 1]]})";
    const struct {
        std::string args, mentions;
    } cases[] = {
        {"--frame 3 --sequence '" + kSample + "'", "holds no frame 3"},
        {"--frame 1 --sequence '" + kSample + "' --look albedo.json", "albedo"},
        {"--frame 1", "--sequence is required"},
        {"--frame 1 --sequence '" + (std::filesystem::path(kSample) / "fluid_data_0002.vdb").string() + "'",
         "has no frame 1"},
    };
    for (const auto& c : cases) {
        const CommandResult r = runFirelook(*dir_, "export-cycles pkg.firelook " + c.args + " -o refused.py");
        EXPECT_NE(r.exit_code, 0) << c.args;
        ASSERT_EQ(lines(r.err).size(), 1u) << r.err;
        EXPECT_EQ(r.err.rfind("firelook: error:", 0), 0u) << r.err;
        EXPECT_NE(r.err.find(c.mentions), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(*dir_ / "refused.py")) << c.args;
    }
}

}  // namespace
