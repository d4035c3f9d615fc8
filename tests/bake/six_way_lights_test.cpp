// `firelook bake --lights six-way` (basis/six_way_lights.h): the six camera-relative lights'
// directions, columns that leave every other column's bytes alone, a default look that keeps them
// off, and light columns that respond.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "../support/temp_dir.h"
#include "bake/bake_pipeline.h"
#include "added_lights_check.h"
#include "bake_test_support.h"
#include "basis/basis_package.h"
#include "basis/look_renderer.h"
#include "basis/six_way_lights.h"
#include "look/look.h"
#include "tiny_sample_bake.h"

namespace firelook::bake {
namespace {

using firelook::testing::TempDir;

// The head-on camera sits at +Z looking down -Z with +X right and +Y up, so the camera frame is the
// world frame and each light's travel direction is exact.
TEST(SixWayLights, TravelOppositeToTheSideTheyComeFrom) {
    const auto d = basis::sixWayTravelDirections(test::headOnCamera(8).worldFromCamera());
    const glm::dvec3 expected[6] = {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}};
    for (int l = 0; l < 6; ++l) {
        EXPECT_NEAR(glm::length(d[l] - expected[l]), 0.0, 1e-12) << basis::kSixWayLightNames[l];
    }
}

// The bins and the scene's light are the same bytes with the six-way lights added.
TEST(SixWayLights, LeaveEveryOtherColumnBitForBit) {
    const render::Medium medium = test::unitBox(2.0f, 0.6f);
    const render::Camera camera = test::headOnCamera(12, 30.0);
    const BasisModel plain = test::basisModel(3, 0.8, {{0.5}, {2.0}, {1.0}});
    BasisModel six = plain;
    six.six_way_first_light = 1;
    for (const glm::dvec3& d : basis::sixWayTravelDirections(camera.worldFromCamera()))
        six.light_directions.push_back(d);
    test::expectAddedLightsLeaveEveryOtherColumn(medium, camera, plain, six, 6, [](int l) {
        return std::string(basis::kSixWayLightNames[l]);
    });
}

double relativeRmse(const std::vector<float>& image, const std::vector<float>& reference) {
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < image.size(); ++i) {
        if (i % 4 == 3) continue;
        num += double(image[i] - reference[i]) * (image[i] - reference[i]);
        den += double(reference[i]) * reference[i];
    }
    return den > 0.0 ? std::sqrt(num / den) : 0.0;
}

std::vector<float> render(const basis::BasisReader& package, int frame, const Look& look) {
    const basis::BakeDescription& d = package.description();
    std::vector<float> rgba(static_cast<size_t>(d.pixelCount()) * 4);
    basis::renderLookImage(d, package.loadResidentFrame(frame, std::pmr::get_default_resource()), look, rgba);
    return rgba;
}

TEST(SixWayLights, PackageDefaultLookMatchesTheBakeWithoutThemAndEachLightResponds) {
    TempDir dir;
    BakeConfig config = test::tinyConfig();
    config.frames = "6";
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / "plain.firelook", config, "test");
    config.scene.six_way_lights = true;
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / "six.firelook", config, "test");
    const basis::BasisReader plain = basis::BasisReader::open(dir / "plain.firelook");
    const basis::BasisReader six = basis::BasisReader::open(dir / "six.firelook");
    const basis::BakeDescription& d = six.description();
    ASSERT_EQ(d.light_directions.size(), 7u);
    EXPECT_EQ(d.six_way_first_light, 1);
    const Look look = parseLook(d.default_look_json, "six-way default look");
    ASSERT_EQ(look.light_irradiance.size(), 7u);
    for (int l = 1; l < 7; ++l) EXPECT_EQ(look.light_irradiance[l], Rgb(0.0f)) << "six-way light " << l << " is on";
    const Look plain_look = parseLook(plain.description().default_look_json, "plain default look");
    EXPECT_EQ(look.light_irradiance[0], plain_look.light_irradiance[0]);

    // The traced columns they share are equal (test above); the packages differ by how each frame's
    // SVD truncation (target 0.003 of the whole basis's Frobenius norm) and storage (basis_error
    // 0.0005) spread over its columns: the default image moved by 0.09% here; 1% leaves room for
    // a look whose image carries a small share of the basis's norm.
    const std::vector<float> a = render(plain, 6, plain_look), b = render(six, 6, look);
    const double err = relativeRmse(b, a);
    std::printf("default look, six-way package against plain: relative RMSE %.5f\n", err);
    EXPECT_LT(err, 0.01);
    for (size_t i = 3; i < a.size(); i += 4) ASSERT_NEAR(a[i], b[i], 1e-6) << "alpha comes from the same depths";

    // Each light alone (no emission) gives a lit image.
    Look dark = look;
    dark.emission = EmissionBins{std::vector<Rgb>(d.bins.count, Rgb(0.0f))};
    for (int l = 0; l < 6; ++l) {
        Look one = dark;
        std::fill(one.light_irradiance.begin(), one.light_irradiance.end(), Rgb(0.0f));
        one.light_irradiance[1 + l] = Rgb(1.0f);
        const std::vector<float> image = render(six, 6, one);
        double sum = 0.0;
        for (size_t i = 0; i < image.size(); i += 4) sum += image[i];
        EXPECT_GT(sum, 0.0) << basis::kSixWayLightNames[l];
    }
    const nlohmann::json meta = nlohmann::json::parse(six.metadataJson());
    EXPECT_EQ(meta.at("provenance").at("settings").at("lights"), "six-way");
    EXPECT_FALSE(nlohmann::json::parse(plain.metadataJson()).at("provenance").at("settings").contains("lights"));
}

}  // namespace
}  // namespace firelook::bake
