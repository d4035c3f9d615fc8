// firelook bench SEQUENCE --package P [--frames 3,7,11] [--looks 20] [--spp 1024] [--split] [-o OUT.json]
//                [--alpha-rays N] [--reference-cache DIR] [--csv FILE --label TEXT]
//                [--emission-scale S] [--corners]
//
// Accuracy of a baked package against the reference path tracer (docs/testing.md):
// random looks inside the baked ranges — T_c, k_s, k_f between grid
// points and near the ends of every range, varied emissivity and light — each
// rendered from the package and path-traced at the same parameters. With
// --split the error is divided by its sources:
//   tracing       basis tracer at exactly the look's (T_c, k_s, k_f) vs reference
//   interpolation uncompressed basis blended between grid points vs that direct trace
//   compression   package (SVD truncation + half U) vs the uncompressed blend
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>
#include <span>

#include "bake/bake_pipeline.h"
#include "bake/basis_tracer.h"
#include "bake/scene_setup.h"
#include "basis/basis_package.h"
#include "basis/coefficients.h"
#include "basis/look_renderer.h"
#include "basis/recombine.h"
#include "cli/commands.h"
#include "cli/interrupt.h"
#include "cli/output_option.h"
#include "cli/progress_bar.h"
#include "cli/sequence_options.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "render/footprint_transmittance.h"
#include "render/random.h"
#include "render/reference_tracer.h"
#include "reference/frame_medium.h"
#include "reference/provenance_read_options.h"
#include "world/package_camera.h"

namespace firelook::cli {
namespace {

using nlohmann::ordered_json;

// How bench draws its looks: `--emission-scale` scales every look's emission (0: the lights alone,
// the regime of sunlit smoke), `--corners` puts every look on a corner of the (T_c, k_s, k_f) box.
struct LookDraw {
    double emission_scale = 1.0;
    bool corners = false;
};

// A look drawn at random inside the package's ranges. A third of the looks put
// each parameter within 5% of one end of its range; the rest draw it uniformly
// (k_s and k_f log-uniformly), so they land between grid points. With draw.corners, look i sits
// on corner i mod 8 (bit 0: T_c, bit 1: k_s, bit 2: k_f at the top of its range).
Look randomLook(const basis::BakeDescription& d, render::Pcg32& rng, int index, const LookDraw& how = {}) {
    int axis_index = 0;
    const auto draw = [&](const std::vector<double>& axis, bool logarithmic) {
        const double lo = axis.front(), hi = axis.back();
        double u = rng.uniform();
        if (index % 3 == 2) u = rng.uniform() < 0.5 ? 0.05 * u : 1.0 - 0.05 * u;
        if (how.corners) u = ((index % 8) >> axis_index) & 1 ? 1.0 : 0.0;
        ++axis_index;
        if (logarithmic && lo > 0.0) return lo * std::pow(hi / lo, u);
        return lo + u * (hi - lo);
    };
    Look look;
    look.source_name = "bench look " + std::to_string(index);
    look.albedo = d.albedo;
    look.temperature_threshold = draw(d.axes.temperature_threshold, false);
    look.smoke_extinction = draw(d.axes.smoke_extinction, true);
    look.flame_extinction = draw(d.axes.flame_extinction, true);
    // Emission: black up to a start temperature, then three stops of random warm colours.
    EmissionStops stops;
    const double t_lo = d.bins.t_lo, t_hi = d.bins.t_hi;
    double t = t_lo + (0.3 + 0.3 * rng.uniform()) * (t_hi - t_lo);
    stops.stops.push_back({t, Rgb(0.0f)});
    for (int s = 0; s < 3; ++s) {
        t += (t_hi - t) * (0.3 + 0.4 * rng.uniform());
        const float intensity = static_cast<float>((1.0 + 12.0 * rng.uniform()) * how.emission_scale);
        const Rgb hue(1.0f, static_cast<float>(0.2 + 0.7 * rng.uniform()), static_cast<float>(0.05 + 0.4 * rng.uniform()));
        stops.stops.push_back({t, intensity * hue});
    }
    look.emission = stops;
    for (size_t l = 0; l < d.light_directions.size(); ++l) {
        const float e = static_cast<float>(0.5 + 3.0 * rng.uniform());
        look.light_irradiance.push_back(Rgb(e, e * static_cast<float>(0.8 + 0.2 * rng.uniform()), e * 0.85f));
    }
    return look;
}

render::RenderImage toImage(const basis::BakeDescription& d, std::vector<float> rgba) {
    return {d.width, d.height, std::move(rgba)};
}

// An uncompressed basis matrix (pixels x columns, row-major) transposed to the column-major
// layout of S V^T, so the coefficient kernel weights its columns.
std::vector<float> columnMajor(const bake::FrameBasis& b) {
    const size_t pixels = static_cast<size_t>(b.width) * b.height, columns = static_cast<size_t>(b.columns);
    std::vector<float> t(b.matrix.size());
    for (size_t p = 0; p < pixels; ++p)
        for (size_t c = 0; c < columns; ++c) t[c * pixels + p] = b.matrix[p * columns + c];
    return t;
}

// The image of a look from an uncompressed basis (columnMajor) traced with `traced`: the
// coefficient kernel with the pixels as its rank (the same weighted sum the package's
// z = S V^T w is), alpha from the package's exact depths.
std::vector<float> imageFromBasis(const basis::BakeDescription& d, const basis::ResidentFrame& factors,
                                  const std::vector<float>& basis_columns, const basis::BasisModel& traced,
                                  const Look& look, const LookModel& model) {
    const int pixels = d.pixelCount();
    std::vector<float> rgb(static_cast<size_t>(pixels) * 3), rgba(static_cast<size_t>(pixels) * 4);
    basis::coefficientKernel(traced, basis_columns.data(), pixels, look.extinction(),
                             model.emission.coefficients.data(), look.light_irradiance.data(), rgb.data());
    for (int p = 0; p < pixels; ++p) {
        for (int ch = 0; ch < 3; ++ch) rgba[p * 4 + ch] = std::max(rgb[p * 3 + ch], 0.0f);
        rgba[p * 4 + 3] = basis::pixelAlpha(d, factors, p, look.extinction());
    }
    return rgba;
}

// The entry farthest from zero, with its sign.
double worstBySize(std::span<const double> v) {
    double worst = 0.0;
    for (double x : v)
        if (std::fabs(x) > std::fabs(worst)) worst = x;
    return worst;
}

// Per RGB channel, the image's total against the reference's, minus 1 (0 where the reference is black).
std::array<double, 3> channelMeanBias(const render::RenderImage& image, const render::RenderImage& reference) {
    std::array<double, 3> sum{}, ref{};
    for (size_t p = 0; p < reference.rgba.size(); ++p) {
        if (p % 4 == 3) continue;
        sum[p % 4] += image.rgba[p];
        ref[p % 4] += reference.rgba[p];
    }
    std::array<double, 3> bias{};
    for (int c = 0; c < 3; ++c) bias[c] = ref[c] > 0.0 ? sum[c] / ref[c] - 1.0 : 0.0;
    return bias;
}

double maxAlphaDifference(const std::vector<float>& rgba, const std::vector<float>& alpha) {
    double worst = 0.0;
    for (size_t p = 0; p < alpha.size(); ++p) worst = std::max(worst, double(std::fabs(rgba[p * 4 + 3] - alpha[p])));
    return worst;
}

// Reference renders and exact alphas kept on disk between bench runs (the sweep
// evaluates many packages against the same looks). Keyed by everything the data
// depends on; FNV-1a because the key only has to be stable, not cryptographic.
// An entry is: key length, key, one double, the floats.
std::filesystem::path cachePath(const std::filesystem::path& dir, const std::string& kind, const std::string& key) {
    uint64_t h = 1469598103934665603ULL;
    for (unsigned char c : key) h = (h ^ c) * 1099511628211ULL;
    char name[40];
    std::snprintf(name, sizeof name, "-%016llx.bin", static_cast<unsigned long long>(h));
    return dir / (kind + name);
}

bool loadCached(const std::filesystem::path& file, const std::string& key, double& scalar, std::vector<float>& values) {
    if (file.empty()) return false;
    std::ifstream in(file, std::ios::binary);
    if (!in) return false;
    uint64_t key_size = 0;
    in.read(reinterpret_cast<char*>(&key_size), sizeof key_size);
    if (!in || key_size != key.size()) return false;
    std::string stored(key_size, '\0');
    in.read(stored.data(), static_cast<std::streamsize>(key_size));
    if (stored != key) return false;  // a hash collision: compute again
    in.read(reinterpret_cast<char*>(&scalar), sizeof scalar);
    in.read(reinterpret_cast<char*>(values.data()), static_cast<std::streamsize>(values.size() * sizeof(float)));
    return static_cast<bool>(in);
}

// Written atomically, so an interrupted bench never leaves a truncated entry.
void storeCached(const std::filesystem::path& file, const std::string& key, double scalar,
                 const std::vector<float>& values) {
    if (file.empty()) return;
    const uint64_t key_size = key.size();
    std::string bytes;
    bytes.append(reinterpret_cast<const char*>(&key_size), sizeof key_size);
    bytes.append(key);
    bytes.append(reinterpret_cast<const char*>(&scalar), sizeof scalar);
    bytes.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
    writeFileAtomically(file, bytes);
}

// One CSV row per bench run (header written when the file is new), for the speed-vs-error sweep.
void appendCsvRow(const std::filesystem::path& file, const std::string& label, const ordered_json& summary) {
    static const char* const kColumns[] = {"looks", "median_relative_rmse", "worst_relative_rmse",
                                           "median_reference_noise", "median_noise_corrected_rmse",
                                           "worst_noise_corrected_rmse", "max_alpha_error",
                                           "median_image_mean_bias", "worst_image_mean_bias",
                                           "median_coefficients_us", "median_image_ms", "package_bytes",
                                           "bake_seconds", "bake_peak_memory_mib",
                                           "worst_channel_image_mean_bias", "median_image_mean_reference_noise"};
    const bool fresh = !std::filesystem::exists(file) || std::filesystem::file_size(file) == 0;
    std::ofstream out(file, std::ios::app);
    if (fresh) {
        out << "label";
        for (const char* c : kColumns) out << ',' << c;
        out << '\n';
    }
    out << label;
    for (const char* c : kColumns) out << ',' << summary.at(c).dump();
    out << '\n';
    if (!out) throw Error(ErrorCode::IoError, file.string() + ": cannot append the bench row");
}


double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double maxOf(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

// A relative RMSE against the reference with the reference's own noise (independent of the error
// measured) subtracted in quadrature.
double withoutReferenceNoise(double error, double reference_noise) {
    return std::sqrt(std::max(0.0, error * error - reference_noise * reference_noise));
}

bake::TraceSettings traceSettingsOf(const ordered_json& metadata) {
    bake::TraceSettings t;
    const ordered_json& s = metadata.at("provenance").at("settings").at("trace");
    // Keys a package may lack (recorded only by later versions) keep the defaults.
    t.cell_voxels = s.at("cell_voxels");
    t.max_cells_per_axis = s.value("max_cells_per_axis", t.max_cells_per_axis);
    t.max_cell_optical_depth = s.value("max_cell_optical_depth", t.max_cell_optical_depth);
    // Packages from before the cells followed the pixels (2026-12-07): the count and depth alone.
    t.cell_pixel_footprints = s.value("cell_pixel_footprints", 0.0);
    t.min_cells_across = s.value("min_cells_across", t.min_cells_across);
    t.light_points_per_axis = s.value("light_points_per_axis", t.light_points_per_axis);
    t.footprint_step = s.value("footprint_step", t.footprint_step);
    t.photons_primary = s.at("photons_primary");
    t.photons_per_order = s.at("photons_per_order");
    t.photon_noise_target = s.value("photon_noise_target", 0.0);  // packages from before it: fixed photons
    t.max_photon_scale = s.value("max_photon_scale", t.max_photon_scale);
    t.photon_pilot_share = s.value("photon_pilot_share", 1.0);  // before the pilot chains: whole ones
    t.min_order_photon_share = s.value("min_order_photon_share", 1.0);  // before it: every order its photons
    t.max_orders = s.at("max_orders");
    t.order_tolerance = s.at("order_tolerance");
    t.track_step_cells = s.value("track_step_cells", 0.5);  // before the key (2026-12-08): half a cell
    t.step_voxels = s.at("step_voxels");
    t.footprint_samples_per_axis = s.value("footprint_samples_per_axis", 1);
    // Packages from before the key: every footprint ray carried radiance, the default.
    t.radiance_samples_per_axis = s.value("radiance_samples_per_axis", t.radiance_samples_per_axis);
    // And from before the trace chose m per frame (2026-12-07): 0 above meant every ray.
    t.radiance_quadrature_target = s.value("radiance_quadrature_target", 0.0);
    // And from before the photon noise's share (2026-12-07): the target alone.
    t.radiance_quadrature_noise_share = s.value("radiance_quadrature_noise_share", 0.0);
    // And from before the trace chose its step (2026-12-07, fourth session): step_voxels always.
    t.max_step_scale = s.value("max_step_scale", 1);
    // And from before step_radiance_target (2026-12-07, fifth session): radiance_quadrature_target.
    t.step_radiance_target = s.value("step_radiance_target", t.radiance_quadrature_target);
    t.step_alpha_target = s.value("step_alpha_target", t.step_alpha_target);
    t.step_mean_change_target = s.value("step_mean_change_target", t.step_mean_change_target);
    return t;
}

}  // namespace

void registerBenchCommand(CLI::App& app) {
    struct Args {
        std::string sequence, package, json_out;
        std::vector<int> frames;
        std::string reference_cache, csv_out, label, bake_report;
        LookDraw draw;
        int looks = 20, spp = 1024, alpha_rays = 8;
        uint64_t seed = 7;
        bool split = false;
        SequenceFlags sequence_flags;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("bench", "Error of a package against the reference path tracer over random looks");
    cmd->add_option("SEQUENCE", args->sequence, "the sequence the package was baked from")->required();
    cmd->add_option("--package", args->package, "baked package")->required()->check(CLI::ExistingFile);
    cmd->add_option("--frames", args->frames, "frames to test (default: first, middle and last baked frame)")
        ->delimiter(',');
    cmd->add_option("--looks", args->looks, "random looks per frame")->capture_default_str();
    cmd->add_option("--spp", args->spp, "reference samples per pixel")->capture_default_str();
    cmd->add_option("--seed", args->seed, "seed for the looks and the reference")->capture_default_str();
    cmd->add_option("--emission-scale", args->draw.emission_scale,
                    "scale every look's emission (0: the lights alone, as for sunlit smoke)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->add_flag("--corners", args->draw.corners,
                  "put every look on a corner of the (T_c, k_s, k_f) ranges (look i on corner i mod 8)");
    cmd->add_flag("--split", args->split, "split the error by source (re-traces each frame's basis)");
    addOutputOption(*cmd, args->json_out, "write every figure as JSON to this file", {"--json"});
    cmd->add_option("--alpha-rays", args->alpha_rays,
                    "rays per pixel along each axis of the exact alpha the package is judged against")
        ->capture_default_str()
        ->check(CLI::Range(1, 16));
    cmd->add_option("--reference-cache", args->reference_cache,
                    "folder that keeps reference renders and exact alphas between runs (same frame, look, size, spp, seed)");
    cmd->add_option("--csv", args->csv_out, "append the summary as one row of this CSV file");
    cmd->add_option("--label", args->label, "the row's label in --csv")->default_str("the package's file name");
    cmd->add_option("--bake-report", args->bake_report,
                    "the package's `firelook bake --report` JSON: adds its bake seconds and peak memory to the summary")
        ->check(CLI::ExistingFile);
    addSequenceFlags(*cmd, args->sequence_flags);
    cmd->callback([args] {
        const basis::BasisReader package = basis::BasisReader::open(args->package);
        const basis::BakeDescription& d = package.description();
        const ordered_json metadata = ordered_json::parse(package.metadataJson());
        // The package's camera as the runtime reads it (checked: finite, a field of view in (0, pi)).
        const std::optional<world::PackageCamera> baked = world::readPackageCamera(package.metadataJson(), args->package);
        if (!baked)
            throw Error(ErrorCode::NotFound,
                        args->package + ": the package records no camera to render references with");
        render::CameraParameters camera_parameters;
        camera_parameters.world_from_camera = baked->world_from_camera;
        camera_parameters.yfov_radians = baked->yfov_radians;
        camera_parameters.width = baked->width;
        camera_parameters.height = baked->height;
        const render::Camera camera(camera_parameters);
        const std::string camera_key = metadata.at("camera").dump();  // the reference cache's key, as before
        vdb::ReadOptions read = reference::provenanceReadOptions(package.metadataJson(), args->package);
        const bool baked_clamped = read.clamp_extreme;
        applySequenceFlags(args->sequence_flags, read);
        // --clamp-extreme adds to the bake's: a package baked with it saw clamped data, and so must its references.
        read.clamp_extreme = read.clamp_extreme || baked_clamped;
        const vdb::VdbSequence sequence = vdb::VdbSequence::open(args->sequence, read);
        std::vector<int> frames = args->frames;
        if (frames.empty()) {
            const auto& f = d.frames;
            frames = {f.front().frame, f[f.size() / 2].frame, f.back().frame};
            frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
        }
        if (!args->reference_cache.empty()) std::filesystem::create_directories(args->reference_cache);
        const bake::TraceSettings trace = traceSettingsOf(metadata);
        const uint64_t bake_seed = metadata.at("provenance").at("settings").at("seed");

        ordered_json rows = ordered_json::array();
        std::vector<double> rmse, ref_noise, mean_bias, channel_bias, mean_noise, b_trace, b_interp, b_compress, alpha_error, corrected, e_trace, e_trace_corrected, e_interp, e_compress, coeff_us, image_ms;
        render::Pcg32 rng(args->seed);
        ProgressBar bar("bench");
        const int total = static_cast<int>(frames.size()) * args->looks;
        int done = 0;
        for (int frame : frames) {
            throwIfInterrupted();
            const render::Medium medium = reference::mediumFromFrame(sequence.load(frame));
            throwIfInterrupted();
            // Built on the first look whose exact alpha is not cached: marching 8x8 rays per
            // pixel is the slow part of a cached bench run.
            std::optional<render::FootprintTransmittance> exact_alpha;
            // The resident form: what the runtime world draws.
            const basis::ResidentFrame factors = package.loadResidentFrame(frame, std::pmr::get_default_resource());
            std::vector<float> full;  // columnMajor of the frame's basis at the package's grid
            bake::TraceSettings frame_trace = trace;
            frame_trace.seed = bake_seed * 1000003ULL + static_cast<uint64_t>(frame);  // as bakePackage seeds it
            const auto keep_tracing = [](double) { return !interruptRequested(); };
            if (args->split)
                full = columnMajor(bake::traceFrameBasis(medium, camera, d, frame_trace, keep_tracing));
            throwIfInterrupted();
            for (int k = 0; k < args->looks; ++k) {
                throwIfInterrupted();
                const Look look = randomLook(d, rng, done, args->draw);
                const LookModel model = makeLookModel(look, d.bins, d.rbf_width, d.light_directions);

                // Runtime cost: coefficients (median of repeats) and a full image.
                std::vector<float> rgba(static_cast<size_t>(d.pixelCount()) * 4), z(factors.rank * 3);
                const basis::LookWeights weights{look.extinction(), model.emission.coefficients, look.light_irradiance};
                std::vector<double> us;
                for (int r = 0; r < 31; ++r) {
                    const auto t0 = std::chrono::steady_clock::now();
                    basis::computeCoefficients(d, factors, weights, z);
                    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
                }
                coeff_us.push_back(median(us));
                const auto t0 = std::chrono::steady_clock::now();
                basis::renderLookImage(d, factors, look, rgba);
                image_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());

                render::ReferenceSettings rs;
                rs.samples_per_pixel = args->spp;
                rs.seed = args->seed * 7919 + static_cast<uint64_t>(done);
                rs.stop_requested = interruptRequested;
                const std::string size_key = "frame " + std::to_string(frame) + " size " + std::to_string(d.width) +
                                             "x" + std::to_string(d.height);
                const std::string scene_key = " bins " + std::to_string(d.bins.t_lo) + " " + std::to_string(d.bins.t_hi) +
                                              " " + std::to_string(d.bins.count) + " camera " + camera_key +
                                              (d.emission_clamp_to_centres ? " emission clamp centres" : "");
                const std::filesystem::path cache_dir = args->reference_cache;
                render::ReferenceResult ref;
                ref.image = {d.width, d.height, std::vector<float>(static_cast<size_t>(d.pixelCount()) * 4)};
                const std::string ref_key = size_key + " spp " + std::to_string(rs.samples_per_pixel) + " seed " +
                                            std::to_string(rs.seed) + scene_key + " look " + lookToJson(look);
                const std::filesystem::path ref_file = cache_dir.empty() ? cache_dir : cachePath(cache_dir, "ref", ref_key);
                if (!loadCached(ref_file, ref_key, ref.estimated_relative_rmse, ref.image.rgba)) {
                    ref = render::renderReference(medium, model, camera, rs);
                    throwIfInterrupted();  // a stopped render is partial: never cache it
                    storeCached(ref_file, ref_key, ref.estimated_relative_rmse, ref.image.rgba);
                }
                const ExtinctionParams e = look.extinction();
                char extinction_key[128];
                std::snprintf(extinction_key, sizeof extinction_key, " alpha rays %d T_c %.17g k_s %.17g k_f %.17g",
                              args->alpha_rays, e.temperature_threshold, e.smoke_extinction, e.flame_extinction);
                const std::string alpha_key = size_key + scene_key + extinction_key;
                const std::filesystem::path alpha_file = cache_dir.empty() ? cache_dir : cachePath(cache_dir, "alpha", alpha_key);
                std::vector<float> exact(static_cast<size_t>(d.pixelCount()));
                double unused = 0.0;
                if (!loadCached(alpha_file, alpha_key, unused, exact)) {
                    if (!exact_alpha)
                        exact_alpha.emplace(medium, camera, d.bins, args->alpha_rays, 0.1, interruptRequested);
                    exact = exact_alpha->alpha(e);
                    storeCached(alpha_file, alpha_key, 0.0, exact);
                }
                const render::RenderImage pkg = toImage(d, rgba);
                const double e_rgb = render::relativeRmse(pkg, ref.image);
                const double a = maxAlphaDifference(rgba, exact);
                const double a_traced = render::maxAlphaError(pkg, ref.image);
                rmse.push_back(e_rgb);
                ref_noise.push_back(ref.estimated_relative_rmse);
                alpha_error.push_back(a);
                corrected.push_back(withoutReferenceNoise(e_rgb, ref.estimated_relative_rmse));
                // Image-mean bias: the package's total RGB against the reference's, and the reference's
                // own standard error of that total (per-pixel errors add in quadrature).
                double pkg_sum = 0.0, ref_sum = 0.0, ref_squares = 0.0;
                for (size_t p = 0; p < ref.image.rgba.size(); ++p) {
                    if (p % 4 == 3) continue;
                    pkg_sum += pkg.rgba[p];
                    ref_sum += ref.image.rgba[p];
                    ref_squares += double(ref.image.rgba[p]) * ref.image.rgba[p];
                }
                mean_bias.push_back(ref_sum > 0.0 ? pkg_sum / ref_sum - 1.0 : 0.0);
                mean_noise.push_back(ref_sum > 0.0 ? ref.estimated_relative_rmse * std::sqrt(ref_squares) / ref_sum : 0.0);
                const std::array<double, 3> rgb_bias = channelMeanBias(pkg, ref.image);
                channel_bias.push_back(worstBySize(rgb_bias));
                ordered_json row = {{"frame", frame},
                                    {"look", lookToJson(look)},
                                    {"T_c", look.temperature_threshold},
                                    {"k_s", look.smoke_extinction},
                                    {"k_f", look.flame_extinction},
                                    {"relative_rmse", e_rgb},
                                    {"reference_noise", ref.estimated_relative_rmse},
                                    {"noise_corrected_rmse", corrected.back()},
                                    {"image_mean_bias", mean_bias.back()},
                                    {"image_mean_bias_rgb", rgb_bias},
                                    {"image_mean_reference_noise", mean_noise.back()},
                                    {"max_alpha_error", a},
                                    {"max_alpha_error_vs_path_traced", a_traced},
                                    {"coefficients_us", coeff_us.back()},
                                    {"image_ms", image_ms.back()}};
                if (args->split) {
                    basis::ParameterAxes point{{look.temperature_threshold}, {look.smoke_extinction}, {look.flame_extinction}};
                    basis::BasisModel direct_model = d;
                    direct_model.axes = point;
                    const std::vector<float> direct =
                        columnMajor(bake::traceFrameBasis(medium, camera, direct_model, frame_trace, keep_tracing));
                    const render::RenderImage direct_image =
                        toImage(d, imageFromBasis(d, factors, direct, direct_model, look, model));
                    const render::RenderImage blended = toImage(d, imageFromBasis(d, factors, full, d, look, model));
                    e_trace.push_back(render::relativeRmse(direct_image, ref.image));
                    // Without the reference's own noise: the tracer's error at exactly this look, which
                    // holds its photon noise (what the bake predicted, photon_noise.h) and the cells'
                    // and the march's errors.
                    e_trace_corrected.push_back(withoutReferenceNoise(e_trace.back(), ref_noise.back()));
                    e_interp.push_back(render::relativeRmse(blended, direct_image));
                    e_compress.push_back(render::relativeRmse(pkg, blended));
                    // The same split of the image-mean bias (worst channel): each source against the
                    // stage before it.
                    b_trace.push_back(worstBySize(channelMeanBias(direct_image, ref.image)));
                    b_interp.push_back(worstBySize(channelMeanBias(blended, direct_image)));
                    b_compress.push_back(worstBySize(channelMeanBias(pkg, blended)));
                    row["split"] = {{"tracing_vs_reference", e_trace.back()},
                                    {"interpolation", e_interp.back()},
                                    {"compression", e_compress.back()},
                                    {"tracing_bias", b_trace.back()},
                                    {"interpolation_bias", b_interp.back()},
                                    {"compression_bias", b_compress.back()}};
                }
                throwIfInterrupted();
                rows.push_back(row);
                ++done;
                bar.update(double(done) / total, "frame " + std::to_string(frame));
            }
        }
        throwIfInterrupted();  // before --json and --csv are written
        bar.finish();
        ordered_json summary = {{"package", args->package},
                                {"frames", frames},
                                {"looks", rmse.size()},
                                {"reference_spp", args->spp},
                                {"alpha_rays_per_pixel", args->alpha_rays * args->alpha_rays},
                                {"median_relative_rmse", median(rmse)},
                                {"worst_relative_rmse", maxOf(rmse)},
                                {"median_reference_noise", median(ref_noise)},
                                {"median_noise_corrected_rmse", median(corrected)},
                                {"worst_noise_corrected_rmse", maxOf(corrected)},
                                {"max_alpha_error", maxOf(alpha_error)},
                                {"median_image_mean_bias", median(mean_bias)},
                                {"worst_image_mean_bias", worstBySize(mean_bias)},
                                {"worst_channel_image_mean_bias", worstBySize(channel_bias)},
                                {"median_image_mean_reference_noise", median(mean_noise)},
                                {"median_coefficients_us", median(coeff_us)},
                                {"median_image_ms", median(image_ms)},
                                {"package_bytes", package.reader().fileSize()}};
        summary["bake_seconds"] = nullptr;
        summary["bake_peak_memory_mib"] = nullptr;
        if (!args->bake_report.empty()) {
            const ordered_json bake_report = ordered_json::parse(std::ifstream(args->bake_report));
            summary["bake_seconds"] = bake_report.at("seconds");
            summary["bake_peak_memory_mib"] = bake_report.at("peak_memory_mib");
        }
        // What the bake predicted (the largest over the frames benched; none for packages baked before
        // the prediction): its photon noise, beside what the split measures (a look's tracing error
        // without the reference's noise), and a look's whole error, beside the worst look measured.
        const auto predicted = [&](const char* key) {
            std::optional<double> largest;
            for (const ordered_json& e : metadata.value("errors", ordered_json::array()))
                if (e.contains(key) && std::find(frames.begin(), frames.end(), e.at("frame").get<int>()) != frames.end())
                    largest = std::max(largest.value_or(0.0), e.at(key).get<double>());
            return largest ? ordered_json(*largest) : ordered_json(nullptr);
        };
        summary["predicted_photon_noise"] = predicted("predicted_photon_noise");
        summary["predicted_look_error"] = predicted("predicted_look_error");
        summary["within_predicted_look_error"] =
            summary["predicted_look_error"].is_null()
                ? ordered_json(nullptr)
                : ordered_json(maxOf(corrected) <= summary["predicted_look_error"].get<double>());
        if (args->split)
            summary["split_median"] = {{"tracing_vs_reference", median(e_trace)},
                                       {"tracing_noise_corrected", median(e_trace_corrected)},
                                       {"tracing_noise_corrected_worst", maxOf(e_trace_corrected)},
                                       {"interpolation", median(e_interp)},
                                       {"compression", median(e_compress)},
                                       {"tracing_bias", median(b_trace)},
                                       {"interpolation_bias", median(b_interp)},
                                       {"compression_bias", median(b_compress)}};
        std::printf("%s\n", summary.dump(2).c_str());
        if (!args->json_out.empty())
            writeFileAtomically(args->json_out, ordered_json{{"summary", summary}, {"looks", rows}}.dump(2) + "\n");
        if (!args->csv_out.empty())
            appendCsvRow(args->csv_out,
                         args->label.empty() ? std::filesystem::path(args->package).stem().string() : args->label,
                         summary);
    });
}

}  // namespace firelook::cli
