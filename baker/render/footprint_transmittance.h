// The exact alpha of every pixel for any extinction parameters, to judge a
// package's alpha against (issue 4's bar; `firelook bench`).
//
// A pixel's alpha is the mean over its footprint of 1 - exp(-tau), tau the
// optical depth of the model (docs/model.md) along the ray:
//   tau = integral of rho(x) (a f(T(x) - T_c) + b) dx.
// Marching every ray again for each look is what made the bench slow, so each
// ray is marched once per frame into a histogram of rho dx over temperature
// nodes (each sample split linearly between its two nodes); a look then costs
// one short dot product per ray. With 128 nodes over the bin range the node
// spacing is 1/8 of a bin width and the linear split's error in f is below
// 0.2 h^2 / (8 dT^2) < 4e-4 of a * O_a, i.e. < 2e-4 in alpha.
#pragma once

#include <functional>
#include <vector>

#include "look/look_model.h"
#include "render/camera.h"
#include "render/medium.h"

namespace firelook::render {

class FootprintTransmittance {
  public:
    static constexpr int kTemperatureNodes = 128;

    // per_axis x per_axis cell-centred rays per pixel, midpoint steps of step_voxels.
    // Multithreaded over rows; the result does not depend on the thread count.
    // stop_requested (thread-safe, cheap) is polled before every row: once it returns true the
    // remaining rows are skipped and the constructor throws RenderError ("stopped on request").
    FootprintTransmittance(const Medium& medium, const Camera& camera, const TemperatureBins& bins, int per_axis,
                           double step_voxels = 0.1, const std::function<bool()>& stop_requested = {});

    // Alpha per pixel (top row first) for these extinction parameters.
    std::vector<float> alpha(const ExtinctionParams& extinction) const;

    int raysPerPixel() const { return per_axis_ * per_axis_; }

  private:
    TemperatureBins bins_;
    int width_ = 0;
    int height_ = 0;
    int per_axis_ = 1;
    // Rays that meet density: their pixel and their histogram (kTemperatureNodes floats each).
    std::vector<int> ray_pixel_;
    std::vector<float> histogram_;
};

}  // namespace firelook::render
