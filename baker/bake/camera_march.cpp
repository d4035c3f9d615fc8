#include "bake/camera_march.h"

#include <algorithm>
#include <cmath>

namespace firelook::bake {

CameraMarch::CameraMarch(const render::Medium& medium, const TraceTables& tables, const ScatterCells& cells,
                         const LightDepthField& light_depths, const render::Camera& camera, double min_step,
                         double footprint_step, bool scattering)
    : medium_(medium),
      tb_(tables),
      cells_(cells),
      light_depths_(light_depths),
      camera_(camera),
      box_(influenceBox(medium)),
      min_step_(min_step),
      footprint_step_(footprint_step),
      pixel_angle_(camera.pixelAngle()),
      scattering_(scattering),
      tau_(tables.points),
      tau_next_(tables.points),
      sigma_t_(tables.points),
      ltau_(tables.points),
      path_(tables.points),
      removed_(tables.points),
      sigmoid_(tables.n_alpha),
      direct_(static_cast<std::size_t>(tables.columns) * tables.points, 0.0f),
      entry_of_slot_(cells.slots, -1) {}

void CameraMarch::beginPixel() {
    for (int slot : touched_) entry_of_slot_[slot] = -1;
    touched_.clear();
    kernel_.clear();
    if (direct_added_) std::fill(direct_.begin(), direct_.end(), 0.0f);
    direct_added_ = false;
}

bool CameraMarch::marchPixelRay(int px, int py, double u, double v, int rays_per_axis, float radiance_weight,
                                double* depth_b, double* depth_a, double phase) {
    const render::Ray world_ray = camera_.generateRay(px, py, u, v);
    const IndexRay ray = toIndexSpace(medium_, world_ray.origin, world_ray.direction);
    double t0, t1;
    if (!clipToBox(ray, box_, t0, t1)) return false;
    const bool radiance = radiance_weight > 0.0f, depths = depth_b != nullptr;
    const float weight = radiance_weight;
    if (radiance) direct_added_ = true;
    const double step = std::max(min_step_, footprint_step_ * pixel_angle_ * t0 / rays_per_axis);
    const TraceTables& tb = tb_;
    const int G = tb.points;
    float smoke[kMaxAxisSamples], flame[kMaxAxisSamples], d_smoke[kMaxAxisSamples], d_flame[kMaxAxisSamples],
        lsm[kMaxAxisSamples], lfl[kMaxAxisSamples];
    int corner_slots[8];
    float corner_w[8];
    std::fill(d_smoke, d_smoke + tb.n_tc, 0.0f);
    std::fill(d_flame, d_flame + tb.n_tc, 0.0f);
    std::fill(tau_.begin(), tau_.end(), 1.0f);
    bool visible = radiance;  // some grid point still sees through to here
    double depth_sum = 0.0;
    if (depths) std::fill(depth_a, depth_a + tb.n_alpha, 0.0);
    // The light a step removes from the view, tau_start - tau_end = sigma_t * path, is what its
    // scattering sources are weighted by (albedo times that, stepPathLength).
    const float light_weight = tb.albedo * kInv4Pi * weight;
    bake::march(medium_, ray, t0, t1, step, phase, [&](const glm::dvec3& p, float dt, float rho, float t) {
        if (!(rho > 0.0f)) return true;
        if (depths) {
            depth_sum += double(rho) * dt;
            tb.alphaSigmoids(t, sigmoid_.data());
            for (int a = 0; a < tb.n_alpha; ++a) depth_a[a] += double(rho) * sigmoid_[a] * dt;
        }
        if (!visible) return depths;  // only the optical depths are still needed, if any
        tb.split(rho, t, smoke, flame);
        tb.advanceDepths(smoke, flame, dt, d_smoke, d_flame);
        tb.transmittance(d_smoke, d_flame, tau_next_.data());
        tb.extinction(smoke, flame, sigma_t_.data());
        {
            const float* __restrict tau = tau_.data();
            const float* __restrict tau_next = tau_next_.data();
            const float* __restrict sigma_t = sigma_t_.data();
            float* __restrict path = path_.data();
            float* __restrict removed = removed_.data();
#pragma omp simd
            for (int g = 0; g < G; ++g) {
                path[g] = stepPathLength(tau[g], tau_next[g], sigma_t[g], dt);
                removed[g] = stepRemoved(tau[g], tau_next[g], sigma_t[g], dt);
            }
        }
        int bin_first, bin_last;
        tb.binWindow(t, bin_first, bin_last);
        for (int i = bin_first; i < bin_last; ++i) {
            const float j = rho * tb.rbf(i, t) * weight;
            const float* __restrict path = path_.data();
            float* __restrict out = direct_.data() + static_cast<std::size_t>(i) * G;
#pragma omp simd
            for (int g = 0; g < G; ++g) out[g] += path[g] * j;
        }
        // Single scattering of each directional light.
        for (int l = 0; l < tb.lights; ++l) {
            light_depths_.sample(l, p, lsm, lfl);
            tb.transmittance(lsm, lfl, ltau_.data());
            const float* __restrict removed = removed_.data();
            const float* __restrict ltau = ltau_.data();
            float* __restrict out = direct_.data() + static_cast<std::size_t>(tb.bins + l) * G;
#pragma omp simd
            for (int g = 0; g < G; ++g) out[g] += light_weight * removed[g] * ltau[g];
        }
        // Scattered light: gather the weights of Lbar's cells.
        if (scattering_) {
            const int n = cells_.corners(p, corner_slots, corner_w);
            for (int c = 0; c < n; ++c) {
                int& entry = entry_of_slot_[corner_slots[c]];
                if (entry < 0) {
                    entry = static_cast<int>(touched_.size());
                    touched_.push_back(corner_slots[c]);
                    kernel_.resize(kernel_.size() + G, 0.0f);
                }
                float* __restrict k = kernel_.data() + static_cast<std::size_t>(entry) * G;
                const float* __restrict removed = removed_.data();
                const float w = corner_w[c] * tb.albedo * weight;
#pragma omp simd
                for (int g = 0; g < G; ++g) k[g] += w * removed[g];
            }
        }
        tau_.swap(tau_next_);
        visible = tb.maxTransmittance(tau_.data()) > kNegligibleTransmittance;
        return visible || depths;
    });
    if (depths) *depth_b = depth_sum;
    return true;
}

void CameraMarch::addDirect(float* row) const {
    if (!direct_added_) return;
    const int G = tb_.points, C = tb_.columns;
    for (int c = 0; c < C; ++c) {
        const float* d = direct_.data() + static_cast<std::size_t>(c) * G;
        for (int g = 0; g < G; ++g) row[g * C + c] += d[g];
    }
}

void CameraMarch::contract(const std::vector<float>& field, float* row) const {
    const int G = tb_.points, C = tb_.columns;
    for (std::size_t e = 0; e < touched_.size(); ++e) {
        const float* k = kernel_.data() + e * G;
        const float* lbar = field.data() + static_cast<std::size_t>(touched_[e]) * G * C;
        for (int g = 0; g < G; ++g) {
            if (k[g] == 0.0f) continue;
            const float kg = k[g];
            const float* __restrict from = lbar + static_cast<std::size_t>(g) * C;
            float* __restrict to = row + static_cast<std::size_t>(g) * C;
#pragma omp simd
            for (int c = 0; c < C; ++c) to[c] += kg * from[c];
        }
    }
}

}  // namespace firelook::bake
