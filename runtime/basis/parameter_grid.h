// The sampled extinction parameters theta = (T_c, k_s, k_f) of a bake, and the
// interpolation weights that blend basis images between grid points
// (docs/model.md). An axis with one value is "collapsed": that parameter
// was fixed at bake time and any request for it uses the baked value.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "look/look_model.h"

namespace firelook::basis {

struct ParameterAxes {
    std::vector<double> temperature_threshold;  // T_c samples, strictly increasing
    std::vector<double> smoke_extinction;       // k_s samples
    std::vector<double> flame_extinction;       // k_f samples

    int pointCount() const {
        return static_cast<int>(temperature_threshold.size() * smoke_extinction.size() *
                                flame_extinction.size());
    }
    // Grid point index of (i_tc, i_ks, i_kf); k_f varies fastest.
    int pointIndex(int i_tc, int i_ks, int i_kf) const {
        return (i_tc * static_cast<int>(smoke_extinction.size()) + i_ks) *
                   static_cast<int>(flame_extinction.size()) +
               i_kf;
    }
    ExtinctionParams point(int index) const;
};

// The two samples around x and x's place between them, t in [0, 1); x clamped to the samples'
// range: at or beyond an end (and for NaN, or one sample) lower == upper and t = 0, the first
// sample below the range. One rule for the grid's axes, the alpha threshold layers (recombine.cpp)
// and the plugin's fl_instance_state. `samples` strictly increasing and not empty.
struct SampleBracket {
    int lower = 0;
    int upper = 0;
    double t = 0.0;
};
SampleBracket sampleBracket(const std::vector<double>& samples, double x);

// One axis's part of the blend: the samples it uses (increasing, consecutive) and their weights.
struct AxisWeights {
    static constexpr int kMaxSamples = 5;
    int count = 0;
    std::array<int, kMaxSamples> index;
    std::array<double, kMaxSamples> weight;
};
// The weights on one axis (samples strictly increasing, not empty) at x: up to 5 (two cubics
// blended), 1 at a sample, outside the range or on a collapsed axis. The rule is
// interpolationWeights' below.
AxisWeights axisWeights(const std::vector<double>& samples, double x);
// A grid point's weight from its three axes' weights: what interpolationWeights lists (there
// points of weight 0 are left out).
inline float pointWeight(double tc, double ks, double kf) { return static_cast<float>(tc * ks * kf); }

// Up to 5 x 5 x 5 grid points with non-zero weight; weights sum to 1 and can be negative.
struct GridWeights {
    static constexpr int kMaxPoints = 125;
    int count = 0;
    std::array<int, kMaxPoints> point{};
    std::array<float, kMaxPoints> weight{};
};

// Per axis a C1 piecewise polynomial through up to 5 samples around the request (two cubics
// blended, parameter_grid.cpp), exact at the samples and for any cubic; an axis of three samples
// blends parabolas (exact for quadratics), one of two samples is linear. A request outside an
// axis's range is clamped to its ends (the baked range is what the package can reproduce).
GridWeights interpolationWeights(const ParameterAxes& axes, const ExtinctionParams& theta);

// Throws an InvalidArgument Error naming the axis if it is empty, unsorted or non-finite.
void validateAxes(const ParameterAxes& axes);

}  // namespace firelook::basis
