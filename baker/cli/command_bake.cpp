// firelook bake SEQUENCE -o OUT.firelook [--frames A-B] [--size WxH] [--bins N]
//                [--scene S.gltf | --camera ...] [--config BAKE.json] [--seed S] [--report R.json]
//                [--resume] [--threads N] [--plan PLAN.json]
// firelook bake SEQUENCE --plan-only -o PLAN.json [read settings]
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "bake/bake_checkpoint.h"
#include "bake/bake_pipeline.h"
#include "bake/sequence_plan.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "cli/commands.h"
#include "cli/interrupt.h"
#include "cli/output_option.h"
#include "cli/progress_bar.h"
#include "cli/scene_options.h"
#include "cli/storage_target_option.h"
#include "cli/version.h"

namespace firelook::cli {
namespace {

// Timings live here, not in the package: the package's bytes depend only on inputs and seed.
void writeReportJson(const std::string& path, const std::string& sequence, const bake::BakeReport& report) {
    nlohmann::ordered_json frames = nlohmann::ordered_json::array();
    for (const bake::FrameBakeReport& f : report.frames)
        frames.push_back(
            {{"frame", f.frame},
             {"resumed", f.resumed},
             {"rank", f.rank},
             {"svd_truncation_relative_error", f.truncation_error},
             {"storage_relative_error", f.quantisation_error},
             {"pixels_with_footprint_rays", f.detailed_pixels},
             {"alpha_storage_error_bound", f.alpha_storage_bound},
             {"bytes", f.u_bytes + f.svt_bytes + f.depth_bytes},
             {"section_bytes", {{"u", f.u_bytes}, {"svt", f.svt_bytes}, {"depths", f.depth_bytes}}},
             {"scattering_orders", f.scattering_orders},
             {"photon_chains", f.photon_chains},
             {"photon_multiple", f.photon_multiple},
             {"order_photon_share", f.order_photon_share},
             {"predicted_photon_noise", f.predicted_photon_noise},
             {"radiance_quadrature_error", f.radiance_quadrature_error},
             {"radiance_rays_per_axis", f.radiance_rays_per_axis},
             {"radiance_quadrature_allowance", f.radiance_quadrature_allowance},
             {"footprint_rays_per_axis", f.footprint_rays_per_axis},
             {"camera_step_voxels", f.camera_step_voxels},
             {"depth_step_voxels", f.depth_step_voxels},
             {"light_steps", bake::lightStepsJson(f.light_steps, true)},
             {"predicted_look_error", f.predictedLookError()},
             {"trace_seconds", f.trace_seconds},
             {"trace_stage_seconds",
              {{"cells_and_sources", f.setup_seconds},
               {"light_depths", f.light_seconds},
               {"photon_passes", f.photon_seconds},
               {"camera_rays", f.camera_seconds},
               {"step_checks", f.check_seconds}}},
             {"svd_seconds", f.compress_seconds},
             {"fire_lights", {{"bytes", f.fire_light_bytes}, {"seconds", f.fire_light_seconds}}},
             {"fire_probes", {{"bytes", f.fire_probe_bytes}, {"seconds", f.fire_probe_seconds}}},
             {"active_voxels", f.active_voxels},
             {"cell_edge_voxels", f.cell_edge_voxels},
             {"light_spacing_voxels", f.light_spacing_voxels},
             {"cell_optical_depth", f.cell_optical_depth},
             {"pixel_footprint_voxels", f.pixel_footprint_voxels},
             {"estimated_peak_mib", f.estimated_peak_bytes / 1048576.0},
             {"columns_traced", f.columns_traced},
             {"predicted_relative_error", std::hypot(f.truncation_error, f.quantisation_error)}});
    for (size_t i = 0; i < report.frames.size(); ++i) {
        if (report.frames[i].has_target) frames[i]["storage_target"] = bake::storageTargetEntry(report.frames[i]);
        // Why the frame took its radiance rays and step: each choice measured and its errors.
        nlohmann::ordered_json candidates = nlohmann::ordered_json::array();
        for (const bake::QuadratureCandidate& c : report.frames[i].quadrature_candidates)
            candidates.push_back({{"rays_per_axis", c.rays_per_axis},
                                  {"step_scale", c.step_scale},
                                  {"quadrature_error", c.radiance_error},
                                  {"mean_change", c.mean_change},
                                  {"alpha_error", c.alpha_error}});
        frames[i]["radiance_candidates"] = std::move(candidates);
    }
    // The sequence's path as typed is provenance of this run, not of the package, whose bytes do
    // not depend on it.
    nlohmann::ordered_json doc = {{"sequence", sequence},
                                  {"sequence_xxh3_64", report.sequence_xxh3_64},
                                  {"seconds", report.seconds},
                                        {"peak_memory_mib", report.peak_memory_kib / 1024.0},
                                        {"memory_budget_mib", report.memory_budget_bytes / 1048576.0},
                                        {"package_bytes", report.package_bytes},
                                        {"uncompressed_basis_bytes", report.uncompressed_basis_bytes},
                                        {"frames", frames}};
    // null when the axes were kept as given without looking (--keep-axes, or no axis to collapse).
    doc["axis_collapse"] = report.axes_analysed ? nlohmann::ordered_json::parse(bake::axisAnalysisToJson(report.axes))
                                                : nlohmann::ordered_json(nullptr);
    doc["axis_derivation"] = nlohmann::ordered_json::parse(bake::axisDerivationToJson(report.derivation));
    writeFileAtomically(path, doc.dump(2) + "\n");
}

bake::SequencePlan readPlan(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorCode::IoError, path + ": cannot open the plan");
    std::ostringstream text;
    text << in.rdbuf();
    return bake::planFromJson(text.str(), path);
}

// bake --plan-only: reads every frame once and writes what the whole sequence gives a bake.
void writePlan(const std::string& sequence_path, const std::string& output, const bake::BakeConfig& config) {
    ProgressBar bar("plan");
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(sequence_path, config.read);
    size_t done = 0;
    const bake::SequencePlan plan = bake::planSequence(sequence, [&](int frame) {
        bar.update(double(done++) / sequence.frames().size(), "frame " + std::to_string(frame));
        throwIfInterrupted();
        return true;
    });
    writeFileAtomically(output, bake::planToJson(plan, sequence_path));
    bar.finish(std::to_string(plan.frames.size()) + " frames");
    std::printf("wrote %s: %zu frames (%d-%d), sequence xxh3 %s\n", output.c_str(), plan.frames.size(),
                plan.frames.front().number, plan.frames.back().number, plan.sequence_xxh3_64.c_str());
}

// One line: what the trace settings (a quality preset, changed by bake.json's keys) choose for this
// image size, each error source's setting.
std::string describeTraceChoice(const bake::BakeConfig& config) {
    const bake::TraceSettings& t = config.trace;
    const int n = bake::footprintSamplesPerAxis(t, config.scene.width, config.scene.height);
    const int m = bake::radianceSamplesPerAxis(t, n);
    char photons[160];
    if (t.photon_noise_target > 0.0)
        std::snprintf(photons, sizeof photons, "photon noise target %g%% (chains of %g of the photons, up to %dx)",
                      100.0 * t.photon_noise_target, t.photon_pilot_share * 0.5, t.max_photon_scale);
    else
        std::snprintf(photons, sizeof photons, "the photons as given (no noise target)");
    const std::vector<int> candidates = bake::radianceCandidates(t, n);
    char radiance[160];
    if (candidates.empty())
        std::snprintf(radiance, sizeof radiance, "%dx%d of them", m, m);
    else
        std::snprintf(
            radiance, sizeof radiance,
            "%dx%d of them, or as few as %dx%d where their quadrature error is within %g%% or %g of "
            "the frame's photon noise (chosen per frame)",
            m, m, candidates.front(), candidates.front(), 100.0 * t.radiance_quadrature_target,
            t.radiance_quadrature_noise_share);
    char step[400];
    if (t.max_step_scale >= 2)
        std::snprintf(step, sizeof step,
                      "march step %g voxel (toward the lights %g of their lattice's spacing), or up to %d times "
                      "it, chosen per frame: the radiance rays' where that moves radiance by at most %g%% and its "
                      "mean by %g%%, alpha's rays' where it moves alpha by at most %g, the lights' where it moves "
                      "the lit source by at most %g%% and its mean by %g%%",
                      t.step_voxels, t.step_voxels, bake::stepScaleCandidates(t).back(),
                      100.0 * t.step_radiance_target, 100.0 * t.step_mean_change_target, t.step_alpha_target,
                      100.0 * t.step_radiance_target, 100.0 * t.step_mean_change_target);
    else
        std::snprintf(step, sizeof step, "march step %g voxel (toward the lights %g of their lattice's spacing)",
                      t.step_voxels, t.step_voxels);
    char line[1024];
    std::snprintf(line, sizeof line,
                  "trace (%s quality): %dx%d footprint rays a pixel for alpha, %s for radiance; %s; %s; "
                  "scattering orders until %g%% is left",
                  config.quality.empty() ? "default" : config.quality.c_str(), n, n, radiance, step, photons,
                  100.0 * t.order_tolerance);
    return line;
}

}  // namespace

void registerBakeCommand(CLI::App& app) {
    struct Args {
        std::string sequence, output, frames, report_json, memory_budget, plan, quality;
        StorageTargetFlags target;
        uint64_t seed = 1;
        int threads = 0;
        bool keep_axes = false, resume = false, fire_lights = false, plan_only = false;
        int fire_probes = 0;
        SceneFlags scene;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("bake", "Bake a VDB sequence into a .firelook package of compressed basis images");
    cmd->add_option("SEQUENCE", args->sequence, "folder of .vdb files or a pattern such as fire_####.vdb")->required();
    addOutputOption(*cmd, args->output, "output package (.firelook)", {"--output"})->required();
    cmd->add_option("--frames", args->frames, "frames: A-B ranges and single frames, comma-separated (numbers from the file names)");
    cmd->add_option("--seed", args->seed, "random seed: the same seed gives the same bytes")->capture_default_str();
    cmd->add_option("--report", args->report_json,
                    "also write what the bake measured (time, peak memory, sizes, per-frame rank and errors) as JSON");
    cmd->add_option("--memory-budget", args->memory_budget,
                    "most memory the bake may hold, e.g. 6G (binary units K, M, G, T); default 60% of the machine's "
                    "physical memory. Each frame's needs are estimated before it is traced: the scattered-light "
                    "cells are coarsened to fit, and a frame that cannot fit stops the bake with nothing written");
    addStorageTargetFlags(*cmd, args->target,
                          "aim the whole sequence's package at this size, e.g. 6M (binary units): each frame gets an equal "
                          "share and is stored at the finest precision that fits it (one factor on every error setting; "
                          "the table and --report say what was chosen and the error it predicts)",
                          "store each frame's basis within this relative error (SVD truncation and storage together, "
                          "e.g. 0.003), in the fewest bytes; the depths for alpha keep their own bound");
    cmd->add_option("--quality", args->quality,
                    "trace settings for an error: preview (about a third of the seconds, for designing looks), "
                    "default, or final (less photon noise, every footprint ray carries radiance); a --config file's "
                    "\"trace\" keys change single settings of it. The table's 'look err' is the error the bake "
                    "predicts (docs/bake-config.md)")
        ->check(CLI::IsMember({"preview", "default", "final"}));
    cmd->add_flag("--keep-axes", args->keep_axes,
                  "bake every sample of every look axis, even an axis whose samples cannot change any frame "
                  "(by default such an axis is baked at one sample and the bake says so)");
    cmd->add_flag("--fire-lights", args->fire_lights,
                  "also store each frame's fire lights: up to 8 point lights approximating the light the fire "
                  "sends into the scene, for any look (fl_package_get_fire_lights, info --json; about 160 KiB a frame)");
    cmd->add_option(
           "--fire-probes", args->fire_probes,
           "also store each frame's fire probes: an N x N x N grid of irradiance probes (order-2 "
           "spherical harmonics) on a box 1.5x the volume's bounds, for any look "
           "(fl_package_get_fire_probes, info --json; 355 KiB a frame for N = 6 on the bundled sample)")
        ->check(CLI::Range(2, bake::kMaxFireProbeResolution));
    cmd->add_flag("--resume", args->resume,
                  "continue an interrupted bake of the same output: the frames it finished (kept in "
                  "OUT.firelook.partial/) are reused when they were baked with the same settings from unchanged files, "
                  "and only the others are baked; the package is byte for byte the one an uninterrupted bake writes");
    CLI::Option* plan_only = cmd->add_flag(
        "--plan-only", args->plan_only,
        "write a plan to -o instead of a package: every frame read once for what the whole sequence gives a bake "
        "(frame hashes, bounds, temperature and density survey), for shards baked with --plan");
    CLI::Option* plan = cmd->add_option(
        "--plan", args->plan,
        "bake with the plan --plan-only wrote (from the same sequence, with the same read settings): only the "
        "frames of --frames are read, each checked against the plan's hash; the same bytes as without");
    plan_only->excludes(plan);
    for (const char* other : {"--frames", "--resume", "--report"}) plan_only->excludes(other);
    cmd->add_option("--threads", args->threads,
                    "worker threads (default: every core); the package's bytes do not depend on it")
        ->check(CLI::NonNegativeNumber);
    addSceneFlags(*cmd, args->scene);
    cmd->callback([cmd, args] {
        bake::BakeConfig config = makeBakeConfig(*cmd, args->scene, args->quality);
        if (args->plan_only) return writePlan(args->sequence, args->output, config);
        if (!args->frames.empty()) config.frames = args->frames;
        if (cmd->count("--seed") || args->scene.config.empty()) config.seed = args->seed;
        if (!args->memory_budget.empty()) config.memory_budget_bytes = bake::parseByteSize(args->memory_budget);
        if (args->keep_axes) config.collapse_unused_axes = false;
        if (args->fire_lights) config.fire_lights = true;
        if (args->fire_probes > 0) config.fire_probes = args->fire_probes;
        config.target = storageTarget(*cmd, args->target);
        std::unique_ptr<tbb::global_control> threads;
        if (args->threads > 0)
            threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                            static_cast<size_t>(args->threads));
        std::fprintf(stderr, "firelook: %s\n", describeTraceChoice(config).c_str());
        ProgressBar bar("bake");
        bake::BakeReport report;
        try {
            report = bake::bakePackage(
                args->sequence, args->output, config, kToolVersion,
                [&](double fraction, const std::string& detail) {
                    bar.update(fraction, detail);
                    throwIfInterrupted();  // unwinds through the writer, which deletes its temporary file
                    return true;
                },
                [](const std::string& line) { std::fprintf(stderr, "firelook: %s\n", line.c_str()); },
                {.resume = args->resume,
                 .plan = args->plan.empty() ? std::nullopt : std::optional(readPlan(args->plan)),
                 .plan_file = args->plan});
        } catch (...) {
            // Finished frames stay for --resume; say where, then report the failure itself.
            const size_t kept = bake::BakeCheckpoint::keptFrames(args->output);
            if (kept > 0)
                std::fprintf(stderr, "firelook: %zu finished frame%s kept in %s; the same command with --resume bakes only the rest\n",
                             kept, kept == 1 ? "" : "s", bake::BakeCheckpoint::folderFor(args->output).c_str());
            throw;
        }
        bar.finish(std::to_string(report.frames.size()) + " frames");
        std::printf("wrote %s: %zu frames, %.1f MB (%.2f%% of the %.1f MB of float basis images)\n",
                    args->output.c_str(), report.frames.size(), report.package_bytes / 1e6,
                    100.0 * report.package_bytes / std::max<double>(1.0, report.uncompressed_basis_bytes),
                    report.uncompressed_basis_bytes / 1e6);
        if (config.target.package_bytes > 0 && !report.frames.empty())
            std::printf("target size %.2f MiB: %.1f KiB a frame; q scales every error setting\n",
                        config.target.package_bytes / 1048576.0, report.frames.front().share_bytes / 1024.0);
        if (config.target.basis_error > 0.0)
            std::printf("target error %.2e per frame (svd and storage together: 'pred err')\n", config.target.basis_error);
        const bool sized = config.target.package_bytes > 0;
        // "photons": the multiple of the settings' photons the noise target asked for; "noise": the
        // photon noise it predicts for the worst column's image (relative RMSE); "quad": the radiance
        // rays' quadrature error, measured, "rays" the radiance rays of the footprint's (m/n an
        // axis) and "step" the camera rays' smallest step in voxels; "look err": all of a look's
        // predicted error together.
        std::printf("%6s %5s %10s %10s %10s %9s %9s %9s %9s %7s %8s %8s %7s %5s %5s %9s %9s %9s%s\n", "frame",
                    "rank", "svd err", "store err", "pred err", "alpha err", "KiB", "U KiB", "depth KiB",
                    "orders", "photons", "noise %", "quad %", "rays", "step", "look err %", "trace s", "svd s",
                    sized ? "      q" : "");
        for (const bake::FrameBakeReport& f : report.frames) {
            const std::string rays = f.footprint_rays_per_axis > 0
                                         ? std::to_string(f.radiance_rays_per_axis) + "/" +
                                               std::to_string(f.footprint_rays_per_axis)
                                         : "-";
            std::printf(
                "%6d %5d %10.2e %10.2e %10.2e %9.1e %9.1f %9.1f %9.1f %7d %7.2fx %8.2f %7.2f %5s %5.3g %10.2f "
                "%9.1f %9.1f",
                f.frame, f.rank, f.truncation_error, f.quantisation_error,
                std::hypot(f.truncation_error, f.quantisation_error), f.alpha_storage_bound,
                (f.u_bytes + f.svt_bytes + f.depth_bytes) / 1024.0, f.u_bytes / 1024.0,
                f.depth_bytes / 1024.0, f.scattering_orders, f.photon_multiple,
                100.0 * f.predicted_photon_noise, 100.0 * f.radiance_quadrature_error, rays.c_str(),
                f.camera_step_voxels, 100.0 * f.predictedLookError(), f.trace_seconds, f.compress_seconds);
            if (sized) std::printf(" %6.3f", f.quality_scale);
            const double noise_target = config.trace.photon_noise_target;
            std::printf("%s%s%s\n", f.has_target && !f.target_met ? "  (over target)" : "",
                        noise_target > 0.0 && f.predicted_photon_noise > noise_target ? "  (photon noise over its target)"
                                                                                      : "",
                        f.resumed ? "  (resumed)" : "");
        }
        std::printf("bake time %.1f s, peak memory %.0f MiB (budget %.0f MiB)\n", report.seconds,
                    report.peak_memory_kib / 1024.0, report.memory_budget_bytes / 1048576.0);
        if (!args->report_json.empty()) writeReportJson(args->report_json, args->sequence, report);
    });
}

}  // namespace firelook::cli
