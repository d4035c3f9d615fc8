#include "reference_worker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <nlohmann/json.hpp>

#include "fl_check.h"
#include "render/reference_tracer.h"

namespace firelook::viewer {
namespace {

bool sequenceExists(const std::filesystem::path& p) {
    // A folder of .vdb files, or a pattern whose folder exists (fire_####.vdb).
    std::error_code e;
    if (std::filesystem::exists(p, e)) return true;
    return p.string().find('#') != std::string::npos && std::filesystem::is_directory(p.parent_path(), e);
}

}  // namespace

reference::BakedScene readReferenceScene(fl_package package, const fl_package_info& info) {
    reference::BakedScene scene;
    fl_camera camera = fl_camera_defaults();
    check(fl_package_get_camera(package, &camera), "fl_package_get_camera");
    std::copy(std::begin(camera.world_from_camera), std::end(camera.world_from_camera),
              scene.camera.world_from_camera.begin());
    scene.camera.yfov_radians = camera.yfov_radians;
    scene.camera.width = camera.width;
    scene.camera.height = camera.height;
    uint32_t count = 0;
    check(fl_package_get_lights(package, nullptr, nullptr, 0, &count), "fl_package_get_lights");
    std::vector<double> directions(3 * size_t{count});
    if (count > 0)
        check(fl_package_get_lights(package, directions.data(), nullptr, count, &count), "fl_package_get_lights");
    for (uint32_t l = 0; l < count; ++l)
        scene.light_directions.emplace_back(directions[3 * l], directions[3 * l + 1], directions[3 * l + 2]);
    scene.bins.t_lo = info.temperature_lo;
    scene.bins.t_hi = info.temperature_hi;
    scene.bins.count = info.bin_count;
    scene.rbf_width = info.rbf_width;
    size_t size = 0;
    check(fl_package_get_metadata_json(package, nullptr, 0, &size), "fl_package_get_metadata_json");
    scene.metadata_json.assign(size, '\0');
    check(fl_package_get_metadata_json(package, scene.metadata_json.data(), size, &size), "fl_package_get_metadata_json");
    scene.metadata_json.resize(size > 0 ? size - 1 : 0);
    return scene;
}

std::string resolveSequencePath(const std::string& recorded, const std::string& package_path) {
    if (recorded.empty()) return {};
    const std::filesystem::path p(recorded);
    if (sequenceExists(p)) return recorded;
    if (p.is_relative()) {
        const std::filesystem::path beside = std::filesystem::path(package_path).parent_path() / p;
        if (sequenceExists(beside)) return beside.string();
    }
    return {};
}

void ReferenceWorker::start(const ReferenceRequest& request) {
    stop();
    cancel_ = false;
    {
        std::lock_guard lock(mutex_);
        const uint64_t version = shared_.version + 1;
        shared_ = ReferenceSnapshot();
        shared_.version = version;
        shared_.running = true;
        shared_.target_spp = request.target_spp;
        shared_.status = "starting";
    }
    thread_ = std::thread([this, request] { run(request); });
}

void ReferenceWorker::stop() {
    cancel_ = true;
    if (thread_.joinable()) thread_.join();
}

bool ReferenceWorker::poll(ReferenceSnapshot& out) const {
    std::lock_guard lock(mutex_);
    if (shared_.version == out.version) return false;
    out = shared_;
    return true;
}

void ReferenceWorker::publish(const ReferenceSnapshot& snapshot) {
    std::lock_guard lock(mutex_);
    const uint64_t version = shared_.version + 1;
    shared_ = snapshot;
    shared_.version = version;
}

void ReferenceWorker::run(ReferenceRequest request) {
    ReferenceSnapshot s;
    s.running = true;
    s.target_spp = request.target_spp;
    const auto start = std::chrono::steady_clock::now();
    try {
        // Everything the bake used: camera, bins and lights (C API), the sequence (META's provenance).
        const nlohmann::json meta = nlohmann::json::parse(request.scene.metadata_json);
        const std::string recorded =
            meta.value("provenance", nlohmann::json::object()).value("sequence", std::string());
        s.sequence_path = request.sequence_override.empty() ? resolveSequencePath(recorded, request.package_path)
                                                             : request.sequence_override;
        if (s.sequence_path.empty())
            throw std::runtime_error(
                recorded.empty()
                    ? request.package_path + " records its sequence by content, not by path; give its path (QA panel or --sequence)"
                    : "the sequence recorded in " + request.package_path + " (\"" + recorded +
                          "\") was not found; give its path (QA panel or --sequence)");
        s.status = "loading frame " + std::to_string(request.frame) + " of " + s.sequence_path;
        publish(s);
        const reference::ReferenceInputs in = reference::referenceInputs(
            request.scene, request.package_path, s.sequence_path, request.frame, request.look_json);

        render::ReferenceSettings settings;
        settings.samples_per_pixel = request.spp_per_pass;
        settings.threads = request.threads > 0 ? request.threads
                                               : std::max(1, static_cast<int>(std::thread::hardware_concurrency()) - 1);
        std::vector<double> sum, variance_sum;
        int passes = 0;
        while (!cancel_ && s.spp < request.target_spp) {
            settings.seed = 1 + static_cast<uint64_t>(passes);  // independent passes
            const render::ReferenceResult r =
                render::renderReference(in.medium, in.model, in.camera, settings, [&](double) { return !cancel_.load(); });
            if (r.cancelled || cancel_) break;
            if (sum.empty()) {
                sum.assign(r.image.rgba.size(), 0.0);
                variance_sum.assign(r.image.rgba.size(), 0.0);
                s.width = r.image.width;
                s.height = r.image.height;
            }
            for (size_t i = 0; i < sum.size(); ++i) {
                sum[i] += r.image.rgba[i];
                variance_sum[i] += r.variance_of_mean.rgba[i];
            }
            ++passes;
            s.spp += r.samples_per_pixel_done;
            // Mean of the passes; its variance is the sum of the passes' variances over passes^2.
            s.rgba.resize(sum.size());
            double signal = 0.0, noise = 0.0;
            for (size_t i = 0; i < sum.size(); ++i) {
                s.rgba[i] = static_cast<float>(sum[i] / passes);
                if (i % 4 != 3) {
                    signal += static_cast<double>(s.rgba[i]) * s.rgba[i];
                    noise += variance_sum[i] / (static_cast<double>(passes) * passes);
                }
            }
            s.estimated_relative_rmse = signal > 0.0 ? std::sqrt(noise / signal) : 0.0;
            s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            s.status = std::to_string(s.spp) + " / " + std::to_string(request.target_spp) + " spp";
            publish(s);
        }
        s.status = cancel_ ? "stopped at " + std::to_string(s.spp) + " spp" : "done, " + std::to_string(s.spp) + " spp";
    } catch (const std::exception& e) {
        s.error = e.what();
        s.status = "failed";
    }
    s.running = false;
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    publish(s);
}

}  // namespace firelook::viewer
