// The C API's file readers and lists for editors (issue 28): fl_look_load_file, the emission preset
// list (fl_emission_preset_count / _name), fit targets (fl_fit_target_load, the reader `firelook fit`
// uses) and fl_fit_difference; each on success and on bad input (missing file, bad content, null
// pointer), with the coded results firelook.h documents.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "../support/temp_dir.h"
#include "firelook/firelook.h"
#include "image/image_io.h"
#include "look/emission_presets.h"
#include "look/look.h"
#include "struct_rule.h"  // plugin_api/src
#include "synthetic_package.h"

namespace {

using firelook::testing::TempDir;

class LookFilesApi : public ::testing::Test {
  protected:
    void SetUp() override {
        const fl_init_desc desc = fl_init_desc_defaults();
        ASSERT_EQ(fl_init(&desc), FL_OK) << fl_last_error();
        firelook::testing::writeSyntheticPackage(dir_ / "p.firelook", shape_);
        ASSERT_EQ(fl_package_load((dir_ / "p.firelook").c_str(), &package_), FL_OK) << fl_last_error();
    }
    void TearDown() override { EXPECT_EQ(fl_shutdown(), FL_OK); }

    // An RGBA image of the package's size: a gradient, alpha below 1 in the left half.
    firelook::image::ImageRGBA targetImage(int width, int height) const {
        firelook::image::ImageRGBA image(width, height);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                float* p = image.at(x, y).data();
                p[3] = x < width / 2 ? 0.5f : 1.0f;
                p[0] = p[3] * 0.1f * x;
                p[1] = p[3] * 0.05f * y;
                p[2] = p[3] * 0.25f;
            }
        return image;
    }
    std::string writeTarget(const std::string& name, int width, int height) const {
        firelook::image::WriteOptions exact;
        exact.exr_pixel_type = firelook::image::ExrPixelType::Float;
        firelook::image::writeImage(dir_ / name, targetImage(width, height), exact);
        return (dir_ / name).string();
    }

    TempDir dir_;
    firelook::testing::SyntheticShape shape_;
    fl_package package_{};
};

std::string lookJson(fl_look look) {
    size_t size = 0;
    EXPECT_EQ(fl_look_to_json(look, nullptr, 0, &size), FL_OK);
    std::string text(size, '\0');
    EXPECT_EQ(fl_look_to_json(look, text.data(), text.size(), &size), FL_OK);
    text.resize(size - 1);
    return text;
}

TEST_F(LookFilesApi, LookLoadFileReadsALookFile) {
    firelook::Look look = firelook::defaultLook();
    look.smoke_extinction = 3.25;
    firelook::saveLook(dir_ / "l.json", look);
    fl_look handle{};
    ASSERT_EQ(fl_look_load_file((dir_ / "l.json").c_str(), &handle), FL_OK) << fl_last_error();
    EXPECT_EQ(lookJson(handle), firelook::lookToJson(look));
    EXPECT_EQ(fl_look_release(handle), FL_OK);
}

TEST_F(LookFilesApi, LookLoadFileRefusesAMissingFileBadJsonAndNullPointers) {
    fl_look handle{};
    const std::string missing = (dir_ / "missing.json").string();
    EXPECT_EQ(fl_look_load_file(missing.c_str(), &handle), FL_ERROR_IO);
    EXPECT_NE(std::string(fl_last_error()).find(missing), std::string::npos) << fl_last_error();
    EXPECT_EQ(handle.id, 0u);
    std::ofstream(dir_ / "bad.json") << "{\"format\": \"firelook-look\", ";
    EXPECT_EQ(fl_look_load_file((dir_ / "bad.json").c_str(), &handle), FL_ERROR_LOOK);
    EXPECT_NE(std::string(fl_last_error()).find("bad.json"), std::string::npos) << fl_last_error();
    EXPECT_EQ(fl_look_load_file(nullptr, &handle), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_look_load_file(missing.c_str(), nullptr), FL_ERROR_INVALID_ARGUMENT);
}

// fl_look_get_desc then fl_look_create gives the same look file, for each emission form.
TEST_F(LookFilesApi, LookDescRoundTripsEveryEmissionForm) {
    firelook::Look preset = firelook::defaultLook(), bins = firelook::defaultLook();
    preset.emission = firelook::EmissionPreset{"blackbody", 2.5};
    bins.emission = firelook::EmissionBins{{firelook::Rgb(1.0f, 2.0f, 3.0f), firelook::Rgb(0.25f, 0.0f, 7.0f)}};
    bins.light_irradiance.push_back(firelook::Rgb(0.5f));
    for (const firelook::Look& look : {firelook::defaultLook(), preset, bins}) {
        const std::string json = firelook::lookToJson(look);
        fl_look source{};
        ASSERT_EQ(fl_look_from_json(json.c_str(), 0, "source", &source), FL_OK) << fl_last_error();
        fl_look_desc desc = fl_look_desc_defaults();
        ASSERT_EQ(fl_look_get_desc(source, &desc, nullptr, 0, nullptr, 0, nullptr, 0), FL_OK) << fl_last_error();
        EXPECT_EQ(desc.stops, nullptr);
        std::vector<double> stops(4 * desc.stop_count);
        std::vector<float> bin_values(3 * desc.bin_count), lights(3 * desc.light_count);
        ASSERT_EQ(fl_look_get_desc(source, &desc, stops.data(), desc.stop_count, bin_values.data(), desc.bin_count,
                                   lights.data(), desc.light_count),
                  FL_OK)
            << fl_last_error();
        EXPECT_EQ(desc.temperature_threshold, look.temperature_threshold);
        desc.stops = stops.data();
        desc.bins = bin_values.data();
        desc.lights = lights.data();
        fl_look made{};
        ASSERT_EQ(fl_look_create(&desc, "made", &made), FL_OK) << fl_last_error();
        EXPECT_EQ(lookJson(made), json);
        EXPECT_EQ(fl_look_release(made), FL_OK);
        EXPECT_EQ(fl_look_release(source), FL_OK);
    }
}

TEST_F(LookFilesApi, LookCreateAndGetDescRefuseBadInput) {
    fl_look look{};
    const std::string json = firelook::lookToJson(firelook::defaultLook());
    ASSERT_EQ(fl_look_from_json(json.c_str(), 0, nullptr, &look), FL_OK);
    fl_look_desc desc = fl_look_desc_defaults();
    ASSERT_EQ(fl_look_get_desc(look, &desc, nullptr, 0, nullptr, 0, nullptr, 0), FL_OK);
    ASSERT_EQ(desc.emission_form, FL_EMISSION_STOPS);
    ASSERT_GT(desc.stop_count, 1u);
    std::vector<double> stops(4 * desc.stop_count);
    std::vector<float> lights(3 * desc.light_count);
    EXPECT_EQ(fl_look_get_desc(look, &desc, stops.data(), desc.stop_count - 1, nullptr, 0, nullptr, 0),
              FL_ERROR_BUFFER_TOO_SMALL);
    EXPECT_EQ(fl_look_get_desc(look, &desc, nullptr, desc.stop_count, nullptr, 0, nullptr, 0), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_look_get_desc(look, nullptr, nullptr, 0, nullptr, 0, nullptr, 0), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_look_get_desc(fl_look{}, &desc, nullptr, 0, nullptr, 0, nullptr, 0), FL_ERROR_INVALID_HANDLE);
    ASSERT_EQ(fl_look_get_desc(look, &desc, stops.data(), desc.stop_count, nullptr, 0, lights.data(), desc.light_count),
              FL_OK);
    desc.stops = stops.data();
    desc.lights = lights.data();

    fl_look made{};
    fl_look_desc bad = desc;
    bad.smoke_extinction = -1.0;
    EXPECT_EQ(fl_look_create(&bad, "edited", &made), FL_ERROR_LOOK);
    EXPECT_NE(std::string(fl_last_error()).find("smoke_extinction"), std::string::npos) << fl_last_error();
    EXPECT_NE(std::string(fl_last_error()).find("edited"), std::string::npos) << fl_last_error();
    bad = desc;
    bad.emission_form = FL_EMISSION_PRESET;
    std::strcpy(bad.preset, "no-such-preset");
    EXPECT_EQ(fl_look_create(&bad, nullptr, &made), FL_ERROR_LOOK);
    std::memset(bad.preset, 'x', sizeof bad.preset);
    EXPECT_EQ(fl_look_create(&bad, nullptr, &made), FL_ERROR_INVALID_ARGUMENT);
    bad = desc;
    bad.emission_form = 7;
    EXPECT_EQ(fl_look_create(&bad, nullptr, &made), FL_ERROR_INVALID_ARGUMENT);
    bad = desc;
    bad.stops = nullptr;
    EXPECT_EQ(fl_look_create(&bad, nullptr, &made), FL_ERROR_INVALID_ARGUMENT);
    bad = desc;
    bad.lights = nullptr;
    EXPECT_EQ(fl_look_create(&bad, nullptr, &made), FL_ERROR_INVALID_ARGUMENT);
    bad = desc;
    bad.struct_size = 0;
    EXPECT_EQ(fl_look_create(&bad, nullptr, &made), FL_ERROR_STRUCT_SIZE);
    EXPECT_EQ(fl_look_create(nullptr, nullptr, &made), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_look_create(&desc, nullptr, nullptr), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(made.id, 0u);
    ASSERT_EQ(fl_look_create(&desc, nullptr, &made), FL_OK) << fl_last_error();
    EXPECT_EQ(lookJson(made), json);
    EXPECT_EQ(fl_look_release(made), FL_OK);
    EXPECT_EQ(fl_look_release(look), FL_OK);
}

TEST_F(LookFilesApi, EmissionPresetsAreTheLibrarysList) {
    uint32_t count = 0;
    ASSERT_EQ(fl_emission_preset_count(&count), FL_OK);
    const std::vector<std::string> names = firelook::presetNames();
    ASSERT_EQ(count, names.size());
    for (uint32_t i = 0; i < count; ++i) {
        size_t size = 0;
        ASSERT_EQ(fl_emission_preset_name(i, nullptr, 0, &size), FL_OK);  // capacity 0 asks for the size
        EXPECT_EQ(size, names[i].size() + 1);
        std::string name(size, '\0');
        ASSERT_EQ(fl_emission_preset_name(i, name.data(), name.size(), &size), FL_OK);
        EXPECT_EQ(name.c_str(), names[i]);
        char tiny[1];
        EXPECT_EQ(fl_emission_preset_name(i, tiny, sizeof tiny, &size), FL_ERROR_BUFFER_TOO_SMALL);
    }
    size_t size = 0;
    EXPECT_EQ(fl_emission_preset_name(count, nullptr, 0, &size), FL_ERROR_NOT_FOUND);
    EXPECT_EQ(fl_emission_preset_count(nullptr), FL_ERROR_INVALID_ARGUMENT);
    char buffer[64];
    EXPECT_EQ(fl_emission_preset_name(0, nullptr, sizeof buffer, &size), FL_ERROR_INVALID_ARGUMENT);
}

TEST_F(LookFilesApi, FitTargetLoadReadsTheTargetAsFitDoes) {
    const std::string path = writeTarget("t.exr", shape_.width, shape_.height);
    const size_t pixels = static_cast<size_t>(shape_.width) * shape_.height;
    fl_fit_target_desc desc = fl_fit_target_desc_defaults();
    desc.frame = 2;
    desc.target_path = path.c_str();
    size_t count = 0;
    ASSERT_EQ(fl_fit_target_load(package_, &desc, nullptr, nullptr, 0, &count, nullptr), FL_OK) << fl_last_error();
    ASSERT_EQ(count, pixels);
    std::vector<float> rgba(pixels * 4), weights(pixels);
    fl_fit_target_info info = fl_fit_target_info_defaults();
    ASSERT_EQ(fl_fit_target_load(package_, &desc, rgba.data(), weights.data(), pixels, &count, &info), FL_OK)
        << fl_last_error();
    EXPECT_EQ(rgba, targetImage(shape_.width, shape_.height).pixels);
    EXPECT_EQ(weights, std::vector<float>(pixels, 1.0f));
    EXPECT_EQ(info.flags, 0u);  // not opaque: its alpha is matched
    EXPECT_EQ(info.clipped_pixels, 0u);

    // Over a background, exposed one stop: colour and background halved, alpha not matched.
    desc.flags = FL_FIT_OVER_BACKGROUND;
    desc.background[0] = 0.5f;
    desc.exposure = 1.0;
    ASSERT_EQ(fl_fit_target_load(package_, &desc, rgba.data(), weights.data(), pixels, nullptr, &info), FL_OK)
        << fl_last_error();
    EXPECT_EQ(info.flags, static_cast<uint32_t>(FL_FIT_OVER_BACKGROUND));
    EXPECT_EQ(info.background[0], 0.25f);
    EXPECT_EQ(rgba[4 * 3 + 0], 0.5f * targetImage(shape_.width, shape_.height).pixels[4 * 3 + 0]);
}

TEST_F(LookFilesApi, FitTargetLoadRefusesMissingWrongAndNull) {
    const size_t pixels = static_cast<size_t>(shape_.width) * shape_.height;
    std::vector<float> rgba(pixels * 4), weights(pixels);
    fl_fit_target_info info = fl_fit_target_info_defaults();
    fl_fit_target_desc desc = fl_fit_target_desc_defaults();
    const auto load = [&] {
        return fl_fit_target_load(package_, &desc, rgba.data(), weights.data(), pixels, nullptr, &info);
    };
    const std::string missing = (dir_ / "missing.exr").string();
    desc.target_path = missing.c_str();
    EXPECT_EQ(load(), FL_ERROR_IO);
    EXPECT_NE(std::string(fl_last_error()).find(missing), std::string::npos) << fl_last_error();
    std::ofstream(dir_ / "garbage.exr") << "not an image";
    const std::string garbage = (dir_ / "garbage.exr").string();
    desc.target_path = garbage.c_str();
    EXPECT_EQ(load(), FL_ERROR_IO);
    EXPECT_NE(std::string(fl_last_error()).find("garbage.exr"), std::string::npos) << fl_last_error();
    const std::string small = writeTarget("small.exr", 4, 4);
    desc.target_path = small.c_str();
    EXPECT_EQ(load(), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(fl_last_error()).find("4x4"), std::string::npos) << fl_last_error();
    const std::string good = writeTarget("good.exr", shape_.width, shape_.height);
    desc.target_path = good.c_str();
    desc.mask_path = missing.c_str();
    EXPECT_EQ(load(), FL_ERROR_IO);
    desc.mask_path = nullptr;
    desc.flags = 64;
    EXPECT_EQ(load(), FL_ERROR_INVALID_ARGUMENT);
    desc.flags = 0;
    EXPECT_EQ(fl_fit_target_load(package_, &desc, rgba.data(), weights.data(), pixels - 1, nullptr, &info),
              FL_ERROR_BUFFER_TOO_SMALL);
    EXPECT_EQ(fl_fit_target_load(package_, &desc, nullptr, weights.data(), pixels, nullptr, &info),
              FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_fit_target_load(package_, &desc, rgba.data(), weights.data(), pixels, nullptr, nullptr),
              FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_fit_target_load(package_, nullptr, rgba.data(), weights.data(), pixels, nullptr, &info),
              FL_ERROR_INVALID_ARGUMENT);
    desc.target_path = nullptr;
    EXPECT_EQ(load(), FL_ERROR_INVALID_ARGUMENT);
    desc.target_path = good.c_str();
    desc.struct_size = 0;
    EXPECT_EQ(load(), FL_ERROR_STRUCT_SIZE);
    desc = fl_fit_target_desc_defaults();
    desc.target_path = good.c_str();
    EXPECT_EQ(fl_fit_target_load(fl_package{}, &desc, rgba.data(), weights.data(), pixels, nullptr, &info),
              FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(load(), FL_OK) << fl_last_error();
}

TEST_F(LookFilesApi, FitDifferenceIsTheAbsoluteErrorAsTheFitComparedIt) {
    const std::vector<float> target = {1.0f, 0.5f, 0.0f, 1.0f, 0.2f, 0.2f, 0.2f, 1.0f};
    const std::vector<float> fit = {0.5f, 0.5f, 0.5f, 0.5f, 0.2f, 0.2f, 0.2f, 1.0f};
    std::vector<float> difference(8);
    ASSERT_EQ(fl_fit_difference(target.data(), fit.data(), 2, 0, nullptr, difference.data()), FL_OK);
    EXPECT_EQ(difference, (std::vector<float>{0.5f, 0.0f, 0.5f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f}));
    // Over a background, the fit's uncovered half shows it: 0.5 + 0.5 * 1 against 1 is exact.
    const float background[3] = {1.0f, 0.0f, 0.0f};
    ASSERT_EQ(fl_fit_difference(target.data(), fit.data(), 2, FL_FIT_OVER_BACKGROUND, background, difference.data()),
              FL_OK);
    EXPECT_EQ(difference[0], 0.0f);
    EXPECT_EQ(fl_fit_difference(nullptr, fit.data(), 2, 0, nullptr, difference.data()), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_fit_difference(target.data(), fit.data(), 2, 0, nullptr, nullptr), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_fit_difference(target.data(), fit.data(), 0, 0, nullptr, difference.data()), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_fit_difference(target.data(), fit.data(), 2, FL_FIT_OVER_BACKGROUND, nullptr, difference.data()),
              FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_fit_difference(target.data(), fit.data(), 2, 64, nullptr, difference.data()), FL_ERROR_INVALID_ARGUMENT);
}

TEST(LookFilesApiStructs, FirstPublishedSizesAreTheWholeStructs) {
    using firelook::plugin::FirstSize;
    EXPECT_EQ(FirstSize<fl_look_desc>::value, sizeof(fl_look_desc));
    EXPECT_EQ(FirstSize<fl_fit_target_desc>::value, sizeof(fl_fit_target_desc));
    EXPECT_EQ(FirstSize<fl_fit_target_info>::value, sizeof(fl_fit_target_info));
}

}  // namespace
