#include "cli/cycles_scene.h"

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "basis/look_renderer.h"
#include "cli/cycles_scene_py.h"  // kCyclesScenePython: cycles_scene.py, embedded by CMake
#include "cli/version.h"
#include "common/error.h"
#include "reference/provenance_read_options.h"
#include "vdb/frame_files.h"
#include "vdb/read_options.h"
#include "world/package_camera.h"

namespace firelook::cli {
namespace {

using nlohmann::ordered_json;

// The frame's file in `sequence`.
std::filesystem::path frameFile(const std::string& sequence, int frame) {
    for (const vdb::FrameFile& f : vdb::findFrameFiles(sequence))
        if (f.number == frame) return std::filesystem::absolute(f.path);
    throw Error(ErrorCode::NotFound, sequence + ": the sequence has no frame " + std::to_string(frame));
}

}  // namespace

std::string cyclesSceneScript(const basis::BasisReader& package, const std::string& package_name, int frame,
                              const Look& look, const std::string& sequence,
                              const CyclesSettings& settings) {
    const basis::BakeDescription& d = package.description();
    if (!d.findFrame(frame))
        throw Error(ErrorCode::NotFound, package_name + ": the package holds no frame " + std::to_string(frame));
    basis::checkBakedAlbedo(d, look);
    const LookModel model = makeLookModel(look, d.bins, d.rbf_width, d.light_directions);
    const std::optional<world::PackageCamera> camera = world::readPackageCamera(package.metadataJson(), package_name);
    if (!camera) throw Error(ErrorCode::NotFound, package_name + ": the package records no camera");
    const vdb::ReadOptions read = reference::provenanceReadOptions(package.metadataJson(), package_name);

    ordered_json scene;
    scene["firelook_version"] = kToolVersion;
    scene["package"] = package_name;
    scene["frame"] = frame;
    scene["vdb"] = frameFile(sequence, frame).string();
    scene["read"] = {{"density_grid", read.density_grid},
                     {"temperature_grid", read.temperature_grid},
                     {"density_scale", read.density_scale},
                     {"temperature_scale", read.temperature_scale},
                     {"temperature_offset", read.temperature_offset}};
    // The reader refuses denser voxels or clamps them to this bound (--clamp-extreme): either way
    // the bake saw nothing denser.
    scene["max_density"] = vdb::kMaxPlausibleDensity;
    scene["camera"] = {{"world_from_camera", camera->world_from_camera},
                       {"yfov_radians", camera->yfov_radians},
                       {"width", camera->width},
                       {"height", camera->height}};
    scene["bins"] = {{"t_lo", d.bins.t_lo}, {"t_hi", d.bins.t_hi}, {"count", d.bins.count}};
    scene["rbf_width"] = d.rbf_width;
    scene["emission_clamp"] = d.emission_clamp_to_centres ? "bin_centres" : "range";
    scene["look"] = {{"temperature_threshold", look.temperature_threshold},
                     {"smoke_extinction", look.smoke_extinction},
                     {"flame_extinction", look.flame_extinction},
                     {"albedo", look.albedo}};
    ordered_json coefficients = ordered_json::array();
    for (const Rgb& c : model.emission.coefficients) coefficients.push_back({c.r, c.g, c.b});
    scene["emission_coefficients"] = coefficients;
    ordered_json lights = ordered_json::array();
    for (const DirectionalLight& l : model.lights)
        if (std::max({l.irradiance.r, l.irradiance.g, l.irradiance.b}) > 0.0f)  // off: no lamp at all
            lights.push_back({{"direction", {l.direction.x, l.direction.y, l.direction.z}},
                              {"irradiance", {l.irradiance.r, l.irradiance.g, l.irradiance.b}}});
    scene["lights"] = lights;
    scene["step_voxels"] = settings.step_voxels;
    scene["volume_max_steps"] = settings.volume_max_steps;
    scene["volume_bounces"] = settings.volume_bounces;

    // JSON in a Python raw string, which json.loads reads exactly as written; a quote inside a
    // string (a path) is written as the JSON escape, so nothing can end the literal early.
    std::string json = scene.dump(2);
    for (size_t at = json.find('\''); at != std::string::npos; at = json.find('\'', at))
        json.replace(at, 1, "\\u0027");
    return "# Written by `firelook export-cycles` (firelook " + std::string(kToolVersion) + "): frame " +
           std::to_string(frame) + " of " + package_name + " with " + look.source_name +
           ".\n# Run: blender -b --factory-startup --python THIS.py -- --spp N -o OUT.exr [--seed S]\n"
           "import json\nSCENE = json.loads(r'''" +
           json + "''')\n\n" + kCyclesScenePython;
}

}  // namespace firelook::cli
