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
      pixel_angle_(2.0 * std::tan(0.5 * camera.parameters().yfov_radians) / camera.height()),
      scattering_(scattering),
      tau_(tables.points),
      tau_next_(tables.points),
      sigma_t_(tables.points),
      ltau_(tables.points),
      path_(tables.points),
      entry_of_slot_(cells.slots, -1) {}

void CameraMarch::beginPixel() {
    for (int slot : touched_) entry_of_slot_[slot] = -1;
    touched_.clear();
    kernel_.clear();
}

bool CameraMarch::marchPixelRay(int px, int py, double u, double v, int rays_per_axis, float weight, float* row,
                                double& depth_b, double* depth_a) {
    const render::Ray world_ray = camera_.generateRay(px, py, u, v);
    const IndexRay ray = toIndexSpace(medium_, world_ray.origin, world_ray.direction);
    double t0, t1;
    if (!clipToBox(ray, box_, t0, t1)) return false;
    const double step = std::max(min_step_, footprint_step_ * pixel_angle_ * t0 / rays_per_axis);
    const TraceTables& tb = tb_;
    const int G = tb.points, C = tb.columns;
    float smoke[kMaxAxisSamples], flame[kMaxAxisSamples], d_smoke[kMaxAxisSamples], d_flame[kMaxAxisSamples],
        lsm[kMaxAxisSamples], lfl[kMaxAxisSamples];
    int corner_slots[8];
    float corner_w[8];
    std::fill(d_smoke, d_smoke + tb.n_tc, 0.0f);
    std::fill(d_flame, d_flame + tb.n_tc, 0.0f);
    std::fill(tau_.begin(), tau_.end(), 1.0f);
    bool visible = true;  // some grid point still sees through to here
    depth_b = 0.0;
    std::fill(depth_a, depth_a + tb.n_alpha, 0.0);
    bake::march(medium_, ray, t0, t1, step, [&](const glm::dvec3& p, float dt, float rho, float t) {
        if (!(rho > 0.0f)) return true;
        depth_b += double(rho) * dt;
        const float tcl = tb.clampT(t);
        for (int a = 0; a < tb.n_alpha; ++a) depth_a[a] += double(rho) * std::tanh((tcl - tb.alpha_tc[a]) * tb.inv_2dt) * dt;
        if (!visible) return true;  // only the optical depths are still needed
        tb.split(rho, t, smoke, flame);
        tb.advanceDepths(smoke, flame, dt, d_smoke, d_flame);
        tb.transmittance(d_smoke, d_flame, tau_next_.data());
        tb.extinction(smoke, flame, sigma_t_.data());
        for (int g = 0; g < G; ++g) path_[g] = stepPathLength(tau_[g], tau_next_[g], sigma_t_[g], dt);
        int bin_first, bin_last;
        tb.binWindow(t, bin_first, bin_last);
        for (int i = bin_first; i < bin_last; ++i) {
            const float j = rho * tb.rbf(i, t) * weight;
            for (int g = 0; g < G; ++g) row[g * C + i] += path_[g] * j;
        }
        // Single scattering of each directional light.
        for (int l = 0; l < tb.lights; ++l) {
            light_depths_.sample(l, p, lsm, lfl);
            tb.transmittance(lsm, lfl, ltau_.data());
            for (int g = 0; g < G; ++g)
                row[g * C + tb.bins + l] += tb.albedo * sigma_t_[g] * path_[g] * ltau_[g] * kInv4Pi * weight;
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
                float* k = kernel_.data() + static_cast<std::size_t>(entry) * G;
                const float w = corner_w[c] * tb.albedo * weight;
                for (int g = 0; g < G; ++g) k[g] += w * sigma_t_[g] * path_[g];
            }
        }
        tau_.swap(tau_next_);
        visible = tb.maxTransmittance(d_smoke, d_flame) > kNegligibleTransmittance;
        return true;
    });
    return true;
}

void CameraMarch::contract(const std::vector<float>& field, float* row) const {
    const int G = tb_.points, C = tb_.columns;
    for (std::size_t e = 0; e < touched_.size(); ++e) {
        const float* k = kernel_.data() + e * G;
        const float* lbar = field.data() + static_cast<std::size_t>(touched_[e]) * G * C;
        for (int g = 0; g < G; ++g) {
            if (k[g] == 0.0f) continue;
            for (int c = 0; c < C; ++c) row[g * C + c] += k[g] * lbar[g * C + c];
        }
    }
}

}  // namespace firelook::bake
