// One camera ray of the basis tracer (basis_tracer.h, step 3), shared by the image itself and by the
// photon-noise estimate (photon_noise.h): the ray marches the exact fine medium once and gathers,
// for every grid point and column at once, the direct emission and the lights' single scattering,
// the optical depths alpha needs, and the weights of the cells whose scattered light it gathers.
// addDirect() and contract() then add them to a pixel's row: the per-column and per-cell work is
// done once per pixel, not once per step. The per-step loops run over the grid points with the
// point index innermost and contiguous (`#pragma omp simd`): they are most of a bake's time.
#pragma once

#include <vector>

#include "bake/index_ray.h"
#include "bake/light_depth_field.h"
#include "bake/scatter_cells.h"
#include "bake/trace_tables.h"
#include "render/camera.h"
#include "render/medium.h"

namespace firelook::bake {

class CameraMarch {
  public:
    // Steps along the camera rays: never finer than min_step (world units), and footprint_step
    // times the spacing of a pixel's footprint rays where the ray enters the volume when that is
    // longer (TraceSettings::footprint_step). `scattering`: whether the medium scatters at all
    // (albedo > 0 and a scattered-light field to contract); without it no cell is gathered.
    CameraMarch(const render::Medium& medium, const TraceTables& tables, const ScatterCells& cells,
                const LightDepthField& light_depths, const render::Camera& camera, double min_step,
                double footprint_step, bool scattering);

    // Forgets the cells gathered for the previous pixel.
    void beginPixel();
    // Marches the camera ray through (px + u, py + v); its step is that of one of rays_per_axis^2
    // rays that share its pixel (TraceSettings::footprint_step). A ray gathers radiance, optical depths or
    // both (the bake's alpha needs more rays a pixel than its radiance:
    // TraceSettings::radiance_samples_per_axis):
    // - radiance_weight > 0: adds that times the ray's direct integrals and the gathered cells'
    //   weights to the pixel's; 0: none (a depth-only ray, several times cheaper);
    // - depth_b and depth_a (both or neither null) get the ray's optical depths, not weighted: b's,
    //   and per alpha threshold. A radiance-only ray stops where no grid point sees further.
    // - phase: the length of the first step as a share of the step (march()): drawn per ray.
    // False, with nothing added or written, when the ray misses the volume.
    bool marchPixelRay(int px, int py, double u, double v, int rays_per_axis, float radiance_weight,
                       double* depth_b, double* depth_a, double phase);
    // row (points x columns) += the direct integrals of the rays marched since beginPixel.
    void addDirect(float* row) const;
    // row += for every cell gathered since beginPixel: its weights times field (slots x points x columns).
    void contract(const std::vector<float>& field, float* row) const;

  private:
    const render::Medium& medium_;
    const TraceTables& tb_;
    const ScatterCells& cells_;
    const LightDepthField& light_depths_;
    const render::Camera& camera_;
    IndexBox box_;
    double min_step_, footprint_step_;
    double pixel_angle_;  // radians a pixel spans vertically
    bool scattering_;
    std::vector<float> tau_, tau_next_, sigma_t_, ltau_, path_, removed_;
    std::vector<double> sigmoid_;     // per alpha threshold
    std::vector<float> direct_;       // [column][point]: the pixel's direct integrals
    bool direct_added_ = false;       // whether direct_ holds anything since beginPixel
    std::vector<int> entry_of_slot_;  // -1, or the index of the slot in touched_
    std::vector<int> touched_;
    std::vector<float> kernel_;  // [entry][point]
};

}  // namespace firelook::bake
