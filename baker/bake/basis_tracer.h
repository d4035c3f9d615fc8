// Basis images of one frame with all orders of scattering (DESIGN.md section 2).
//
// Method (a deterministic-march variant of the paper's "trace once, re-weight"):
// every path and camera ray is marched once, and along it the optical depths
// split into smoke and flame parts per sampled T_c are accumulated, so the
// transmittance exp(-k_s D_s(T_c) - k_f D_f(T_c)) is exact for every grid point
// at once and nothing is re-weighted by ratios of sampling densities.
//   1. Primary sources Q0: emission rho*phi_i(T) per bin, and the single-scatter
//      source sigma_s * tau_light / (4 pi) per directional light (its light
//      transmittance from a per-voxel optical depth field).
//   2. Scattering orders: the mean radiance Lbar = (1/4pi) integral L dw that
//      each order's source produces is estimated on a coarse cell grid with a
//      track-length estimator (photons start at points drawn from the source,
//      fly straight, and deposit transmittance-weighted track length into the
//      cells they cross). The next order's source is sigma_s * Lbar. Orders are
//      added until one adds less than `order_tolerance` of the total.
//   3. Camera rays march the exact fine-resolution medium and integrate
//      tau * (Q0 + sigma_s * sum of Lbar) for every grid point and column; the
//      per-pixel optical depths for exact alpha come from the same march.
// Errors: quadrature of the marches (step_voxels), Monte Carlo noise of the
// photon tracks, and the coarse cell grid's smoothing of Lbar (cell_voxels).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "basis/parameter_grid.h"
#include "look/look_model.h"
#include "render/camera.h"
#include "render/medium.h"

namespace firelook::bake {

// The part of a bake that fixes what the basis images are.
struct BasisModel {
    TemperatureBins bins;
    double rbf_width = 0.9;
    double albedo = 0.8;
    basis::ParameterAxes axes;
    std::vector<glm::dvec3> light_directions;  // direction each light travels
    std::vector<double> alpha_thresholds;      // T_c samples for the optical depth maps

    int columnsPerPoint() const { return bins.count + static_cast<int>(light_directions.size()); }
};

struct TraceSettings {
    // Coarse grid cell edge, in voxels, for Lbar. 2 because the cells' smoothing of the
    // scattered light is the largest error source left (scripts/bench/speed_vs_error.sh,
    // frames 3 and 7 at 128x128, 14 looks: noise-corrected relative RMSE median / worst
    // 1.05% / 3.27% with 4-voxel cells, 0.41% / 1.40% with 2); the cost, measured unloaded
    // on frame 7 at 256x256: bake 26.5 -> 30.7 s, peak memory 651 -> 811 MiB.
    int cell_voxels = 2;
    int photons_primary = 262144;     // photons for the primary sources
    int photons_per_order = 131072;   // photons for each further scattering order
    int max_orders = 12;              // scattering orders at most
    double order_tolerance = 0.002;   // stop when an order adds less than this fraction
    // March step in voxels (camera rays and light depths; photon tracks use >= 1 voxel).
    // 0.25 because at 0.5 the midpoint rule misses silhouette optical depths by enough to
    // move alpha by 0.0116 against the same rays marched at 0.1 (frame 3, 128x128, k_s 15);
    // 0.25: 0.0018, 0.1: 0.0006, at no measurable bake-time cost (camera rays are cheap
    // next to the photon passes). Relative RMSE of that look: 2.07% / 1.92% / 1.80%.
    double step_voxels = 0.25;
    // Camera rays per pixel along each axis of its footprint (n x n, cell-centred): a
    // pixel is the mean over its footprint, and alpha = mean(1 - exp(-tau)) needs the
    // optical depths of each ray, which are all stored. 3 x 3 because the footprint
    // quadrature of alpha against 16 x 16 rays, on the bundled sample's most opaque
    // looks (k_s 16, k_f 4), is at most 0.0109 / 0.0055 / 0.0031 at 128x128 for
    // n = 2 / 3 / 4, and 0.0076 / 0.0032 / 0.0017 at 256x256 (tests/bake/
    // alpha_footprint_report); below 128x128 use 4 (64x64: 0.0116 at n = 3).
    int footprint_samples_per_axis = 3;
    uint64_t seed = 1;
};

struct FrameBasis {
    int width = 0;
    int height = 0;
    int columns = 0;
    std::vector<float> matrix;          // pixels x columns, pixel-major; column = point * C + c
    int footprint_samples = 1;          // rays per pixel
    std::vector<float> depth_density;   // O_b: footprint sample x pixel
    std::vector<float> depth_sigmoid;   // O_a: footprint sample x alpha threshold x pixel
    int scattering_orders = 0;          // orders traced
    double last_order_fraction = 0.0;   // share of the total the last order added
};

// progress(fraction) returns false to cancel; traceFrameBasis then throws
// std::runtime_error("cancelled") without a result.
FrameBasis traceFrameBasis(const render::Medium& medium, const render::Camera& camera, const BasisModel& model,
                           const TraceSettings& settings, const std::function<bool(double)>& progress = {});

}  // namespace firelook::bake
