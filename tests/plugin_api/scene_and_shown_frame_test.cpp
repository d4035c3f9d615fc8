// The C API's scene, look and cached-frame calls (firelook.h): fl_package_get_camera,
// fl_package_get_lights, fl_package_get_metadata_json, fl_look_get_bin_emissivity,
// fl_instance_get_look, fl_instance_get_frame_u / _depths. Values against the C++ runtime's own
// (the package's META and description, resolveBinEmissivity, sampledLook, the package's own GPU
// layers), bad handles, struct sizes per the struct rule, and no NaN in any output.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "../support/temp_dir.h"
#include "basis/basis_package.h"
#include "firelook/firelook.h"
#include "look/look.h"
#include "struct_rule.h"
#include "synthetic_package.h"
#include "world/look_track.h"
#include "world/package.h"

namespace {

using firelook::testing::TempDir;
namespace basis = firelook::basis;

// The camera written into the test package's META (column-major, a camera 5 units down +Z).
const double kWorldFromCamera[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5, -0.25, 5, 1};
constexpr double kYfov = 0.61;

// A package like synthetic_package.h's, with two lights, four footprint rays per pixel (so some
// pixels keep every ray and others only their mean: both paths of the resident depths) and
// `camera_json` as META's "camera" (none when empty).
void writeScenePackage(const std::filesystem::path& file, const std::string& camera_json,
                       glm::dvec3 second_light = {1.0, -1.0, 0.5}) {
    firelook::testing::SyntheticShape shape;
    shape.frames = {3, 4, 5};
    shape.lights = 2;
    basis::BakeDescription d = firelook::testing::syntheticDescription(shape);
    d.light_directions = {{0.0, -2.0, 0.0}, second_light};  // not unit: the API normalises
    d.footprint_samples = 4;
    firelook::package::ContainerWriter writer(file, firelook::package::WriterOptions{1});
    for (int frame : shape.frames) {
        const int rank = 8 - static_cast<int>(d.frames.size());
        basis::FrameFactors f = firelook::testing::syntheticFrame(d, frame, rank, 7);
        const size_t pixels = static_cast<size_t>(f.pixels), t = d.alpha_thresholds.size();
        std::vector<float> density(pixels * 4), sigmoid(pixels * 4 * t);
        for (size_t s = 0; s < 4; ++s)
            for (size_t p = 0; p < pixels; ++p) {
                // Odd pixels' rays differ (kept), even pixels' agree (mean ray only).
                const float spread = p % 2 ? 1.0f + 0.4f * static_cast<float>(s) : 1.0f;
                density[s * pixels + p] = f.depth_b[p] * spread;
                for (size_t j = 0; j < t; ++j) sigmoid[(s * t + j) * pixels + p] = f.depth_a[j * pixels + p] * spread;
            }
        f.depth_b = std::move(density);
        f.depth_a = std::move(sigmoid);
        basis::writeFrameFactors(writer, d, f);
        d.frames.push_back({frame, rank});
    }
    const std::string camera = camera_json.empty() ? "" : R"(, "camera": )" + camera_json;
    writer.addMetadata(basis::makeMetadata(
        d, R"({"provenance": {"tool": "scene_test", "sequence": "fire_####.vdb"})" + camera + "}"));
    writer.commit();
}

std::string cameraJson(const std::string& yfov = "0.61", const std::string& size = R"("width": 16, "height": 12)") {
    std::string m;
    for (double v : kWorldFromCamera) m += (m.empty() ? "" : ", ") + std::to_string(v);
    return R"({"source": "test", "world_from_camera": [)" + m + R"(], "yfov_radians": )" + yfov + ", " + size + "}";
}

std::string jsonOf(fl_look look) {
    size_t size = 0;
    EXPECT_EQ(fl_look_to_json(look, nullptr, 0, &size), FL_OK);
    std::string text(size, '\0');
    EXPECT_EQ(fl_look_to_json(look, text.data(), size, &size), FL_OK);
    text.resize(size - 1);
    return text;
}

class SceneApi : public ::testing::Test {
  protected:
    void SetUp() override {
        fl_init_desc desc = fl_init_desc_defaults();
        ASSERT_EQ(fl_init(&desc), FL_OK) << fl_last_error();
        path_ = (dir_ / "scene.firelook").string();
        writeScenePackage(path_, cameraJson());
        ASSERT_EQ(fl_package_load(path_.c_str(), &package_), FL_OK) << fl_last_error();
        ASSERT_EQ(fl_package_get_info(package_, &info_), FL_OK);
        ASSERT_EQ(fl_world_create(nullptr, &world_), FL_OK);
    }
    void TearDown() override { EXPECT_EQ(fl_shutdown(), FL_OK); }

    fl_look look(const std::string& json) {
        fl_look l{};
        EXPECT_EQ(fl_look_from_json(json.c_str(), 0, "test look", &l), FL_OK) << fl_last_error();
        return l;
    }
    // An instance paused at frame position `position` (frames 3..5 at rate 1).
    fl_instance instanceAt(double position, bool image = false) {
        const fl_instance_desc d = [&] {
            fl_instance_desc x = fl_instance_desc_defaults();
            x.package = package_;
            return x;
        }();
        fl_instance i{};
        EXPECT_EQ(fl_instance_create(world_, &d, &i), FL_OK) << fl_last_error();
        if (image) {
            fl_outputs_desc out = fl_outputs_desc_defaults();
            out.image = 1;
            EXPECT_EQ(fl_instance_set_outputs(world_, i, &out), FL_OK);
        }
        seek(i, position);
        return i;
    }
    void seek(fl_instance i, double position) {
        fl_playback_desc pb = fl_playback_desc_defaults();
        pb.paused = 1;
        pb.rate = 1.0;
        pb.time = position - 3.0;
        EXPECT_EQ(fl_instance_set_playback(world_, i, &pb), FL_OK);
    }
    std::vector<float> image(fl_instance i) {
        std::vector<float> rgba(static_cast<size_t>(info_.width) * info_.height * 4);
        EXPECT_EQ(fl_instance_get_image(world_, i, rgba.data(), rgba.size()), FL_OK) << fl_last_error();
        return rgba;
    }

    TempDir dir_;
    std::string path_;
    fl_package package_{};
    fl_package_info info_ = fl_package_info_defaults();
    fl_world world_{};
};

// Looks for this package (albedo 0.7, two lights, bins 0..3).
std::string stopsLook(double tc) {
    return R"({"format": "firelook-look", "version": 1, "temperature_threshold": )" + std::to_string(tc) +
           R"(, "smoke_extinction": 5.0, "flame_extinction": 1.2, "albedo": 0.7,
      "emission": {"stops": [[1.3, 0,0,0], [1.7, 2.0,0.6,0.08], [2.3, 8.0,4.0,0.9], [3.0, 14.0,11.0,6.0]]},
      "light_irradiance": [[2.5, 2.4, 2.25], [0.5, 0.25, 1.0]]})";
}
// A sharp step per bin: its exact interpolant goes negative, so its fit is the non-negative one.
std::string stepBinsLook() {
    std::string bins;
    for (int i = 0; i < 16; ++i) bins += std::string(i ? ", " : "") + (i < 8 ? "[0, 0, 0]" : "[6, 3, 1]");
    return R"({"format": "firelook-look", "version": 1, "temperature_threshold": 1.9, "smoke_extinction": 9.0,
      "flame_extinction": 3.0, "albedo": 0.7, "emission": {"bins": [)" + bins + R"(]},
      "light_irradiance": [[1, 1, 1], [0, 0, 0]]})";
}

TEST_F(SceneApi, CameraIsTheOneRecordedAndFollowsTheStructRule) {
    fl_camera c = fl_camera_defaults();
    ASSERT_EQ(fl_package_get_camera(package_, &c), FL_OK) << fl_last_error();
    EXPECT_EQ(c.struct_size, sizeof(fl_camera));
    EXPECT_EQ(c.width, 16);
    EXPECT_EQ(c.height, 12);
    EXPECT_EQ(c.yfov_radians, kYfov);
    for (int i = 0; i < 16; ++i) EXPECT_EQ(c.world_from_camera[i], kWorldFromCamera[i]) << i;

    // The struct rule: below the first published size refused, a newer caller's extra bytes untouched.
    EXPECT_EQ(firelook::plugin::FirstSize<fl_camera>::value, sizeof(fl_camera));
    fl_camera small = fl_camera_defaults();
    small.struct_size = static_cast<uint32_t>(offsetof(fl_camera, world_from_camera));
    EXPECT_EQ(fl_package_get_camera(package_, &small), FL_ERROR_STRUCT_SIZE);
    EXPECT_NE(std::string(fl_last_error()).find("out_camera->struct_size"), std::string::npos) << fl_last_error();
    struct {
        fl_camera base;
        unsigned char added[16];
    } larger;
    std::memset(&larger, 0xAB, sizeof larger);
    larger.base.struct_size = sizeof larger;
    ASSERT_EQ(fl_package_get_camera(package_, &larger.base), FL_OK);
    EXPECT_EQ(larger.base.struct_size, sizeof larger);
    EXPECT_EQ(larger.base.yfov_radians, kYfov);
    for (unsigned char b : larger.added) ASSERT_EQ(b, 0xAB);

    EXPECT_EQ(fl_package_get_camera(package_, nullptr), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_package_get_camera(fl_package{0}, &c), FL_ERROR_INVALID_HANDLE);
    const fl_package released = package_;
    ASSERT_EQ(fl_package_release(package_), FL_OK);
    EXPECT_EQ(fl_package_get_camera(released, &c), FL_ERROR_INVALID_HANDLE);
    fl_look l{};
    ASSERT_EQ(fl_look_from_json(stopsLook(1.5).c_str(), 0, "x", &l), FL_OK);
    EXPECT_EQ(fl_package_get_camera(fl_package{l.id}, &c), FL_ERROR_INVALID_HANDLE);  // a look's id
}

TEST_F(SceneApi, NoCameraIsNotFoundAndAMalformedOneIsCorruptButThePackageStillPlays) {
    const std::string none = (dir_ / "none.firelook").string();
    writeScenePackage(none, "");
    fl_package p{};
    ASSERT_EQ(fl_package_load(none.c_str(), &p), FL_OK) << fl_last_error();
    fl_camera c = fl_camera_defaults();
    EXPECT_EQ(fl_package_get_camera(p, &c), FL_ERROR_NOT_FOUND);
    EXPECT_NE(std::string(fl_last_error()).find("none.firelook"), std::string::npos) << fl_last_error();

    const std::pair<std::string, std::string> bad[] = {{cameraJson("3.5"), "yfov_radians"},
                                                       {cameraJson("0.6", R"("width": 0, "height": 12)"), "size"},
                                                       {R"({"world_from_camera": [1, 2, 3], "yfov_radians": 0.6,
                                                            "width": 16, "height": 12})", "16 numbers"}};
    for (const auto& [json, problem] : bad) {
        const std::string file = (dir_ / "bad.firelook").string();
        writeScenePackage(file, json);
        fl_package q{};
        ASSERT_EQ(fl_package_load(file.c_str(), &q), FL_OK) << fl_last_error();
        EXPECT_EQ(fl_package_get_camera(q, &c), FL_ERROR_CORRUPT) << json;
        const std::string message = fl_last_error();
        EXPECT_NE(message.find("bad.firelook"), std::string::npos) << message;
        EXPECT_NE(message.find(problem), std::string::npos) << message;
        fl_instance_desc d = fl_instance_desc_defaults();
        d.package = q;
        fl_instance i{};
        ASSERT_EQ(fl_instance_create(world_, &d, &i), FL_OK) << fl_last_error();
        EXPECT_EQ(fl_world_update(world_, 0.0), FL_OK) << fl_last_error();
        EXPECT_EQ(fl_instance_destroy(world_, i), FL_OK);
        EXPECT_EQ(fl_package_release(q), FL_OK);
    }
    EXPECT_EQ(fl_package_release(p), FL_OK);
}

TEST_F(SceneApi, LightsAreThePackagesDirectionsAndTheDefaultLooksIrradiance) {
    const basis::BasisReader reference = basis::BasisReader::open(path_);
    const firelook::Look default_look =
        firelook::parseLook(reference.description().default_look_json, "default look");
    uint32_t count = 0;
    ASSERT_EQ(fl_package_get_lights(package_, nullptr, nullptr, 0, &count), FL_OK);
    ASSERT_EQ(count, 2u);
    ASSERT_EQ(static_cast<int>(count), info_.light_count);
    double directions[6];
    float irradiance[6];
    EXPECT_EQ(fl_package_get_lights(package_, directions, irradiance, 1, &count), FL_ERROR_BUFFER_TOO_SMALL);
    ASSERT_EQ(fl_package_get_lights(package_, directions, irradiance, 2, &count), FL_OK) << fl_last_error();
    for (int l = 0; l < 2; ++l) {
        const glm::dvec3 d = reference.description().light_directions[static_cast<size_t>(l)];
        const double length = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        for (int i = 0; i < 3; ++i) {
            // Exactly the division the API documents; no rounding tolerance needed.
            EXPECT_EQ(directions[3 * l + i], d[i] / length) << l << " " << i;
            EXPECT_EQ(irradiance[3 * l + i], default_look.light_irradiance[static_cast<size_t>(l)][i]);
            EXPECT_TRUE(std::isfinite(directions[3 * l + i]) && std::isfinite(irradiance[3 * l + i]));
        }
    }
    // One array alone.
    float only[6] = {};
    ASSERT_EQ(fl_package_get_lights(package_, nullptr, only, 2, nullptr), FL_OK);
    EXPECT_EQ(only[3], irradiance[3]);
    EXPECT_EQ(fl_package_get_lights(fl_package{0}, directions, irradiance, 2, &count), FL_ERROR_INVALID_HANDLE);

    // A direction of length 0 has no unit vector: such a package does not load (its default look
    // cannot be lit), so every loaded package's directions are unit and finite.
    const std::string zero = (dir_ / "zero_light.firelook").string();
    writeScenePackage(zero, "", {0.0, 0.0, 0.0});
    fl_package p{};
    EXPECT_EQ(fl_package_load(zero.c_str(), &p), FL_ERROR_LOOK);
    EXPECT_NE(std::string(fl_last_error()).find("zero_light.firelook"), std::string::npos) << fl_last_error();
}

TEST_F(SceneApi, MetadataIsThePackagesMetaDocument) {
    size_t size = 0;
    ASSERT_EQ(fl_package_get_metadata_json(package_, nullptr, 0, &size), FL_OK);
    std::string text(size, '\0');
    EXPECT_EQ(fl_package_get_metadata_json(package_, text.data(), size - 1, &size), FL_ERROR_BUFFER_TOO_SMALL);
    ASSERT_EQ(fl_package_get_metadata_json(package_, text.data(), size, &size), FL_OK);
    EXPECT_EQ(text.back(), '\0');
    text.pop_back();
    EXPECT_EQ(text, basis::BasisReader::open(path_).metadataJson());
    EXPECT_NE(text.find("fire_####.vdb"), std::string::npos);
    EXPECT_EQ(fl_package_get_metadata_json(fl_package{0}, nullptr, 0, &size), FL_ERROR_INVALID_HANDLE);
}

TEST_F(SceneApi, BinEmissivityIsTheLooksResolutionAndRendersTheSameImage) {
    const basis::BakeDescription d = basis::BasisReader::open(path_).description();
    const std::string preset = R"({"format": "firelook-look", "version": 1, "temperature_threshold": 1.5,
      "smoke_extinction": 4.0, "flame_extinction": 1.0, "albedo": 0.7,
      "emission": {"preset": "blackbody", "scale": 2.5}, "light_irradiance": [[1, 1, 1], [1, 1, 1]]})";
    for (const std::string& json : {stopsLook(1.6), preset, stepBinsLook()}) {
        const fl_look l = look(json);
        uint32_t count = 0;
        ASSERT_EQ(fl_look_get_bin_emissivity(l, package_, nullptr, 0, &count), FL_OK);
        ASSERT_EQ(count, 16u);
        std::vector<float> rgb(3 * 16);
        EXPECT_EQ(fl_look_get_bin_emissivity(l, package_, rgb.data(), 15, &count), FL_ERROR_BUFFER_TOO_SMALL);
        ASSERT_EQ(fl_look_get_bin_emissivity(l, package_, rgb.data(), 16, &count), FL_OK) << fl_last_error();
        const std::vector<firelook::Rgb> want = firelook::resolveBinEmissivity(firelook::parseLook(json, "x"), d.bins);
        for (size_t i = 0; i < 16; ++i)
            for (int c = 0; c < 3; ++c) {
                EXPECT_EQ(rgb[3 * i + c], want[i][c]) << i;
                EXPECT_TRUE(std::isfinite(rgb[3 * i + c]) && rgb[3 * i + c] >= 0.0f);
            }

        // The header's promise: that emissivity in bins form renders the same image (the same
        // values at the same centres fit to the same coefficients: rounding only).
        firelook::Look as_bins = firelook::parseLook(json, "x");
        firelook::EmissionBins bins;
        for (size_t i = 0; i < 16; ++i) bins.emissivity.emplace_back(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
        as_bins.emission = bins;
        const fl_look b = look(firelook::lookToJson(as_bins));
        const fl_instance original = instanceAt(4.0, true), converted = instanceAt(4.0, true);
        ASSERT_EQ(fl_instance_set_look(world_, original, l), FL_OK);
        ASSERT_EQ(fl_instance_set_look(world_, converted, b), FL_OK);
        ASSERT_EQ(fl_world_update(world_, 0.0), FL_OK);
        const std::vector<float> a = image(original), c = image(converted);
        double peak = 0.0;
        for (float v : a) peak = std::max(peak, static_cast<double>(v));
        ASSERT_GT(peak, 0.0);
        for (size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(a[i], c[i], 1e-6 * peak) << i;
        fl_instance_destroy(world_, original);
        fl_instance_destroy(world_, converted);
        fl_look_release(b);
        fl_look_release(l);
    }

    // A bins look of another count does not fit: FL_ERROR_LOOK naming the look.
    std::string eight;
    for (int i = 0; i < 8; ++i) eight += std::string(i ? ", " : "") + "[1, 1, 1]";
    const fl_look wrong = look(R"({"format": "firelook-look", "version": 1, "temperature_threshold": 1.5,
      "smoke_extinction": 4.0, "flame_extinction": 1.0, "albedo": 0.7, "emission": {"bins": [)" + eight +
                                R"(]}, "light_irradiance": [[1, 1, 1], [1, 1, 1]]})");
    float rgb[48];
    EXPECT_EQ(fl_look_get_bin_emissivity(wrong, package_, rgb, 16, nullptr), FL_ERROR_LOOK);
    EXPECT_NE(std::string(fl_last_error()).find("test look"), std::string::npos) << fl_last_error();
    EXPECT_EQ(fl_look_get_bin_emissivity(fl_look{0}, package_, rgb, 16, nullptr), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_look_get_bin_emissivity(wrong, fl_package{wrong.id}, rgb, 16, nullptr), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_look_release(wrong), FL_OK);
    EXPECT_EQ(fl_look_get_bin_emissivity(wrong, package_, rgb, 16, nullptr), FL_ERROR_INVALID_HANDLE);
}

TEST_F(SceneApi, InstanceLookIsTheLookSetOrTheRuntimesInterpolation) {
    // Default look: the package's own.
    const fl_instance i = instanceAt(4.0, true);
    fl_look shown{}, fallback{};
    ASSERT_EQ(fl_instance_get_look(world_, i, &shown), FL_OK) << fl_last_error();
    ASSERT_EQ(fl_package_default_look(package_, &fallback), FL_OK);
    EXPECT_EQ(jsonOf(shown), jsonOf(fallback));
    fl_look_release(shown);
    fl_look_release(fallback);

    // A constant look comes back exactly (form included).
    const fl_look a = look(stopsLook(1.3)), b = look(stepBinsLook());
    ASSERT_EQ(fl_instance_set_look(world_, i, a), FL_OK);
    ASSERT_EQ(fl_instance_get_look(world_, i, &shown), FL_OK);
    EXPECT_EQ(jsonOf(shown), jsonOf(a));
    fl_look_release(shown);

    // Keys at 3 and 5, shown at 3.5 (an update sets the position): the runtime's sampledLook. Key b's
    // emission needed the non-negative fit, so the blend of fits is not the fit of the blend.
    const fl_keyframe keys[2] = {{3.0, a, 0}, {5.0, b, 0}};
    ASSERT_EQ(fl_instance_set_keyframes(world_, i, keys, 2), FL_OK);
    seek(i, 3.5);
    ASSERT_EQ(fl_world_update(world_, 0.0), FL_OK);
    fl_instance_state state = fl_instance_state_defaults();
    ASSERT_EQ(fl_instance_get_state(world_, i, &state), FL_OK);
    ASSERT_EQ(state.frame_position, 3.5);
    ASSERT_EQ(fl_instance_get_look(world_, i, &shown), FL_OK) << fl_last_error();
    const basis::BakeDescription d = basis::BasisReader::open(path_).description();
    const std::vector<firelook::world::Keyframe> resolved = {
        {3.0, firelook::world::resolveLook(firelook::parseLook(stopsLook(1.3), "a"), d)},
        {5.0, firelook::world::resolveLook(firelook::parseLook(stepBinsLook(), "b"), d)}};
    ASSERT_FALSE(resolved[1].look.exact_interpolant);
    const firelook::Look want = firelook::world::sampledLook(resolved, 3.5, d);
    const firelook::Look got = firelook::parseLook(jsonOf(shown), "shown");
    EXPECT_EQ(got.temperature_threshold, want.temperature_threshold);
    EXPECT_EQ(got.temperature_threshold, state.temperature_threshold);
    EXPECT_EQ(got.smoke_extinction, state.smoke_extinction);
    ASSERT_TRUE(std::holds_alternative<firelook::EmissionBins>(got.emission));
    const auto& e = std::get<firelook::EmissionBins>(got.emission).emissivity;
    const auto& w = std::get<firelook::EmissionBins>(want.emission).emissivity;
    ASSERT_EQ(e.size(), 16u);
    for (size_t j = 0; j < 16; ++j)
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(e[j][c], w[j][c]) << j;
            EXPECT_TRUE(std::isfinite(e[j][c]) && e[j][c] >= 0.0f);
        }
    for (size_t l = 0; l < 2; ++l) EXPECT_EQ(got.light_irradiance[l], want.light_irradiance[l]);

    // The promise: a look that shows what the instance shows. Another instance holding it constant
    // renders the keyed instance's image up to the refit's float rounding (1e-5 of the peak: the
    // collocation system's condition number is ~2, float coefficients ~1e-7 each).
    const fl_instance copy = instanceAt(3.5, true);
    ASSERT_EQ(fl_instance_set_look(world_, copy, shown), FL_OK) << fl_last_error();
    ASSERT_EQ(fl_world_update(world_, 0.0), FL_OK);
    const std::vector<float> keyed = image(i), held = image(copy);
    double peak = 0.0;
    for (float v : keyed) peak = std::max(peak, static_cast<double>(v));
    ASSERT_GT(peak, 0.0);
    for (size_t k = 0; k < keyed.size(); ++k) ASSERT_NEAR(keyed[k], held[k], 1e-5 * peak) << k;
    fl_look_release(shown);

    // Handles.
    EXPECT_EQ(fl_instance_get_look(world_, i, nullptr), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_instance_get_look(world_, fl_instance{0}, &shown), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(shown.id, 0u);
    fl_world other{};
    ASSERT_EQ(fl_world_create(nullptr, &other), FL_OK);
    EXPECT_EQ(fl_instance_get_look(other, i, &shown), FL_ERROR_INVALID_HANDLE);
    ASSERT_EQ(fl_instance_destroy(world_, i), FL_OK);
    EXPECT_EQ(fl_instance_get_look(world_, i, &shown), FL_ERROR_INVALID_HANDLE);
    fl_look_release(a);
    fl_look_release(b);
}

// The shown frame's layers from the world's cache are the package's own, byte for byte, and need
// no read: the package is loaded from borrowed bytes which are overwritten after the update.
TEST_F(SceneApi, InstanceFrameLayersComeFromTheCacheAndEqualThePackages) {
    std::ifstream in(path_, std::ios::binary);
    const std::vector<char> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto* bytes = static_cast<char*>(std::aligned_alloc(64, (file.size() + 63) / 64 * 64));
    std::memcpy(bytes, file.data(), file.size());
    fl_package_memory_desc md = fl_package_memory_desc_defaults();
    md.flags = FL_PACKAGE_MEMORY_BORROW;
    fl_package borrowed{};
    ASSERT_EQ(fl_package_load_memory(bytes, file.size(), "borrowed", &md, &borrowed), FL_OK) << fl_last_error();
    fl_instance_desc desc = fl_instance_desc_defaults();
    desc.package = borrowed;
    fl_instance i{};
    ASSERT_EQ(fl_instance_create(world_, &desc, &i), FL_OK);
    seek(i, 4.0);

    size_t count = 0;
    EXPECT_EQ(fl_instance_get_frame_u(world_, i, nullptr, 0, &count), FL_ERROR_NO_DATA);
    EXPECT_EQ(fl_instance_get_frame_depths(world_, i, nullptr, 0, &count), FL_ERROR_NO_DATA);
    ASSERT_EQ(fl_world_update(world_, 0.0), FL_OK);
    fl_instance_state state = fl_instance_state_defaults();
    ASSERT_EQ(fl_instance_get_state(world_, i, &state), FL_OK);
    ASSERT_EQ(state.frame, 4);

    size_t u_count = 0, depth_count = 0;
    ASSERT_EQ(fl_package_get_frame_u(package_, 4, nullptr, 0, &u_count), FL_OK);
    ASSERT_EQ(fl_package_get_frame_depths(package_, 4, nullptr, 0, &depth_count), FL_OK);
    std::vector<uint16_t> u_package(u_count), u_cache(u_count, 0xFFFF);
    std::vector<float> depth_package(depth_count), depth_cache(depth_count, -1.0f);
    ASSERT_EQ(fl_package_get_frame_u(package_, 4, u_package.data(), u_count, &u_count), FL_OK);
    ASSERT_EQ(fl_package_get_frame_depths(package_, 4, depth_package.data(), depth_count, &depth_count), FL_OK);
    // The package's depths really differ between rays at some pixels (both resident paths run).
    ASSERT_NE(depth_package[1], depth_package[static_cast<size_t>(info_.width) * info_.height + 1]);
    ASSERT_EQ(depth_package[0], depth_package[static_cast<size_t>(info_.width) * info_.height]);

    std::memset(bytes, 0x5A, file.size());  // nothing may read the package from here on
    ASSERT_EQ(fl_instance_get_frame_u(world_, i, nullptr, 0, &count), FL_OK);
    EXPECT_EQ(count, u_count);
    ASSERT_EQ(fl_instance_get_frame_depths(world_, i, nullptr, 0, &count), FL_OK);
    EXPECT_EQ(count, depth_count);
    EXPECT_EQ(fl_instance_get_frame_u(world_, i, u_cache.data(), u_count - 1, &count), FL_ERROR_BUFFER_TOO_SMALL);
    EXPECT_EQ(fl_instance_get_frame_u(world_, i, nullptr, u_count, &count), FL_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ(fl_instance_get_frame_u(world_, i, u_cache.data(), u_count, &count), FL_OK) << fl_last_error();
    ASSERT_EQ(fl_instance_get_frame_depths(world_, i, depth_cache.data(), depth_count, &count), FL_OK);
    EXPECT_EQ(std::memcmp(u_cache.data(), u_package.data(), u_count * sizeof(uint16_t)), 0);
    EXPECT_EQ(std::memcmp(depth_cache.data(), depth_package.data(), depth_count * sizeof(float)), 0);
    for (float v : depth_cache) ASSERT_TRUE(std::isfinite(v));

    // New outputs hold nothing until the next update; handles are checked.
    fl_outputs_desc out = fl_outputs_desc_defaults();
    ASSERT_EQ(fl_instance_set_outputs(world_, i, &out), FL_OK);
    EXPECT_EQ(fl_instance_get_frame_u(world_, i, u_cache.data(), u_count, &count), FL_ERROR_NO_DATA);
    EXPECT_EQ(fl_instance_get_frame_depths(world_, fl_instance{0}, depth_cache.data(), depth_count, &count),
              FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_get_frame_u(fl_world{0}, i, u_cache.data(), u_count, &count), FL_ERROR_INVALID_HANDLE);
    ASSERT_EQ(fl_world_destroy(world_), FL_OK);  // before the borrowed bytes go
    ASSERT_EQ(fl_package_release(borrowed), FL_OK);
    std::free(bytes);
}

// The default look is parsed and fitted once, by Package::open: instances start from that
// resolution and fl_package_default_look hands out that look.
TEST_F(SceneApi, DefaultLookIsResolvedOnceByThePackage) {
    const auto package = firelook::world::Package::open(path_);
    const basis::BakeDescription& d = package->description();
    const firelook::world::ResolvedLook want =
        firelook::world::resolveLook(firelook::parseLook(d.default_look_json, "default"), d);
    EXPECT_EQ(package->resolvedDefaultLook().rbf, want.rbf);
    EXPECT_EQ(package->resolvedDefaultLook().lights, want.lights);
    EXPECT_EQ(firelook::lookToJson(package->defaultLook()), firelook::lookToJson(want.source));
    fl_look l{};
    ASSERT_EQ(fl_package_default_look(package_, &l), FL_OK);
    EXPECT_EQ(jsonOf(l), firelook::lookToJson(want.source));
    EXPECT_EQ(fl_look_release(l), FL_OK);
}

}  // namespace
