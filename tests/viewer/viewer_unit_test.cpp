// Unit tests of the viewer's non-GL parts (compiled from samples/viewer): the editable look and
// its JSON, the keyframe file, emission form conversions (which must not change the look), the
// export file names and the QA error measures. No display needed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../support/temp_dir.h"
#include "fl_check.h"
#include "fire_session.h"
#include "heat_map.h"
#include "image_export.h"
#include "keyframes_file.h"
#include "look_edit.h"
#include "look_resolution.h"
#include "text_file.h"

namespace firelook::viewer {
namespace {

class ViewerUnit : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        fl_init_desc desc = fl_init_desc_defaults();
        ASSERT_EQ(fl_init(&desc), FL_OK) << fl_last_error();
    }
    static void TearDownTestSuite() { fl_shutdown(); }
};

std::string looksDir() { return FIRELOOK_LOOKS_DIR; }

// The package the viewer tests bake (ctest fixture); baked here when run by hand.
const std::string& packagePath() {
    static const std::string path = [] {
        if (!std::filesystem::exists(FIRELOOK_VIEWER_PACKAGE)) {
            const std::string command =
                std::string("'") + FIRELOOK_CLI + "' " + FIRELOOK_VIEWER_BAKE_ARGS + " > /dev/null 2>&1";
            EXPECT_EQ(std::system(command.c_str()), 0) << command;
        }
        return std::string(FIRELOOK_VIEWER_PACKAGE);
    }();
    return path;
}

TEST_F(ViewerUnit, LookFilesRoundTripExactly) {
    for (const char* name : {"fireball.json", "inferno.json", "smoky.json"}) {
        const std::string file = looksDir() + "/" + name;
        const LookEdit look = parseLookEdit(readTextFile(file), file);
        // Edit -> JSON -> library -> canonical JSON is the library's own JSON of the file.
        EXPECT_EQ(parseLookEdit(lookEditToJson(look), "again"), look) << name;
        fl_look original{};
        const std::string text = readTextFile(file);
        ASSERT_EQ(fl_look_from_json(text.c_str(), 0, name, &original), FL_OK);
        size_t size = 0;
        fl_look_to_json(original, nullptr, 0, &size);
        std::string canonical(size, '\0');
        fl_look_to_json(original, canonical.data(), size, &size);
        canonical.resize(size - 1);
        fl_look_release(original);
        EXPECT_EQ(canonicalLookJson(look), canonical) << name;
    }
}

TEST_F(ViewerUnit, BadLookNamesTheSource) {
    try {
        parseLookEdit(R"({"format": "firelook-look", "version": 1})", "my_look.json");
        FAIL() << "accepted a look without keys";
    } catch (const ViewerError& e) {
        EXPECT_NE(std::string(e.what()).find("my_look.json"), std::string::npos) << e.what();
    }
}

TEST_F(ViewerUnit, ColourIntensitySplitsAndJoins) {
    const Rgb3 e{4.0f, 1.0f, 0.5f};
    const ColourIntensity c = splitEmissivity(e);
    EXPECT_FLOAT_EQ(c.intensity, 4.0f);
    EXPECT_FLOAT_EQ(c.colour[0], 1.0f);
    const Rgb3 back = joinEmissivity(c);
    for (int i = 0; i < 3; ++i) EXPECT_FLOAT_EQ(back[i], e[i]);
    EXPECT_EQ(splitEmissivity({0, 0, 0}).intensity, 0.0f);
}

TEST_F(ViewerUnit, KeyframeFileRoundTripsAndSorts) {
    firelook::testing::TempDir dir;
    const LookEdit a = parseLookEdit(readTextFile(looksDir() + "/fireball.json"), "a");
    const LookEdit b = parseLookEdit(readTextFile(looksDir() + "/smoky.json"), "b");
    std::vector<Keyframe> keys;
    insertKey(keys, {8.0, b});
    insertKey(keys, {5.0, a});
    insertKey(keys, {8.0, a});  // replaces the key at 8
    ASSERT_EQ(keys.size(), 2u);
    EXPECT_EQ(keys[0].frame, 5.0);
    EXPECT_EQ(keys[1].look, a);
    const auto file = dir / "keys.json";
    saveKeyframes(file, keys);
    const std::vector<Keyframe> loaded = loadKeyframes(file);
    ASSERT_EQ(loaded.size(), 2u);
    EXPECT_EQ(loaded[0].frame, 5.0);
    EXPECT_EQ(loaded[0].look, a);
    EXPECT_EQ(loaded[1].look, a);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"keys.json"});  // atomic write left nothing behind

    std::ofstream(dir / "bad.json") << R"({"format": "firelook-viewer-keyframes", "version": 1,
        "keys": [{"frame": 1, "look": {"format": "firelook-look", "version": 1}}]})";
    try {
        loadKeyframes(dir / "bad.json");
        FAIL() << "accepted a bad key";
    } catch (const ViewerError& e) {
        EXPECT_NE(std::string(e.what()).find("keys[0].look"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
    }
}

// CPU image of one look through the C API.
std::vector<float> renderThroughApi(fl_package package, const fl_package_info& info, const LookEdit& look, int frame) {
    fl_world world{};
    EXPECT_EQ(fl_world_create(nullptr, &world), FL_OK);
    fl_instance_desc desc = fl_instance_desc_defaults();
    desc.package = package;
    fl_instance instance{};
    EXPECT_EQ(fl_instance_create(world, &desc, &instance), FL_OK);
    const fl_look handle = makeFlLook(look, "test");
    EXPECT_EQ(fl_instance_set_look(world, instance, handle), FL_OK) << fl_last_error();
    fl_look_release(handle);
    fl_playback_desc pb = fl_playback_desc_defaults();
    pb.paused = 1;
    pb.rate = 1.0;
    pb.time = frame - info.first_frame;
    fl_instance_set_playback(world, instance, &pb);
    fl_outputs_desc out = fl_outputs_desc_defaults();
    out.image = 1;
    fl_instance_set_outputs(world, instance, &out);
    EXPECT_EQ(fl_world_update(world, 0.0), FL_OK);
    std::vector<float> rgba(static_cast<size_t>(info.width) * info.height * 4);
    EXPECT_EQ(fl_instance_get_image(world, instance, rgba.data(), rgba.size()), FL_OK);
    fl_world_destroy(world);
    return rgba;
}

// Switching the editor between preset, stops and per-bin forms must keep the image: bins are
// the resolved emissivity at the bin centres and stops sit at the bin centres.
TEST_F(ViewerUnit, EmissionFormConversionsKeepTheImage) {
    fl_package package{};
    ASSERT_EQ(fl_package_load(packagePath().c_str(), &package), FL_OK) << fl_last_error();
    fl_package_info info = fl_package_info_defaults();
    ASSERT_EQ(fl_package_get_info(package, &info), FL_OK);
    for (const char* name : {"fireball.json", "smoky.json"}) {  // stops, preset
        const LookEdit look = parseLookEdit(readTextFile(looksDir() + "/" + name), name);
        LookEdit bins = look;
        bins.mode = EmissionMode::Bins;
        bins.bins = resolveBins(look, package);
        ASSERT_EQ(static_cast<int>(bins.bins.size()), info.bin_count);
        LookEdit stops = look;
        stops.mode = EmissionMode::Stops;
        stops.stops.clear();
        for (int b = 0; b < info.bin_count; ++b) stops.stops.push_back({binCentre(info, b), bins.bins[static_cast<size_t>(b)]});
        const std::vector<float> want = renderThroughApi(package, info, look, 5);
        double peak = 0.0;
        for (size_t i = 0; i < want.size(); ++i)
            if (i % 4 != 3) peak = std::max(peak, static_cast<double>(want[i]));
        ASSERT_GT(peak, 0.0);
        for (const LookEdit* converted : {&bins, &stops}) {
            const std::vector<float> got = renderThroughApi(package, info, *converted, 5);
            for (size_t i = 0; i < want.size(); ++i)
                ASSERT_NEAR(got[i], want[i], 1e-6 * peak) << name << " value " << i;
        }
    }
    fl_package_release(package);
}

// The look QA renders while keys play is the one the instance shows (FireSession::shownLookJson, from
// the library). The package's frames are 5 and 6 (positions 5 to 7); the keys sit inside that range
// at binary fractions, so seeking (time = offset / 24 fps) lands exactly on the positions below.
TEST_F(ViewerUnit, KeyedLookHoldsAtKeysAndBlendsBetween) {
    std::unique_ptr<FireSession> session = FireSession::open(packagePath());
    const LookEdit a = parseLookEdit(readTextFile(looksDir() + "/fireball.json"), "a");
    const LookEdit b = parseLookEdit(readTextFile(looksDir() + "/smoky.json"), "b");
    session->keys() = {{5.25, a}, {6.25, b}};
    session->setAnimateKeys(true);
    const auto keyedLookJson = [&](double position) {
        session->seek(position);
        session->update(0.0);
        EXPECT_EQ(session->state().frame_position, position);
        return session->shownLookJson();
    };
    EXPECT_EQ(parseLookEdit(keyedLookJson(5.0), "k"), a);
    EXPECT_EQ(parseLookEdit(keyedLookJson(6.5), "k"), b);
    const LookEdit mid = parseLookEdit(keyedLookJson(5.75), "k");
    EXPECT_DOUBLE_EQ(mid.temperature_threshold, 0.5 * (a.temperature_threshold + b.temperature_threshold));
    EXPECT_DOUBLE_EQ(mid.smoke_extinction, 0.5 * (a.smoke_extinction + b.smoke_extinction));
    EXPECT_EQ(mid.mode, EmissionMode::Bins);
}

TEST(ViewerExport, SequenceFileNames) {
    EXPECT_EQ(sequenceFramePath("out/fire_####.exr", 12), "out/fire_0012.exr");
    EXPECT_EQ(sequenceFramePath("f_##.png", 7), "f_07.png");
    EXPECT_EQ(sequenceFramePath("out/fire.exr", 3), "out/fire_0003.exr");
}

TEST(ViewerQa, MeasuresAreThoseOfFirelookCompare) {
    // 2 pixels: RGB error (0.1, 0, 0) against a reference of squares summing to 1 + 1 = 2.
    const std::vector<float> reference = {1, 0, 0, 0.5f, 0, 1, 0, 1};
    const std::vector<float> image = {1.1f, 0, 0, 0.25f, 0, 1, 0, 1};
    const ErrorMeasures m = compareImages(image, reference, 2, 1);
    EXPECT_NEAR(m.relative_rmse, std::sqrt(0.01 / 2.0), 1e-6);
    EXPECT_NEAR(m.max_alpha_error, 0.25, 1e-7);
    std::vector<unsigned char> heat;
    makeHeatMap(image, reference, 2, 1, 1.0f, heat);
    ASSERT_EQ(heat.size(), 8u);
    EXPECT_GT(heat[0], 0);  // the pixel with an error is not black
    EXPECT_EQ(heat[4] + heat[5] + heat[6], 0);  // the exact one is
}

}  // namespace
}  // namespace firelook::viewer
