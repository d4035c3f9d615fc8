// Unit tests of the viewer's non-GL parts (compiled from samples/viewer): the editable look and
// its JSON, the keyframe file, emission form conversions (which must not change the look), the
// export file names, the QA error measures and the "Match target" fit session. No display needed.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "../support/temp_dir.h"
#include "image/image_io.h"
#include "fl_check.h"
#include "fire_session.h"
#include "fit_session.h"
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
        // Edit -> library -> JSON -> library is the same look, and the library's own JSON of the file.
        EXPECT_EQ(parseLookEdit(canonicalLookJson(look), "again"), look) << name;
        EXPECT_EQ(loadLookEdit(file), look) << name;
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

// Look files, the emission presets and bad files all come from the library (fl_look_load_file,
// fl_emission_preset_name, fl_look_create), not from a copy of the schema in the viewer.
TEST_F(ViewerUnit, LooksAndPresetsComeFromTheLibrary) {
    std::vector<std::string> names = presetNames();
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"blackbody", "fire"}));
    const std::string missing = looksDir() + "/no_such_look.json";
    try {
        loadLookEdit(missing);
        FAIL() << "loaded a missing file";
    } catch (const ViewerError& e) {
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("FL_ERROR_IO"), std::string::npos) << e.what();
    }
    LookEdit bad = loadLookEdit(looksDir() + "/fireball.json");
    bad.smoke_extinction = -1.0;
    try {
        canonicalLookJson(bad);
        FAIL() << "accepted a negative extinction";
    } catch (const ViewerError& e) {
        EXPECT_NE(std::string(e.what()).find("smoke_extinction"), std::string::npos) << e.what();
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

// CPU image of one look through the C API (the fit session's renderer).
std::vector<float> renderThroughApi(fl_package package, const fl_package_info& info, const LookEdit& look, int frame) {
    const fl_look handle = makeFlLook(look, "test");
    std::vector<float> rgba = renderLookImage(package, info, handle, frame);
    fl_look_release(handle);
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


// ---- Match target (fit_session.h) ----

// Polls until the fit leaves Running (the 64x64 package fits in well under a second in release;
// the bound only keeps a broken fit from hanging the suite, also under the sanitizers).
FitSnapshot waitForFit(const FitSession& fit) {
    FitSnapshot snapshot;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(100);
    while (std::chrono::steady_clock::now() < deadline) {
        fit.poll(snapshot);
        if (snapshot.status != FitStatus::Running) return snapshot;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ADD_FAILURE() << "the fit did not finish";
    return snapshot;
}

double relativeRmse(const std::vector<float>& image, const std::vector<float>& target) {
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < target.size(); ++i) {
        if (i % 4 == 3) continue;
        num += (image[i] - target[i]) * (image[i] - target[i]);
        den += static_cast<double>(target[i]) * target[i];
    }
    return std::sqrt(num / den);
}

// A target rendered from a known look inside the baked ranges, written as a float EXR.
struct KnownTarget {
    LookEdit look;
    std::vector<float> rgba;
};
KnownTarget writeKnownTarget(FireSession& session, const std::string& path) {
    const fl_package_info& info = session.info();
    KnownTarget known;
    known.look = session.look();
    known.look.temperature_threshold = 0.5 * (info.temperature_threshold_min + info.temperature_threshold_max);
    known.look.smoke_extinction = 0.5 * (info.smoke_extinction_min + info.smoke_extinction_max);
    known.look.preset_scale *= 1.5;
    known.rgba = renderThroughApi(session.package(), info, known.look, 5);
    image::ImageRGBA img(info.width, info.height);
    img.pixels = known.rgba;
    image::WriteOptions options;
    options.exr_pixel_type = image::ExrPixelType::Float;
    image::writeImage(path, img, options);
    return known;
}

TEST_F(ViewerUnit, FitMatchesATargetOfAKnownLookAndAcceptSetsIt) {
    firelook::testing::TempDir dir;
    std::unique_ptr<FireSession> session = FireSession::open(packagePath());
    const std::string target = (dir.path() / "target.exr").string();
    const KnownTarget known = writeKnownTarget(*session, target);
    FitSession fit;
    FitRequest request;
    request.frame = 5;
    request.target = target;
    fit.start(session->package(), session->info(), request);
    const FitSnapshot done = waitForFit(fit);
    ASSERT_EQ(done.status, FitStatus::Done) << done.error;
    // The fit's self-consistency bar (README "Look fitting"): within 0.5 % relative RMSE of the target.
    EXPECT_LT(done.report.relative_rmse, 0.005);
    EXPECT_LT(relativeRmse(done.fit_rgba, known.rgba), 0.005);
    EXPECT_EQ(done.target_rgba, known.rgba);
    ASSERT_EQ(done.difference_rgba.size(), known.rgba.size());
    for (size_t i = 0; i < known.rgba.size(); i += 4)
        ASSERT_FLOAT_EQ(done.difference_rgba[i], std::abs(done.fit_rgba[i] - known.rgba[i])) << i;
    EXPECT_DOUBLE_EQ(done.fraction, 1.0);

    // Accept: the edited look becomes the fitted one and the viewer's instance shows the fit's image.
    fit.accept(*session);
    EXPECT_EQ(session->look(), parseLookEdit(done.look_json, "fitted"));
    EXPECT_EQ(session->look().mode, EmissionMode::Bins);
    session->setOutputs(true, FlareSettings{});
    session->seek(5.0);
    session->update(0.0);
    std::vector<float> shown;
    session->readImage(shown);
    EXPECT_EQ(shown, done.fit_rgba);
}

TEST_F(ViewerUnit, CancelledFitLeavesTheLookUnchanged) {
    firelook::testing::TempDir dir;
    std::unique_ptr<FireSession> session = FireSession::open(packagePath());
    const std::string target = (dir.path() / "target.exr").string();
    writeKnownTarget(*session, target);
    const LookEdit before = session->look();
    FitSession fit;
    FitRequest request;
    request.frame = 5;
    request.target = target;
    fit.start(session->package(), session->info(), request);
    fit.cancel();
    FitSnapshot snapshot;
    fit.poll(snapshot);
    EXPECT_EQ(snapshot.status, FitStatus::Cancelled);
    EXPECT_TRUE(snapshot.fit_rgba.empty());
    EXPECT_THROW(fit.accept(*session), ViewerError);
    EXPECT_EQ(session->look(), before);
}

TEST_F(ViewerUnit, FitErrorsNameTheFile) {
    firelook::testing::TempDir dir;
    std::unique_ptr<FireSession> session = FireSession::open(packagePath());
    FitSession fit;
    const auto messageOf = [&](const FitRequest& request) {
        try {
            fit.start(session->package(), session->info(), request);
        } catch (const ViewerError& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    FitRequest request;
    request.frame = 5;
    request.target = (dir.path() / "missing.exr").string();
    EXPECT_NE(messageOf(request).find(request.target), std::string::npos) << messageOf(request);

    const std::string small = (dir.path() / "small.exr").string();
    image::writeImage(small, image::ImageRGBA(3, 2));
    request.target = small;
    const std::string wrong_size = messageOf(request);
    EXPECT_NE(wrong_size.find(small), std::string::npos) << wrong_size;
    EXPECT_NE(wrong_size.find("3x2"), std::string::npos) << wrong_size;

    const std::string target = (dir.path() / "target.exr").string();
    writeKnownTarget(*session, target);
    request.target = target;
    request.mask_kind = MaskKind::File;
    request.mask = (dir.path() / "no_mask.png").string();
    EXPECT_NE(messageOf(request).find(request.mask), std::string::npos);

    // A threshold above every pixel's luminance leaves nothing to fit.
    request.mask_kind = MaskKind::Threshold;
    request.threshold = 1e30f;
    const std::string nothing = messageOf(request);
    EXPECT_NE(nothing.find(target), std::string::npos) << nothing;
    EXPECT_NE(nothing.find("threshold"), std::string::npos) << nothing;
}

// The threshold mask leaves out the pixels at or below it: a fit to a target whose masked-out
// pixels were spoiled still recovers the look.
TEST_F(ViewerUnit, ThresholdMaskLeavesPixelsOut) {
    firelook::testing::TempDir dir;
    std::unique_ptr<FireSession> session = FireSession::open(packagePath());
    const std::string clean = (dir.path() / "clean.exr").string();
    const KnownTarget known = writeKnownTarget(*session, clean);
    // Spoil the transparent pixels with a colour (alpha kept 0): only a mask on alpha ignores them.
    image::ImageRGBA spoiled(session->info().width, session->info().height);
    spoiled.pixels = known.rgba;
    size_t spoiled_count = 0;
    for (size_t p = 0; p < spoiled.pixels.size() / 4; ++p)
        if (spoiled.pixels[4 * p + 3] <= 0.0f) {
            spoiled.pixels[4 * p] = 5.0f;
            ++spoiled_count;
        }
    ASSERT_GT(spoiled_count, 0u);
    const std::string target = (dir.path() / "spoiled.exr").string();
    image::WriteOptions options;
    options.exr_pixel_type = image::ExrPixelType::Float;
    image::writeImage(target, spoiled, options);
    FitSession fit;
    FitRequest request;
    request.frame = 5;
    request.target = target;
    request.mask_kind = MaskKind::Threshold;
    request.threshold_on_alpha = true;
    request.threshold = 0.0f;
    fit.start(session->package(), session->info(), request);
    const FitSnapshot done = waitForFit(fit);
    ASSERT_EQ(done.status, FitStatus::Done) << done.error;
    EXPECT_LT(relativeRmse(done.fit_rgba, known.rgba), 0.005);
}

}  // namespace
}  // namespace firelook::viewer
