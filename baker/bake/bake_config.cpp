#include "bake/bake_config.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

#include "basis/sphere_lights.h"
#include "common/error.h"

namespace firelook::bake {

using nlohmann::json;

namespace {

std::vector<double> axisFromJson(const json& value) {
    if (value.is_number()) return {value.get<double>()};
    if (value.is_array()) return value.get<std::vector<double>>();
    // {"min": a, "max": b, "count": n, "spacing": "linear"|"geometric"}
    const double lo = value.at("min").get<double>(), hi = value.at("max").get<double>();
    const int count = value.at("count").get<int>();
    const bool geometric = value.value("spacing", std::string("linear")) == "geometric";
    if (count < 1 || (count > 1 && !(hi > lo)) || (geometric && !(lo > 0)))
        throw Error(ErrorCode::InvalidArgument,
                    "axis needs count >= 1, max > min (and min > 0 when geometric)");
    std::vector<double> out;
    for (int i = 0; i < count; ++i) {
        const double t = count == 1 ? 0.0 : double(i) / (count - 1);
        out.push_back(geometric ? lo * std::pow(hi / lo, t) : lo + t * (hi - lo));
    }
    return out;
}

void checkKeys(const json& object, const std::set<std::string>& known, const std::string& where) {
    for (const auto& [key, value] : object.items())
        if (!known.count(key))
            throw Error(ErrorCode::InvalidArgument, "unknown key '" + key + "' in " + where);
}

}  // namespace

void applyConfigFile(BakeConfig& c, const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) throw Error(ErrorCode::IoError, file.string() + ": cannot open bake config");
    try {
        std::stringstream text;
        text << in.rdbuf();
        const json j = json::parse(text.str());
        checkKeys(j, {"format", "version", "frames", "size", "bins", "t_lo", "t_hi", "rbf_width", "albedo", "axes",
                      "alpha_threshold_samples", "trace", "compression", "seed", "up", "density_grid",
                      "temperature_grid", "temperature_scale", "temperature_offset", "density_scale", "scene", "camera",
                      "memory_budget", "lights", "fire_lights", "fire_probes", "quality"},
                  "the bake config");
        // "all" is how configToJson records every frame, so a package's recorded settings bake again.
        if (j.contains("quality") && c.quality.empty()) applyQuality(c, j["quality"].get<std::string>());
        if (j.contains("frames")) c.frames = j["frames"].get<std::string>() == "all" ? "" : j["frames"].get<std::string>();
        if (j.contains("scene")) c.scene.scene_path = j["scene"].get<std::string>();
        if (j.contains("fire_lights")) c.fire_lights = j["fire_lights"].get<bool>();
        if (j.contains("fire_probes")) c.fire_probes = j["fire_probes"].get<int>();
        if (j.contains("lights")) {
            applyLightsChoice(c.scene, j["lights"].get<std::string>());
        }
        if (j.contains("camera")) {
            const std::vector<double> camera = j["camera"].get<std::vector<double>>();
            if (camera.size() != 7)
                throw Error(ErrorCode::InvalidArgument,
                            "camera needs 7 numbers: position, target, fov in degrees");
            std::array<double, 7> values;
            std::copy(camera.begin(), camera.end(), values.begin());
            c.scene.camera = values;
        }
        if (j.contains("size")) std::tie(c.scene.width, c.scene.height) = parseSize(j["size"].get<std::string>());
        if (j.contains("bins")) c.bins = j["bins"].get<int>();
        if (j.contains("t_lo")) c.t_lo = j["t_lo"].get<double>();
        if (j.contains("t_hi")) c.t_hi = j["t_hi"].get<double>();
        if (j.contains("rbf_width")) c.rbf_width = j["rbf_width"].get<double>();
        if (j.contains("albedo")) c.albedo = j["albedo"].get<double>();
        if (j.contains("alpha_threshold_samples")) c.alpha_threshold_samples = j["alpha_threshold_samples"].get<int>();
        if (j.contains("seed")) c.seed = j["seed"].get<uint64_t>();
        if (j.contains("up")) {
            const std::string up = j["up"].get<std::string>();
            if (up != "y" && up != "z")
                throw Error(ErrorCode::InvalidArgument, "up must be \"y\" or \"z\", not \"" + up + "\"");
            c.scene.up = up == "z" ? render::UpAxis::Z : render::UpAxis::Y;
        }
        if (j.contains("density_grid")) c.read.density_grid = j["density_grid"].get<std::string>();
        if (j.contains("temperature_grid")) c.read.temperature_grid = j["temperature_grid"].get<std::string>();
        if (j.contains("temperature_scale")) c.read.temperature_scale = j["temperature_scale"].get<double>();
        if (j.contains("temperature_offset")) c.read.temperature_offset = j["temperature_offset"].get<double>();
        if (j.contains("density_scale")) {
            c.read.density_scale = j["density_scale"].get<double>();
            if (!(c.read.density_scale > 0.0 && std::isfinite(c.read.density_scale)))
                throw Error(ErrorCode::InvalidArgument, "density_scale must be a positive number");
        }
        if (j.contains("axes")) {
            const json& a = j["axes"];
            checkKeys(a, {"temperature_threshold", "smoke_extinction", "flame_extinction", "collapse_unused"}, "axes");
            if (a.contains("collapse_unused")) c.collapse_unused_axes = a["collapse_unused"].get<bool>();
            const char* names[3] = {"temperature_threshold", "smoke_extinction", "flame_extinction"};
            std::optional<std::vector<double>>* axes[3] = {&c.axes.temperature_threshold, &c.axes.smoke_extinction,
                                                           &c.axes.flame_extinction};
            for (int i = 0; i < 3; ++i)
                if (a.contains(names[i])) *axes[i] = axisFromJson(a[names[i]]);
        }
        if (j.contains("trace")) {
            const json& t = j["trace"];
            checkKeys(t,
                      {"cell_voxels",
                       "max_cells_per_axis",
                       "max_cell_optical_depth",
                       "cell_pixel_footprints",
                       "min_cells_across",
                       "light_points_per_axis",
                       "photons_primary",
                       "photons_per_order",
                       "photon_noise_target",
                       "max_photon_scale",
                       "photon_pilot_share",
                       "min_order_photon_share",
                       "max_orders",
                       "order_tolerance",
                       "track_step_cells",
                       "step_voxels",
                       "footprint_step",
                       "footprint_samples_per_axis",
                       "radiance_samples_per_axis",
                       "radiance_quadrature_target",
                       "radiance_quadrature_noise_share",
                       "max_step_scale",
                       "step_radiance_target",
                       "step_alpha_target",
                       "step_mean_change_target"},
                      "trace");
            c.trace.cell_voxels = t.value("cell_voxels", c.trace.cell_voxels);
            c.trace.max_cells_per_axis = t.value("max_cells_per_axis", c.trace.max_cells_per_axis);
            c.trace.max_cell_optical_depth = t.value("max_cell_optical_depth", c.trace.max_cell_optical_depth);
            c.trace.cell_pixel_footprints = t.value("cell_pixel_footprints", c.trace.cell_pixel_footprints);
            c.trace.min_cells_across = t.value("min_cells_across", c.trace.min_cells_across);
            c.trace.light_points_per_axis = t.value("light_points_per_axis", c.trace.light_points_per_axis);
            c.trace.footprint_step = t.value("footprint_step", c.trace.footprint_step);
            c.trace.photons_primary = t.value("photons_primary", c.trace.photons_primary);
            c.trace.photons_per_order = t.value("photons_per_order", c.trace.photons_per_order);
            c.trace.photon_noise_target = t.value("photon_noise_target", c.trace.photon_noise_target);
            c.trace.max_photon_scale = t.value("max_photon_scale", c.trace.max_photon_scale);
            c.trace.photon_pilot_share = t.value("photon_pilot_share", c.trace.photon_pilot_share);
            c.trace.min_order_photon_share = t.value("min_order_photon_share", c.trace.min_order_photon_share);
            c.trace.max_orders = t.value("max_orders", c.trace.max_orders);
            c.trace.order_tolerance = t.value("order_tolerance", c.trace.order_tolerance);
            c.trace.track_step_cells = t.value("track_step_cells", c.trace.track_step_cells);
            c.trace.step_voxels = t.value("step_voxels", c.trace.step_voxels);
            c.trace.footprint_samples_per_axis = t.value("footprint_samples_per_axis", c.trace.footprint_samples_per_axis);
            c.trace.radiance_samples_per_axis = t.value("radiance_samples_per_axis", c.trace.radiance_samples_per_axis);
            c.trace.radiance_quadrature_target =
                t.value("radiance_quadrature_target", c.trace.radiance_quadrature_target);
            c.trace.radiance_quadrature_noise_share =
                t.value("radiance_quadrature_noise_share", c.trace.radiance_quadrature_noise_share);
            c.trace.max_step_scale = t.value("max_step_scale", c.trace.max_step_scale);
            c.trace.step_radiance_target = t.value("step_radiance_target", c.trace.step_radiance_target);
            c.trace.step_alpha_target = t.value("step_alpha_target", c.trace.step_alpha_target);
            c.trace.step_mean_change_target = t.value("step_mean_change_target", c.trace.step_mean_change_target);
        }
        if (j.contains("compression")) {
            const json& t = j["compression"];
            checkKeys(t, {"target_relative_error", "max_rank", "alpha_error", "footprint_error", "basis_error",
                          "target_size", "target_error"},
                      "compression");
            if (t.contains("target_size")) c.target.package_bytes = parseByteSize(t["target_size"].get<std::string>());
            if (t.contains("target_error")) c.target.basis_error = t["target_error"].get<double>();
            checkStorageTarget(c.target);
            c.compression.target_relative_error = t.value("target_relative_error", c.compression.target_relative_error);
            c.compression.max_rank = t.value("max_rank", c.compression.max_rank);
            c.storage.alpha_error = t.value("alpha_error", c.storage.alpha_error);
            c.storage.basis_error = t.value("basis_error", c.storage.basis_error);
            c.storage.footprint_error = t.value("footprint_error", c.storage.footprint_error);
        }
        basis::validateAxes(derivedAxes(c.axes, AxisDerivation{}));  // the given ones, the design's beside them
        if (c.bins < 1 || c.bins > 256) throw Error(ErrorCode::InvalidArgument, "bins must be 1..256");
        if (c.fire_probes != 0 && (c.fire_probes < 2 || c.fire_probes > kMaxFireProbeResolution))
            throw Error(ErrorCode::InvalidArgument, "fire_probes must be 0 (none) or 2.." +
                                                        std::to_string(kMaxFireProbeResolution) +
                                                        " probes an axis");
        if (!(c.albedo >= 0.0 && c.albedo <= 1.0))
            throw Error(ErrorCode::InvalidArgument, "albedo must be in [0, 1]");
        if (j.contains("memory_budget")) c.memory_budget_bytes = parseByteSize(j["memory_budget"].get<std::string>());
        if (c.trace.step_voxels <= 0.0 || c.trace.cell_voxels < 1 || c.trace.photons_primary < 1 ||
            c.trace.max_cells_per_axis < 1 || !(c.trace.max_cell_optical_depth > 0.0) ||
            !(c.trace.cell_pixel_footprints >= 0.0) || c.trace.min_cells_across < 1 ||
            c.trace.light_points_per_axis < 2 || !(c.trace.footprint_step >= 0.0) ||
            c.trace.photons_per_order < 1 || c.trace.footprint_samples_per_axis < 0 ||
            c.trace.footprint_samples_per_axis > 8 || c.trace.radiance_samples_per_axis < 0 ||
            c.trace.radiance_samples_per_axis > 8 || !(c.trace.radiance_quadrature_target >= 0.0) ||
            !(c.trace.radiance_quadrature_noise_share >= 0.0) || c.trace.max_step_scale < 1 ||
            c.trace.max_step_scale > 16 || !(c.trace.step_radiance_target >= 0.0) ||
            !(c.trace.step_alpha_target >= 0.0) ||
            !(c.trace.step_mean_change_target >= 0.0) || !(c.trace.photon_noise_target >= 0.0) ||
            c.trace.max_photon_scale < 1 || c.trace.max_photon_scale > 64 ||
            !(c.trace.photon_pilot_share > 0.0 && c.trace.photon_pilot_share <= 1.0) ||
            !(c.trace.min_order_photon_share > 0.0 && c.trace.min_order_photon_share <= 1.0) ||
            !(c.trace.track_step_cells > 0.0))
            throw Error(
                ErrorCode::InvalidArgument,
                "trace settings must be positive (footprint_samples_per_axis 0..8, 0 = from the image size; "
                "radiance_samples_per_axis 0..8, 0 = from radiance_quadrature_target (>= 0, 0 = every "
                "footprint ray) and radiance_quadrature_noise_share (>= 0); "
                "photon_noise_target >= 0, 0 = the photons as given; max_photon_scale 1..64; "
                "photon_pilot_share and min_order_photon_share in (0, 1]; track_step_cells > 0; cell_pixel_footprints >= 0, 0 = "
                "off; max_step_scale 1..16, 1 = step_voxels always; step_radiance_target, step_alpha_target and "
                "step_mean_change_target >= 0)");
    } catch (const Error& e) {
        throw Error(e.code(), file.string() + ": " + e.what());
    } catch (const std::exception& e) {  // nlohmann-json's: the file is not the JSON a config is
        throw Error(ErrorCode::InvalidArgument, file.string() + ": " + e.what());
    }
}

void checkStorageTarget(const StorageTarget& target) {
    if (target.package_bytes > 0 && target.basis_error > 0.0)
        throw Error(ErrorCode::InvalidArgument,
                    "a target size and a target error cannot both be given: one decides the other");
    if (target.basis_error != 0.0 && !(target.basis_error > 0.0 && target.basis_error < 1.0))
        throw Error(ErrorCode::InvalidArgument, "the target error must be a relative error in (0, 1), got " +
                                                    std::to_string(target.basis_error));
}

uint64_t parseByteSize(const std::string& text) {
    // A number with an optional binary unit: 6GiB, 6G, 512MiB, 512M, 1048576.
    std::size_t used = 0;
    double value = 0.0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    std::string unit = text.substr(used);
    if (unit.ends_with("iB")) unit.resize(unit.size() - 2);
    else if (unit.ends_with("B")) unit.resize(unit.size() - 1);
    double scale = 0.0;
    if (unit.empty()) scale = 1.0;
    else if (unit == "K" || unit == "k") scale = 1024.0;
    else if (unit == "M") scale = 1024.0 * 1024.0;
    else if (unit == "G") scale = 1024.0 * 1024.0 * 1024.0;
    else if (unit == "T") scale = 1024.0 * 1024.0 * 1024.0 * 1024.0;
    if (used == 0 || scale == 0.0 || !(value > 0.0) || !(value * scale < 1.8e19))
        throw Error(ErrorCode::InvalidArgument,
                    "a size must be a positive number with an optional unit K, M, G or T "
                    "(binary, e.g. 6G or 6GiB), got \"" +
                        text + "\"");
    return static_cast<uint64_t>(value * scale);
}

TraceSettings qualityTrace(const std::string& quality) {
    TraceSettings t;
    if (quality == "default") return t;
    if (quality == "preview") {
        t.radiance_samples_per_axis = 2;
        t.photon_noise_target = 0.02;
        t.photon_pilot_share = 0.25;
        t.max_photon_scale = 2;
        t.order_tolerance = 0.005;
        return t;
    }
    if (quality == "final") {
        t.step_voxels = 0.125;
        t.radiance_quadrature_target = 0.0;  // every footprint ray carries radiance
        t.max_step_scale = 1;                // at the fine step
        t.photon_noise_target = 0.005;
        t.max_photon_scale = 8;
        t.order_tolerance = 0.001;
        t.track_step_cells = 0.5;
        return t;
    }
    throw Error(ErrorCode::InvalidArgument, "quality must be preview, default or final, not \"" + quality + "\"");
}

void applyQuality(BakeConfig& config, const std::string& quality) {
    config.trace = qualityTrace(quality);
    config.quality = quality;
}

void applyLightsChoice(SceneOptions& scene, const std::string& lights) {
    scene.six_way_lights = lights == "six-way";
    scene.sphere_lights = 0;
    if (lights == "scene" || lights == "six-way") return;
    for (int n : basis::kSphereLightCounts)
        if (lights == "sphere:" + std::to_string(n)) scene.sphere_lights = n;
    if (lights == "sphere") scene.sphere_lights = kDefaultSphereLights;
    if (scene.sphere_lights == 0)
        throw Error(
            ErrorCode::InvalidArgument,
            "lights must be \"scene\", \"six-way\", \"sphere\", \"sphere:12\" or \"sphere:42\", not \"" +
                lights + "\"");
}

std::string lightsChoiceName(const SceneOptions& scene) {
    if (scene.six_way_lights) return "six-way";
    if (scene.sphere_lights > 0) return "sphere:" + std::to_string(scene.sphere_lights);
    return "scene";
}

std::string configToJson(const BakeConfig& c) {
    json j;
    j["frames"] = c.frames.empty() ? "all" : c.frames;
    j["size"] = std::to_string(c.scene.width) + "x" + std::to_string(c.scene.height);
    j["up"] = c.scene.up == render::UpAxis::Z ? "z" : "y";
    if (!c.scene.scene_path.empty()) j["scene"] = c.scene.scene_path;
    if (c.scene.camera) j["camera"] = *c.scene.camera;
    if (c.fire_lights) j["fire_lights"] = true;  // only when set, as "lights"
    if (c.fire_probes > 0) j["fire_probes"] = c.fire_probes;
    // Only when set: other bakes keep their settings hash.
    if (c.scene.six_way_lights || c.scene.sphere_lights > 0) j["lights"] = lightsChoiceName(c.scene);
    j["density_grid"] = c.read.density_grid;
    j["temperature_grid"] = c.read.temperature_grid;
    j["temperature_scale"] = c.read.temperature_scale;
    j["temperature_offset"] = c.read.temperature_offset;
    if (c.read.density_scale != 1.0) j["density_scale"] = c.read.density_scale;  // only when set: other bakes keep their settings hash
    j["bins"] = c.bins;
    if (c.t_lo) j["t_lo"] = *c.t_lo;
    if (c.t_hi) j["t_hi"] = *c.t_hi;
    j["rbf_width"] = c.rbf_width;
    j["albedo"] = c.albedo;
    // Only the given axes: an unset one reads back unset, and is derived again.
    j["axes"] = json::object();
    if (c.axes.temperature_threshold) j["axes"]["temperature_threshold"] = *c.axes.temperature_threshold;
    if (c.axes.smoke_extinction) j["axes"]["smoke_extinction"] = *c.axes.smoke_extinction;
    if (c.axes.flame_extinction) j["axes"]["flame_extinction"] = *c.axes.flame_extinction;
    j["axes"]["collapse_unused"] = c.collapse_unused_axes;
    j["alpha_threshold_samples"] = c.alpha_threshold_samples;
    // Only when set, so other bakes keep their settings hash; the trace keys below say the rest.
    if (!c.quality.empty() && c.quality != "default") j["quality"] = c.quality;
    j["trace"] = {{"cell_voxels", c.trace.cell_voxels},
                  {"max_cells_per_axis", c.trace.max_cells_per_axis},
                  {"max_cell_optical_depth", c.trace.max_cell_optical_depth},
                  {"cell_pixel_footprints", c.trace.cell_pixel_footprints},
                  {"min_cells_across", c.trace.min_cells_across},
                  {"light_points_per_axis", c.trace.light_points_per_axis},
                  {"footprint_step", c.trace.footprint_step},
                  {"photons_primary", c.trace.photons_primary},
                  {"photons_per_order", c.trace.photons_per_order},
                  {"photon_noise_target", c.trace.photon_noise_target},
                  {"max_photon_scale", c.trace.max_photon_scale},
                  {"photon_pilot_share", c.trace.photon_pilot_share},
                  {"min_order_photon_share", c.trace.min_order_photon_share},
                  {"max_orders", c.trace.max_orders},
                  {"order_tolerance", c.trace.order_tolerance},
                  {"track_step_cells", c.trace.track_step_cells},
                  {"step_voxels", c.trace.step_voxels},
                  {"footprint_samples_per_axis", c.trace.footprint_samples_per_axis},
                  {"radiance_samples_per_axis", c.trace.radiance_samples_per_axis},
                  {"radiance_quadrature_target", c.trace.radiance_quadrature_target},
                  {"radiance_quadrature_noise_share", c.trace.radiance_quadrature_noise_share},
                  {"max_step_scale", c.trace.max_step_scale},
                  {"step_radiance_target", c.trace.step_radiance_target},
                  {"step_alpha_target", c.trace.step_alpha_target},
                  {"step_mean_change_target", c.trace.step_mean_change_target}};
    j["compression"] = {{"target_relative_error", c.compression.target_relative_error},
                        {"max_rank", c.compression.max_rank},
                        {"alpha_error", c.storage.alpha_error},
                        {"footprint_error", c.storage.footprint_error},
                        {"basis_error", c.storage.basis_error}};
    // Only when given, so that packages baked without a target keep their recorded settings.
    if (c.target.package_bytes > 0) j["compression"]["target_size"] = std::to_string(c.target.package_bytes);
    if (c.target.basis_error > 0.0) j["compression"]["target_error"] = c.target.basis_error;
    j["seed"] = c.seed;
    return j.dump();
}

}  // namespace firelook::bake
