#include "reference_worker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "basis/basis_package.h"
#include "look/look.h"
#include "render/camera.h"
#include "render/medium.h"
#include "render/reference_tracer.h"
#include "vdb/dense_volume.h"
#include "vdb/vdb_sequence.h"

namespace firelook::viewer {
namespace {

bool sequenceExists(const std::filesystem::path& p) {
    // A folder of .vdb files, or a pattern whose folder exists (fire_####.vdb).
    std::error_code e;
    if (std::filesystem::exists(p, e)) return true;
    return p.string().find('#') != std::string::npos && std::filesystem::is_directory(p.parent_path(), e);
}

render::Camera cameraFromMetadata(const nlohmann::json& meta, const std::string& package) {
    if (!meta.contains("camera")) throw std::runtime_error(package + ": no camera recorded in the package");
    const nlohmann::json& c = meta["camera"];
    render::CameraParameters p;
    const auto m = c.at("world_from_camera").get<std::vector<double>>();
    if (m.size() != 16) throw std::runtime_error(package + ": camera.world_from_camera must have 16 numbers");
    std::copy(m.begin(), m.end(), p.world_from_camera.begin());
    p.yfov_radians = c.at("yfov_radians").get<double>();
    p.width = c.at("width").get<int>();
    p.height = c.at("height").get<int>();
    return render::Camera(p);
}

}  // namespace

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
        // Everything the bake used: camera, sequence and grid mapping (META), bins and lights.
        const basis::BasisPackage package = basis::BasisPackage::open(request.package_path);
        const basis::BakeDescription& d = package.description();
        const nlohmann::json meta = nlohmann::json::parse(package.metadataJson());
        const render::Camera camera = cameraFromMetadata(meta, request.package_path);
        const nlohmann::json provenance = meta.value("provenance", nlohmann::json::object());
        const std::string recorded = provenance.value("sequence", std::string());
        s.sequence_path = request.sequence_override.empty() ? resolveSequencePath(recorded, request.package_path)
                                                             : request.sequence_override;
        if (s.sequence_path.empty())
            throw std::runtime_error("the sequence recorded in " + request.package_path + " (\"" + recorded +
                                     "\") was not found; give its path (QA panel or --sequence)");
        vdb::ReadOptions read;
        read.density_grid = provenance.value("density_grid", std::string());
        read.temperature_grid = provenance.value("temperature_grid", std::string());
        read.temperature_scale = provenance.value("temperature_scale", 1.0);
        read.temperature_offset = provenance.value("temperature_offset", 0.0);

        s.status = "loading frame " + std::to_string(request.frame) + " of " + s.sequence_path;
        publish(s);
        const vdb::VdbSequence sequence = vdb::VdbSequence::open(s.sequence_path, read);
        const vdb::DenseVolume dense = vdb::toDense(sequence.load(request.frame));
        // As bake::mediumFromFrame: a dense copy of the sparse grids.
        const render::Medium medium = dense.voxelCount() == 0
                                          ? render::Medium()
                                          : render::Medium(dense.origin, dense.dims, dense.density,
                                                           dense.temperature, dense.index_to_world, 0.0f);
        const Look look = parseLook(request.look_json, "QA look");
        const LookModel model = makeLookModel(look, d.bins, d.rbf_width, d.light_directions);

        render::ReferenceSettings settings;
        settings.samples_per_pixel = request.spp_per_pass;
        settings.threads = request.threads > 0 ? request.threads
                                               : std::max(1, static_cast<int>(std::thread::hardware_concurrency()) - 1);
        std::vector<double> sum, variance_sum;
        int passes = 0;
        while (!cancel_ && s.spp < request.target_spp) {
            settings.seed = 1 + static_cast<uint64_t>(passes);  // independent passes
            const render::ReferenceResult r =
                render::renderReference(medium, model, camera, settings, [&](double) { return !cancel_.load(); });
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
