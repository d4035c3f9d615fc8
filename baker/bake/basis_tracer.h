// Basis images of one frame with all orders of scattering (docs/model.md, section "basis images").
//
// Method (a deterministic-march variant of the paper's "trace once, re-weight"):
// every path and camera ray is marched once, and along it the optical depths
// split into smoke and flame parts per sampled T_c are accumulated, so the
// transmittance exp(-k_s D_s(T_c) - k_f D_f(T_c)) is exact for every grid point
// at once and nothing is re-weighted by ratios of sampling densities. Every march step is
// integrated exactly for its sampled extinction (trace_tables.h, stepPathLength), so optically
// thick steps are right too: a thick emitter glows with L_e / kappa at its surface.
//   1. Primary sources Q0: emission rho*phi_i(T) per bin, and the single-scatter
//      source sigma_s * tau_light / (4 pi) per directional light (its light
//      transmittance from a lattice of optical depths, light_depth_field.h).
//   2. Scattering orders: the sigma_s-weighted mean radiance Lbar of each order is estimated on
//      coarse cells (scatter_cells.h) with a track-length estimator (photon_pass.h); the next
//      order's source is sigma_s * Lbar. Independent chains of orders (scattered_light.h) predict
//      their own photon noise in the image (photon_noise.h); a pair of chains of the size it asks
//      for is added where it does not meet TraceSettings::photon_noise_target. Orders are added until, for
//      every column on its own, the geometric tail of the orders left is within `order_tolerance` of that
//      column's scattered power, and that tail is added (order_series.h). The weighting makes each cell's
//      scattered power exact whatever its size, so cells follow the world extent (a cap per axis), not the
//      voxel count.
//   3. Camera rays march the exact fine-resolution medium and integrate
//      tau * (Q0 + sigma_s * sum of Lbar) for every grid point and column; the
//      per-pixel optical depths for exact alpha come from the same march. Their step follows the
//      pixel footprint, never finer than step_voxels or the coarser steps the frame's measured
//      quadrature allows, one for the radiance rays and one for alpha's depth-only rays
//      (camera_quadrature.h, TraceSettings::max_step_scale).
// Errors: quadrature of the marches, Monte Carlo noise of the photon tracks, and the
// interpolation of Lbar between cell centres.
// Memory: planFrameTrace() says what a frame needs before any tracing; nothing is stored per
// voxel besides the medium itself.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "basis/bake_description.h"
#include "basis/parameter_grid.h"
#include "look/look_model.h"
#include "render/camera.h"
#include "render/medium.h"

namespace firelook::bake {

// The part of a bake that fixes what the basis images are: one struct with the package's
// description, which extends it (basis/bake_description.h).
using basis::BasisModel;

struct TraceSettings {
    // Smallest edge of the coarse cells that hold the scattered light, in voxels. The cells'
    // smoothing of the scattered light was the largest error source on the bundled sample
    // (scripts/bench/speed_vs_error.sh, frames 3 and 7 at 128x128, 14 looks: noise-corrected
    // relative RMSE median / worst 1.05% / 3.27% with 4-voxel cells, 0.41% / 1.40% with 2). 1,
    // because what sizes the cells is max_cells_per_axis below: with 2 here a small fire was
    // held by few cells (the sample's frame 3, 28 voxels across, by 14), and its thickest look's
    // image mean came out 0.36% low at 128x128 (issue 27's emission regime; -0.29% at 64x64,
    // -0.12% with 1-voxel cells). Only frames whose influence box (active voxels and margins)
    // spans at most 48 voxels get 1-voxel cells, so the cost stays bounded by the cells' count:
    // of the sample, frames 1-4 (up to 37 voxels across; frame 5, 46 across, keeps 2-voxel
    // cells), and its frames 1-6 at 256x256 baked in 102.6-103.2 s against 91.3-96.6 s with 2
    // (peak 1.19 against 0.85 GB; the scalar march before 2026-12-06's vectorised one).
    int cell_voxels = 1;
    // At most this many cells along any axis of the volume: 48 keeps the bundled 80^3 sample at
    // 2-voxel cells and makes the memory and cost of the scattered light independent of the
    // resolution beyond it (a 480^3 frame gets 11-voxel cells of the same world size)...
    int max_cells_per_axis = 48;
    // ...unless that leaves cells optically thicker than this at the densest voxel and the largest
    // extinction on the axes: then cells are made finer (down to cell_voxels, and as the memory
    // budget allows). A cell's sigma_s-weighted mean conserves its scattered power, but the camera
    // sees only the first mean free path of a thick cell: measured on a 16^3 box of smoke
    // (tau 8 across, albedo 0.9, a sun), the image's energy against the reference was 0.999 /
    // 0.993 / 0.962 with cells of optical depth 0.5 / 1 / 2 (tests/bake/basis_tracer_test.cpp).
    // Finer cells cost by their number: every photon pass sums, normalises and carries whole
    // fields of points x columns per cell. 0.5 here would give dense smoke (samples/data/smoke at
    // the top of a dense k_s axis, 2-voxel cells of optical depth 0.53, within issue 27's bars)
    // 1-voxel cells and a bake several times slower. Splitting only the thick cells of a frame
    // was tried (2026-12-06) and made it worse: on frame 3's thickest look at 64x64 the image-mean
    // bias went from -0.29% (no cell split) to +0.15..+0.29% (the cells above optical depth
    // 0.3..0.5 split), against -0.12% with every cell split. Where fine cells meet coarse ones the
    // coarse cells' errors in transport and in what the camera sees no longer cancel.
    double max_cell_optical_depth = 1.0;
    // Cells need not be finer than the image resolves: where the pixels are coarser than the voxels,
    // cells are at least this many pixel footprints wide (at the influence box's corner nearest the
    // camera, pixelFootprintVoxels()), as long as min_cells_across of them still span the box's
    // longest axis; before the optical-depth rule above, which may make them finer again. 0: off.
    // What a cell smooths is a world-size field (the scattered light), whose error in the image
    // does not shrink with the pixels once they resolve the cells: the bundled sample's frames have
    // 2-voxel cells, 25-37 across, at every size, 3.2-3.5 footprints at 128x128 (the accuracy suite)
    // and 6.4-7 at 256x256 (scripts/bench/bake_vs_reference.sh: 0.32% on frame 12). 7 and 32 keep
    // the sample and samples/data/smoke as they are at every size and give a frame whose voxels are
    // finer than its pixels cells of that world size: frame 12 upsampled 4x gets 8-voxel cells, 36
    // across, at 128x128 (2.3 voxels a pixel) and at 256x256 (1.15), where 3.5 gave 6-voxel ones at
    // 256x256 (48, max_cells_per_axis): photon passes 14.3 s against about 7 s. At 128x128 with
    // 3.5, 8-voxel cells against 6-voxel ones measured photon passes 7.4 s against 20.1 s (2 photon
    // chains against 4; the predicted photon noise 0.89% against 0.70%), noise-corrected error of 3
    // looks against a 272-spp judge 0.56% / 0.60% (median / worst) against 0.51% / 0.60%.
    double cell_pixel_footprints = 7.0;
    int min_cells_across = 32;
    // At most this many light-depth lattice points along any axis (shadow resolution of the
    // single-scattered light): 128 keeps the sample at one point per voxel.
    int light_points_per_axis = 128;
    // Photons for the primary sources and for each further scattering order, split over two
    // independent chains (scattered_light.h) whose difference predicts the photon noise. The
    // target below may multiply them.
    int photons_primary = 131072;
    int photons_per_order = 65536;
    // The photon noise each column's image may have, as a relative RMSE predicted from the chains
    // (photon_noise.h): when the first two chains predict more for any column, the tracer adds a
    // pair of chains that brings the photons to what the prediction asks for 0.95 of it (at least a
    // quarter of the pilot's more), up to max_photon_scale times the photons above. 0 keeps
    // the photons as given. 0.01 because a look mixes columns and the worst look of issue 27's bars
    // may have 1.5% error in all: measured on the regimes of scripts/bench/accuracy.sh (64x64,
    // predictions of two chains at these photons), the emission frames' worst columns are 0.3-0.5%
    // (no change), dense smoke's cold temperature bins 1.5-2.2% (4x the photons: its sunlit column
    // 0.71% -> 0.36%, which the looks of that regime are made of).
    double photon_noise_target = 0.01;
    int max_photon_scale = 4;
    // With a target, every chain holds this share of the photons above, so the first two (the
    // pilot) can ask for fewer photons than the settings name as well as for more: a frame whose
    // noise is well within the target then costs that share. 1 (whole chains) by default, as what a
    // look's image gets of the photon noise is 0.15-0.52 of the worst column's prediction on the
    // regimes of scripts/bench/accuracy.sh (tracing error of `bench --split`, median over looks),
    // and the frames the defaults were measured with predicted 0.46-1.09%: with 0.25, frame 12 of
    // the bundled sample at 256x256 baked in 53.3 s against 65.5 s, its prediction 0.96% against
    // 0.47% (0.25 with a target of 0.007: 4 quarter chains, 0.70%, 63.6 s).
    double photon_pilot_share = 1.0;
    // Photons of each order after the first further one, as a share of photons_per_order: that
    // order's expected power over the first further order's (OrderSeries::nextOrderShare: the share
    // that minimises the summed noise of the orders for their photons), never below this. Where the
    // orders fall off fast (thin or absorbing media: frame 12 of the bundled sample, r = 0.2-0.4),
    // later orders cost a fraction of the first; in dense high-albedo smoke (r near the albedo) each
    // gets nearly all. 1 gives every order the same photons (the bytes of bakes before it). The
    // chains' noise sample (scattered_light.h) still measures what the orders hand on, so the noise
    // target holds either way. Below 0.125 an order's ratio to the one before, which decides when
    // orders stop and their tail, would rest on too few photons.
    double min_order_photon_share = 0.125;
    // Scattering orders (photon passes) at most; 0 traces none (direct light and single scattering
    // of the lights only: a diagnostic, tests/bake/scatter_order_report).
    int max_orders = 12;
    // Stop when, for every column, the geometric tail of the orders not yet traced is at most this
    // share of the column's own scattered power; the tail is then added (order_series.h).
    double order_tolerance = 0.002;
    // Photon tracks' step in cells (at least a voxel): what it costs and adds is in basis_tracer.cpp,
    // where it is used. `final` takes half a cell.
    double track_step_cells = 1.0;
    // Smallest march step in voxels (camera rays and light depths; photon tracks step
    // track_step_cells). Each camera ray's first step is a random share of it (march()): rays that
    // run along a grid axis from a voxel face (a view along an axis) otherwise put every midpoint
    // at the same place within its voxel, and the midpoint rule's error at the trilinear field's
    // kinks adds up instead of cancelling. Frame 3 of the bundled sample at 128x128 (T_c 1.05, k_s
    // 15.2, k_f 3.8, 4096-spp reference, noise of its mean 0.014%), emission and extinction only
    // (albedo 0): image mean -0.23% at 0.25 with every ray at the same phase, +0.04% with a phase
    // per ray, +0.04% at 0.125; relative RMSE 0.46%, 0.37% and 0.35%. At 0.5 with phases +0.11% and
    // 0.63%. With scattering (albedo 0.7) -0.15%, -0.08% and -0.07%; sunlit smoke
    // (samples/data/smoke frame 20, k_s 50, emission off) -0.077% at either step. So 0.25: the
    // camera rays and light depths take half the time of 0.125 (`final` keeps 0.125). Alpha: at 0.5
    // the silhouettes' optical depths moved alpha by 0.0116 against the same rays marched at 0.1
    // (frame 3, 128x128, k_s 15); 0.25: 0.0018, 0.1: 0.0006.
    double step_voxels = 0.25;
    // Camera-ray step as a fraction of the spacing of the rays a pixel marches where the ray enters
    // the volume (the n x n footprint rays; the m x m radiance rays where they are fewer), when
    // that is longer than step_voxels: finer detail than the rays' own spacing is averaged away by
    // the footprint anyway, so fine volumes cost per pixel, not per voxel.
    double footprint_step = 0.5;
    // Camera rays per pixel along each axis of its footprint (n x n, cell-centred): a
    // pixel is the mean over its footprint, and alpha = mean(1 - exp(-tau)) needs the
    // optical depths of each ray, which are all stored. 0 (the default) takes n from the
    // image size, footprintSamplesPerAxis(): the footprint quadrature's alpha error grows as
    // the pixels do, and the bake's alpha bar is 0.005 at every size.
    int footprint_samples_per_axis = 0;
    // Of those, how many (m x m, cell-centred in the same footprint) gather the pixel's radiance;
    // the other rays march for alpha's optical depths only, several times cheaper. 0 (the default):
    // m from radiance_quadrature_target below; m > 0: that m (at most n). The radiance is linear in
    // what each ray carries where alpha is not, but fewer rays still cost accuracy where a frame has
    // detail below the pixel: with m = ceil(n / 2) (2 of 4 at 128x128) for every frame,
    // scripts/bench/accuracy.sh measured the emission regime's worst look at 1.64% against 0.83%
    // (over issue 27's 1.5% bar; median 0.43% against 0.17%), the corners' median 0.42% against
    // 0.20%, the other regimes within 0.05 points, for camera rays 2.6 times as fast. The preview
    // quality takes m = 2 (bake_config.h).
    int radiance_samples_per_axis = 0;
    // With radiance_samples_per_axis 0, the trace measures each frame's radiance quadrature error
    // before its camera pass, on every 16th pixel (the check of FrameBasis::radiance_quadrature_error),
    // for every m that marches at most half the footprint's rays (2 m^2 <= n^2: with fewer rays
    // saved, the depth-only rays that still march make it no faster; 3 of 4 was measured at the
    // same seconds as 4 of 4), the pixel's centre ray alone (m = 1) among them, and takes the
    // smallest m whose error is at most this; else m = n. Where a pixel spans about a voxel or less
    // one ray is as good as more: frame 12 upsampled 4x at 256x256 (1.15 voxels a pixel) measured
    // 0.23% with 1 of 3, within the share of its photon noise below, camera rays 4.1 s against 10.4
    // s with 2 of 3; at 128x128 the accuracy suite's frames measured 0.65-2.5% with 1 of 4. 0:
    // m = n always. 0.0015 because a look's error from it was about the measured error in the
    // median and 3.5 times it in the worst look (the emission regime above: m = 2 on frames 3, 7
    // and 11, whose errors were 0.13-0.40%), so 0.15% keeps the worst look within 0.5 points of the
    // every-ray bake. Measured on frame 12 of the bundled sample: 0.13% with 2 of 4 at 128x128 and
    // 0.034% with 2 of 3 at 256x256 (camera rays 10.5 s against 19.0 s); frame 3 at 128x128 0.40%
    // (4 of 4 kept).
    double radiance_quadrature_target = 0.0015;
    // ...or this share of the frame's predicted photon noise (photon_noise.h), where that is more:
    // the two add in quadrature, so at 0.3 of it the frame's predicted error rises by at most 4.4%
    // (sqrt(1 + 0.3^2)). Measured on frame 12 of the bundled sample upsampled 4x at 128x128 (photon
    // noise 0.70%): 2 of 4 rays had 0.155%, just over the target above; with them the camera rays
    // took 6.9 s against 24.8 s, and three looks' noise-corrected error against 2%-noise references
    // was 0.505% / 0.601% (median / worst) against 0.474% / 0.568% with every ray. 0: the target
    // alone (the bakes before 2026-12-07's second session).
    double radiance_quadrature_noise_share = 0.3;
    // The smallest steps may be step_voxels times 2, 4, ... up to this, chosen per frame by what
    // each changes on a sparse sample (camera_quadrature.h, light_depth_field.h), each step by its
    // own criteria:
    // - the radiance rays': the coarsest at which all footprint rays' radiance is within
    //   step_radiance_target of theirs at step_voxels and its sums move by at most
    //   step_mean_change_target, never coarser than alpha's (kRadianceStepOverDepthStep); the
    //   radiance rays' m then gets what it leaves of the allowance;
    // - alpha's depth-only rays': the coarsest whose pixels' alpha moves by at most
    //   step_alpha_target for any look on the axes;
    // - each light's depths' (toward the lights the step is step_voxels times the lattice's
    //   spacing): the coarsest whose lit source moves within step_radiance_target (relative norm)
    //   and step_mean_change_target (its sum).
    // The midpoint rule's error is the field's, not the step's alone: frame 12 of the bundled
    // sample upsampled 4x (smooth at the voxel scale) takes 1 voxel for its camera rays and 1.5
    // toward its key light (light depths 2.1-2.4 s against 3.0-3.4 s at 0.75); the sample's own
    // frames 0.25-1 voxel. 1: step_voxels always (the bakes before 2026-12-07's fourth session).
    int max_step_scale = 16;
    // What a coarser step may move of the radiance (and of each light's lit source): half of
    // radiance_quadrature_target, so that the radiance rays' m keeps most of the allowance. Not
    // the photon noise's share, because a midpoint error can be a bias where photon noise is not.
    // With the radiance rays' step allowed twice alpha's and the whole target, the accuracy
    // suite's smoke frame took its radiance rays to 1 voxel at a measured 0.137%, their 2x2 rays
    // then 0.264% of the noise share's allowance, and dense smoke at albedo 0.95 had its median look
    // error rise from 0.38% to 0.47% (the bar is 0.5%).
    double step_radiance_target = 0.00075;
    // A fifth of the bake's alpha bar of 0.005 (its measured worst is at most 0.0029 on
    // scripts/bench/accuracy.sh, with these steps as without): the check sees 1/64 of the pixels,
    // and a silhouette between them can move more than the ones it sees.
    double step_alpha_target = 0.001;
    // ...and the checked pixels' sums, per grid point and source, may move by at most this share
    // (QuadratureCandidate::mean_change): a sixth of the accuracy suite's bias bar of 0.3%, whose
    // measured worst is 0.22% (scripts/bench/accuracy.sh), as the midpoint rule's error at a field's
    // kinks can add up where photon noise cancels. Measured at most 0.004% on the bundled sample's
    // frame 12 and 0.0005% on it upsampled 4x: each camera ray's own phase keeps it from adding up.
    double step_mean_change_target = 5e-4;
    // Bytes the trace may use for what it can size (the scattered-light cells): 0 = no limit.
    // planFrameTrace() coarsens the cells until they fit.
    std::uint64_t memory_budget_bytes = 0;
    uint64_t seed = 1;
};

// What tracing one frame will hold, decided before any tracing.
struct TracePlan {
    int cell_edge_voxels = 0;
    std::size_t cell_slots = 0;     // an upper bound (cells touched by non-empty bricks)
    int light_spacing_voxels = 0;
    double pixel_footprint_voxels = 0.0;  // pixelFootprintVoxels()
    // Optical depth across one cell at the densest voxel and the largest extinction on the axes.
    double cell_optical_depth = 0.0;
    std::size_t basis_bytes = 0;    // the pixels x columns matrix
    std::size_t depth_bytes = 0;    // per-ray optical depths
    std::size_t cell_bytes = 0;     // scattered-light fields and their photon buffers
    std::size_t light_bytes = 0;    // light depth lattice
    std::size_t sampler_bytes = 0;  // the photon start samplers' cube weights
    std::size_t medium_bytes = 0;   // the medium as given (already resident)
    std::size_t totalBytes() const {
        return basis_bytes + depth_bytes + cell_bytes + light_bytes + sampler_bytes + medium_bytes;
    }
    bool fits = true;               // false if even the coarsest cells exceed the budget
};

// The n of a pixel's n x n footprint rays: settings.footprint_samples_per_axis where given, else
// the smallest n whose alpha quadrature stays within 0.005 of 16 x 16 rays at this image size on
// the bundled sample's most opaque looks (tests/bake/alpha_footprint_report): largest per-pixel
// error at n = 3 / 4 was 0.0032 / 0.0017 at 256x256, 0.0055 / 0.0031 at 128x128, and 0.0116 / ...
// at 64x64, so 3 from 256 pixels on the short side, 4 from 128, 5 below.
int footprintSamplesPerAxis(const TraceSettings& settings, int width, int height);
// The m of a pixel's m x m radiance rays (TraceSettings::radiance_samples_per_axis), for n x n
// footprint rays: the given m, or n where the trace chooses (the most it can choose).
int radianceSamplesPerAxis(const TraceSettings& settings, int footprint_per_axis);
// The m the trace measures before its camera pass and may choose instead of n, smallest first (empty
// where m is given or radiance_quadrature_target is 0).
std::vector<int> radianceCandidates(const TraceSettings& settings, int footprint_per_axis);

// The coarser steps the trace measures, as multiples of step_voxels: 2, 4, ... up to
// max_step_scale (empty at 1).
std::vector<int> stepScaleCandidates(const TraceSettings& settings);

// The width of a pixel's footprint at the corner of the medium's influence box nearest the camera
// (the smallest any pixel has on the box), in the medium's smallest voxel edge; 0 where that corner
// is not in front of the camera.
double pixelFootprintVoxels(const render::Medium& medium, const render::Camera& camera);

TracePlan planFrameTrace(const render::Medium& medium, const render::Camera& camera, const BasisModel& model,
                         const TraceSettings& settings);

// One measured choice of camera_quadrature.h: m x m radiance rays at step_scale times step_voxels.
// radiance_error: the relative error of the pixels' radiance, as a look sees it (per grid point the
// emission bins summed, and each light's column), against all n x n rays at step_voxels (for the
// n x n rays at a coarser step) or at the step taken (for m < n). mean_change: for a coarser step,
// how much the checked pixels' sums move, per grid point and source as above, the magnitudes
// weighted by those sums (the image-mean bias a look would see). alpha_error: the largest change of
// a checked pixel's alpha over every look on the axes' samples against step_voxels. Both 0 for
// m < n (alpha is from the n x n rays).
struct QuadratureCandidate {
    int rays_per_axis = 0;
    int step_scale = 1;
    double radiance_error = 0.0;
    double mean_change = 0.0;
    double alpha_error = 0.0;
};

// What a march toward a light at step_scale times the finest step changes, on one lattice point
// near density of every kLightStepCheckStride^3 block (light_depth_field.h, chooseLightSteps).
struct LightStepCandidate {
    int step_scale = 1;
    // The single-scatter source sigma_s tau_light at the checked points against the finest step's,
    // per grid point and light: the relative Frobenius norm of the difference, the points weighted
    // by their density (the source's other factor); and the relative change of its sum (a bias).
    double source_error = 0.0;
    double mean_change = 0.0;
};

// One light's depths' step as chooseLightSteps took it, and every step it measured.
struct LightStep {
    int step_scale = 1;
    double step_voxels = 0.0;   // the march step taken, in voxels
    double source_error = 0.0;  // the one taken's (0 at the finest step)
    std::vector<LightStepCandidate> candidates;
};

struct FrameBasis {
    int width = 0;
    int height = 0;
    int columns = 0;
    std::vector<float> matrix;          // pixels x columns, pixel-major; column = point * C + c
    int footprint_samples = 1;          // rays per pixel for alpha's optical depths
    int radiance_samples = 1;           // rays per pixel for its radiance
    // With fewer radiance rays than footprint rays or a coarser step: the relative error of the
    // basis's radiance against all the footprint rays' at step_voxels, as a look sees it: per grid
    // point, the emission bins summed and each light's column; the step's (on every 64th pixel) and
    // the rays' (on every 16th) in quadrature (camera_quadrature.h). 0 for every ray at step_voxels.
    double radiance_quadrature_error = 0.0;
    // The quadrature error the frame allowed its radiance rays and step (TraceSettings::
    // radiance_quadrature_target and radiance_quadrature_noise_share); 0 where neither was chosen.
    double radiance_quadrature_allowance = 0.0;
    // What each measured choice of radiance rays and step had (camera_quadrature.h): all n x n rays
    // at each coarser step of stepScaleCandidates, then the m of radianceCandidates (or the given m
    // where it was fewer than n) at the step taken; empty where nothing was measured.
    std::vector<QuadratureCandidate> quadrature_candidates;
    double camera_step_voxels = 0.0;  // the radiance rays' smallest step taken, in voxels
    double depth_step_voxels = 0.0;   // the depth-only rays' (alpha's), in voxels
    // Each light's depths' march step, as chooseLightSteps took it (its source_error is part of the
    // predicted look error).
    std::vector<LightStep> light_steps;
    std::vector<float> depth_b;   // O_b: footprint sample x pixel
    std::vector<float> depth_a;   // O_a: footprint sample x alpha threshold x pixel
    int scattering_orders = 0;          // orders traced
    double last_order_fraction = 0.0;   // largest share of a column's scattered power the last order added
    double tail_fraction = 0.0;         // largest share of a column's scattered power the added tail is
    int photon_chains = 0;              // independent photon chains traced
    double photon_multiple = 0.0;       // photons traced / the photons the settings name
    double order_photon_share = 1.0;    // ScatteredLightTracer::orderPhotonShare
    double predicted_photon_noise = 0.0;  // photon_noise.h: the worst column's prediction
    int cell_edge_voxels = 0;           // what the plan chose
    int light_spacing_voxels = 0;
    double cell_optical_depth = 0.0;
    // Seconds spent per stage (for the bake report; not stored in packages): seconds_checks is the
    // light depths' and the camera rays' step checks, which the other stages leave out.
    double seconds_setup = 0.0, seconds_light = 0.0, seconds_photons = 0.0, seconds_camera = 0.0,
           seconds_checks = 0.0;
};

// progress(fraction) returns false to cancel; traceFrameBasis then throws
// a Cancelled Error ("cancelled") without a result. It is called from one thread at a time, but
// not always the caller's. Without a plan, the trace makes its own with planFrameTrace(settings).
FrameBasis traceFrameBasis(const render::Medium& medium, const render::Camera& camera, const BasisModel& model,
                           const TraceSettings& settings, const std::function<bool(double)>& progress = {});
FrameBasis traceFrameBasis(const render::Medium& medium, const render::Camera& camera, const BasisModel& model,
                           const TraceSettings& settings, const TracePlan& plan,
                           const std::function<bool(double)>& progress = {});

}  // namespace firelook::bake
