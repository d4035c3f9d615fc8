#include "render/footprint_transmittance.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/parallel_for.h>

#include "render/ray.h"
#include "render/render_error.h"

namespace firelook::render {

FootprintTransmittance::FootprintTransmittance(const Medium& medium, const Camera& camera,
                                               const TemperatureBins& bins, int per_axis, double step_voxels,
                                               const std::function<bool()>& stop_requested)
    : bins_(bins), width_(camera.width()), height_(camera.height()), per_axis_(std::max(per_axis, 1)) {
    if (medium.empty()) return;
    const WorldBox box = medium.worldBounds();
    const double step = step_voxels * medium.minVoxelEdge();
    const double node_spacing = (bins.t_hi - bins.t_lo) / (kTemperatureNodes - 1);
    const int rays_per_pixel = per_axis_ * per_axis_;

    // Rows are marched in parallel into per-row buffers, then joined in row order
    // so the layout (and every later sum) is the same for any thread count.
    std::vector<std::vector<int>> row_pixels(height_);
    std::vector<std::vector<float>> row_histograms(height_);
    std::atomic<bool> stopped{false};
    tbb::parallel_for(0, height_, [&](int py) {
        if (stopped.load(std::memory_order_relaxed) || (stop_requested && stop_requested())) {
            stopped.store(true, std::memory_order_relaxed);
            return;
        }
        std::vector<float> h(kTemperatureNodes);
        for (int px = 0; px < width_; ++px)
            for (int s = 0; s < rays_per_pixel; ++s) {
                const Ray ray = camera.generateRay(px, py, (s % per_axis_ + 0.5) / per_axis_,
                                                   (s / per_axis_ + 0.5) / per_axis_);
                double t0 = 0.0, t1 = 0.0;
                if (!intersectBox(ray.origin, ray.direction, box.min, box.max, t0, t1)) continue;
                std::fill(h.begin(), h.end(), 0.0f);
                bool any = false;
                for (double t = t0; t < t1; t += step) {
                    const double dt = std::min(step, t1 - t);
                    const MediumSample m = medium.sampleWorld(ray.origin + (t + 0.5 * dt) * ray.direction);
                    if (!(m.density > 0.0f)) continue;
                    const double x = node_spacing > 0.0 ? (bins.clamp(m.temperature) - bins.t_lo) / node_spacing : 0.0;
                    const int lower = std::min(static_cast<int>(x), kTemperatureNodes - 2);
                    const double w = std::clamp(x - lower, 0.0, 1.0);
                    h[lower] += static_cast<float>((1.0 - w) * m.density * dt);
                    h[lower + 1] += static_cast<float>(w * m.density * dt);
                    any = true;
                }
                if (!any) continue;
                row_pixels[py].push_back(py * width_ + px);
                row_histograms[py].insert(row_histograms[py].end(), h.begin(), h.end());
            }
    });
    if (stopped.load())
        throw RenderError(ErrorCode::Cancelled, "footprint transmittance: stopped on request");
    for (int py = 0; py < height_; ++py) {
        ray_pixel_.insert(ray_pixel_.end(), row_pixels[py].begin(), row_pixels[py].end());
        histogram_.insert(histogram_.end(), row_histograms[py].begin(), row_histograms[py].end());
    }
}

std::vector<float> FootprintTransmittance::alpha(const ExtinctionParams& extinction) const {
    // Extinction per unit density at each node: a f(T - T_c) + b.
    std::vector<double> kappa(kTemperatureNodes);
    for (int n = 0; n < kTemperatureNodes; ++n) {
        const double t = bins_.t_lo + (bins_.t_hi - bins_.t_lo) * n / (kTemperatureNodes - 1);
        kappa[n] = extinctionPerDensity(t, extinction, bins_);
    }
    std::vector<double> sum(static_cast<size_t>(width_) * height_, 0.0);
    for (size_t r = 0; r < ray_pixel_.size(); ++r) {
        const float* h = histogram_.data() + r * kTemperatureNodes;
        double tau = 0.0;
        for (int n = 0; n < kTemperatureNodes; ++n) tau += kappa[n] * h[n];
        sum[ray_pixel_[r]] += 1.0 - std::exp(-std::max(tau, 0.0));
    }
    std::vector<float> alpha(sum.size());
    const double rays = static_cast<double>(per_axis_ * per_axis_);
    for (size_t p = 0; p < sum.size(); ++p) alpha[p] = static_cast<float>(sum[p] / rays);
    return alpha;
}

}  // namespace firelook::render
