// How the frame codec stores optical depths (frame_codec.h, docs/package-format.md, "Frame
// codec"): the companding g, whose uniform grid bounds the alpha error of any look in the axes'
// range (the proof is in depth_companding.cpp), and the levels of such a grid, from which the
// resident form's DepthTable is built.
#pragma once

#include "basis/parameter_grid.h"

namespace firelook::basis {

// Optical depths decode to at most this, the largest finite half (layout 1 stored depths as
// halves): every transmittance exp(-k * 65504) is 0 in float for k above 0.0016.
inline constexpr float kLargestDepth = 65504.0f;

// The depth companding: g, its inverse and the alpha bound factor c.
struct DepthCompanding {
    double k_lo = 1.0, k_hi = 1.0;
    static DepthCompanding forAxes(const ParameterAxes& axes);
    double forward(double depth) const;   // g(O), in [0, limit())
    double inverse(double value) const;   // O for g(O) = value; +inf at or above limit()
    double limit() const;                 // g(infinity)
    double alphaFactor() const;           // c
    double k_f_hi = 1.0, k_s_lo = 1.0;
};

// Levels of the depth grid of step `step`, rounded up so that rounding g(O) / step is within half
// a step even for the deepest rays (the top level may decode to +inf, stored as kLargestDepth).
double depthLevels(const DepthCompanding& g, double step);

}  // namespace firelook::basis
