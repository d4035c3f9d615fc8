// The look axes and default look derived from the data (bake/axis_derivation.h): the bundled
// sample keeps the design's axes exactly, the same data in other units gets the units' image of
// them, and a bake in other units renders the same image with its default look.
#include "bake/axis_derivation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "../support/temp_dir.h"
#include "package_images.h"
#include "bake/bake_pipeline.h"
#include "basis/basis_package.h"
#include "basis/frame_factors.h"
#include "basis/look_renderer.h"
#include "look/look.h"
#include "tiny_sample_bake.h"
#include "vdb/vdb_sequence.h"

namespace firelook::bake {
namespace {

using firelook::testing::TempDir;

TEST(AxisDerivation, RoundsToTwoSignificantDigits) {
    EXPECT_EQ(roundTwoDigits(1.0), 1.0);
    EXPECT_EQ(roundTwoDigits(0.9987), 1.0);
    EXPECT_EQ(roundTwoDigits(0.2497), 0.25);
    EXPECT_EQ(roundTwoDigits(1006.7), 1000.0);
    EXPECT_EQ(roundTwoDigits(4.99), 5.0);
    EXPECT_EQ(roundTwoDigits(0.001234), 0.0012);
    EXPECT_EQ(roundTwoDigits(123456.0), 120000.0);
}

TEST(AxisDerivation, DesignRangeAndDepthAreTheIdentity) {
    const AxisDerivation d = deriveAxes({}, {kDesignTLo, kDesignTHi, 16}, {true, kDesignDensityDepth, 1.0, 1.0});
    EXPECT_TRUE(d.identity());
    const BakeConfig config;
    EXPECT_EQ(derivedAxes(config.axes, d).temperature_threshold, designAxes().temperature_threshold);
    EXPECT_EQ(lookToJson(derivedDefaultLook(d)), lookToJson(defaultLook()));
}

TEST(AxisDerivation, GivenAxesAreKeptAndNoDensityKeepsTheExtinctions) {
    // Kelvin-like bins, no density measured: temperatures mapped, extinction factor 1.
    BakeAxes given;
    given.design = {{1.0, 2.0}, {4.0}, {1.5}};
    given.smoke_extinction = {3.0};
    const AxisDerivation d = deriveAxes(given, {300.0, 3300.0, 16}, {});
    EXPECT_EQ(d.derived, (std::array<bool, 3>{true, false, true}));
    EXPECT_EQ(d.temperature_scale, 1000.0);
    EXPECT_EQ(d.temperature_offset, 300.0);
    EXPECT_EQ(d.extinction_scale, 1.0);
    const basis::ParameterAxes axes = derivedAxes(given, d);
    EXPECT_EQ(axes.temperature_threshold, (std::vector<double>{1300.0, 2300.0}));
    EXPECT_EQ(axes.smoke_extinction, (std::vector<double>{3.0})) << "given, not the design's";
    EXPECT_EQ(axes.flame_extinction, (std::vector<double>{1.5}));
    // A derived k_f with a depth 4x the design's: a quarter of the design's k.
    BakeAxes two_given = given;
    two_given.temperature_threshold = {1.0, 2.0};
    const AxisDerivation denser = deriveAxes(two_given, {300.0, 3300.0, 16}, {true, 4.0 * kDesignDensityDepth, 4.0, 1.0});
    EXPECT_EQ(derivedAxes(two_given, denser).flame_extinction, (std::vector<double>{0.375}));
    EXPECT_EQ(derivedAxes(two_given, denser).temperature_threshold, (std::vector<double>{1.0, 2.0})) << "given";
    EXPECT_EQ(derivedAxes(two_given, denser).smoke_extinction, (std::vector<double>{3.0})) << "given";
}

// The bundled sample at the defaults: every factor exactly 1, so its axes, alpha thresholds and
// default look are the design's to the bit (and its packages keep their bytes).
TEST(AxisDerivation, BundledSampleKeepsTheDesignAxes) {
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(FIRELOOK_SAMPLE_DIR);
    BakeConfig config;
    config.scene.width = config.scene.height = 16;
    config.scene.up = render::UpAxis::Z;
    const SceneSetup scene = resolveScene(sequence, config.scene);
    const DescribedBake derived = describeDerivedBake(sequence, config, scene);
    std::printf("sample: bins [%g, %g], density p99 %.4g, dense side %.4g, depth %.4g\n",
                derived.derivation.t_lo, derived.derivation.t_hi, derived.derivation.density.density_p99,
                derived.derivation.density.dense_side, derived.derivation.density.depth);
    EXPECT_EQ(derived.derivation.derived, (std::array<bool, 3>{true, true, true}));
    EXPECT_TRUE(derived.derivation.identity());
    EXPECT_EQ(derived.description.axes.temperature_threshold, designAxes().temperature_threshold);
    EXPECT_EQ(derived.description.axes.smoke_extinction, designAxes().smoke_extinction);
    EXPECT_EQ(derived.description.axes.flame_extinction, designAxes().flame_extinction);
    BakeConfig given = config;
    given.axes = designAxes();  // all three given
    const basis::BakeDescription fixed = describeBake(sequence, given, scene);
    EXPECT_EQ(derived.description.alpha_thresholds, fixed.alpha_thresholds);
    EXPECT_EQ(derived.description.default_look_json, fixed.default_look_json);
}

// Axes set in code are given, as bake.json's are, with no flag to forget: on data 4x denser, where the
// derivation quarters the design's extinctions, the ones set are baked as set and only the one left
// unset is scaled. (When "given" was a separate flag, tests that set axes in code had them scaled a
// second time.)
TEST(AxisDerivation, AxesSetInCodeAreGiven) {
    vdb::ReadOptions denser;
    denser.density_scale = 4.0;
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(FIRELOOK_SAMPLE_DIR, denser);
    BakeConfig config;
    config.scene.width = config.scene.height = 16;
    config.scene.up = render::UpAxis::Z;
    config.axes.temperature_threshold = {1.5};
    config.axes.smoke_extinction = {2.0, 8.0};
    const SceneSetup scene = resolveScene(sequence, config.scene);
    const DescribedBake bake = describeDerivedBake(sequence, config, scene);
    EXPECT_EQ(bake.derivation.extinction_scale, 0.25);
    EXPECT_EQ(bake.derivation.derived, (std::array<bool, 3>{false, false, true}));
    EXPECT_EQ(bake.description.axes.temperature_threshold, (std::vector<double>{1.5}));
    EXPECT_EQ(bake.description.axes.smoke_extinction, (std::vector<double>{2.0, 8.0}));
    EXPECT_EQ(bake.description.axes.flame_extinction, (std::vector<double>{0.125, 0.25, 0.5, 1.0}));
}

// A small bake whose axes are derived from the design {1, 2} x {4} x {1.5}; frame 6 (the fire
// well under way), 24x24.
BakeConfig derivedTinyConfig() {
    BakeConfig c = test::tinyConfig();
    c.frames = "6";
    c.scene.width = c.scene.height = 24;
    c.axes = BakeAxes{};
    c.axes.design = {{1.0, 2.0}, {4.0}, {1.5}};
    return c;
}

std::vector<float> renderDefaultLook(const std::filesystem::path& file, int frame) {
    const basis::BasisReader package = basis::BasisReader::open(file);
    return test::renderFrame(package, frame, parseLook(package.description().default_look_json, "default"));
}

// `image` against `reference` (package_images.h), which must not be empty.
test::ImageDifference compare(const std::vector<float>& image, const std::vector<float>& reference) {
    const test::ImageDifference d = test::compareImages(image, reference);
    EXPECT_GT(d.reference_norm, 0.0) << "an empty image proves nothing";
    return d;
}

// The sample's temperatures read as Kelvin (T_K = 1000 T + 300): the bins, axes, alpha thresholds
// and default look are the affine image of the unscaled bake's, and the default render the same.
TEST(AxisDerivation, KelvinTemperaturesGiveTheAffineImage) {
    TempDir dir;
    BakeConfig celsius_like = derivedTinyConfig();
    BakeConfig kelvin = celsius_like;
    kelvin.read.temperature_scale = 1000.0;
    kelvin.read.temperature_offset = 300.0;
    kelvin.t_lo = 300.0;
    kelvin.t_hi = 3300.0;
    const BakeReport a = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "a.firelook", celsius_like, "test");
    std::vector<std::string> notices;
    const BakeReport b = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "b.firelook", kelvin, "test", {},
                                     [&](const std::string& line) { notices.push_back(line); });
    EXPECT_TRUE(a.derivation.identity());
    EXPECT_EQ(b.derivation.temperature_scale, 1000.0);
    EXPECT_EQ(b.derivation.temperature_offset, 300.0);
    EXPECT_EQ(b.derivation.extinction_scale, 1.0);
    ASSERT_FALSE(notices.empty());
    EXPECT_NE(notices[0].find("look axes from the data: temperatures x1000 +300"), std::string::npos) << notices[0];

    const basis::BasisReader pa = basis::BasisReader::open(dir / "a.firelook");
    const basis::BasisReader pb = basis::BasisReader::open(dir / "b.firelook");
    const basis::BakeDescription &da = pa.description(), &db = pb.description();
    ASSERT_EQ(da.axes.temperature_threshold.size(), db.axes.temperature_threshold.size());
    for (size_t i = 0; i < da.axes.temperature_threshold.size(); ++i)
        EXPECT_NEAR(db.axes.temperature_threshold[i], 1000.0 * da.axes.temperature_threshold[i] + 300.0, 1e-9);
    ASSERT_EQ(da.alpha_thresholds.size(), db.alpha_thresholds.size());
    for (size_t i = 0; i < da.alpha_thresholds.size(); ++i)
        EXPECT_NEAR(db.alpha_thresholds[i], 1000.0 * da.alpha_thresholds[i] + 300.0, 1e-9);
    EXPECT_EQ(db.axes.smoke_extinction, da.axes.smoke_extinction);
    const Look la = parseLook(da.default_look_json, "a"), lb = parseLook(db.default_look_json, "b");
    EXPECT_NEAR(lb.temperature_threshold, 1000.0 * la.temperature_threshold + 300.0, 1e-9);
    const auto& sa = std::get<EmissionStops>(la.emission).stops;
    const auto& sb = std::get<EmissionStops>(lb.emission).stops;
    ASSERT_EQ(sa.size(), sb.size());
    for (size_t i = 0; i < sa.size(); ++i) EXPECT_NEAR(sb[i].temperature, 1000.0 * sa[i].temperature + 300.0, 1e-9);
    const nlohmann::json meta = nlohmann::json::parse(pb.metadataJson());
    EXPECT_EQ(meta.at("axis_derivation").at("temperature").at("scale"), 1000.0);
    EXPECT_FALSE(nlohmann::json::parse(pa.metadataJson()).contains("axis_derivation")) << "identity: not recorded";

    // Same physics in other units, same seed: the traces differ only by float rounding of the
    // temperatures (1000 T + 300 in float32 keeps ~7 digits), never by the seed's noise (measured
    // 1.1e-9 relative RMSE, alpha identical).
    const test::ImageDifference d = compare(renderDefaultLook(dir / "b.firelook", 6), renderDefaultLook(dir / "a.firelook", 6));
    std::printf("Kelvin vs unscaled default render: relative RMSE %.2e, worst alpha %.2e\n", d.relative_rmse,
                d.worst_alpha);
    EXPECT_LT(d.relative_rmse, 1e-3);
    EXPECT_LT(d.worst_alpha, 1e-3);
}

// Density read 4x denser (ReadOptions::density_scale): the extinction axes and the default look's
// k a quarter of the unscaled bake's, the optical depths and so the default render the same.
TEST(AxisDerivation, DenserDataGetsProportionallySmallerExtinctions) {
    TempDir dir;
    BakeConfig plain = derivedTinyConfig();
    BakeConfig dense = plain;
    dense.read.density_scale = 4.0;
    const BakeReport a = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "a.firelook", plain, "test");
    const BakeReport b = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "b.firelook", dense, "test");
    EXPECT_EQ(a.derivation.extinction_scale, 1.0);
    EXPECT_EQ(b.derivation.extinction_scale, 0.25);
    EXPECT_NEAR(b.derivation.density.depth, 4.0 * a.derivation.density.depth, 1e-6 * a.derivation.density.depth);
    const basis::BasisReader pa = basis::BasisReader::open(dir / "a.firelook");
    const basis::BasisReader pb = basis::BasisReader::open(dir / "b.firelook");
    const basis::BakeDescription &da = pa.description(), &db = pb.description();
    EXPECT_EQ(db.axes.smoke_extinction, (std::vector<double>{1.0}));
    EXPECT_EQ(db.axes.flame_extinction, (std::vector<double>{0.375}));
    EXPECT_EQ(db.axes.temperature_threshold, da.axes.temperature_threshold);
    const Look la = parseLook(da.default_look_json, "a"), lb = parseLook(db.default_look_json, "b");
    EXPECT_EQ(lb.smoke_extinction, 0.25 * la.smoke_extinction);
    EXPECT_EQ(lb.flame_extinction, 0.25 * la.flame_extinction);

    // k rho is the same product in other factors, and the emissivity per unit density scales with k:
    // alpha agrees to float rounding (measured 0); the colours to the tracer's photon noise, whose
    // emission photons are drawn from the absolute emission the density scales (measured 2.8e-3
    // relative RMSE with the tiny bake's 2000 photons; the bound leaves room for other platforms).
    const test::ImageDifference d = compare(renderDefaultLook(dir / "b.firelook", 6), renderDefaultLook(dir / "a.firelook", 6));
    std::printf("4x density vs unscaled default render: relative RMSE %.2e, worst alpha %.2e\n", d.relative_rmse,
                d.worst_alpha);
    EXPECT_LT(d.relative_rmse, 1e-2);
    EXPECT_LT(d.worst_alpha, 1e-3);
}

// Axes a bake.json gives win over the derivation; the others are still derived.
TEST(AxisDerivation, BakeJsonAxesAreGiven) {
    TempDir dir;
    {
        std::ofstream(dir / "bake.json") << R"({"axes": {"smoke_extinction": [3.0]}})";
    }
    BakeConfig c;
    applyConfigFile(c, dir / "bake.json");
    EXPECT_FALSE(c.axes.temperature_threshold.has_value());
    EXPECT_EQ(c.axes.smoke_extinction, (std::vector<double>{3.0}));
    EXPECT_FALSE(c.axes.flame_extinction.has_value());
    const AxisDerivation d = deriveAxes(c.axes, {kDesignTLo, kDesignTHi, 16}, {});
    EXPECT_EQ(d.derived, (std::array<bool, 3>{true, false, true}));
}

}  // namespace
}  // namespace firelook::bake
