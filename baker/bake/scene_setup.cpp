#include "bake/scene_setup.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "basis/six_way_lights.h"
#include "basis/sphere_lights.h"
#include "common/error.h"
#include "gltf/gltf_scene.h"
#include "vdb/frame_grids.h"

namespace firelook::bake {

SceneSetup resolveScene(const vdb::VdbSequence& sequence, const SceneOptions& options) {
    std::optional<render::Camera> camera;
    SceneSetup setup{render::Camera(render::CameraParameters{}), {}, {}, "default", -1, -1, {}};
    if (!options.scene_path.empty()) {
        const gltf::Scene scene = gltf::loadScene(options.scene_path);
        if (scene.camera)
            camera = render::Camera::fromWorldFromCamera(scene.camera->world_from_camera, scene.camera->yfov_radians,
                                                         options.width, options.height);
        for (const gltf::DirectionalLight& light : scene.lights) {
            setup.light_directions.push_back(light.direction);
            setup.light_colors.push_back(Rgb(light.color * light.intensity));
        }
        setup.camera_source = options.scene_path;
    }
    if (options.camera) {
        const auto& c = *options.camera;
        const glm::dvec3 up = options.up == render::UpAxis::Z ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
        camera = render::Camera::lookAt({c[0], c[1], c[2]}, {c[3], c[4], c[5]}, up, c[6] * std::numbers::pi / 180.0,
                                        options.width, options.height);
        setup.camera_source = "--camera";
    }
    if (!camera) {
        const vdb::Aabb& bounds = sequence.sequenceWorldBounds();
        if (bounds.empty())
            throw Error(ErrorCode::BadVolume,
                        sequence.source() + ": every frame is empty; no camera can frame it");
        camera = render::defaultCamera(bounds.min, bounds.max, options.up, options.width, options.height);
    }
    setup.camera = *camera;
    if (options.scene_path.empty()) {
        // Key light from above, slightly from the camera's side, so lit smoke shows its shape.
        const glm::dvec3 down = options.up == render::UpAxis::Z ? glm::dvec3(0.35, 0.45, -0.82)
                                                                : glm::dvec3(0.35, -0.82, -0.45);
        setup.light_directions.push_back(glm::normalize(down));
        setup.light_colors.push_back(Rgb(1.0f, 0.95f, 0.9f));
    }
    if (options.six_way_lights && options.sphere_lights > 0)
        throw Error(ErrorCode::InvalidArgument, "--lights takes six-way or a sphere, not both");
    const glm::dmat4 world_from_camera = setup.camera.worldFromCamera();
    if (options.sphere_lights > 0) {
        setup.sphere_first_light = static_cast<int>(setup.light_directions.size());
        setup.sphere_triangles = basis::geodesicSphere(options.sphere_lights).triangles;
        for (const glm::dvec3& d : basis::sphereTravelDirections(world_from_camera, options.sphere_lights)) {
            setup.light_directions.push_back(d);
            setup.light_colors.push_back(Rgb(0.0f));  // off in the default look, as the six-way lights
        }
    }
    if (options.six_way_lights) {
        setup.six_way_first_light = static_cast<int>(setup.light_directions.size());
        for (const glm::dvec3& d : basis::sixWayTravelDirections(world_from_camera)) {
            setup.light_directions.push_back(d);
            setup.light_colors.push_back(Rgb(0.0f));  // off in the default look: a look turns them on
        }
    }
    return setup;
}

void TemperatureSpan::add(const vdb::VolumeFrame& frame) {
    // From the ambient temperature (the grid's background, after the read's temperature mapping:
    // 0 for Blender's 0-based heat, 300 for the same in Kelvin), so ambient air sits in bin 0 and
    // a mapped temperature gives the mapped range.
    const double ambient = frame.grids->temperature->background();
    lo = std::min(lo.value_or(ambient), ambient);
    hi = std::max(hi.value_or(ambient), ambient);
    if (frame.temperature_stats.active_voxels == 0) return;
    lo = std::min(*lo, frame.temperature_stats.min);
    hi = std::max(*hi, frame.temperature_stats.max);
}

std::pair<double, double> TemperatureSpan::range() const {
    const double l = lo.value_or(0.0), h = hi.value_or(0.0);
    return {l, h > l ? h : l + 1.0};  // a constant field still needs a non-empty range
}

std::pair<double, double> sequenceTemperatureRange(const vdb::VdbSequence& sequence) {
    TemperatureSpan span;
    for (const vdb::FrameFile& file : sequence.frames()) span.add(sequence.load(file.number));
    return span.range();
}

std::vector<std::pair<int, int>> parseFrameRanges(const std::string& selection) {
    // A comma-separated list of "A-B" ranges and single frames; empty selects all.
    std::vector<std::pair<int, int>> ranges;
    size_t start = 0;
    while (start <= selection.size() && !selection.empty()) {
        const size_t comma = std::min(selection.find(',', start), selection.size());
        const std::string part = selection.substr(start, comma - start);
        const size_t dash = part.find('-', 1);
        try {
            const int first = std::stoi(part.substr(0, dash));
            ranges.emplace_back(first, dash == std::string::npos ? first : std::stoi(part.substr(dash + 1)));
        } catch (const std::exception&) {
            throw Error(ErrorCode::InvalidArgument,
                        "--frames '" + selection + "' is not a list of A-B ranges or frames");
        }
        start = comma + 1;
    }
    return ranges;
}

std::vector<int> selectFrames(const vdb::VdbSequence& sequence, const std::string& selection) {
    const std::vector<std::pair<int, int>> ranges = parseFrameRanges(selection);
    std::vector<int> frames;
    for (const vdb::FrameFile& f : sequence.frames()) {
        const bool wanted = ranges.empty() || std::any_of(ranges.begin(), ranges.end(), [&](const auto& r) {
                                return f.number >= r.first && f.number <= r.second;
                            });
        if (wanted) frames.push_back(f.number);
    }
    if (frames.empty())
        throw Error(ErrorCode::InvalidArgument, sequence.source() + ": no frame in '" + selection + "'");
    // Numbers the selection names but the sequence lacks (a gap, or past either end) are skipped:
    // said once, or refused under --strict. The union of the ranges minus the frames, as intervals.
    std::vector<std::pair<long long, long long>> wanted;
    for (const auto& [first, last] : ranges)
        if (first <= last) wanted.emplace_back(first, last);
    std::sort(wanted.begin(), wanted.end());
    std::vector<std::pair<long long, long long>> merged;
    for (const auto& r : wanted) {
        if (!merged.empty() && r.first <= merged.back().second + 1)
            merged.back().second = std::max(merged.back().second, r.second);
        else
            merged.push_back(r);
    }
    std::string skipped;
    long long skipped_count = 0;
    const auto skip = [&](long long a, long long b) {
        if (a > b) return;
        skipped += (skipped.empty() ? "" : ", ") + std::to_string(a) + (b > a ? "-" + std::to_string(b) : "");
        skipped_count += b - a + 1;
    };
    for (const auto& [a, b] : merged) {
        long long next = a;  // first number of [a, b] not yet accounted for
        for (const vdb::FrameFile& f : sequence.frames()) {
            if (f.number < a || f.number > b) continue;
            skip(next, f.number - 1LL);
            next = f.number + 1LL;
        }
        skip(next, b);
    }
    if (skipped_count > 0) {
        const std::string message = sequence.source() + ": --frames " + selection + " skips " +
                                    (skipped_count == 1 ? "frame " : "frames ") + skipped + " (no file)";
        if (sequence.options().strict)
            throw Error(ErrorCode::InvalidArgument, message + " (refused by --strict)");
        if (sequence.options().warn) sequence.options().warn(message);
    }
    return frames;
}

std::pair<int, int> parseSize(const std::string& text) {
    const size_t x = text.find('x');
    try {
        if (x == std::string::npos) throw Error(ErrorCode::InvalidArgument, "no x");
        size_t w_end = 0, h_end = 0;
        const std::string w_text = text.substr(0, x), h_text = text.substr(x + 1);
        const int w = std::stoi(w_text, &w_end), h = std::stoi(h_text, &h_end);
        if (w_end != w_text.size() || h_end != h_text.size())
            throw Error(ErrorCode::InvalidArgument, "trailing characters");
        if (w < 1 || h < 1 || w > 16384 || h > 16384) throw Error(ErrorCode::InvalidArgument, "range");
        return {w, h};
    } catch (const std::exception&) {
        throw Error(ErrorCode::InvalidArgument, "--size '" + text + "' is not WxH with 1..16384 pixels each");
    }
}

}  // namespace firelook::bake
