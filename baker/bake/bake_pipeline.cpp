#include "bake/bake_pipeline.h"

#include <sys/resource.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "basis/basis_package.h"
#include "look/look.h"
#include "package/package_writer.h"
#include "vdb/volume_frame.h"

namespace firelook::bake {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string fileHash(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    XXH3_state_t* state = XXH3_createState();
    XXH3_64bits_reset(state);
    std::vector<char> buffer(1 << 20);
    while (in) {
        in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        XXH3_64bits_update(state, buffer.data(), static_cast<size_t>(in.gcount()));
    }
    const XXH64_hash_t hash = XXH3_64bits_digest(state);
    XXH3_freeState(state);
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
    return text;
}

long peakMemoryKiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;
}

double clampTo(const std::vector<double>& axis, double v) { return std::min(std::max(v, axis.front()), axis.back()); }

}  // namespace

basis::BakeDescription describeBake(const vdb::VdbSequence& sequence, const BakeConfig& config,
                                    const SceneSetup& scene) {
    basis::BakeDescription d;
    d.bins.count = config.bins;
    if (config.t_lo && config.t_hi) {
        d.bins.t_lo = *config.t_lo;
        d.bins.t_hi = *config.t_hi;
    } else {
        const auto [lo, hi] = sequenceTemperatureRange(sequence);
        d.bins.t_lo = config.t_lo.value_or(lo);
        d.bins.t_hi = config.t_hi.value_or(hi);
    }
    if (!(d.bins.t_hi > d.bins.t_lo)) throw std::invalid_argument("temperature range needs t_hi > t_lo");
    d.rbf_width = config.rbf_width;
    d.albedo = config.albedo;
    d.axes = config.axes;
    basis::validateAxes(d.axes);
    const auto& tc = d.axes.temperature_threshold;
    const int n_alpha = tc.size() == 1 ? 1 : std::max(config.alpha_threshold_samples, 2);
    for (int i = 0; i < n_alpha; ++i)
        d.alpha_thresholds.push_back(n_alpha == 1 ? tc.front() : tc.front() + (tc.back() - tc.front()) * i / (n_alpha - 1));
    d.footprint_samples = config.trace.footprint_samples_per_axis * config.trace.footprint_samples_per_axis;
    d.light_directions = scene.light_directions;
    d.width = scene.camera.width();
    d.height = scene.camera.height();

    Look look = defaultLook();
    look.albedo = config.albedo;
    look.temperature_threshold = clampTo(d.axes.temperature_threshold, look.temperature_threshold);
    look.smoke_extinction = clampTo(d.axes.smoke_extinction, look.smoke_extinction);
    look.flame_extinction = clampTo(d.axes.flame_extinction, look.flame_extinction);
    look.light_irradiance.assign(scene.light_colors.begin(), scene.light_colors.end());
    if (scene.camera_source == "default" || config.scene.scene_path.empty())
        look.light_irradiance = defaultLook().light_irradiance;
    look.light_irradiance.resize(scene.light_directions.size(), Rgb(1.0f));
    d.default_look_json = lookToJson(look);
    return d;
}

BasisModel basisModelOf(const basis::BakeDescription& d) {
    BasisModel m;
    m.bins = d.bins;
    m.rbf_width = d.rbf_width;
    m.albedo = d.albedo;
    m.axes = d.axes;
    m.light_directions = d.light_directions;
    m.alpha_thresholds = d.alpha_thresholds;
    return m;
}

BakeReport bakePackage(const std::string& sequence_path, const std::filesystem::path& output,
                       const BakeConfig& config, const std::string& tool_version,
                       const std::function<bool(double, const std::string&)>& progress) {
    const auto start = std::chrono::steady_clock::now();
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(sequence_path, config.read);
    const std::vector<int> frames = selectFrames(sequence, config.frames);
    const SceneSetup scene = resolveScene(sequence, config.scene);
    basis::BakeDescription description = describeBake(sequence, config, scene);
    const BasisModel model = basisModelOf(description);

    package::PackageWriter writer(output);
    BakeReport report;
    nlohmann::ordered_json sources = nlohmann::ordered_json::array();
    nlohmann::ordered_json frame_errors = nlohmann::ordered_json::array();
    for (size_t n = 0; n < frames.size(); ++n) {
        const int frame_number = frames[n];
        const std::string detail = "frame " + std::to_string(frame_number) + " (" + std::to_string(n + 1) + "/" +
                                   std::to_string(frames.size()) + ")";
        const auto frame_progress = [&](double f) {
            return !progress || progress((double(n) + 0.9 * f) / frames.size(), detail);
        };
        if (!frame_progress(0.0)) throw std::runtime_error("cancelled");
        const vdb::VolumeFrame frame = sequence.load(frame_number);
        sources.push_back({{"frame", frame_number},
                           {"file", frame.file.filename().string()},
                           {"xxh3_64", fileHash(frame.file)},
                           {"cleaned_non_finite", frame.cleaned_non_finite},
                           {"cleaned_negative_density", frame.cleaned_negative_density}});
        const render::Medium medium = mediumFromFrame(frame);

        FrameBakeReport fr;
        fr.frame = frame_number;
        auto t0 = std::chrono::steady_clock::now();
        TraceSettings trace = config.trace;
        trace.seed = config.seed * 1000003ULL + static_cast<uint64_t>(frame_number);
        const FrameBasis traced = traceFrameBasis(medium, scene.camera, model, trace, frame_progress);
        fr.trace_seconds = secondsSince(t0);
        fr.scattering_orders = traced.scattering_orders;
        fr.last_order_fraction = traced.last_order_fraction;

        t0 = std::chrono::steady_clock::now();
        const CompressedFrame compressed = compressFrameBasis(traced, frame_number, config.compression);
        fr.compress_seconds = secondsSince(t0);
        fr.rank = compressed.factors.rank;
        fr.truncation_error = compressed.truncation_error;
        fr.quantisation_error = compressed.quantisation_error;
        writeFrameFactors(writer, compressed.factors);
        description.frames.push_back({frame_number, fr.rank});
        report.uncompressed_basis_bytes += traced.matrix.size() * sizeof(float);
        frame_errors.push_back({{"frame", frame_number},
                                {"rank", fr.rank},
                                {"svd_truncation_relative_error", fr.truncation_error},
                                {"half_quantisation_relative_error", fr.quantisation_error},
                                {"scattering_orders", fr.scattering_orders},
                                {"last_order_fraction", fr.last_order_fraction}});
        report.frames.push_back(fr);
        if (progress && !progress(double(n + 1) / frames.size(), detail)) throw std::runtime_error("cancelled");
    }

    nlohmann::ordered_json extra;
    extra["provenance"] = {{"tool", "firelook"},
                           {"tool_version", tool_version},
                           {"sequence", sequence_path},
                           {"density_grid", sequence.options().density_grid},
                           {"temperature_grid", sequence.options().temperature_grid},
                           {"temperature_scale", sequence.options().temperature_scale},
                           {"temperature_offset", sequence.options().temperature_offset},
                           {"sources", sources},
                           {"settings", nlohmann::ordered_json::parse(configToJson(config))}};
    const render::CameraParameters& cam = scene.camera.parameters();
    extra["camera"] = {{"source", scene.camera_source},
                       {"world_from_camera", cam.world_from_camera},
                       {"yfov_radians", cam.yfov_radians},
                       {"width", cam.width},
                       {"height", cam.height}};
    extra["errors"] = frame_errors;
    writer.addMetadata(basis::makeMetadata(description, extra.dump()));
    writer.commit();

    report.seconds = secondsSince(start);
    report.package_bytes = std::filesystem::file_size(output);
    report.peak_memory_kib = peakMemoryKiB();
    return report;
}

}  // namespace firelook::bake
