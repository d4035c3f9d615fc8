// Predicted photon noise of a frame's basis images (issues 27 and 30): the scattered light's noise
// sample (scattered_light.h) carried through the camera like Lbar itself, on a coarse grid of the
// image's pixels, one ray each at the pixel's centre.
//
// For every grid point g and column c the coarse image gives V(g, c) = sum over pixels of the
// column's value squared (direct light, single scattering and Lbar's in-scattering) and
// N(g, c) = the same sum of the noise sample's in-scattering squared, whose expectation is the
// squared photon noise of the estimate. A column's prediction is the root mean square over grid
// points of sqrt(N / V): the relative RMSE its image has from photon noise, each grid point
// weighed alike as random looks weigh them. One centre ray per pixel has at least the noise of the
// bake's footprint mean of n x n rays, so the prediction errs high, never low, on that count.
#pragma once

#include <atomic>
#include <vector>

#include "bake/light_depth_field.h"
#include "bake/scatter_cells.h"
#include "bake/trace_tables.h"
#include "render/camera.h"
#include "render/medium.h"

namespace firelook::bake {


struct PhotonNoiseInputs {
    const render::Medium& medium;
    const TraceTables& tables;
    const ScatterCells& cells;
    const LightDepthField& light_depths;
    const render::Camera& camera;
    double min_step;        // world units: the camera rays' smallest step
    double footprint_step;  // and their step against the footprint (TraceSettings::footprint_step)
    // The columns 0..counted-1 of each grid point that are judged.
    int counted;
};

// The largest column prediction (0 when no column has light). `lbar` and `noise` are the chains'
// weighted sums and their total weight (ScatteredLightTracer::sum(), signedSum() and weight()).
// Stops early, returning what it has, when `stop` is set.
double predictPhotonNoise(const PhotonNoiseInputs& in, const std::vector<float>& lbar,
                          const std::vector<float>& noise, double weight, const std::atomic<bool>& stop);

// Pixels along each axis of the coarse grid at most: 64 costs about 1/64 of the camera stage of a
// 128x128 bake (16 rays per pixel there) and holds a few thousand pixels, enough to average over
// the cells' noise.
inline constexpr int kPhotonNoisePixelsPerAxis = 64;

}  // namespace firelook::bake
