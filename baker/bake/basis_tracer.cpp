#include "bake/basis_tracer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>

#include "bake/index_ray.h"
#include "bake/light_depth_field.h"
#include "bake/order_series.h"
#include "bake/photon_pass.h"
#include "bake/photon_start_sampler.h"
#include "bake/scatter_cells.h"
#include "bake/trace_tables.h"
#include "common/error.h"

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
}

}  // namespace

int footprintSamplesPerAxis(const TraceSettings& settings, int width, int height) {
    if (settings.footprint_samples_per_axis > 0) return settings.footprint_samples_per_axis;
    const int short_side = std::min(width, height);
    return short_side >= 256 ? 3 : short_side >= 128 ? 4 : short_side >= 64 ? 6 : 8;
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
    const auto cellBytes = [&](int edge, std::size_t slots) {
        const std::size_t field = slots * G * C * sizeof(float);
        // Lbar summed over orders, the previous order, and what a photon pass holds at its peak;
        // the masses; the per-cell part sums while the cells are built.
        return 2 * field + photonPassBytes(slots * G * C) + slots * G * sizeof(float) +
               scatterCellCount(medium, edge) * 2 * tb.n_tc * sizeof(double);
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
    const LightDepthField light_depths =
        buildLightDepths(medium, model, tb, cells, plan.light_spacing_voxels, settings.step_voxels, stage(0.02, 0.05));
    gate.checkpoint(0.05);
    out.seconds_light = lapSeconds(clock);

    // Scattering orders: Lbar_sum = sum over orders of the mean radiance each produces.
    // Tracks only feed cell averages and each step is integrated exactly for its extinction: half a
    // cell per step (at least a voxel, which is what the sample's 2-voxel cells get) is enough.
    const double track_step = std::max(1.0, 0.5 * cells.edge) * voxel;
    const TransportContext ctx{medium, tb, cells, light_depths, track_step,
                               static_cast<size_t>(cells.slots) * G * C, gate.stopFlag()};
    std::vector<float> lbar_sum;
    if (model.albedo > 0.0) lbar_sum.assign(ctx.field_size, 0.0f);
    if (model.albedo > 0.0 && settings.max_orders > 0) {
        // Emission photons are drawn half by density and half equally per bin, so rare hot bins
        // get as many photons as common cool ones. Masses from cube centres, summed per z-layer of
        // bricks and then in order (the same bytes with any number of threads).
        const int layers = medium.brickCounts().z;
        std::vector<double> layer_mass(static_cast<size_t>(layers) * (1 + tb.bins), 0.0);
        tbb::parallel_for(0, layers, [&](int layer) {
            double* m = layer_mass.data() + static_cast<size_t>(layer) * (1 + tb.bins);
            const int size = render::Medium::kBrickSize;
            forEachCubeInSlab(medium, layer * size, (layer + 1) * size, [&](const glm::ivec3&, float rho, float t) {
                m[0] += rho;
                int first, last;
                tb.binWindow(t, first, last);
                for (int i = first; i < last; ++i) m[1 + i] += rho * tb.rbf(i, t);
            });
        });
        double density_mass = 0.0;
        std::vector<double> bin_mass(tb.bins, 0.0);
        for (int layer = 0; layer < layers; ++layer) {
            density_mass += layer_mass[static_cast<size_t>(layer) * (1 + tb.bins)];
            for (int i = 0; i < tb.bins; ++i) bin_mass[i] += layer_mass[static_cast<size_t>(layer) * (1 + tb.bins) + 1 + i];
        }
        int active_bins = 0;
        for (double m : bin_mass) active_bins += m > 0.0;
        const PhotonStartSampler emission_sampler(medium, [&](float rho, float t) {
            double per_bin = 0.0;
            int first, last;
            tb.binWindow(t, first, last);
            for (int i = first; i < last; ++i)
                if (bin_mass[i] > 0.0) per_bin += tb.rbf(i, t) / bin_mass[i];
            return rho * (0.5 / density_mass + 0.5 * per_bin / std::max(active_bins, 1));
        });
        const PhotonStartSampler density_sampler(medium, [](float rho, float) { return double(rho); });
        gate.checkpoint(0.08);

        std::vector<float> order =
            photonPass(ctx, SourceKind::Emission, emission_sampler, nullptr, settings.photons_primary, settings.seed);
        gate.checkpoint(0.15);
        if (tb.lights > 0) {
            const std::vector<float> light = photonPass(ctx, SourceKind::LightScatter, density_sampler, nullptr,
                                                        settings.photons_primary, settings.seed + 1);
            gate.throwIfStopped();
            for (size_t i = 0; i < order.size(); ++i) order[i] += light[i];
        }
        // The stopping test weighs the bins and the scene's own lights only: six-way lights
        // (basis/six_way_lights.h) then never change how many orders the other columns get, so
        // every other column is the same bytes as in a bake without them (paths are shared).
        const int counted = model.six_way_first_light >= 0 ? tb.bins + model.six_way_first_light : C;
        OrderSeries series(cells, G, C, counted, model.albedo);
        series.add(order);
        for (size_t i = 0; i < order.size(); ++i) lbar_sum[i] += order[i];
        gate.checkpoint(0.25);
        for (int k = 2; k <= settings.max_orders; ++k) {
            order = photonPass(ctx, SourceKind::Scattered, density_sampler, &order, settings.photons_per_order,
                               settings.seed + 16 * k);
            gate.throwIfStopped();
            series.add(order);
            for (size_t i = 0; i < order.size(); ++i) lbar_sum[i] += order[i];
            gate.checkpoint(0.25 + 0.35 * k / settings.max_orders);
            if (series.converged(settings.order_tolerance)) break;
        }
        // The orders not traced, as the geometric tail of each column's series (order_series.h).
        const std::vector<float> tail = series.tailFactors();
        for (size_t i = 0; i < order.size(); ++i) lbar_sum[i] += tail[i % (static_cast<size_t>(G) * C)] * order[i];
        out.scattering_orders = series.orders();
        out.last_order_fraction = series.lastOrderFraction();
        out.tail_fraction = series.tailFraction();
    }
    gate.checkpoint(0.6);
    out.seconds_photons = lapSeconds(clock);

    // Camera rays: exact march of the fine medium, with a step from the pixel footprint.
    const IndexBox box = influenceBox(medium);
    const double pixel_angle = 2.0 * std::tan(0.5 * camera.parameters().yfov_radians) / out.height;
    const double min_step = settings.step_voxels * voxel;
    std::atomic<int> rows_done{0};
    tbb::parallel_for(tbb::blocked_range<int>(0, out.height, 4), [&](const tbb::blocked_range<int>& rows) {
        std::vector<float> tau(G), tau_next(G), sigma_t(G), ltau(G), path(G);
        std::vector<int> entry_of_slot(cells.slots, -1);
        std::vector<int> touched;
        std::vector<float> kernel;  // [entry][G]
        std::vector<double> depth_a(tb.n_alpha);
        float smoke[kMaxAxisSamples], flame[kMaxAxisSamples], d_smoke[kMaxAxisSamples], d_flame[kMaxAxisSamples],
            lsm[kMaxAxisSamples], lfl[kMaxAxisSamples];
        int corner_slots[8];
        float corner_w[8];
        for (int py = rows.begin(); py != rows.end(); ++py) {
            if (gate.stopped()) return;
            for (int px = 0; px < out.width; ++px) {
                const size_t pixel = static_cast<size_t>(py) * out.width + px;
                float* row = out.matrix.data() + pixel * out.columns;
                touched.clear();
                kernel.clear();
                const float sample_weight = 1.0f / static_cast<float>(out.footprint_samples);
                for (int sample = 0; sample < out.footprint_samples; ++sample) {
                    const render::Ray world_ray = camera.generateRay(px, py, (sample % per_axis + 0.5) / per_axis,
                                                                     (sample / per_axis + 0.5) / per_axis);
                    const IndexRay ray = toIndexSpace(medium, world_ray.origin, world_ray.direction);
                    double t0, t1;
                    if (!clipToBox(ray, box, t0, t1)) continue;
                    const double step = std::max(min_step, settings.footprint_step * pixel_angle * t0 / per_axis);
                    std::fill(d_smoke, d_smoke + tb.n_tc, 0.0f);
                    std::fill(d_flame, d_flame + tb.n_tc, 0.0f);
                    std::fill(tau.begin(), tau.end(), 1.0f);
                    bool visible = true;  // some grid point still sees through to here
                    double depth_b = 0.0;
                    std::fill(depth_a.begin(), depth_a.end(), 0.0);
                    march(medium, ray, t0, t1, step, [&](const glm::dvec3& p, float dt, float rho, float t) {
                        if (!(rho > 0.0f)) return true;
                        depth_b += double(rho) * dt;
                        const float tcl = tb.clampT(t);
                        for (int a = 0; a < tb.n_alpha; ++a)
                            depth_a[a] += double(rho) * std::tanh((tcl - tb.alpha_tc[a]) * tb.inv_2dt) * dt;
                        if (!visible) return true;  // only the optical depths are still needed
                        tb.split(rho, t, smoke, flame);
                        tb.advanceDepths(smoke, flame, dt, d_smoke, d_flame);
                        tb.transmittance(d_smoke, d_flame, tau_next.data());
                        tb.extinction(smoke, flame, sigma_t.data());
                        for (int g = 0; g < G; ++g) path[g] = stepPathLength(tau[g], tau_next[g], sigma_t[g], dt);
                        // The pixel is the mean of its footprint rays: each adds 1/samples of its integral.
                        int bin_first, bin_last;
                        tb.binWindow(t, bin_first, bin_last);
                        for (int i = bin_first; i < bin_last; ++i) {
                            const float j = rho * tb.rbf(i, t) * sample_weight;
                            for (int g = 0; g < G; ++g) row[g * C + i] += path[g] * j;
                        }
                        // Single scattering of each directional light.
                        for (int l = 0; l < tb.lights; ++l) {
                            light_depths.sample(l, p, lsm, lfl);
                            tb.transmittance(lsm, lfl, ltau.data());
                            for (int g = 0; g < G; ++g)
                                row[g * C + tb.bins + l] +=
                                    tb.albedo * sigma_t[g] * path[g] * ltau[g] * kInv4Pi * sample_weight;
                        }
                        // Scattered light: gather the weights of Lbar's cells, contract once per pixel.
                        if (model.albedo > 0.0) {
                            const int n = cells.corners(p, corner_slots, corner_w);
                            for (int c = 0; c < n; ++c) {
                                int& entry = entry_of_slot[corner_slots[c]];
                                if (entry < 0) {
                                    entry = static_cast<int>(touched.size());
                                    touched.push_back(corner_slots[c]);
                                    kernel.resize(kernel.size() + G, 0.0f);
                                }
                                float* k = kernel.data() + static_cast<size_t>(entry) * G;
                                const float w = corner_w[c] * tb.albedo * sample_weight;
                                for (int g = 0; g < G; ++g) k[g] += w * sigma_t[g] * path[g];
                            }
                        }
                        tau.swap(tau_next);
                        visible = tb.maxTransmittance(d_smoke, d_flame) > kNegligibleTransmittance;
                        return true;
                    });
                    out.depth_b[static_cast<size_t>(sample) * pixels + pixel] = static_cast<float>(depth_b);
                    float* sigmoid_out = out.depth_a.data() + static_cast<size_t>(sample) * tb.n_alpha * pixels + pixel;
                    for (int a = 0; a < tb.n_alpha; ++a) sigmoid_out[a * pixels] = static_cast<float>(depth_a[a]);
                }
                for (size_t e = 0; e < touched.size(); ++e) {
                    const float* k = kernel.data() + e * G;
                    const float* lbar = lbar_sum.data() + static_cast<size_t>(touched[e]) * G * C;
                    for (int g = 0; g < G; ++g) {
                        if (k[g] == 0.0f) continue;
                        for (int c = 0; c < C; ++c) row[g * C + c] += k[g] * lbar[g * C + c];
                    }
                    entry_of_slot[touched[e]] = -1;
                }
            }
            gate.report(0.6 + 0.4 * (rows_done.fetch_add(1) + 1) / out.height);
        }
    });
    gate.throwIfStopped();
    out.seconds_camera = lapSeconds(clock);
    return out;
}

}  // namespace firelook::bake
