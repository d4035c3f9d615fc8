// The "bake" object of a package's metadata (runtime/basis/bake_description.h).
#include "basis/bake_description.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "look/look.h"

namespace firelook::basis {
namespace {

BakeDescription sampleDescription() {
    BakeDescription d;
    d.bins = {0.25, 3.125, 5};
    d.rbf_width = 0.7;
    d.albedo = 0.65;
    d.axes = {{1.0, 1.5, 2.0}, {2.0, 8.0}, {0.5}};
    d.alpha_thresholds = {1.0, 1.25, 1.5, 1.75, 2.0};
    d.light_directions = {{0.1, -0.9, 0.3}, {0.0, 0.0, -1.0}};
    d.width = 24;
    d.height = 16;
    d.frames = {{3, 7}, {4, 0}, {12, 31}};
    d.default_look_json = lookToJson(defaultLook());
    return d;
}

std::string descriptionErrorOf(const std::string& text, const std::string& source) {
    try {
        parseBakeDescription(text, source);
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

TEST(BakeDescription, CountsFollowBinsLightsAndAxes) {
    const BakeDescription d = sampleDescription();
    EXPECT_EQ(d.columnsPerPoint(), 5 + 2);
    EXPECT_EQ(d.columnCount(), 3 * 2 * 1 * 7);
    EXPECT_EQ(d.pixelCount(), 24 * 16);
    ASSERT_NE(d.findFrame(12), nullptr);
    EXPECT_EQ(d.findFrame(12)->rank, 31);
    EXPECT_EQ(d.findFrame(5), nullptr);
}

TEST(BakeDescription, JsonRoundTripIsExact) {
    const BakeDescription d = sampleDescription();
    const BakeDescription r = parseBakeDescription(bakeDescriptionToJson(d), "test");
    EXPECT_EQ(r.bins.t_lo, d.bins.t_lo);
    EXPECT_EQ(r.bins.t_hi, d.bins.t_hi);
    EXPECT_EQ(r.bins.count, d.bins.count);
    EXPECT_EQ(r.rbf_width, d.rbf_width);
    EXPECT_EQ(r.albedo, d.albedo);
    EXPECT_EQ(r.axes.temperature_threshold, d.axes.temperature_threshold);
    EXPECT_EQ(r.axes.smoke_extinction, d.axes.smoke_extinction);
    EXPECT_EQ(r.axes.flame_extinction, d.axes.flame_extinction);
    EXPECT_EQ(r.alpha_thresholds, d.alpha_thresholds);
    EXPECT_EQ(r.light_directions, d.light_directions);
    EXPECT_EQ(r.width, d.width);
    EXPECT_EQ(r.height, d.height);
    ASSERT_EQ(r.frames.size(), d.frames.size());
    for (size_t i = 0; i < d.frames.size(); ++i) {
        EXPECT_EQ(r.frames[i].frame, d.frames[i].frame);
        EXPECT_EQ(r.frames[i].rank, d.frames[i].rank);
    }
    // The look is stored as a JSON object (re-serialised), so compare its meaning.
    EXPECT_EQ(nlohmann::json::parse(r.default_look_json), nlohmann::json::parse(d.default_look_json));
    EXPECT_NO_THROW(parseLook(r.default_look_json, "round trip"));
}

TEST(BakeDescription, NoDefaultLookRoundTripsAsEmpty) {
    BakeDescription d = sampleDescription();
    d.default_look_json.clear();
    EXPECT_TRUE(parseBakeDescription(bakeDescriptionToJson(d), "test").default_look_json.empty());
}

TEST(BakeDescription, ParseErrorsNameTheSource) {
    const std::string good = bakeDescriptionToJson(sampleDescription());
    const std::string source = "/some/where/pkg.firelook";

    std::string e = descriptionErrorOf("{ not json", source);
    EXPECT_EQ(e.rfind(source, 0), 0u) << e;

    nlohmann::json j = nlohmann::json::parse(good);
    j.erase("albedo");
    e = descriptionErrorOf(j.dump(), source);
    EXPECT_EQ(e.rfind(source, 0), 0u) << e;
    EXPECT_NE(e.find("albedo"), std::string::npos) << e;

    j = nlohmann::json::parse(good);
    j["axes"]["smoke_extinction"] = {8.0, 2.0};
    e = descriptionErrorOf(j.dump(), source);
    EXPECT_EQ(e.rfind(source, 0), 0u) << e;
    EXPECT_NE(e.find("smoke_extinction"), std::string::npos) << e;

    j = nlohmann::json::parse(good);
    j["temperature_bins"]["count"] = 0;
    e = descriptionErrorOf(j.dump(), source);
    EXPECT_NE(e.find("bins"), std::string::npos) << e;

    j = nlohmann::json::parse(good);
    j["temperature_bins"]["t_hi"] = j["temperature_bins"]["t_lo"];
    EXPECT_NE(descriptionErrorOf(j.dump(), source).find(source), std::string::npos);

    j = nlohmann::json::parse(good);
    j["width"] = 0;
    e = descriptionErrorOf(j.dump(), source);
    EXPECT_NE(e.find("size"), std::string::npos) << e;

    j = nlohmann::json::parse(good);
    j["alpha_thresholds"] = nlohmann::json::array();
    e = descriptionErrorOf(j.dump(), source);
    EXPECT_NE(e.find("alpha"), std::string::npos) << e;

    j = nlohmann::json::parse(good);
    j["frames"] = "three";
    EXPECT_EQ(descriptionErrorOf(j.dump(), source).rfind(source, 0), 0u);
}

}  // namespace
}  // namespace firelook::basis
