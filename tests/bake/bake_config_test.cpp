// The --config bake.json (baker/bake/bake_config.h): every key applied, axis forms, and errors that
// name the file.
#include "bake/bake_config.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../support/temp_dir.h"

namespace firelook::bake {
namespace {

using firelook::testing::TempDir;

std::filesystem::path writeConfig(const TempDir& dir, const std::string& text) {
    const auto path = dir / "bake.json";
    std::ofstream(path) << text;
    return path;
}

BakeConfig apply(const TempDir& dir, const std::string& text) {
    BakeConfig c;
    applyConfigFile(c, writeConfig(dir, text));
    return c;
}

std::string errorOf(const TempDir& dir, const std::string& text) {
    try {
        apply(dir, text);
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

TEST(BakeConfig, AppliesEveryKey) {
    TempDir dir;
    const BakeConfig c = apply(dir, R"({
        "format": "firelook-bake", "version": 1,
        "frames": "2-5", "size": "32x24", "bins": 8, "t_lo": -1, "t_hi": 4, "rbf_width": 0.8,
        "albedo": 0.5, "alpha_threshold_samples": 9, "seed": 42, "up": "z",
        "density_grid": "smoke", "temperature_grid": "heat", "temperature_scale": 0.001,
        "temperature_offset": -273,
        "axes": {"temperature_threshold": [1, 2], "smoke_extinction": 3, "flame_extinction": [0.5, 1]},
        "trace": {"cell_voxels": 2, "photons_primary": 100, "photons_per_order": 50, "max_orders": 3,
                  "order_tolerance": 0.01, "step_voxels": 0.25, "photon_pilot_share": 0.5,
                  "min_order_photon_share": 0.5, "radiance_quadrature_target": 0.002,
                  "radiance_quadrature_noise_share": 0.5, "cell_pixel_footprints": 2.5, "min_cells_across": 20,
                  "max_step_scale": 2, "step_radiance_target": 0.0005, "step_alpha_target": 0.002,
                  "step_mean_change_target": 0.001, "track_step_cells": 0.75},
        "compression": {"target_relative_error": 0.01, "max_rank": 7}
    })");
    EXPECT_EQ(c.frames, "2-5");
    EXPECT_EQ(c.scene.width, 32);
    EXPECT_EQ(c.scene.height, 24);
    EXPECT_EQ(c.bins, 8);
    EXPECT_EQ(c.t_lo, -1.0);
    EXPECT_EQ(c.t_hi, 4.0);
    EXPECT_EQ(c.rbf_width, 0.8);
    EXPECT_EQ(c.albedo, 0.5);
    EXPECT_EQ(c.alpha_threshold_samples, 9);
    EXPECT_EQ(c.seed, 42u);
    EXPECT_EQ(c.scene.up, render::UpAxis::Z);
    EXPECT_EQ(c.read.density_grid, "smoke");
    EXPECT_EQ(c.read.temperature_grid, "heat");
    EXPECT_EQ(c.read.temperature_scale, 0.001);
    EXPECT_EQ(c.read.temperature_offset, -273.0);
    EXPECT_EQ(c.axes.temperature_threshold, (std::vector<double>{1.0, 2.0}));
    EXPECT_EQ(c.axes.smoke_extinction, (std::vector<double>{3.0}));
    EXPECT_EQ(c.axes.flame_extinction, (std::vector<double>{0.5, 1.0}));
    EXPECT_EQ(c.trace.cell_voxels, 2);
    EXPECT_EQ(c.trace.photons_primary, 100);
    EXPECT_EQ(c.trace.photons_per_order, 50);
    EXPECT_EQ(c.trace.max_orders, 3);
    EXPECT_EQ(c.trace.order_tolerance, 0.01);
    EXPECT_EQ(c.trace.track_step_cells, 0.75);
    EXPECT_EQ(c.trace.step_voxels, 0.25);
    EXPECT_EQ(c.trace.photon_pilot_share, 0.5);
    EXPECT_EQ(c.trace.min_order_photon_share, 0.5);
    EXPECT_EQ(c.trace.radiance_quadrature_target, 0.002);
    EXPECT_EQ(c.trace.radiance_quadrature_noise_share, 0.5);
    EXPECT_EQ(c.trace.cell_pixel_footprints, 2.5);
    EXPECT_EQ(c.trace.min_cells_across, 20);
    EXPECT_EQ(c.trace.max_step_scale, 2);
    EXPECT_EQ(c.trace.step_radiance_target, 0.0005);
    EXPECT_EQ(c.trace.step_alpha_target, 0.002);
    EXPECT_EQ(c.trace.step_mean_change_target, 0.001);
    EXPECT_EQ(c.compression.target_relative_error, 0.01);
    EXPECT_EQ(c.compression.max_rank, 7);
}

TEST(BakeConfig, AbsentKeysKeepTheDefaults) {
    TempDir dir;
    const BakeConfig defaults;
    const BakeConfig c = apply(dir, R"({"bins": 4, "trace": {"max_orders": 2}})");
    EXPECT_EQ(c.bins, 4);
    EXPECT_EQ(c.trace.max_orders, 2);
    EXPECT_EQ(c.trace.photons_primary, defaults.trace.photons_primary);
    EXPECT_EQ(c.axes.smoke_extinction, defaults.axes.smoke_extinction);
    EXPECT_FALSE(c.axes.smoke_extinction.has_value()) << "not given: derived from the data";
    EXPECT_EQ(c.albedo, defaults.albedo);
    EXPECT_FALSE(c.t_lo.has_value());
}

TEST(BakeConfig, AxisForms) {
    TempDir dir;
    BakeConfig c = apply(dir, R"({"axes": {
        "temperature_threshold": {"min": 1, "max": 2, "count": 5},
        "smoke_extinction": {"min": 1, "max": 16, "count": 5, "spacing": "geometric"},
        "flame_extinction": {"min": 0.5, "max": 0.5, "count": 1}}})");
    ASSERT_TRUE(c.axes.temperature_threshold && c.axes.smoke_extinction);
    const std::vector<double>& tc = *c.axes.temperature_threshold;
    const std::vector<double>& ks = *c.axes.smoke_extinction;
    ASSERT_EQ(tc.size(), 5u);
    for (int i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(tc[i], 1.0 + 0.25 * i);
    ASSERT_EQ(ks.size(), 5u);
    // lo (hi/lo)^t: pow() rounding, a few ulps.
    for (int i = 0; i < 5; ++i) EXPECT_NEAR(ks[i], std::pow(2.0, i), 1e-12 * std::pow(2.0, i));
    EXPECT_EQ(c.axes.flame_extinction, (std::vector<double>{0.5}));

    c = apply(dir, R"({"axes": {"smoke_extinction": 2.5, "flame_extinction": [0.25, 1, 4]}})");
    EXPECT_EQ(c.axes.smoke_extinction, (std::vector<double>{2.5}));
    EXPECT_EQ(c.axes.flame_extinction, (std::vector<double>{0.25, 1.0, 4.0}));
}

// "axes": {"collapse_unused": false} keeps every sample (docs/bake-config.md); recorded, so it bakes again.
TEST(BakeConfig, CollapseUnusedAxesKey) {
    TempDir dir;
    EXPECT_TRUE(BakeConfig().collapse_unused_axes) << "on by default";
    BakeConfig c = apply(dir, R"({"axes": {"collapse_unused": false, "smoke_extinction": 3}})");
    EXPECT_FALSE(c.collapse_unused_axes);
    EXPECT_EQ(c.axes.smoke_extinction, (std::vector<double>{3.0}));
    const nlohmann::json j = nlohmann::json::parse(configToJson(c));
    EXPECT_EQ(j.at("axes").at("collapse_unused"), false);
    EXPECT_TRUE(apply(dir, R"({"axes": {"collapse_unused": true}})").collapse_unused_axes);
    EXPECT_THROW(apply(dir, R"({"axes": {"collapse_unused": "no"}})"), std::runtime_error);
}

TEST(BakeConfig, ErrorsNameTheFileAndTheProblem) {
    TempDir dir;
    const std::string file = (dir / "bake.json").string();
    const auto expectError = [&](const std::string& text, const std::string& what) {
        const std::string e = errorOf(dir, text);
        EXPECT_EQ(e.rfind(file, 0), 0u) << "for " << text << ": " << e;
        EXPECT_NE(e.find(what), std::string::npos) << "for " << text << ": " << e;
    };
    expectError(R"({"bins": 4, "photons": 100})", "photons");
    expectError(R"({"trace": {"photon_count": 10}})", "photon_count");
    expectError(R"({"axes": {"T_c": [1, 2]}})", "T_c");
    expectError(R"({"compression": {"rank": 4}})", "rank");
    expectError(R"({"bins": 4,)", "");
    expectError(R"({"bins": 0})", "bins");
    expectError(R"({"bins": "many"})", "");
    expectError(R"({"albedo": 1.5})", "albedo");
    expectError(R"({"size": "16by16"})", "size");
    expectError(R"({"axes": {"smoke_extinction": [4, 2]}})", "smoke_extinction");
    expectError(R"({"axes": {"flame_extinction": []}})", "flame_extinction");
    expectError(R"({"axes": {"smoke_extinction": {"min": 2, "max": 1, "count": 3}}})", "axis");
    expectError(R"({"axes": {"smoke_extinction": {"min": 0, "max": 1, "count": 3, "spacing": "geometric"}}})",
                "geometric");
    expectError(R"({"axes": {"smoke_extinction": {"min": 1, "max": 2}}})", "count");
    expectError(R"({"trace": {"step_voxels": 0}})", "trace");
    expectError(R"({"trace": {"photon_pilot_share": 0}})", "photon_pilot_share");
    expectError(R"({"trace": {"photon_pilot_share": 1.5}})", "photon_pilot_share");
    expectError(R"({"trace": {"min_order_photon_share": 0}})", "min_order_photon_share");
    expectError(R"({"trace": {"min_order_photon_share": 2}})", "min_order_photon_share");
    expectError(R"({"trace": {"radiance_samples_per_axis": 9}})", "radiance_samples_per_axis");
    expectError(R"({"trace": {"radiance_quadrature_noise_share": -1}})", "radiance_quadrature_noise_share");
    expectError(R"({"trace": {"cell_pixel_footprints": -1}})", "cell_pixel_footprints");
    expectError(R"({"trace": {"min_cells_across": 0}})", "trace");
    expectError(R"({"trace": {"track_step_cells": 0}})", "track_step_cells");
    expectError(R"({"trace": {"max_step_scale": 0}})", "max_step_scale");
    expectError(R"({"trace": {"max_step_scale": 17}})", "max_step_scale");
    expectError(R"({"trace": {"step_alpha_target": -0.1}})", "step_alpha_target");
    expectError(R"({"trace": {"step_mean_change_target": -0.1}})", "step_mean_change_target");
    expectError(R"({"trace": {"step_radiance_target": -0.1}})", "step_radiance_target");
    expectError(R"({"quality": "best"})", "preview, default or final");
    expectError(R"({"up": "x"})", "up");
    expectError(R"({"camera": [0, 0, 10, 0, 0, 0]})", "camera");

    BakeConfig c;
    try {
        applyConfigFile(c, dir / "missing.json");
        ADD_FAILURE() << "no error for a missing file";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("missing.json"), std::string::npos) << e.what();
    }
}

// A quality preset sets the trace settings (baker/bake/bake_config.h); a file's "trace" keys change
// single settings of it, and firelook bake --quality (applied before the file) wins over its key.
TEST(BakeConfig, QualityPresetsAndTheirOverrides) {
    TempDir dir;
    const TraceSettings defaults;
    const TraceSettings preview = qualityTrace("preview"), final_ = qualityTrace("final");
    BakeConfig named_default;
    applyQuality(named_default, "default");
    EXPECT_EQ(configToJson(named_default), configToJson(BakeConfig()))
        << "default is the declared settings, recorded the same";
    EXPECT_EQ(preview.step_voxels, defaults.step_voxels);
    EXPECT_LT(final_.step_voxels, defaults.step_voxels) << "final: the finer step";
    EXPECT_GT(preview.photon_noise_target, defaults.photon_noise_target);
    EXPECT_LT(preview.photon_pilot_share, defaults.photon_pilot_share);
    EXPECT_LT(final_.photon_noise_target, defaults.photon_noise_target);
    EXPECT_EQ(radianceSamplesPerAxis(defaults, 4), 4) << "default and final: up to every footprint ray";
    EXPECT_EQ(radianceCandidates(defaults, 4), (std::vector<int>{1, 2}))
        << "default: one ray or 2x2 where their error allows";
    EXPECT_EQ(radianceSamplesPerAxis(final_, 4), 4);
    EXPECT_EQ(radianceCandidates(final_, 4), std::vector<int>{}) << "final: every footprint ray";
    EXPECT_EQ(stepScaleCandidates(final_), std::vector<int>{}) << "final: at its finer step always";
    EXPECT_EQ(defaults.track_step_cells, 1.0) << "default: photon tracks step a cell";
    EXPECT_EQ(preview.track_step_cells, 1.0);
    EXPECT_EQ(final_.track_step_cells, 0.5) << "final: half a cell";
    EXPECT_EQ(stepScaleCandidates(preview), (std::vector<int>{2, 4, 8, 16}));
    EXPECT_EQ(stepScaleCandidates(defaults), (std::vector<int>{2, 4, 8, 16}));
    EXPECT_EQ(radianceSamplesPerAxis(preview, 4), 2) << "preview: 2x2 of them";

    const BakeConfig from_file = apply(dir, R"({"quality": "preview", "trace": {"step_voxels": 0.2}})");
    EXPECT_EQ(from_file.quality, "preview");
    EXPECT_EQ(from_file.trace.photon_noise_target, preview.photon_noise_target);
    EXPECT_EQ(from_file.trace.step_voxels, 0.2) << "the file's trace key changes the preset";

    BakeConfig flag;
    applyQuality(flag, "final");
    applyConfigFile(flag, writeConfig(dir, R"({"quality": "preview"})"));
    EXPECT_EQ(flag.quality, "final") << "the flag wins over the file's key";
    EXPECT_EQ(flag.trace.photon_noise_target, final_.photon_noise_target);

    // Recorded with the preset's name and every trace key: baked again, the same settings.
    const std::string recorded = configToJson(from_file);
    EXPECT_EQ(nlohmann::json::parse(recorded).at("quality"), "preview");
    BakeConfig again;
    applyConfigFile(again, writeConfig(dir, recorded));
    EXPECT_EQ(configToJson(again), recorded);
    EXPECT_THROW(qualityTrace("fast"), std::runtime_error);
}

TEST(BakeConfig, ConfigToJsonRecordsTheSettings) {
    BakeConfig c;
    c.frames = "3";
    c.seed = 77;
    c.axes = {{1.0}, {2.0, 3.0}, {0.5}};
    const nlohmann::json j = nlohmann::json::parse(configToJson(c));
    EXPECT_EQ(j.at("frames"), "3");
    EXPECT_EQ(j.at("seed"), 77);
    EXPECT_EQ(j.at("axes").at("smoke_extinction"), (std::vector<double>{2.0, 3.0}));
    EXPECT_EQ(j.at("size"), "256x256");
    EXPECT_EQ(j.at("trace").at("photons_primary"), c.trace.photons_primary);
    EXPECT_EQ(nlohmann::json::parse(configToJson(BakeConfig())).at("frames"), "all") << "empty frames = all";
}

// The settings a package records (provenance.settings) are a valid bake.json that gives the same
// settings back, so a package can be baked again from what it says about itself.
TEST(BakeConfig, RecordedSettingsBakeAgain) {
    TempDir dir;
    BakeConfig c;
    c.frames = "2-5";
    c.seed = 9;
    c.scene.width = 64;
    c.scene.up = render::UpAxis::Z;
    c.scene.scene_path = "shot.gltf";
    c.scene.camera = std::array<double, 7>{1, 2, 3, 0, 0, 0, 40};
    c.axes = {{1.0, 1.5}, {2.0, 3.0}, {0.5}};
    c.trace.footprint_samples_per_axis = 4;
    c.compression.max_rank = 12;
    const std::string recorded = configToJson(c);
    BakeConfig again;
    applyConfigFile(again, writeConfig(dir, recorded));
    EXPECT_EQ(configToJson(again), recorded);

    BakeConfig all;
    applyConfigFile(all, writeConfig(dir, configToJson(BakeConfig())));
    EXPECT_EQ(all.frames, "") << "\"all\" reads back as every frame";
}

}  // namespace
}  // namespace firelook::bake
