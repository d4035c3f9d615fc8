// `firelook flipbook` end to end (docs/cli.md, "firelook flipbook"): a six-way bake of two frames
// of the bundled sample, its atlases lit the way Unity's six-way shader lights them, compared with
// `firelook render` under the same light; the RLT/BBF packing; refusals; the fire probes beside the
// atlases.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../support/command.h"
#include "../support/temp_dir.h"
#include "../support/tiny_bake_config.h"
#include "image/image_io.h"

namespace {

using namespace firelook::testing;
using firelook::image::ImageRGBA;
using nlohmann::json;

const std::string kSample = FIRELOOK_SAMPLE_DIR;

// Bakes frames 6-7 at 24x24 with the six-way lights, once for the whole suite.
class Flipbook : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = new TempDir;
        json config = json::parse(kTinyBakeConfig);
        config["frames"] = "6-7";
        config["size"] = "24x24";
        config["up"] = "z";
        config["lights"] = "six-way";
        std::ofstream(*dir_ / "bake.json") << config.dump();
        const CommandResult r = runFirelook(*dir_, "bake '" + kSample + "' --config bake.json -o six.firelook");
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    static void TearDownTestSuite() { delete dir_; }
    static TempDir* dir_;
};
TempDir* Flipbook::dir_ = nullptr;

// Unity's six-way lighting of one texel (HDRP SixWayLit EvaluateBSDF and URP SixWayLightBlend,
// without colour absorption, base colour white): the direction towards the light in the sprite's
// local frame (x right, y up, z = -normal, i.e. away from the viewer), squared, weights the
// positive-axis map (right, top, back) where the component is >= 0, else the negative one.
float unitySixWay(const std::array<float, 3>& rtb, const std::array<float, 3>& lbf, const std::array<double, 3>& dir) {
    double t = 0.0;
    for (int a = 0; a < 3; ++a) t += dir[a] * dir[a] * (dir[a] >= 0.0 ? rtb[a] : lbf[a]);
    return static_cast<float>(t);
}

struct Relit {
    std::vector<float> rgba;
    double bound = 0.0;  // the largest error the atlas's storage allows at any value (see below)
};

// The atlases of frame cell `cell` relit by a white light of irradiance `e` from camera-frame
// direction `to_light` (+Z towards the viewer), plus the emission atlas, premultiplied.
Relit relight(const std::filesystem::path& folder, const std::string& ext, int cell, std::array<double, 3> to_light,
              double e) {
    const json sidecar = json::parse(readFile(folder / "flipbook.json"));
    const double ls = sidecar["normalisation"]["lightmap_scale"], es = sidecar["normalisation"]["emission_scale"];
    const ImageRGBA a = firelook::image::readDataImage(folder / ("six_way_a." + ext));
    const ImageRGBA b = firelook::image::readDataImage(folder / ("six_way_b." + ext));
    const ImageRGBA em = firelook::image::readDataImage(folder / ("emission." + ext));
    const int w = sidecar["frame_size"]["width"], h = sidecar["frame_size"]["height"];
    const int columns = sidecar["grid"]["columns"];
    const int x0 = (cell % columns) * w, y0 = (cell / columns) * h;
    const double n = std::sqrt(to_light[0] * to_light[0] + to_light[1] * to_light[1] + to_light[2] * to_light[2]);
    const std::array<double, 3> dir{to_light[0] / n, to_light[1] / n, -to_light[2] / n};  // Unity's local z
    Relit out;
    out.rgba.resize(static_cast<size_t>(w) * h * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const auto pa = a.at(x0 + x, y0 + y), pb = b.at(x0 + x, y0 + y), pe = em.at(x0 + x, y0 + y);
            const float lit = static_cast<float>(e * ls) * unitySixWay({pa[0], pa[1], pa[2]}, {pb[0], pb[1], pb[2]}, dir);
            float* o = &out.rgba[(static_cast<size_t>(y) * w + x) * 4];
            for (int c = 0; c < 3; ++c) o[c] = lit + static_cast<float>(es) * pe[c];
            o[3] = pa[3];
        }
    // 8-bit texels are within half a step (1/510 of the scale) of the value: the lightmaps' weights
    // sum to 1, so the light adds at most e * ls / 510, the emission es / 510. EXR stores halves.
    out.bound = ext == "exr" ? 0.0 : (e * ls + es) / 510.0;
    return out;
}

// The default look with the scene's key light off and the six-way lights at Unity's weights for the
// same direction: what `firelook render` must show for that light.
json lookFor(const json& default_look, std::array<double, 3> to_light, double e) {
    json look = default_look;
    const double n = std::sqrt(to_light[0] * to_light[0] + to_light[1] * to_light[1] + to_light[2] * to_light[2]);
    // right, top, back, left, bottom, front: back is camera -Z.
    const std::array<double, 3> d{to_light[0] / n, to_light[1] / n, -to_light[2] / n};
    json irradiance = json::array({{0, 0, 0}});  // the key light
    for (int side = 0; side < 2; ++side)
        for (int a = 0; a < 3; ++a) {
            const bool positive = side == 0;
            const double w = (d[a] >= 0.0) == positive ? d[a] * d[a] * e : 0.0;
            irradiance.push_back({w, w, w});
        }
    look["light_irradiance"] = irradiance;
    return look;
}

void expectRelitMatchesRender(const TempDir& dir, const std::string& folder, const std::string& ext, int cell,
                              int frame, std::array<double, 3> to_light) {
    const double e = 2.0;
    const json sidecar = json::parse(readFile(dir / folder / "flipbook.json"));
    std::ofstream(dir / "light.json") << lookFor(sidecar["look"], to_light, e).dump();
    const CommandResult r =
        runFirelook(dir, "render six.firelook --frame " + std::to_string(frame) + " --look light.json -o r.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const ImageRGBA rendered = firelook::image::readImage(dir / "r.exr");
    const Relit relit = relight(dir / folder, ext, cell, to_light, e);
    double peak = 0.0;
    for (float v : rendered.pixels) peak = std::max(peak, double(v));
    double worst = 0.0, worst_allowed = 0.0;
    for (size_t i = 0; i < relit.rgba.size(); ++i) {
        // Both sides went through half floats when stored as EXR (relative 2^-11 each): 1e-3 of
        // the value. And each layer's reconstruction is clamped at 0 on its own (recombine.h), so
        // the SVD's small negative ringing, cut once per layer instead of once in the sum, moves
        // dark pixels by up to the truncation target's order: 1e-3 of the image's peak.
        const double allowed = relit.bound + 1e-3 * std::fabs(rendered.pixels[i]) + 1e-3 * peak;
        const double err = std::fabs(relit.rgba[i] - rendered.pixels[i]);
        worst = std::max(worst, err / allowed);
        if (err > allowed) worst_allowed = allowed;
    }
    EXPECT_LE(worst, 1.0) << folder << " frame " << frame << " light (" << to_light[0] << ", " << to_light[1] << ", "
                          << to_light[2] << "): error " << worst << " x the allowed " << worst_allowed;
    EXPECT_GT(peak, 0.0) << "nothing lit";
}

TEST_F(Flipbook, SixWayUnityAtlasesLitAsUnityDoesMatchRender) {
    for (const std::string& format : {std::string("exr"), std::string("png")}) {
        const CommandResult r =
            runFirelook(*dir_, "flipbook six.firelook --layout six-way-unity --grid 2x1 --format " + format + " -o fb_" + format);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const json sidecar = json::parse(readFile(*dir_ / ("fb_" + format) / "flipbook.json"));
        EXPECT_EQ(sidecar["layout"], "six-way-unity");
        EXPECT_EQ(sidecar["frames"], json::array({6, 7}));
        EXPECT_EQ(sidecar["grid"]["columns"], 2);
        EXPECT_EQ(sidecar["atlases"][0]["channels"], json::array({"right", "top", "back", "transparency"}));
        EXPECT_EQ(sidecar["atlases"][1]["channels"], json::array({"left", "bottom", "front", "emission"}));
        if (format == "exr") {
            EXPECT_EQ(sidecar["normalisation"]["lightmap_scale"], 1.0);
        }
        // Each side on its own (exact for a baked direction), then directions between them.
        const std::vector<std::array<double, 3>> directions = {
            {1, 0, 0}, {0, 1, 0}, {0, 0, -1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {1, 1, -1}, {-1, -2, 0.5}};
        for (const auto& d : directions) {
            expectRelitMatchesRender(*dir_, "fb_" + format, format, 0, 6, d);
            expectRelitMatchesRender(*dir_, "fb_" + format, format, 1, 7, d);
        }
    }
}

TEST_F(Flipbook, RltBbfPacksTheSameLightmaps) {
    ASSERT_EQ(runFirelook(*dir_, "flipbook six.firelook --layout six-way-unity -o unity").exit_code, 0);
    const CommandResult r = runFirelook(*dir_, "flipbook six.firelook --layout six-way-rlt-bbf --format tga -o rlt");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_EQ(runFirelook(*dir_, "flipbook six.firelook --layout six-way-unity --format tga -o unity_tga").exit_code, 0);
    const ImageRGBA a = firelook::image::readDataImage(*dir_ / "unity_tga/six_way_a.tga");
    const ImageRGBA b = firelook::image::readDataImage(*dir_ / "unity_tga/six_way_b.tga");
    const ImageRGBA rlt = firelook::image::readDataImage(*dir_ / "rlt/rlt.tga");
    const ImageRGBA bbf = firelook::image::readDataImage(*dir_ / "rlt/bbf.tga");
    ASSERT_EQ(a.width, 48) << "two 24x24 frames side by side (the squarest grid for 2 is 2x1)";
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            // The same 8-bit values moved between channels: equal exactly.
            ASSERT_EQ(rlt.at(x, y)[0], a.at(x, y)[0]);  // right
            ASSERT_EQ(rlt.at(x, y)[1], b.at(x, y)[0]);  // left
            ASSERT_EQ(rlt.at(x, y)[2], a.at(x, y)[1]);  // top
            ASSERT_EQ(rlt.at(x, y)[3], a.at(x, y)[3]);  // transparency
            ASSERT_EQ(bbf.at(x, y)[0], b.at(x, y)[1]);  // bottom
            ASSERT_EQ(bbf.at(x, y)[1], a.at(x, y)[2]);  // back
            ASSERT_EQ(bbf.at(x, y)[2], b.at(x, y)[2]);  // front
            ASSERT_EQ(bbf.at(x, y)[3], b.at(x, y)[3]);  // emission
        }
    // The emission channel is the emission atlas's luminance (Rec. 709), within float rounding.
    const ImageRGBA e = firelook::image::readDataImage(*dir_ / "unity/emission.exr");
    const ImageRGBA be = firelook::image::readDataImage(*dir_ / "unity/six_way_b.exr");
    for (int y = 0; y < e.height; ++y)
        for (int x = 0; x < e.width; ++x) {
            const auto p = e.at(x, y);
            const float luminance = 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
            ASSERT_NEAR(be.at(x, y)[3], luminance, 2e-3 * luminance + 1e-6) << "halves on both sides";
        }
}

TEST_F(Flipbook, RefusesAGridTooSmallAndAPackageWithoutSixWayLights) {
    CommandResult r = runFirelook(*dir_, "flipbook six.firelook --layout six-way-unity --grid 1x1 -o small");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("--grid 1x1"), std::string::npos) << r.err;
    EXPECT_EQ(lines(r.err).size(), 1u) << r.err;
    EXPECT_FALSE(std::filesystem::exists(*dir_ / "small"));
    json config = json::parse(kTinyBakeConfig);
    config["frames"] = "6";
    config["size"] = "8x8";
    config["up"] = "z";
    std::ofstream(*dir_ / "plain.json") << config.dump();
    ASSERT_EQ(runFirelook(*dir_, "bake '" + kSample + "' --config plain.json -o plain.firelook").exit_code, 0);
    r = runFirelook(*dir_, "flipbook plain.firelook --layout six-way-unity -o plain_fb");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("plain.firelook"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--lights six-way"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(*dir_ / "plain_fb"));
    // rgba needs no six-way lights: the look's own image.
    r = runFirelook(*dir_, "flipbook plain.firelook --layout rgba -o plain_rgba");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(*dir_ / "plain_rgba/rgba.exr"));
}

TEST_F(Flipbook, WritesTheLooksFireProbesAsRawData) {
    json config = json::parse(kTinyBakeConfig);
    config["frames"] = "6-7";
    config["size"] = "8x8";
    config["up"] = "z";
    config["fire_probes"] = 2;
    std::ofstream(*dir_ / "probes.json") << config.dump();
    ASSERT_EQ(runFirelook(*dir_, "bake '" + kSample + "' --config probes.json -o probes.firelook").exit_code,
              0);
    const CommandResult r = runFirelook(*dir_, "flipbook probes.firelook --layout rgba -o probes_fb");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json sidecar = json::parse(std::ifstream(*dir_ / "probes_fb/flipbook.json"));
    const json& probes = sidecar.at("fire_probes");
    EXPECT_EQ(probes.at("file"), "fire_probes.bin");
    ASSERT_EQ(probes.at("frames").size(), 2u);
    // The same numbers `info --json` gives for the default look (the flipbook's look here), frame by
    // frame at the offsets the sidecar names: 8 probes x 9 coefficients x RGB.
    std::ifstream in(*dir_ / "probes_fb/fire_probes.bin", std::ios::binary);
    std::vector<float> data(2 * 8 * 27);
    in.read(reinterpret_cast<char*>(data.data()), data.size() * sizeof(float));
    EXPECT_EQ(in.gcount(), static_cast<std::streamsize>(data.size() * sizeof(float)));
    EXPECT_EQ(in.peek(), std::char_traits<char>::eof());
    const json info =
        json::parse(runFirelook(*dir_, "info --json probes.firelook").out).at("fire_probes").at("frames");
    for (int f = 0; f < 2; ++f) {
        const json& grid = probes.at("frames")[f];
        EXPECT_EQ(grid.at("frame"), info[f].at("frame"));
        EXPECT_EQ(grid.at("counts"), info[f].at("counts"));
        EXPECT_EQ(grid.at("origin"), info[f].at("origin"));
        const size_t offset = grid.at("offset_floats").get<size_t>();
        EXPECT_EQ(offset, f * 8u * 27u);
        for (int p = 0; p < 8; ++p)
            for (int k = 0; k < 9; ++k)
                for (int c = 0; c < 3; ++c)
                    EXPECT_EQ(data[offset + 27 * p + 3 * k + c], info[f].at("probes")[p][k][c].get<float>());
    }
    // Without probes in the package, no such file and no such key.
    ASSERT_EQ(runFirelook(*dir_, "flipbook six.firelook --layout rgba -o no_probes").exit_code, 0);
    EXPECT_FALSE(std::filesystem::exists(*dir_ / "no_probes/fire_probes.bin"));
    EXPECT_FALSE(json::parse(std::ifstream(*dir_ / "no_probes/flipbook.json")).contains("fire_probes"));
}

}  // namespace
