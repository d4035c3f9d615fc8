// Which look axes can change an image of the frames being baked (docs/bake-config.md, "axes").
//
// Extinction is the only place the axes enter the model (docs/model.md):
//   kappa = k_s (1 - p) + k_f p,   p(T; T_c) = (1 + f(T - T_c)) / 2 = 1 / (1 + exp(-(T - T_c) / dT)),
// with T clamped into the bins first; emission and the lights do not depend on theta. So where
// the data's temperatures (at the points whose interpolated density is non-zero) keep the flame
// share p nearly the same for every T_c sample, the T_c axis cannot change an image; where p is
// nearly 0 (smoke only) k_f cannot, and where it is nearly 1 (flame only) k_s cannot.
//
// The measure, per axis: the largest relative change of sigma_t = kappa rho at any point with
// density, for any grid point of the other two axes, across the axis's samples. It bounds what
// collapsing the axis to one sample does to every basis image and alpha: a relative change eps
// of sigma_t (and sigma_s = albedo sigma_t) moves a footprint ray's transmittance by at most
// eps tau exp(-tau (1 - eps)) <= eps / (e (1 - eps)), and a light path's contribution, to first
// order, by eps (tau_path + scattering events). The tolerance collapseTolerance() leaves room for
// tau_path + events up to 5 within the frame codec's basis error.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "basis/bake_description.h"
#include "basis/frame_codec.h"
#include "basis/parameter_grid.h"
#include "look/look_model.h"
#include "render/medium.h"

namespace firelook::bake {

// Raw temperatures (not yet clamped into the bins) wherever the interpolated density can be
// non-zero: over the medium's bricks that hold density, which include the voxels interpolation
// reads around them. any_density is false for frames with no density (nothing to draw).
struct DensityTemperatureRange {
    bool any_density = false;
    double t_min = 0.0, t_max = 0.0;
    void merge(const DensityTemperatureRange& other);
};
DensityTemperatureRange densityTemperatureRange(const render::Medium& medium);

struct AxisCollapse {
    std::string axis;               // "temperature_threshold", "smoke_extinction" or "flame_extinction"
    std::vector<double> requested;  // the samples the settings asked for
    double kept = 0.0;              // the one sample baked: the lowest (see collapseUnusedAxes)
    double relative_change = 0.0;   // the bound above, across `requested`
};

struct AxisAnalysis {
    DensityTemperatureRange temperatures;  // of the frames baked
    TemperatureBins bins;
    double tolerance = 0.0;
    // The bound above per axis, in ParameterAxes order (T_c, k_s, k_f); 0 for a one-sample axis,
    // infinity where an extinction of 0 on an axis makes a relative change unbounded.
    std::array<double, 3> relative_change{};
    std::vector<AxisCollapse> collapsed;
};

// min(basis_error, alpha_error) / 5: the collapse adds less than the codec may already add to the
// basis for paths whose optical depth plus scattering events stay below 5, and moves alpha by at
// most 0.37 of it. 1e-4 at the defaults.
double collapseTolerance(const basis::FrameCodecSettings& storage);

// The bounds per axis, and the axes to collapse: T_c first, then k_f, then k_s, each while the
// sum of the collapsed axes' bounds stays within `tolerance` (their changes add, to first order).
AxisAnalysis analyseAxes(const basis::ParameterAxes& axes, const TemperatureBins& bins,
                         const DensityTemperatureRange& temperatures, double tolerance);

// Replaces each collapsed axis of the description by its kept sample; a collapsed T_c also leaves
// one alpha threshold (the depths are the same for every T_c within the bound). The default look
// stays as the full axes clamp it: its image is the same within the bound.
void applyAxisCollapse(basis::BakeDescription& description, const AxisAnalysis& analysis);

// The analysis as JSON (the bake report and the package's metadata, key "axis_collapse").
std::string axisAnalysisToJson(const AxisAnalysis& analysis);

// One line for the terminal: which axis, to what, and why (the temperatures against the samples).
std::string describeAxisCollapse(const AxisCollapse& collapse, const AxisAnalysis& analysis);

}  // namespace firelook::bake
