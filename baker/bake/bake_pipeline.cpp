#include "bake/bake_pipeline.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "bake/bake_checkpoint.h"
#include "bake/bake_metadata.h"
#include "bake/fire_light_tracer.h"
#include "bake/fire_probe_tracer.h"
#include "bake/package_merge.h"
#include "bake/sequence_plan.h"
#include "basis/basis_package.h"
#include "common/error.h"
#include "look/look.h"
#include "package/container_writer.h"
#include "vdb/volume_frame.h"

namespace firelook::bake {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

long peakMemoryKiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;
}

double clampTo(const std::vector<double>& axis, double v) { return std::min(std::max(v, axis.front()), axis.back()); }

std::string mib(uint64_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"; }

}  // namespace

nlohmann::ordered_json storageTargetEntry(const FrameBakeReport& fr) {
    if (!fr.has_target) return nullptr;
    return {{"predicted_error", fr.predicted_error},
            {"met", fr.target_met},
            {"quality_scale", fr.quality_scale},
            {"share_bytes", fr.share_bytes},
            {"truncation_target", fr.compression_used.target_relative_error},
            {"basis_error", fr.storage_used.basis_error},
            {"alpha_error", fr.storage_used.alpha_error},
            {"footprint_error", fr.storage_used.footprint_error}};
}

nlohmann::ordered_json lightStepsJson(const std::vector<LightStep>& steps, bool candidates) {
    nlohmann::ordered_json lights = nlohmann::ordered_json::array();
    for (const LightStep& light : steps) {
        nlohmann::ordered_json entry = {{"step_voxels", light.step_voxels}, {"source_error", light.source_error}};
        if (candidates) {
            entry["candidates"] = nlohmann::ordered_json::array();
            for (const LightStepCandidate& c : light.candidates)
                entry["candidates"].push_back(
                    {{"step_scale", c.step_scale}, {"source_error", c.source_error}, {"mean_change", c.mean_change}});
        }
        lights.push_back(std::move(entry));
    }
    return lights;
}

uint64_t defaultMemoryBudget() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page <= 0) return uint64_t(4) << 30;
    return static_cast<uint64_t>(pages) * static_cast<uint64_t>(page) / 10 * 6;
}

uint64_t FrameMemoryPlan::peakBytes() const { return trace.totalBytes() + compression_bytes + fixed_bytes; }

FrameMemoryPlan frameMemoryPlan(const render::Medium& medium, const render::Camera& camera, const BasisModel& model,
                                const TraceSettings& trace, const CompressionSettings& compression,
                                uint64_t budget_bytes) {
    FrameMemoryPlan plan;
    // Libraries, allocator slack and the sequence's metadata: the resident size of a bake of an
    // empty frame, measured at about 60 MiB, rounded up.
    plan.fixed_bytes = uint64_t(96) << 20;
    const uint64_t columns = static_cast<uint64_t>(model.axes.pointCount()) * model.columnsPerPoint();
    const uint64_t pixels = static_cast<uint64_t>(camera.width()) * camera.height();
    const uint64_t rank = std::min<uint64_t>(columns, static_cast<uint64_t>(std::max(compression.max_rank, 1)));
    const uint64_t per_axis = footprintSamplesPerAxis(trace, camera.width(), camera.height());
    const uint64_t rays = per_axis * per_axis;
    // While the basis is compressed (the traced matrix is still held): the Gram matrix and the
    // eigen solver's copies in double, a block of rows, U in float and half, and the copied depths.
    plan.compression_bytes = 3 * columns * columns * 8 + 256 * columns * 8 + pixels * rank * 6 +
                             pixels * rays * (1 + model.alpha_thresholds.size()) * 4;
    TraceSettings sized = trace;
    const uint64_t others = plan.compression_bytes + plan.fixed_bytes;
    sized.memory_budget_bytes = budget_bytes == 0 ? 0 : (budget_bytes > others ? budget_bytes - others : 1);
    plan.trace = planFrameTrace(medium, camera, model, sized);
    return plan;
}

DescribedBake describeDerivedBake(const vdb::VdbSequence& sequence, const BakeConfig& config,
                                  const SceneSetup& scene, const SequenceSurvey* survey) {
    DescribedBake out;
    basis::BakeDescription& d = out.description;
    d.bins.count = config.bins;
    const SequenceSurvey measured = survey ? SequenceSurvey{} : surveySequence(sequence);
    const SequenceSurvey& surveyed = survey ? *survey : measured;
    d.bins.t_lo = config.t_lo.value_or(surveyed.temperature_range.first);
    d.bins.t_hi = config.t_hi.value_or(surveyed.temperature_range.second);
    if (!(d.bins.t_hi > d.bins.t_lo))
        throw Error(ErrorCode::InvalidArgument, "temperature range needs t_hi > t_lo");
    d.rbf_width = config.rbf_width;
    d.albedo = config.albedo;
    // The default look is always the data's; only the axes not given are mapped.
    out.derivation = deriveAxes(config.axes, d.bins, surveyed.density);
    d.axes = derivedAxes(config.axes, out.derivation);
    basis::validateAxes(d.axes);
    const auto& tc = d.axes.temperature_threshold;
    const int n_alpha = tc.size() == 1 ? 1 : std::max(config.alpha_threshold_samples, 2);
    for (int i = 0; i < n_alpha; ++i)
        d.alpha_thresholds.push_back(n_alpha == 1 ? tc.front() : tc.front() + (tc.back() - tc.front()) * i / (n_alpha - 1));
    const int per_axis = footprintSamplesPerAxis(config.trace, scene.camera.width(), scene.camera.height());
    d.footprint_samples = per_axis * per_axis;
    d.light_directions = scene.light_directions;
    d.six_way_first_light = scene.six_way_first_light;
    d.sphere_first_light = scene.sphere_first_light;
    d.sphere_light_count = scene.sphere_first_light >= 0
                               ? static_cast<int>(scene.light_directions.size()) - scene.sphere_first_light
                               : 0;
    d.sphere_triangles = scene.sphere_triangles;
    d.width = scene.camera.width();
    d.height = scene.camera.height();

    Look look = derivedDefaultLook(out.derivation);
    look.albedo = config.albedo;
    look.temperature_threshold = clampTo(d.axes.temperature_threshold, look.temperature_threshold);
    look.smoke_extinction = clampTo(d.axes.smoke_extinction, look.smoke_extinction);
    look.flame_extinction = clampTo(d.axes.flame_extinction, look.flame_extinction);
    look.light_irradiance.assign(scene.light_colors.begin(), scene.light_colors.end());
    if (scene.camera_source == "default" || config.scene.scene_path.empty())
        look.light_irradiance = defaultLook().light_irradiance;
    look.light_irradiance.resize(scene.light_directions.size(), Rgb(1.0f));
    // The six-way or sphere lights are off by default, so a default render shows the scene's lights alone.
    for (size_t l = std::max(d.relightFirstLight(), 0);
         d.relightFirstLight() >= 0 && l < look.light_irradiance.size(); ++l)
        look.light_irradiance[l] = Rgb(0.0f);
    d.default_look_json = lookToJson(look);
    return out;
}

basis::BakeDescription describeBake(const vdb::VdbSequence& sequence, const BakeConfig& config,
                                    const SceneSetup& scene) {
    return describeDerivedBake(sequence, config, scene).description;
}

namespace {

// A frame's entry in META's "errors" list, and the reverse (for a frame resumed from an earlier
// run): the keys live here only.
nlohmann::ordered_json errorsEntry(const FrameBakeReport& fr) {
    nlohmann::ordered_json entry = {
        {"frame", fr.frame},
        {"rank", fr.rank},
        {"svd_truncation_relative_error", fr.truncation_error},
        {"storage_relative_error", fr.quantisation_error},
        {"pixels_with_footprint_rays", fr.detailed_pixels},
        {"alpha_storage_error_bound", fr.alpha_storage_bound},
        {"bytes", {{"u", fr.u_bytes}, {"svt", fr.svt_bytes}, {"depths", fr.depth_bytes}}},
        {"scattering_orders", fr.scattering_orders},
        {"cell_edge_voxels", fr.cell_edge_voxels},
        {"light_spacing_voxels", fr.light_spacing_voxels},
        {"cell_optical_depth", fr.cell_optical_depth},
        {"last_order_fraction", fr.last_order_fraction},
        {"scattering_tail_fraction", fr.tail_fraction},
        {"photon_chains", fr.photon_chains},
        {"photon_multiple", fr.photon_multiple},
        {"order_photon_share", fr.order_photon_share},
        {"predicted_photon_noise", fr.predicted_photon_noise},
        {"radiance_quadrature_error", fr.radiance_quadrature_error},
        {"radiance_rays_per_axis", fr.radiance_rays_per_axis},
        {"footprint_rays_per_axis", fr.footprint_rays_per_axis},
        {"camera_step_voxels", fr.camera_step_voxels},
        {"depth_step_voxels", fr.depth_step_voxels},
        {"light_steps", lightStepsJson(fr.light_steps, false)},
        {"predicted_look_error", fr.predictedLookError()}};
    if (fr.has_target) entry["storage_target"] = storageTargetEntry(fr);
    return entry;
}

FrameBakeReport reportFromMetadata(int frame, const FrameMetadata& kept) {
    const nlohmann::ordered_json& e = kept.errors;
    FrameBakeReport fr;
    fr.frame = frame;
    fr.resumed = true;
    fr.rank = e.at("rank");
    fr.truncation_error = e.at("svd_truncation_relative_error");
    fr.quantisation_error = e.at("storage_relative_error");
    fr.detailed_pixels = e.at("pixels_with_footprint_rays");
    fr.alpha_storage_bound = e.at("alpha_storage_error_bound");
    fr.u_bytes = e.at("bytes").at("u");
    fr.svt_bytes = e.at("bytes").at("svt");
    fr.depth_bytes = e.at("bytes").at("depths");
    fr.scattering_orders = e.at("scattering_orders");
    fr.cell_edge_voxels = e.at("cell_edge_voxels");
    fr.light_spacing_voxels = e.at("light_spacing_voxels");
    fr.cell_optical_depth = e.at("cell_optical_depth");
    fr.last_order_fraction = e.at("last_order_fraction");
    fr.tail_fraction = e.value("scattering_tail_fraction", 0.0);  // packages before 2026-12-03 lack it
    fr.photon_chains = e.value("photon_chains", 0);                // and before 2026-12-06 these
    fr.predicted_photon_noise = e.value("predicted_photon_noise", 0.0);
    fr.radiance_quadrature_error = e.value("radiance_quadrature_error", 0.0);  // before 2026-12-06's radiance rays
    fr.radiance_rays_per_axis = e.value("radiance_rays_per_axis", 0);  // before 2026-12-07: not recorded
    fr.footprint_rays_per_axis = e.value("footprint_rays_per_axis", 0);
    fr.camera_step_voxels = e.value("camera_step_voxels", 0.0);  // before 2026-12-07 (fourth session): not recorded
    // Before 2026-12-07 (fifth session) the depth-only rays marched at the radiance rays' step.
    fr.depth_step_voxels = e.value("depth_step_voxels", fr.camera_step_voxels);
    // ...and no light's step was chosen (none recorded).
    if (e.contains("light_steps"))
        for (const auto& light : e.at("light_steps"))
            fr.light_steps.push_back({0, light.at("step_voxels"), light.at("source_error"), {}});
    // Before the pilot chains (2026-12-06) every chain held half the settings' photons.
    fr.photon_multiple = e.value("photon_multiple", 0.5 * fr.photon_chains);
    fr.order_photon_share = e.value("order_photon_share", 1.0);  // before 2026-12-06 every order had its photons
    if (e.contains("storage_target")) {
        const nlohmann::ordered_json& t = e.at("storage_target");
        fr.has_target = true;
        fr.predicted_error = t.at("predicted_error");
        fr.target_met = t.at("met");
        fr.quality_scale = t.at("quality_scale");
        fr.share_bytes = t.at("share_bytes");
        fr.compression_used.target_relative_error = t.at("truncation_target");
        fr.storage_used.basis_error = t.at("basis_error");
        fr.storage_used.alpha_error = t.at("alpha_error");
        fr.storage_used.footprint_error = t.at("footprint_error");
    }
    return fr;
}

// The META document without its per-frame entries (bake_metadata.h): the description, provenance,
// camera and axis analysis, all of them from the whole sequence and the settings, never from which
// frames this process bakes, so that shards of a bake merge into the bytes of one bake.
nlohmann::ordered_json sharedMetadata(const SequencePlan& plan, const vdb::VdbSequence& sequence,
                                      const BakeConfig& config, const std::string& tool_version,
                                      const SceneSetup& scene, const basis::BakeDescription& description,
                                      const BakeReport& report) {
    // The frames a package holds are listed per frame; the selection that chose them is not a
    // setting of the frames themselves.
    // The axes as derived (before any collapse), so that the recorded settings, saved as a
    // bake.json, bake this package again.
    BakeConfig recorded = config;
    recorded.axes = derivedAxes(config.axes, report.derivation);
    nlohmann::ordered_json settings = nlohmann::ordered_json::parse(configToJson(recorded));
    settings.erase("frames");
    const std::string settings_text = settings.dump();
    nlohmann::ordered_json extra;
    extra["provenance"] = {{"tool", "firelook"},
                           {"tool_version", tool_version},
                           // The sequence by content, not by path: the same files anywhere bake alike.
                           {"sequence_xxh3_64", plan.sequence_xxh3_64},
                           {"sequence_frames", selectFrames(sequence, "")},
                           {"density_grid", sequence.options().density_grid},
                           {"temperature_grid", sequence.options().temperature_grid},
                           {"temperature_scale", sequence.options().temperature_scale},
                           {"temperature_offset", sequence.options().temperature_offset},
                           {"clamp_extreme", sequence.options().clamp_extreme},
                           {"sources", nlohmann::ordered_json::array()},
                           {"settings", settings},
                           {"settings_xxh3_64", xxh3Hex(settings_text)}};
    // Only when set, so that packages read without it keep their bytes.
    if (sequence.options().density_scale != 1.0)
        extra["provenance"]["density_scale"] = sequence.options().density_scale;
    const render::CameraParameters& cam = scene.camera.parameters();
    extra["camera"] = {{"source", scene.camera_source},
                       {"world_from_camera", cam.world_from_camera},
                       {"yfov_radians", cam.yfov_radians},
                       {"width", cam.width},
                       {"height", cam.height}};
    extra["errors"] = nlohmann::ordered_json::array();
    if (report.axes_analysed) extra["axis_collapse"] = nlohmann::ordered_json::parse(axisAnalysisToJson(report.axes));
    // Only where it changed something: the bundled sample's packages keep their bytes.
    if (!report.derivation.identity())
        extra["axis_derivation"] = nlohmann::ordered_json::parse(axisDerivationToJson(report.derivation));
    basis::BakeDescription without_frames = description;
    without_frames.frames.clear();
    return nlohmann::ordered_json::parse(basis::makeMetadata(without_frames, extra.dump()));
}

}  // namespace

BakeReport bakePackage(const std::string& sequence_path, const std::filesystem::path& output,
                       const BakeConfig& config, const std::string& tool_version,
                       const std::function<bool(double, const std::string&)>& progress,
                       const std::function<void(const std::string&)>& notice, const BakeRunOptions& run) {
    const auto start = std::chrono::steady_clock::now();
    // With a plan (bake --plan) only the folder is listed and only the selected frames are read;
    // without, every frame is read once here for the same plan.
    std::optional<SequencePlan> plan = run.plan;
    const vdb::VdbSequence sequence =
        plan ? vdb::VdbSequence::openKnown(sequence_path, plannedReadOptions(*plan, config.read, run.plan_file),
                                           plan->world_bounds)
             : vdb::VdbSequence::open(sequence_path, config.read);
    if (plan) checkPlanFiles(*plan, sequence, run.plan_file);
    const std::vector<int> frames = selectFrames(sequence, config.frames);
    const SceneSetup scene = resolveScene(sequence, config.scene);
    BakeReport report;
    // Before any tracing, since every frame of a package shares the axes: one extra load of each
    // frame of the whole sequence (not only the frames selected, so that shards agree), small
    // beside a frame's trace, measures what deriving the axes and the default look, and
    // collapsing the axes, need, and hashes the frames' files (the sequence's identity).
    const basis::ParameterAxes ax = derivedAxes(config.axes, AxisDerivation{});  // counts only: a derivation maps values
    const bool collapse = config.collapse_unused_axes && (ax.temperature_threshold.size() > 1 ||
                                                          ax.smoke_extinction.size() > 1 || ax.flame_extinction.size() > 1);
    // The first frame to trace is kept from that pass as it was read (LoadedFrame): a one-frame bake
    // reads its file once (frame 12 upsampled 4x: 0.8 s less of a 17 s bake at 128x128).
    LoadedFrame first_frame;
    if (!plan)
        plan = planSequence(
            sequence,
            [&](int frame) {
                return !progress || progress(0.0, "frame " + std::to_string(frame) + ": checking the look axes");
            },
            frames.empty() ? -1 : frames.front(), &first_frame);
    const SequenceSurvey& survey = plan->survey;
    report.sequence_xxh3_64 = plan->sequence_xxh3_64;
    DescribedBake described = describeDerivedBake(sequence, config, scene, &survey);
    basis::BakeDescription& description = described.description;
    report.derivation = described.derivation;
    if (notice && !config.axes.allGiven()) notice(describeAxisDerivation(report.derivation, description.axes));
    // The collapse looks at the derived axes: it runs after the derivation.
    if (collapse) {
        report.axes = analyseAxes(description.axes, description.bins, survey.temperatures,
                                  collapseTolerance(config.storage));
        report.axes_analysed = true;
        applyAxisCollapse(description, report.axes);
        if (notice)
            for (const AxisCollapse& c : report.axes.collapsed) notice(describeAxisCollapse(c, report.axes));
    }
    const BasisModel model = description;
    const nlohmann::ordered_json shared =
        sharedMetadata(*plan, sequence, config, tool_version, scene, description, report);

    // A size target shares the package's bytes equally among the sequence's frames (storage_target.h).
    const uint64_t share_bytes =
        config.target.package_bytes > 0
            ? frameShareBytes(config.target, sequence.frames().size(), shared.dump().size())
            : 0;

    const uint64_t budget = config.memory_budget_bytes ? config.memory_budget_bytes : defaultMemoryBudget();
    report.memory_budget_bytes = budget;
    BakeCheckpoint checkpoint(output, run.resume);
    std::vector<std::filesystem::path> parts;
    // The float basis images a frame stands for (traced or resumed): pixels x columns.
    const uint64_t frame_basis_bytes = uint64_t(description.width) * description.height *
                                       model.axes.pointCount() * model.columnsPerPoint() * sizeof(float);
    for (size_t n = 0; n < frames.size(); ++n) {
        const int frame_number = frames[n];
        const std::string detail = "frame " + std::to_string(frame_number) + " (" + std::to_string(n + 1) + "/" +
                                   std::to_string(frames.size()) + ")";
        const auto frame_progress = [&](double f) {
            return !progress || progress((double(n) + 0.9 * f) / frames.size(), detail);
        };
        if (!frame_progress(0.0)) throw Error(ErrorCode::Cancelled, "cancelled");
        if (first_frame.number != frame_number) first_frame = LoadedFrame{};  // used, or resumed: released
        parts.push_back(checkpoint.partPath(frame_number));
        // Every frame is hashed as it is baked and must be the file the plan hashed: a frame changed
        // since then would mix two sequences in one package.
        const vdb::FrameFile& file = *std::find_if(sequence.frames().begin(), sequence.frames().end(),
                                                   [&](const vdb::FrameFile& f) { return f.number == frame_number; });
        const std::string source_hash = fileXxh3(file.path);
        if (source_hash != plan->find(frame_number)->xxh3_64)
            throw Error(ErrorCode::InvalidArgument,
                        file.path.string() + ": its content (xxh3 " + source_hash + ") is not what " +
                            (run.plan ? run.plan_file.string() + " recorded" : "this bake read a moment ago") + " (" +
                            plan->find(frame_number)->xxh3_64 + "): the frame changed" +
                            (run.plan ? " since the plan was made; make the plan again" : " during the bake"));
        if (run.resume) {
            std::string why;
            if (const std::optional<FrameMetadata> kept = checkpoint.reusable(frame_number, shared, source_hash, why)) {
                report.frames.push_back(reportFromMetadata(frame_number, *kept));
                report.uncompressed_basis_bytes += frame_basis_bytes;
                if (progress && !progress(double(n + 1) / frames.size(), detail + " kept"))
                    throw Error(ErrorCode::Cancelled, "cancelled");
                continue;
            }
            if (notice && !why.empty()) notice(why);
        }
        FrameBakeReport fr;
        fr.frame = frame_number;
        FrameMetadata entries;
        // The frame's grids are released once the medium holds its voxels.
        const LoadedFrame loaded =
            first_frame.number == frame_number ? std::move(first_frame) : loadFrame(sequence.load(frame_number));
        entries.source = {{"frame", frame_number},
                          {"file", loaded.file},
                          {"xxh3_64", source_hash},
                          {"cleaned_non_finite", loaded.cleaned_non_finite},
                          {"cleaned_negative_density", loaded.cleaned_negative_density},
                          {"clamped_extreme", loaded.clamped_extreme}};
        fr.active_voxels = loaded.active_voxels;
        const render::Medium& medium = loaded.medium;

        TraceSettings trace = config.trace;
        trace.seed = config.seed * 1000003ULL + static_cast<uint64_t>(frame_number);
        const FrameMemoryPlan plan = frameMemoryPlan(medium, scene.camera, model, trace, config.compression, budget);
        if (!plan.fits(budget))
            throw Error(ErrorCode::InvalidArgument,
                        "frame " + std::to_string(frame_number) + " needs an estimated " +
                            mib(plan.peakBytes()) + " (basis images " + mib(plan.trace.basis_bytes) +
                            ", optical depths " + mib(plan.trace.depth_bytes) + ", scattered light " +
                            mib(plan.trace.cell_bytes + plan.trace.sampler_bytes) + ", medium " + mib(plan.trace.medium_bytes) +
                            ", compression " + mib(plan.compression_bytes) +
                            "), more than the memory budget of " + mib(budget) +
                            "; lower --size, --bins or the look axes' samples, or raise --memory-budget");
        fr.cell_edge_voxels = plan.trace.cell_edge_voxels;
        fr.light_spacing_voxels = plan.trace.light_spacing_voxels;
        fr.cell_optical_depth = plan.trace.cell_optical_depth;
        fr.pixel_footprint_voxels = plan.trace.pixel_footprint_voxels;
        fr.estimated_peak_bytes = plan.peakBytes();
        fr.columns_traced = static_cast<uint64_t>(model.axes.pointCount()) * model.columnsPerPoint();
        auto t0 = std::chrono::steady_clock::now();
        const FrameBasis traced = traceFrameBasis(medium, scene.camera, model, trace, plan.trace, frame_progress);
        fr.trace_seconds = secondsSince(t0);
        fr.scattering_orders = traced.scattering_orders;
        fr.last_order_fraction = traced.last_order_fraction;
        fr.tail_fraction = traced.tail_fraction;
        fr.photon_chains = traced.photon_chains;
        fr.photon_multiple = traced.photon_multiple;
        fr.order_photon_share = traced.order_photon_share;
        fr.predicted_photon_noise = traced.predicted_photon_noise;
        fr.radiance_quadrature_error = traced.radiance_quadrature_error;
        fr.radiance_rays_per_axis = static_cast<int>(std::lround(std::sqrt(traced.radiance_samples)));
        fr.footprint_rays_per_axis = static_cast<int>(std::lround(std::sqrt(traced.footprint_samples)));
        fr.radiance_quadrature_allowance = traced.radiance_quadrature_allowance;
        fr.quadrature_candidates = traced.quadrature_candidates;
        fr.camera_step_voxels = traced.camera_step_voxels;
        fr.depth_step_voxels = traced.depth_step_voxels;
        fr.light_steps = traced.light_steps;
        fr.setup_seconds = traced.seconds_setup;
        fr.light_seconds = traced.seconds_light;
        fr.photon_seconds = traced.seconds_photons;
        fr.camera_seconds = traced.seconds_camera;
        fr.check_seconds = traced.seconds_checks;

        t0 = std::chrono::steady_clock::now();
        const FramePrecision chosen =
            chooseFramePrecision(traced, frame_number, description, config.compression, config.storage, config.target,
                                 share_bytes, [&] { return frame_progress(1.0); });
        fr.compress_seconds = secondsSince(t0);
        fr.rank = chosen.compressed.factors.rank;
        fr.truncation_error = chosen.compressed.truncation_error;
        fr.has_target = config.target.active();
        fr.predicted_error = chosen.predicted_error;
        fr.quality_scale = chosen.quality_scale;
        fr.share_bytes = share_bytes;
        fr.target_met = chosen.target_met;
        fr.compression_used = chosen.compression;
        fr.storage_used = chosen.storage;
        if (notice && !chosen.target_met)
            notice("frame " + std::to_string(frame_number) +
                   (config.target.package_bytes > 0
                        ? ": does not fit its share of --target-size (" + std::to_string(share_bytes) +
                              " bytes) even at 64 times the configured errors; stored in " +
                              std::to_string(chosen.stored_bytes) + " bytes"
                        : ": --target-error needs more than the maximum rank (" +
                              std::to_string(config.compression.max_rank) + "); predicted error " +
                              std::to_string(chosen.predicted_error)));
        checkStoredError(frame_number, chosen.encoded, chosen.storage);
        // The frame's own package in the checkpoint folder, written atomically: from here on an
        // interrupted bake keeps it.
        package::ContainerWriter writer(parts.back());
        const basis::StoredFrame stored = basis::writeEncodedFrame(writer, frame_number, chosen.encoded);
        // The fire's point lights (basis/fire_lights.h), when asked for: optional, so older readers skip them.
        if (config.fire_lights) {
            t0 = std::chrono::steady_clock::now();
            fr.fire_light_bytes = writer
                                      .addSection(basis::kSectionFireLights, static_cast<uint32_t>(frame_number),
                                                  basis::encodeFireLights(traceFireLights(medium, model)),
                                                  package::Codec::Zstd, false)
                                      .stored_size;
            fr.fire_light_seconds = secondsSince(t0);
        }
        // The fire's probe grid (basis/fire_probes.h), the same way.
        if (config.fire_probes > 0) {
            t0 = std::chrono::steady_clock::now();
            FireProbeSettings settings;
            settings.resolution = config.fire_probes;
            fr.fire_probe_bytes =
                writer
                    .addSection(basis::kSectionFireProbes, static_cast<uint32_t>(frame_number),
                                basis::encodeFireProbes(traceFireProbes(medium, model, settings)),
                                package::Codec::Zstd, false)
                    .stored_size;
            fr.fire_probe_seconds = secondsSince(t0);
        }
        fr.quantisation_error = std::hypot(chosen.compressed.quantisation_error, stored.u_error, stored.svt_error);
        fr.detailed_pixels = stored.detailed_pixels;
        fr.alpha_storage_bound = stored.alpha_bound;
        fr.u_bytes = stored.u_bytes;
        fr.svt_bytes = stored.svt_bytes;
        fr.depth_bytes = stored.depth_bytes;
        entries.record = {{"frame", frame_number}, {"rank", fr.rank}};
        entries.errors = errorsEntry(fr);
        writer.addMetadata(joinMetadata(shared, {&entries}));
        writer.commit();
        report.uncompressed_basis_bytes += frame_basis_bytes;
        report.frames.push_back(fr);
        if (progress && !progress(double(n + 1) / frames.size(), detail))
            throw Error(ErrorCode::Cancelled, "cancelled");
    }

    // The package from the frames' parts, as `firelook merge` writes it; the selection may skip
    // frames of the sequence on purpose.
    report.package_bytes = mergePackages(parts, output, {.allow_gaps = true, .only = {}}).package_bytes;
    checkpoint.remove();
    report.seconds = secondsSince(start);
    report.peak_memory_kib = peakMemoryKiB();
    return report;
}

}  // namespace firelook::bake
