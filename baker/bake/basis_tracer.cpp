#include "bake/basis_tracer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "bake/camera_march.h"
#include "bake/camera_quadrature.h"
#include "bake/index_ray.h"
#include "bake/light_depth_field.h"
#include "bake/photon_noise.h"
#include "bake/photon_pass.h"
#include "bake/photon_start_sampler.h"
#include "bake/scatter_cells.h"
#include "bake/scattered_light.h"
#include "bake/trace_tables.h"
#include "common/error.h"
#include "render/random.h"

namespace firelook::bake {
namespace {

// Progress from worker threads: one report at a time (whoever gets the lock), never below the last
// one (a thread may reach the lock after another reported a later fraction), and a stop flag every
// loop polls so a cancel ends the work within a fraction of a second.
class ProgressGate {
  public:
    explicit ProgressGate(const std::function<bool(double)>& progress) : progress_(progress) {}
    void report(double fraction) {
        if (!progress_ || stop_.load(std::memory_order_relaxed)) return;
        std::unique_lock lock(mutex_, std::try_to_lock);
        if (!lock.owns_lock() || fraction < last_) return;
        last_ = fraction;
        if (!progress_(fraction)) stop_.store(true);
    }
    // Reports from the caller's thread and throws if the work was cancelled.
    void checkpoint(double fraction) {
        report(fraction);
        throwIfStopped();
    }
    void throwIfStopped() const {
        if (stop_.load()) throw Error(ErrorCode::Cancelled, "cancelled");
    }
    const std::atomic<bool>& stopFlag() const { return stop_; }
    bool stopped() const { return stop_.load(std::memory_order_relaxed); }

  private:
    const std::function<bool(double)>& progress_;
    std::mutex mutex_;
    double last_ = 0.0;  // guarded by mutex_
    std::atomic<bool> stop_{false};
};

// Seconds since `start`, which then moves to now: the time of one stage after another.
double lapSeconds(std::chrono::steady_clock::time_point& start) {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - start).count();
    start = now;
    return s;
}

void validateModel(const BasisModel& model) {
    basis::validateAxes(model.axes);
    if (model.axes.temperature_threshold.size() > kMaxAxisSamples ||
        model.axes.smoke_extinction.size() > kMaxAxisSamples || model.axes.flame_extinction.size() > kMaxAxisSamples ||
        model.alpha_thresholds.size() > kMaxAxisSamples || model.alpha_thresholds.empty())
        throw Error(ErrorCode::InvalidArgument,
                    "at most 64 samples per parameter axis and 1..64 alpha thresholds");
    const std::size_t n_tc = model.axes.temperature_threshold.size();
    if (n_tc * std::max(model.axes.smoke_extinction.size(), model.axes.flame_extinction.size()) >
        kMaxAxisFactors)
        throw Error(ErrorCode::InvalidArgument,
                    "at most " + std::to_string(kMaxAxisFactors) +
                        " temperature thresholds times smoke (or flame) extinctions; the model has " +
                        std::to_string(n_tc) + " x " + std::to_string(model.axes.smoke_extinction.size()) +
                        " (" + std::to_string(model.axes.flame_extinction.size()) + ")");
}

// The smallest pair of chains the noise target adds, in pilot chains: a prediction just above the
// target costs at most a quarter more photons than the pilot's. Whole pairs of pilot chains doubled
// them: frame 12 of the bundled sample upsampled 4x at 128x128 with 6-voxel cells, whose two chains
// predicted between 1% and 1.12%, traced 4 chains in 20.1 s, and 2.5 chains' photons in 15.0 s. Not
// smaller, because a chain's passes over whole fields cost the same for any photons: there, about
// 1.25 s a chain of 7 orders against 8 s for the pilot's photons.
constexpr double kSmallestChainPair = 0.25;

// The pair is sized for this share of the noise target: the second prediction scatters about
// 1/sqrt(photons) by a few percent (the accuracy suite's sunlit frame, its pair sized for the target
// itself, predicted 1.02% afterwards, and the bake marked it over the target; 0.99% with 0.95). 0.95
// costs about a tenth more photons in the frames that grow.
constexpr double kPhotonNoiseAim = 0.95;

}  // namespace

int footprintSamplesPerAxis(const TraceSettings& settings, int width, int height) {
    if (settings.footprint_samples_per_axis > 0) return settings.footprint_samples_per_axis;
    const int short_side = std::min(width, height);
    return short_side >= 256 ? 3 : short_side >= 128 ? 4 : short_side >= 64 ? 6 : 8;
}

int radianceSamplesPerAxis(const TraceSettings& settings, int footprint_per_axis) {
    const int m = settings.radiance_samples_per_axis > 0 ? settings.radiance_samples_per_axis : footprint_per_axis;
    return std::min(m, footprint_per_axis);
}

std::vector<int> radianceCandidates(const TraceSettings& settings, int footprint_per_axis) {
    std::vector<int> candidates;
    if (settings.radiance_samples_per_axis > 0 || !(settings.radiance_quadrature_target > 0.0))
        return candidates;
    for (int m = 1; 2 * m * m <= footprint_per_axis * footprint_per_axis; ++m) candidates.push_back(m);
    return candidates;
}

std::vector<int> stepScaleCandidates(const TraceSettings& settings) {
    std::vector<int> scales;
    for (int scale = 2; scale <= settings.max_step_scale; scale *= 2) scales.push_back(scale);
    return scales;
}

double pixelFootprintVoxels(const render::Medium& medium, const render::Camera& camera) {
    const glm::dvec3 forward = -glm::normalize(glm::dvec3(camera.worldFromCamera()[2]));
    double nearest = std::numeric_limits<double>::infinity();
    for (const glm::dvec3& corner : medium.worldCorners())
        nearest = std::min(nearest, glm::dot(corner - camera.position(), forward));
    if (!(nearest > 0.0)) return 0.0;
    return camera.pixelAngle() * nearest / medium.minVoxelEdge();
}

TracePlan planFrameTrace(const render::Medium& medium, const render::Camera& camera, const BasisModel& model,
                         const TraceSettings& settings) {
    validateModel(model);
    const TraceTables tb(model);
    const std::size_t G = tb.points, C = tb.columns;
    const std::size_t pixels = static_cast<std::size_t>(camera.width()) * camera.height();
    const int per_axis = footprintSamplesPerAxis(settings, camera.width(), camera.height());
    const std::size_t rays = static_cast<std::size_t>(per_axis) * per_axis;
    TracePlan plan;
    plan.basis_bytes = pixels * G * C * sizeof(float);
    plan.depth_bytes = pixels * rays * (1 + tb.n_alpha) * sizeof(float);
    const glm::ivec3 d = medium.dims();
    plan.medium_bytes = static_cast<std::size_t>(d.x) * d.y * d.z * 2 * sizeof(float) +
                        static_cast<std::size_t>(medium.brickCounts().x) * medium.brickCounts().y *
                            medium.brickCounts().z * sizeof(render::BrickRange);
    if (medium.empty()) return plan;

    plan.light_spacing_voxels = lightLatticeSpacing(medium, settings.light_points_per_axis);
    const glm::ivec3 lattice = lightLatticeCount(medium, plan.light_spacing_voxels);
    plan.light_bytes = static_cast<std::size_t>(lattice.x) * lattice.y * lattice.z * tb.lights * 2 * tb.n_tc *
                       sizeof(float);
    if (model.albedo > 0.0) plan.sampler_bytes = 2 * PhotonStartSampler::bytesFor(medium);
    const auto cellBytes = [&](int edge, std::size_t slots) {
        const std::size_t field = slots * G * C * sizeof(float);
        // The chains' sum and signed sum (scattered_light.h), the previous order, and what a photon
        // pass holds at its peak; the masses; the per-cell part sums while the cells are built; the
        // noise prediction's per-row sums (photon_noise.h).
        return 3 * field + photonPassBytes(slots * G * C, slots) + slots * G * sizeof(float) +
               scatterCellCount(medium, edge) * 2 * tb.n_tc * sizeof(double) +
               kPhotonNoisePixelsPerAxis * G * C * 2 * sizeof(double);
    };
    const int longest = longestInfluenceAxis(medium);
    float max_density = 0.0f;
    const glm::ivec3 bricks = medium.brickCounts();
    for (int z = 0; z < bricks.z; ++z)
        for (int y = 0; y < bricks.y; ++y)
            for (int x = 0; x < bricks.x; ++x) max_density = std::max(max_density, medium.brick({x, y, z}).max_density);
    const double max_k = std::max(model.axes.smoke_extinction.back(), model.axes.flame_extinction.back());
    const double depth_per_voxel = max_k * max_density * medium.minVoxelEdge();
    int edge = scatterCellEdge(medium, settings.cell_voxels, settings.max_cells_per_axis);
    plan.pixel_footprint_voxels = pixelFootprintVoxels(medium, camera);
    if (settings.cell_pixel_footprints > 0.0) {
        const double by_pixels = std::floor(settings.cell_pixel_footprints * plan.pixel_footprint_voxels);
        const int by_count = longest / std::max(settings.min_cells_across, 1);
        edge = std::max(edge, static_cast<int>(std::min<double>(by_pixels, by_count)));
    }
    if (depth_per_voxel * edge > settings.max_cell_optical_depth) {
        const double thin = std::floor(settings.max_cell_optical_depth / depth_per_voxel);
        edge = std::max(settings.cell_voxels, static_cast<int>(std::min<double>(thin, edge)));
    }
    for (;;) {
        plan.cell_edge_voxels = edge;
        plan.cell_slots = model.albedo > 0.0 ? scatterSlotUpperBound(medium, edge) : 0;
        plan.cell_bytes = model.albedo > 0.0 ? cellBytes(edge, plan.cell_slots) : 0;
        if (settings.memory_budget_bytes == 0 || plan.totalBytes() <= settings.memory_budget_bytes) break;
        if (edge >= longest) {
            plan.fits = false;
            break;
        }
        edge = std::min(longest, std::max(edge + 1, edge * 5 / 4));
    }
    plan.cell_optical_depth = depth_per_voxel * plan.cell_edge_voxels;
    return plan;
}

FrameBasis traceFrameBasis(const render::Medium& medium, const render::Camera& camera,
                           const BasisModel& model, const TraceSettings& settings,
                           const std::function<bool(double)>& progress) {
    return traceFrameBasis(medium, camera, model, settings, planFrameTrace(medium, camera, model, settings), progress);
}

FrameBasis traceFrameBasis(const render::Medium& medium, const render::Camera& camera,
                           const BasisModel& model, const TraceSettings& settings, const TracePlan& plan,
                           const std::function<bool(double)>& progress) {
    validateModel(model);
    ProgressGate gate(progress);
    const TraceTables tb(model);
    const int G = tb.points, C = tb.columns;
    FrameBasis out;
    out.width = camera.width();
    out.height = camera.height();
    out.columns = G * C;
    const size_t pixels = static_cast<size_t>(out.width) * out.height;
    out.matrix.assign(pixels * out.columns, 0.0f);
    const int per_axis = footprintSamplesPerAxis(settings, camera.width(), camera.height());
    out.footprint_samples = per_axis * per_axis;
    const int given_per_axis = radianceSamplesPerAxis(settings, per_axis);
    out.radiance_samples = given_per_axis * given_per_axis;  // until the camera pass measures
    out.camera_step_voxels = settings.step_voxels;           // and its steps
    out.depth_step_voxels = settings.step_voxels;
    out.depth_b.assign(pixels * out.footprint_samples, 0.0f);
    out.depth_a.assign(pixels * out.footprint_samples * tb.n_alpha, 0.0f);
    if (medium.empty()) return out;

    auto clock = std::chrono::steady_clock::now();
    out.cell_edge_voxels = plan.cell_edge_voxels;
    out.light_spacing_voxels = plan.light_spacing_voxels;
    out.cell_optical_depth = plan.cell_optical_depth;
    const double voxel = medium.minVoxelEdge();
    // The setup stages report from their worker threads and stop within a layer of their work.
    const auto stage = [&](double from, double to) {
        return [&gate, from, to](double done) {
            gate.report(from + (to - from) * done);
            return !gate.stopped();
        };
    };
    const ScatterCells cells = buildScatterCells(medium, tb, plan.cell_edge_voxels, stage(0.0, 0.02));
    gate.checkpoint(0.02);
    if (cells.slots == 0) return out;
    out.seconds_setup = lapSeconds(clock);
    // The light depths' step, measured on a sparse lattice (light_depth_field.h), as the camera
    // rays' is below.
    out.light_steps = chooseLightSteps(medium, model, tb, cells, plan.light_spacing_voxels, settings.step_voxels,
                                       stepScaleCandidates(settings), settings.step_radiance_target,
                                       settings.step_mean_change_target, gate.stopFlag());
    gate.throwIfStopped();
    out.seconds_checks = lapSeconds(clock);
    std::vector<double> light_step_voxels;
    for (const LightStep& light : out.light_steps) light_step_voxels.push_back(light.step_voxels);
    const LightDepthField light_depths =
        buildLightDepths(medium, model, tb, cells, plan.light_spacing_voxels, light_step_voxels, stage(0.02, 0.05));
    gate.checkpoint(0.05);
    out.seconds_light = lapSeconds(clock);

    // Scattering orders: Lbar summed over orders, from independent photon chains
    // (scattered_light.h). Tracks only feed cell averages and each step is integrated exactly for
    // its extinction, so a track steps a cell at a time by default (track_step_cells, at least a
    // voxel). A photon starts at a random point, so its steps' midpoints fall at a random phase
    // along its track: the midpoint rule's depth is right on average over photons, and each cell
    // gets the steps whose midpoint lies in it, its chord's share in expectation. A longer step
    // adds noise, which the chains' prediction measures, and a bias only through the
    // transmittance's curvature within a step. Frame 12 of the bundled sample upsampled 4x at
    // 128x128 (8-voxel cells), a cell against half a cell: photon passes 5.3 s against 6.6 s,
    // predicted photon noise 0.894% both; noise-corrected error of 3 looks against a 265-spp judge
    // 0.55% / 0.61% (median / worst) against 0.52% / 0.60% (a quarter cell: 0.54% / 0.60%, the
    // judge's spread), image-mean bias -0.09% / -0.10% against -0.07% / -0.07%.
    const double track_step = std::max(1.0, settings.track_step_cells * cells.edge) * voxel;
    const TransportContext ctx{medium, tb, cells, light_depths, track_step,
                               static_cast<size_t>(cells.slots) * G * C, gate.stopFlag()};
    const double min_step = settings.step_voxels * voxel;
    std::vector<float> lbar_sum;
    if (model.albedo > 0.0 && settings.max_orders > 0) {
        ScatteredLightTracer scattered(ctx, model, settings);
        gate.checkpoint(0.08);
        const PhotonNoiseInputs noise_inputs{medium, tb, cells, light_depths, camera, min_step,
                                             settings.footprint_step, scattered.countedColumns()};
        const auto predict = [&] {
            const double worst = predictPhotonNoise(noise_inputs, scattered.sum(), scattered.signedSum(),
                                                    scattered.weight(), gate.stopFlag());
            gate.throwIfStopped();
            return worst;
        };
        // Two chains (the pilot: the photons the settings name, or photon_pilot_share of them with a
        // target), and the first noise prediction. Then, where the target asks for more, one pair of
        // chains that makes the photons what it asks (noise falls as 1/sqrt(photons)), up to
        // max_photon_scale times the settings' photons, and the prediction again for the report.
        scattered.addChainPair(1.0, [&](double done) { gate.checkpoint(0.08 + 0.22 * done); });
        double noise = predict();
        const double target = settings.photon_noise_target;
        const double most = 2.0 * settings.max_photon_scale / scattered.chainShare();  // in pilot chains
        if (target > 0.0 && noise > target && most > 2.0) {
            const double aim = kPhotonNoiseAim * target;
            const double wanted = 2.0 * (noise / aim) * (noise / aim);
            const double size =
                std::min(std::max(kSmallestChainPair, 0.5 * (wanted - 2.0)), 0.5 * (most - 2.0));
            scattered.addChainPair(size, [&](double done) { gate.checkpoint(0.3 + 0.28 * done); });
            noise = predict();
        }
        out.photon_chains = scattered.chains();
        out.photon_multiple = scattered.photonMultiple();
        out.order_photon_share = scattered.orderPhotonShare();
        out.predicted_photon_noise = noise;
        lbar_sum = std::move(scattered).estimate();
        out.scattering_orders = scattered.orders();
        out.last_order_fraction = scattered.lastOrderFraction();
        out.tail_fraction = scattered.tailFraction();
    }  // else no scattered light: lbar_sum stays empty and the camera gathers no cells
    gate.checkpoint(0.6);
    out.seconds_photons = lapSeconds(clock);

    // Camera rays: exact march of the fine medium, with a step from the pixel footprint. Which m x m
    // of the n x n footprint rays gather radiance, and how far the smallest step may grow, is
    // measured first on a sparse grid of pixels (camera_quadrature.h): the allowance is
    // radiance_quadrature_target, or radiance_quadrature_noise_share of the frame's predicted photon
    // noise where that is more.
    QuadratureOptions options;
    options.rays = radianceCandidates(settings, per_axis);
    options.rays_given = options.rays.empty() && given_per_axis < per_axis;
    if (options.rays_given) options.rays = {given_per_axis};
    options.step_scales = stepScaleCandidates(settings);
    options.allowance = std::max(settings.radiance_quadrature_target,
                                 settings.radiance_quadrature_noise_share * out.predicted_photon_noise);
    options.step_allowance = std::min(options.allowance, settings.step_radiance_target);
    options.mean_change_allowance = settings.step_mean_change_target;
    options.alpha_allowance = settings.step_alpha_target;
    if (!options.step_scales.empty() || (!options.rays_given && !options.rays.empty()))
        out.radiance_quadrature_allowance = options.allowance;
    const CameraQuadratureInputs quadrature_inputs{medium, tb, cells, light_depths, camera, lbar_sum,
                                                   min_step, settings.footprint_step, per_axis};
    const CameraQuadrature quadrature = chooseCameraQuadrature(quadrature_inputs, options, gate.stopFlag());
    gate.throwIfStopped();
    out.seconds_checks += lapSeconds(clock);
    const int radiance_per_axis = quadrature.rays_per_axis;
    out.radiance_quadrature_error = quadrature.radiance_error;
    out.quadrature_candidates = quadrature.candidates;
    out.camera_step_voxels = settings.step_voxels * quadrature.step_scale;
    out.depth_step_voxels = settings.step_voxels * quadrature.depth_step_scale;
    const double camera_step = quadrature.step_scale * min_step;
    const double depth_step = quadrature.depth_step_scale * min_step;
    out.radiance_samples = radiance_per_axis * radiance_per_axis;
    const bool shared = radiance_per_axis == per_axis && quadrature.step_scale == quadrature.depth_step_scale;
    std::atomic<int> rows_done{0};
    tbb::parallel_for(tbb::blocked_range<int>(0, out.height, 4), [&](const tbb::blocked_range<int>& rows) {
        CameraMarch ray_march(medium, tb, cells, light_depths, camera, depth_step, settings.footprint_step,
                              !lbar_sum.empty());
        // The radiance rays' own march, where they are not the footprint rays at alpha's step.
        std::optional<CameraMarch> radiance_march;
        if (!shared)
            radiance_march.emplace(medium, tb, cells, light_depths, camera, camera_step, settings.footprint_step,
                                   !lbar_sum.empty());
        std::vector<double> depth_a(tb.n_alpha);
        const float radiance_weight = 1.0f / static_cast<float>(out.radiance_samples);
        for (int py = rows.begin(); py != rows.end(); ++py) {
            if (gate.stopped()) return;
            for (int px = 0; px < out.width; ++px) {
                const size_t pixel = static_cast<size_t>(py) * out.width + px;
                float* row = out.matrix.data() + pixel * out.columns;
                ray_march.beginPixel();
                // The pixel is the mean of its footprint rays: each radiance ray adds 1/samples of
                // its integral. Where the radiance rays are the footprint rays, one march does both;
                // otherwise these rays are depth-only and gather nothing.
                for (int sample = 0; sample < out.footprint_samples; ++sample) {
                    double depth_b = 0.0;
                    if (!ray_march.marchPixelRay(px, py, (sample % per_axis + 0.5) / per_axis,
                                                 (sample / per_axis + 0.5) / per_axis, per_axis,
                                                 shared ? radiance_weight : 0.0f, &depth_b, depth_a.data(),
                                                 cameraRayPhase(pixel, sample)))
                        continue;
                    out.depth_b[static_cast<size_t>(sample) * pixels + pixel] = static_cast<float>(depth_b);
                    float* sigmoid_out = out.depth_a.data() + static_cast<size_t>(sample) * tb.n_alpha * pixels + pixel;
                    for (int a = 0; a < tb.n_alpha; ++a) sigmoid_out[a * pixels] = static_cast<float>(depth_a[a]);
                }
                if (shared) {
                    addGathered(ray_march, lbar_sum, row);
                    continue;
                }
                radiance_march->beginPixel();
                gatherRadianceRays(*radiance_march, lbar_sum, out.width, px, py, radiance_per_axis, row);
            }
            gate.report(0.6 + 0.4 * (rows_done.fetch_add(1) + 1) / out.height);
        }
    });
    gate.throwIfStopped();
    out.seconds_camera = lapSeconds(clock);
    return out;
}

}  // namespace firelook::bake
