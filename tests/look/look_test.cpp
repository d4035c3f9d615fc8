// The Look, the look file and its resolution into a LookModel.
#include "look/look.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "look/emission_presets.h"

namespace firelook {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSource = "looks/test_look.json";

const char* kValidLook = R"({
  "format": "firelook-look", "version": 1,
  "temperature_threshold": 1.4,
  "smoke_extinction": 6.0,
  "flame_extinction": 1.5,
  "albedo": 0.8,
  "emission": { "stops": [[0.0, 0,0,0], [1.0, 4,1,0.2], [2.0, 12,6,2]] },
  "light_irradiance": [[1.0, 0.95, 0.9]]
})";

// kValidLook with `key`'s value text replaced (the key must occur once).
std::string withValue(const std::string& key, const std::string& value) {
    std::string text = kValidLook;
    const size_t start = text.find("\"" + key + "\":") + key.size() + 3;
    size_t end = start;
    int depth = 0;
    while (depth > 0 || (text[end] != ',' && text[end] != '\n')) {
        depth += (text[end] == '[' || text[end] == '{') - (text[end] == ']' || text[end] == '}');
        ++end;
    }
    return text.substr(0, start) + " " + value + text.substr(end);
}

// Parses `text` expecting a LookError whose message names the file and `key`.
void expectError(const std::string& text, const std::string& key) {
    try {
        parseLook(text, kSource);
        ADD_FAILURE() << "no error for key " << key << " in\n" << text;
    } catch (const LookError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find(kSource), std::string::npos) << message;
        EXPECT_NE(message.find(key), std::string::npos) << message;
    }
}

class TempDir {
  public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = fs::temp_directory_path() /
                ("firelook_look_" + std::string(info->name()) + "_" + std::to_string(std::random_device{}()));
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ignored;
        fs::remove_all(path_, ignored);
    }
    const fs::path& path() const { return path_; }

  private:
    fs::path path_;
};

TEST(ParseLook, ReadsTheDesignNoteExample) {
    const Look look = parseLook(kValidLook, kSource);
    EXPECT_EQ(look.temperature_threshold, 1.4);
    EXPECT_EQ(look.smoke_extinction, 6.0);
    EXPECT_EQ(look.flame_extinction, 1.5);
    EXPECT_EQ(look.albedo, 0.8);
    ASSERT_TRUE(std::holds_alternative<EmissionStops>(look.emission));
    const auto& stops = std::get<EmissionStops>(look.emission).stops;
    ASSERT_EQ(stops.size(), 3u);
    EXPECT_EQ(stops[1].temperature, 1.0);
    EXPECT_EQ(stops[1].emissivity, Rgb(4.0f, 1.0f, 0.2f));
    ASSERT_EQ(look.light_irradiance.size(), 1u);
    EXPECT_EQ(look.light_irradiance[0], Rgb(1.0f, 0.95f, 0.9f));
    EXPECT_EQ(look.source_name, kSource);
}

TEST(ParseLook, IgnoresUnknownKeys) {
    std::string text = withValue("emission", R"({"stops": [[0, 1,1,1]], "interpolation": "cubic"})");
    text.insert(1, R"("comment": "made by hand", "future": {"x": [1, 2]},)");
    const Look look = parseLook(text, kSource);
    EXPECT_EQ(look.albedo, 0.8);
    EXPECT_EQ(std::get<EmissionStops>(look.emission).stops.size(), 1u);
}

TEST(ParseLook, ReadsBinsAndPresets) {
    const Look bins = parseLook(withValue("emission", R"({"bins": [[1,2,3], [4,5,6]]})"), kSource);
    ASSERT_TRUE(std::holds_alternative<EmissionBins>(bins.emission));
    EXPECT_EQ(std::get<EmissionBins>(bins.emission).emissivity[1], Rgb(4, 5, 6));

    const Look preset = parseLook(withValue("emission", R"({"preset": "blackbody", "scale": 3.5})"), kSource);
    ASSERT_TRUE(std::holds_alternative<EmissionPreset>(preset.emission));
    EXPECT_EQ(std::get<EmissionPreset>(preset.emission).name, "blackbody");
    EXPECT_EQ(std::get<EmissionPreset>(preset.emission).scale, 3.5);

    const Look unscaled = parseLook(withValue("emission", R"({"preset": "fire"})"), kSource);
    EXPECT_EQ(std::get<EmissionPreset>(unscaled.emission).scale, 1.0);
}

TEST(ParseLook, EveryErrorNamesTheFileAndTheKey) {
    expectError("{not json", "");
    expectError("[1, 2]", "");
    expectError(withValue("format", R"("firelook-package")"), "format");
    expectError(withValue("format", "7"), "format");
    expectError(withValue("version", "2"), "version");
    expectError(withValue("version", "1.5"), "version");
    expectError(withValue("version", "0"), "version");
    expectError(withValue("temperature_threshold", R"("hot")"), "temperature_threshold");
    expectError(withValue("smoke_extinction", "-1"), "smoke_extinction");
    expectError(withValue("flame_extinction", "1e400"),
                "1e400");  // the JSON reader names the number, not the key
    expectError(withValue("flame_extinction", "true"), "flame_extinction");
    expectError(withValue("albedo", "1.01"), "albedo");
    expectError(withValue("albedo", "-0.1"), "albedo");
    expectError(withValue("emission", "[]"), "emission");
    expectError(withValue("emission", "{}"), "emission");
    expectError(withValue("emission", R"({"bins": [[1,1,1]], "preset": "fire"})"), "emission");
    expectError(withValue("emission", R"({"bins": [[1,1]]})"), "emission.bins[0]");
    expectError(withValue("emission", R"({"bins": [[1,-1,1]]})"), "emission.bins[0]");
    expectError(withValue("emission", R"({"bins": [[1,1,1], [1,1e39,1]]})"),
                "emission.bins[1]");  // not a float
    expectError(withValue("emission", R"({"bins": [[1,"x",1]]})"), "emission.bins[0]");
    expectError(withValue("emission", R"({"bins": []})"), "emission.bins");
    expectError(withValue("emission", R"({"stops": [[1, 1,1,1], [0, 1,1,1]]})"), "emission.stops[1]");
    expectError(withValue("emission", R"({"stops": [[1, 1,1]]})"), "emission.stops[0]");
    expectError(withValue("emission", R"({"preset": "plasma"})"), "emission.preset");
    expectError(withValue("emission", R"({"preset": 3})"), "emission.preset");
    expectError(withValue("emission", R"({"preset": "fire", "scale": -2})"), "emission.scale");
    expectError(withValue("light_irradiance", "[[1, -1, 1]]"), "light_irradiance[0]");
    expectError(withValue("light_irradiance", "{}"), "light_irradiance");
    std::string missing = kValidLook;
    missing.replace(missing.find("\"albedo\""), 8,
                    "\"albedoo\"");  // a typo must not pass as "missing = default"
    expectError(missing, "albedo");
}

TEST(ParseLook, UnknownPresetListsTheKnownOnes) {
    try {
        parseLook(withValue("emission", R"({"preset": "plasma"})"), kSource);
        FAIL() << "expected LookError";
    } catch (const LookError& error) {
        for (const std::string& name : presetNames())
            EXPECT_NE(std::string(error.what()).find(name), std::string::npos);
    }
}

TEST(LookJson, RoundTripsExactly) {
    Look look;
    look.temperature_threshold = 0.1 + 1e-12;  // needs all 17 digits
    look.smoke_extinction = 1.0 / 3.0;
    look.flame_extinction = 0.0;
    look.albedo = 1.0;
    look.light_irradiance = {Rgb(0.1f, 1e-7f, 3e10f), Rgb(0.0f)};
    look.source_name = kSource;

    const std::vector<EmissionSpec> emissions = {
        EmissionBins{{Rgb(0.1f, 0.2f, 0.3f), Rgb(1.0f / 3.0f, 0.0f, 7.0f)}},
        EmissionStops{{{-1.5, Rgb(0.0f)}, {-1.5, Rgb(2.0f)}, {2.25e-5, Rgb(0.7f, 0.01f, 9.0f)}}},
        EmissionPreset{"blackbody", 12.5},
    };
    for (const EmissionSpec& emission : emissions) {
        look.emission = emission;
        const Look back = parseLook(lookToJson(look), kSource);
        EXPECT_EQ(back.temperature_threshold, look.temperature_threshold);
        EXPECT_EQ(back.smoke_extinction, look.smoke_extinction);
        EXPECT_EQ(back.flame_extinction, look.flame_extinction);
        EXPECT_EQ(back.albedo, look.albedo);
        EXPECT_EQ(back.light_irradiance, look.light_irradiance);
        EXPECT_EQ(back.emission.index(), look.emission.index());
        // Written text is stable: writing what was read gives the same bytes.
        EXPECT_EQ(lookToJson(back), lookToJson(look));
        const TemperatureBins bins{-2.0, 3.0, 2};
        EXPECT_EQ(resolveBinEmissivity(back, bins), resolveBinEmissivity(look, bins));
    }
    look.emission = emissions[1];
    const Look back = parseLook(lookToJson(look), kSource);
    const auto& stops = std::get<EmissionStops>(back.emission).stops;
    EXPECT_EQ(stops[2].temperature, 2.25e-5);
    EXPECT_EQ(stops[2].emissivity, Rgb(0.7f, 0.01f, 9.0f));
}

TEST(LookJson, DefaultLookRoundTripsAndIsValid) {
    const Look look = defaultLook();
    EXPECT_NO_THROW(validateLook(look));
    const Look back = parseLook(lookToJson(look), kSource);
    EXPECT_EQ(lookToJson(back), lookToJson(look));
}

TEST(LookJson, WritingAnInvalidLookFailsWithItsName) {
    Look look = defaultLook();
    look.source_name = "viewer edit";
    look.albedo = 2.0;
    try {
        lookToJson(look);
        FAIL() << "expected LookError";
    } catch (const LookError& error) {
        EXPECT_NE(std::string(error.what()).find("viewer edit"), std::string::npos);
        EXPECT_NE(std::string(error.what()).find("albedo"), std::string::npos);
    }
}

TEST(LookFile, SaveThenLoadLeavesNoTemporaryFile) {
    const TempDir dir;
    const fs::path path = dir.path() / "my look.json";
    saveLook(path, defaultLook());
    saveLook(path, defaultLook());  // replaces an existing file
    const Look loaded = loadLook(path);
    EXPECT_EQ(loaded.source_name, path.string());
    EXPECT_EQ(lookToJson(loaded), lookToJson(defaultLook()));
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

TEST(LookFile, LoadErrorsNameThePath) {
    const TempDir dir;
    const fs::path missing = dir.path() / "missing.json";
    try {
        loadLook(missing);
        FAIL() << "expected LookError";
    } catch (const LookError& error) {
        EXPECT_NE(std::string(error.what()).find(missing.string()), std::string::npos);
    }
    const fs::path bad = dir.path() / "bad.json";
    std::ofstream(bad) << withValue("albedo", "7");
    try {
        loadLook(bad);
        FAIL() << "expected LookError";
    } catch (const LookError& error) {
        EXPECT_NE(std::string(error.what()).find(bad.string()), std::string::npos);
        EXPECT_NE(std::string(error.what()).find("albedo"), std::string::npos);
    }
}

TEST(LookFile, SaveIntoAMissingFolderFailsWithThePathAndLeavesNothing) {
    const TempDir dir;
    const fs::path path = dir.path() / "no" / "such" / "folder" / "look.json";
    try {
        saveLook(path, defaultLook());
        FAIL() << "expected LookError";
    } catch (const LookError& error) {
        EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos);
    }
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(ResolveBinEmissivity, StopsAreLinearBetweenAndClampedOutside) {
    Look look = parseLook(kValidLook, kSource);  // stops at T = 0, 1, 2
    const TemperatureBins bins{-1.0, 3.0, 8};    // centres -0.75, -0.25, 0.25, ..., 2.75
    const std::vector<Rgb> e = resolveBinEmissivity(look, bins);
    EXPECT_EQ(e[0], Rgb(0.0f));               // below the first stop
    EXPECT_EQ(e[7], Rgb(12.0f, 6.0f, 2.0f));  // above the last
    const Rgb quarter = e[2];                 // T = 0.25
    EXPECT_FLOAT_EQ(quarter.r, 1.0f);
    EXPECT_FLOAT_EQ(quarter.b, 0.05f);
    EXPECT_FLOAT_EQ(e[4].r, 6.0f);  // T = 1.25: a quarter from 4 to 12
}

TEST(ResolveBinEmissivity, EqualStopTemperaturesMakeAStep) {
    Look look;
    look.emission = EmissionStops{{{1.0, Rgb(0.0f)}, {1.0, Rgb(5.0f)}}};
    const std::vector<Rgb> e = resolveBinEmissivity(look, TemperatureBins{0.0, 2.0, 4});
    EXPECT_EQ(e, (std::vector<Rgb>{Rgb(0), Rgb(0), Rgb(5), Rgb(5)}));
}

TEST(ResolveBinEmissivity, BinCountMismatchNamesTheFileAndKey) {
    const Look look = parseLook(withValue("emission", R"({"bins": [[1,1,1], [2,2,2], [3,3,3]]})"), kSource);
    EXPECT_EQ(resolveBinEmissivity(look, TemperatureBins{0.0, 1.0, 3}).size(), 3u);
    try {
        resolveBinEmissivity(look, TemperatureBins{0.0, 1.0, 16});
        FAIL() << "expected LookError";
    } catch (const LookError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find(kSource), std::string::npos);
        EXPECT_NE(message.find("emission.bins"), std::string::npos);
        EXPECT_NE(message.find("16"), std::string::npos);
    }
}

TEST(ResolveBinEmissivity, PresetIsScaledAndUnitIndependent) {
    Look look;
    look.emission = EmissionPreset{"fire", 4.0};
    const std::vector<Rgb> tiny = resolveBinEmissivity(look, TemperatureBins{0.0, 1e-3, 16});
    const std::vector<Rgb> huge = resolveBinEmissivity(look, TemperatureBins{300.0, 1e4, 16});
    EXPECT_EQ(tiny, huge);
    const EmissionPresetDefinition* fire = findEmissionPreset("fire");
    EXPECT_EQ(tiny[15], fire->evaluate(15.5 / 16) * 4.0f);
}

TEST(MakeLookModel, PairsLightsAndFitsEmission) {
    const Look look = defaultLook();
    const TemperatureBins bins{0.0, 3.0, 16};
    const std::vector<glm::dvec3> directions = {glm::dvec3(0.0, -2.0, 0.0)};
    const LookModel model = makeLookModel(look, bins, kDefaultRbfWidth, directions);
    EXPECT_EQ(model.albedo, look.albedo);
    EXPECT_EQ(model.extinction.temperature_threshold, 1.4);
    ASSERT_EQ(model.lights.size(), 1u);
    EXPECT_EQ(model.lights[0].direction, glm::dvec3(0.0, -1.0, 0.0));
    EXPECT_EQ(model.lights[0].irradiance, look.light_irradiance[0]);
    ASSERT_EQ(model.emission.coefficients.size(), 16u);
    // Smoke (below T_c) must not glow; the hottest bins glow orange-yellow (r > g > b).
    const Rgb cold = model.emission.evaluate(0.5);
    EXPECT_LT(std::max({cold.r, cold.g, cold.b}),
              1e-3f);  // the fit's tail from the first glowing bin is below this
    const Rgb hot = model.emission.evaluate(bins.center(15));
    EXPECT_GT(hot.r, hot.g);
    EXPECT_GT(hot.g, hot.b);
    EXPECT_GT(hot.b, 0.0f);

    const std::vector<glm::dvec3> two = {glm::dvec3(0, -1, 0), glm::dvec3(1, 0, 0)};
    EXPECT_THROW(makeLookModel(look, bins, kDefaultRbfWidth, two), LookError);
    const std::vector<glm::dvec3> zero = {glm::dvec3(0.0)};
    EXPECT_THROW(makeLookModel(look, bins, kDefaultRbfWidth, zero), LookError);
    EXPECT_THROW(makeLookModel(look, bins, 0.0, directions), LookError);
    EXPECT_THROW(makeLookModel(look, TemperatureBins{1.0, 1.0, 16}, kDefaultRbfWidth, directions), LookError);
}

TEST(MakeLookModel, WorksForOneAndSixtyFourBins) {
    const Look look = defaultLook();
    const std::vector<glm::dvec3> directions = {glm::dvec3(0, -1, 0)};
    for (int count : {1, 64}) {
        const LookModel model =
            makeLookModel(look, TemperatureBins{0.0, 3.0, count}, kDefaultRbfWidth, directions);
        ASSERT_EQ(static_cast<int>(model.emission.coefficients.size()), count);
        for (double t = -1.0; t <= 4.0; t += 0.01) {
            const Rgb v = model.emission.evaluate(t);
            EXPECT_TRUE(v.r >= 0.0f && v.g >= 0.0f && v.b >= 0.0f && std::isfinite(v.r)) << count << " " << t;
        }
    }
}

}  // namespace
}  // namespace firelook
