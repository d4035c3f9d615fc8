// How a frame's camera rays sample each pixel (basis_tracer.h, step 3): the m x m radiance rays of
// its n x n footprint rays and the smallest march step, chosen per frame by measuring, before the
// camera pass, what each choice changes on a sparse grid of pixels (issue 30). The march's
// quadrature error is not a constant of the step: a frame whose field is smooth at the voxel scale
// (an upsampled or filtered simulation) marched at a quarter voxel is no nearer the truth than at a
// whole one, while the bundled sample's frames need the quarter (TraceSettings::step_voxels).
#pragma once

#include <atomic>
#include <cstddef>
#include <vector>

#include "bake/camera_march.h"

namespace firelook::bake {

// The phase of a camera ray's first step (march()), in (0, 1]: a fixed pseudo-random number per
// pixel and ray index, so the image does not depend on the threads, the optical depths not on the
// photons' seed, and a pixel's m x m radiance rays are what n = m footprint rays would march.
double cameraRayPhase(std::size_t pixel, int ray);

// to += the direct light and the gathered cells' weights contracted of the rays marched since
// beginPixel: once per pixel. lbar_sum empty: no scattered light.
void addGathered(const CameraMarch& ray_march, const std::vector<float>& lbar_sum, float* to);

// Adds pixel (px, py)'s radiance from m x m radiance-only rays to `to` (after beginPixel). They
// march at the step of their own spacing (TraceSettings::footprint_step), never finer than the
// march's smallest step.
void gatherRadianceRays(CameraMarch& ray_march, const std::vector<float>& lbar_sum, int width, int px, int py,
                        int m, float* to);

// QuadratureCandidate (one measured choice) is in basis_tracer.h, whose FrameBasis reports them.

struct CameraQuadratureInputs {
    const render::Medium& medium;
    const TraceTables& tables;
    const ScatterCells& cells;
    const LightDepthField& light_depths;
    const render::Camera& camera;
    const std::vector<float>& lbar_sum;  // the scattered light the camera gathers (empty: none)
    double min_step;                     // world units: the smallest step (TraceSettings::step_voxels)
    double footprint_step;               // TraceSettings::footprint_step
    int footprint_per_axis;              // n
};

struct QuadratureOptions {
    // The m measured, ascending, each below n; or, with rays_given, the one m the settings give,
    // taken at the smallest step whatever its error.
    std::vector<int> rays;
    bool rays_given = false;
    std::vector<int> step_scales;  // the coarser steps measured (multiples of min_step above 1), ascending
    double allowance = 0.0;        // radiance_error a choice may have, the step's and the rays' together
    // What a coarser step alone may have: its radiance_error (TraceSettings::step_radiance_target,
    // at most `allowance`), its mean_change and its alpha_error.
    double step_allowance = 0.0;
    double mean_change_allowance = 0.0;
    double alpha_allowance = 0.0;
};

struct CameraQuadrature {
    int rays_per_axis = 0;
    int step_scale = 1;        // the radiance rays' smallest step, in min_step
    int depth_step_scale = 1;  // the depth-only rays' (alpha's), in min_step
    // The chosen one's error against all n x n rays at the smallest step: the step's and the rays'
    // (at that step) in quadrature; 0 for all n x n rays at the smallest step.
    double radiance_error = 0.0;
    // Every one measured: all n x n rays at the coarser steps marched (against the smallest step,
    // with alpha; ascending, from the coarsest down to where the choice was settled), then each m at
    // the step taken (against all n x n at that step; alpha_error 0: alpha is always from the n x n
    // rays).
    std::vector<QuadratureCandidate> candidates;
};

// 1. The steps: on every stepCheckStride()-th pixel of every such row, all n x n rays at the
//    coarser steps against the smallest, from the coarsest down until the choice is settled (a
//    finer step cannot change it: each takes the coarsest within its criteria, and finer steps are
//    measured only while one is not found). Alpha's depth-only rays take the coarsest whose
//    alpha_error is within its allowance; the radiance rays the coarsest whose radiance_error and
//    mean_change are, up to kRadianceStepOverDepthStep times alpha's (so never coarser, and finer
//    where radiance moves more than alpha); both provided at least
//    kMinStepCheckPixels of those pixels have density on their rays (else the smallest).
// 2. The radiance rays: on every kQuadratureCheckStride-th pixel of every kQuadratureCheckStride-th
//    row, all n x n rays at that step against each m; the fewest m whose error is within what the
//    step left of the allowance (the two add in quadrature) is taken (else n), or the given m.
// Rows are measured in parallel and their sums added in row order: the same choice on any number
// of threads. Stops early (the result then meaningless) when `stop` is set.
CameraQuadrature chooseCameraQuadrature(const CameraQuadratureInputs& in, const QuadratureOptions& options,
                                        const std::atomic<bool>& stop);

// 1/16 of the pixels: about 1/16 more camera time at 128x128 with every ray at one step.
inline constexpr int kQuadratureCheckStride = 4;
// The step's check sees every stepCheckStride()-th pixel of every such row: 1/64 of them (every
// 8th) from 128x128 up, and at least about this many below (every 4th at 64x64). All n x n rays at
// the smallest step cost as much as a whole image's would at 4 times the step with a stride of 4:
// frame 12 upsampled 4x at 256x256 took 13.5 s for its camera stage with the step checked on
// every 4th pixel, against 9.6 s for the camera pass alone at that step; at 128x128 5.4 s with
// every 4th and 3.7 s with every 8th (alpha changes measured 0.00073 and 0.00083 at 4 times the
// step: the sparser grid saw no less).
inline constexpr int kStepCheckPixels = 256;
int stepCheckStride(int width, int height);
// A coarser step is judged on at least this many checked pixels whose rays cross density: a
// small volume in the image (a 16x16 bake of the bundled sample's frame 1) leaves the 4 pixels of
// a sparse grid empty, and measured no change at any step.
inline constexpr int kMinStepCheckPixels = 32;
// The radiance rays' step is at most this many times alpha's (chooseCameraQuadrature): 1, never
// coarser. The radiance error this check measures (quadratureCheck: emission bins summed, each
// light's column) understated what a coarser step did to a look's image several times over:
// frame 12 of the bundled sample at 256x256 measured 0.044% for its 3x3 rays at 1 voxel against
// 0.25, while its default look's image moved by 0.23% between 1 and 0.5 voxel (0.34% with its
// 2x2 radiance rays), and its error against a 2%-noise reference rose from 0.32% to 0.59%. Alpha's
// check sees each pixel's depths, and where it allows a step the image has held.
inline constexpr int kRadianceStepOverDepthStep = 1;

}  // namespace firelook::bake
