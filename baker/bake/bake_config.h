// Every setting of a bake, with defaults that suit the bundled sample, and the
// optional --config JSON file that overrides them (docs/bake-config.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "bake/axis_derivation.h"
#include "bake/basis_compression.h"
#include "bake/basis_tracer.h"
#include "bake/scene_setup.h"
#include "bake/storage_target.h"
#include "basis/frame_codec.h"
#include "basis/parameter_grid.h"
#include "vdb/read_options.h"

namespace firelook::bake {

// The most probes per axis a bake stores (BakeConfig::fire_probes; the FPRB section allows 64): the
// tracer's memory grows as the cube, outside the bake's estimate (fire_probe_tracer.h).
inline constexpr int kMaxFireProbeResolution = 16;

struct BakeConfig {
    std::string frames;  // "A-B,C,...", empty = all
    SceneOptions scene;
    vdb::ReadOptions read;
    int bins = 16;
    std::optional<double> t_lo, t_hi;  // default: the sequence's temperature range
    double rbf_width = kDefaultRbfWidth;
    double albedo = 0.7;
    // The sampled look parameters T_c, k_s, k_f; one value collapses an axis (that parameter is
    // fixed). An axis left unset is the design's (designAxes()) mapped to the data's own units by
    // the bake; one set here or by bake.json's "axes" keys is baked as it is (axis_derivation.h).
    BakeAxes axes;
    // An axis whose samples cannot change any frame's image is baked at one sample (axis_collapse.h).
    // JSON: "axes": {"collapse_unused": false}; firelook bake --keep-axes.
    bool collapse_unused_axes = true;
    int alpha_threshold_samples = 21;  // T_c samples of the per-pixel optical depths (exact alpha)
    // The preset `trace` started from (applyQuality; empty: the defaults). A bake.json's "trace"
    // keys then change single settings of it.
    std::string quality;
    TraceSettings trace;
    CompressionSettings compression;
    // How precisely the package stores each frame (JSON: under "compression").
    basis::FrameCodecSettings storage;
    // A package size or a per-frame error to aim at instead of the settings above as given
    // (storage_target.h; JSON: "compression": {"target_size": "6MiB"} or {"target_error": 0.003}).
    StorageTarget target;
    // Store each frame's fire lights (runtime/basis/fire_lights.h; firelook bake --fire-lights, JSON
    // "fire_lights": true): point lights for an engine's scene lighting, about 160 KiB a frame, so
    // only when asked for.
    bool fire_lights = false;
    // Store each frame's fire probes (runtime/basis/fire_probes.h; firelook bake --fire-probes N,
    // JSON "fire_probes": N): an N x N x N grid of SH irradiance probes around the effect, N from 2
    // to kMaxFireProbeResolution (16); 0 = none. 9 floats a probe, bin and term (3 terms on the
    // bundled sample: 355 KiB a frame at N = 6), so only when asked for.
    int fire_probes = 0;
    uint64_t seed = 1;
    // Bytes the bake may hold at its peak (firelook bake --memory-budget); 0 = defaultMemoryBudget().
    uint64_t memory_budget_bytes = 0;
};

// Applies the keys present in a bake.json; unknown keys are an error (a typo
// in a bake setting should not silently bake the wrong thing). Its "quality" is applied first, and
// only when config.quality is still empty (firelook bake --quality wins over the file).
void applyConfigFile(BakeConfig& config, const std::filesystem::path& file);

// The trace settings of a quality preset (firelook bake --quality, bake.json "quality"; what each
// costs and reaches: docs/bake-config.md):
//   "preview": fewer seconds, for looks being designed: 2x2 of the footprint rays carry radiance,
//              photon noise up to 2% with chains of a quarter of the photons, orders until 0.5%
//              is left;
//   "default": TraceSettings as declared (issue 27's accuracy bars, scripts/bench/accuracy.sh):
//              2x2 radiance rays in the frames whose quadrature error they keep within 0.15%;
//   "final":   a 0.125-voxel step, every footprint ray carrying radiance, photon noise up to 0.5%
//              (up to 8 times the photons), orders until 0.1% is left.
// Anything else is an InvalidArgument Error naming the three.
TraceSettings qualityTrace(const std::string& quality);
// config.quality = quality and config.trace = qualityTrace(quality).
void applyQuality(BakeConfig& config, const std::string& quality);

// Throws an InvalidArgument Error when both targets are given or the error is not in (0, 1).
void checkStorageTarget(const StorageTarget& target);

// "6G", "6GiB", "512M", "1048576": bytes. Throws an InvalidArgument Error naming the text.
uint64_t parseByteSize(const std::string& text);

// The whole configuration as JSON, recorded in the package as provenance.
std::string configToJson(const BakeConfig& config);

// "scene", "six-way", "sphere" (42 lights) or "sphere:N" (N of basis/sphere_lights.h's counts)
// into `scene`'s six_way_lights and sphere_lights. An InvalidArgument Error naming the text for
// anything else.
void applyLightsChoice(SceneOptions& scene, const std::string& lights);
// The same as it is written back ("scene" when neither is set).
std::string lightsChoiceName(const SceneOptions& scene);

}  // namespace firelook::bake
