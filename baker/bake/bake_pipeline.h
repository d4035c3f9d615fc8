// `firelook bake`: VDB sequence -> .firelook package, one frame at a time
// (memory bounded by one frame's basis matrix), written atomically.
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bake/axis_collapse.h"
#include "bake/axis_derivation.h"
#include "bake/bake_config.h"
#include "bake/sequence_plan.h"
#include "basis/bake_description.h"

namespace firelook::bake {

struct FrameBakeReport {
    int frame = 0;
    bool resumed = false;  // kept from an interrupted run (--resume): no timings, the sizes and errors it recorded
    int rank = 0;
    double truncation_error = 0.0;
    double quantisation_error = 0.0;  // of U and S V^T as stored, relative to ||B||_F
    size_t detailed_pixels = 0;       // pixels that keep all their footprint rays
    double alpha_storage_bound = 0.0;  // largest alpha error the stored depths can add
    uint64_t u_bytes = 0, svt_bytes = 0, depth_bytes = 0;  // the frame's sections in the package
    uint64_t fire_light_bytes = 0;     // its fire lights' section (not recorded in META)
    double fire_light_seconds = 0.0;
    uint64_t fire_probe_bytes = 0;  // its fire probes' section (not recorded in META)
    double fire_probe_seconds = 0.0;
    int scattering_orders = 0;
    double last_order_fraction = 0.0;  // largest share of a column's scattered power the last order added
    double tail_fraction = 0.0;        // largest share the geometric tail of the untraced orders added
    int photon_chains = 0;             // independent photon chains traced
    double photon_multiple = 0.0;      // photons traced / the photons the settings name
    double order_photon_share = 1.0;   // the further orders' photons / equal ones (min_order_photon_share)
    double predicted_photon_noise = 0.0;  // the worst column's predicted photon noise (photon_noise.h)
    // The radiance rays' quadrature error as a look sees it, measured on every 16th pixel
    // (FrameBasis::radiance_quadrature_error; 0 when every footprint ray carries radiance).
    double radiance_quadrature_error = 0.0;
    // The m of the m x m radiance rays a pixel the frame was traced with, and the n of its footprint
    // rays (TraceSettings::radiance_quadrature_target chooses m per frame).
    int radiance_rays_per_axis = 0, footprint_rays_per_axis = 0;
    // The radiance rays' and the depth-only rays' smallest steps, in voxels
    // (FrameBasis::camera_step_voxels and depth_step_voxels; 0 in packages from before they were
    // recorded).
    double camera_step_voxels = 0.0, depth_step_voxels = 0.0;
    // Each light's depths' march step and its measured source error (FrameBasis::light_steps; none
    // in packages from before they were chosen), with every step measured (--report only).
    std::vector<LightStep> light_steps;
    double lightStepError() const {
        double worst = 0.0;
        for (const LightStep& light : light_steps) worst = std::max(worst, light.source_error);
        return worst;
    }
    // Each choice of radiance rays and step the trace measured, and the error it allowed
    // (FrameBasis::quadrature_candidates and radiance_quadrature_allowance; --report only).
    std::vector<QuadratureCandidate> quadrature_candidates;
    double radiance_quadrature_allowance = 0.0;
    // What the bake predicts for a look's relative RMSE: the SVD and storage error, the photon noise
    // (its worst column's) and the quadrature error together in quadrature. A guide, not a bound:
    // the blend between grid points and the march step's bias are not in it (scripts/bench/
    // accuracy.sh: it held the worst look in 11 of the 12 regime runs of 2026-12-06, not thin-late's
    // 0.97% against 0.54% with the default settings).
    double predictedLookError() const {
        return std::sqrt(truncation_error * truncation_error + quantisation_error * quantisation_error +
                         predicted_photon_noise * predicted_photon_noise +
                         radiance_quadrature_error * radiance_quadrature_error +
                         lightStepError() * lightStepError());
    }
    double trace_seconds = 0.0;
    double compress_seconds = 0.0;
    // What the memory plan chose and estimated before tracing (frameMemoryPlan).
    int cell_edge_voxels = 0;
    int light_spacing_voxels = 0;
    double cell_optical_depth = 0.0;
    double pixel_footprint_voxels = 0.0;  // what the cells were sized against (not kept for resumed frames)
    double setup_seconds = 0.0, light_seconds = 0.0, photon_seconds = 0.0, camera_seconds = 0.0,
           check_seconds = 0.0;
    uint64_t estimated_peak_bytes = 0;
    uint64_t active_voxels = 0;
    uint64_t columns_traced = 0;  // basis columns: grid points x (bins + lights)
    // What a --target-size or --target-error chose (storage_target.h); has_target false without one.
    bool has_target = false;
    double predicted_error = 0.0;  // hypot(truncation_error, quantisation_error)
    double quality_scale = 1.0;    // --target-size: the factor on every error setting
    uint64_t share_bytes = 0;      // --target-size: the frame's share of the package
    bool target_met = true;
    CompressionSettings compression_used;
    basis::FrameCodecSettings storage_used;
};

struct BakeReport {
    std::vector<FrameBakeReport> frames;
    std::string sequence_xxh3_64;  // the sequence's identity (sequence_plan.h), as META records it
    double seconds = 0.0;
    uint64_t package_bytes = 0;
    uint64_t uncompressed_basis_bytes = 0;  // float32 basis images the package stands for
    long peak_memory_kib = 0;
    uint64_t memory_budget_bytes = 0;  // the budget the bake ran under
    // Which axes could not change any frame and were baked at one sample (axis_collapse.h);
    // axes_analysed is false when no axis had two samples or collapse_unused_axes was off.
    bool axes_analysed = false;
    AxisAnalysis axes;
    // The axes not given explicitly and the default look, mapped to the data's units
    // (axis_derivation.h); what it derived and from what.
    AxisDerivation derivation;
};

// What a --target-size or --target-error chose for a frame, as META's errors[].storage_target and
// the --report JSON record it (null without a target).
nlohmann::ordered_json storageTargetEntry(const FrameBakeReport& frame);

// Each light's step as META's errors[].light_steps records it (step_voxels, source_error), with
// every step measured where `candidates` (the --report JSON).
nlohmann::ordered_json lightStepsJson(const std::vector<LightStep>& steps, bool candidates);

// The default --memory-budget: 60% of the machine's physical memory (the rest for the system and
// whatever runs beside the bake).
uint64_t defaultMemoryBudget();

// What baking one frame holds at its peak, estimated before tracing, with the trace's plan sized
// to fit `budget_bytes` (0: no limit): the trace (basis, depths, cells, light lattice, medium),
// the compression, and the process's fixed share (libraries, the sequence's metadata).
struct FrameMemoryPlan {
    TracePlan trace;
    uint64_t compression_bytes = 0;
    uint64_t fixed_bytes = 0;
    uint64_t peakBytes() const;
    bool fits(uint64_t budget_bytes) const { return trace.fits && (budget_bytes == 0 || peakBytes() <= budget_bytes); }
};
FrameMemoryPlan frameMemoryPlan(const render::Medium& medium, const render::Camera& camera, const BasisModel& model,
                                const TraceSettings& trace, const CompressionSettings& compression,
                                uint64_t budget_bytes);

// The description (bins, axes, lights, size) a bake of this sequence with this configuration
// produces, with the axes not given explicitly derived from the data (axis_derivation.h) and the
// default look in the data's units; also used by `reference` to match it. `survey`: the
// sequence's, or null to have it measured here (one load of every frame).
struct DescribedBake {
    basis::BakeDescription description;
    AxisDerivation derivation;
};
DescribedBake describeDerivedBake(const vdb::VdbSequence& sequence, const BakeConfig& config,
                                  const SceneSetup& scene, const SequenceSurvey* survey = nullptr);
basis::BakeDescription describeBake(const vdb::VdbSequence& sequence, const BakeConfig& config,
                                    const SceneSetup& scene);

// How this run goes about a bake; nothing here changes the package's bytes.
struct BakeRunOptions {
    // Reuse the frames an interrupted bake of the same output kept (bake/bake_checkpoint.h) when
    // they were baked with the same settings from unchanged files; bake only the others.
    bool resume = false;
    // What the whole sequence gives the bake (bake --plan), read from `plan_file`; without it the
    // bake reads every frame once for it. The same bytes either way.
    std::optional<SequencePlan> plan;
    std::filesystem::path plan_file;
};

// Each finished frame is kept as its own small package in "<output>.partial/"; the package is
// assembled from those parts at the end (bake/package_merge.h) and the folder removed. A frame's
// bytes depend only on the settings, the whole sequence (temperature range, camera, axis analysis)
// and the frame itself, never on which other frames the bake selects: shards of a sequence baked
// separately merge into the package one bake writes.
// progress(fraction, detail) returns false to cancel: the bake then throws, leaves no package
// behind and keeps the finished frames for --resume. notice gets one line saying the axes derived
// from the data (when an axis was not given), one per axis collapsed, before any tracing, and one per kept frame that cannot be resumed.
BakeReport bakePackage(const std::string& sequence_path, const std::filesystem::path& output,
                       const BakeConfig& config, const std::string& tool_version,
                       const std::function<bool(double, const std::string&)>& progress = {},
                       const std::function<void(const std::string&)>& notice = {},
                       const BakeRunOptions& run = {});

}  // namespace firelook::bake
