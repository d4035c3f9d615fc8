#include "basis/parameter_grid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace firelook::basis {
namespace {

// The grid samples one axis blends and their weights: up to 4 (a C1 cubic), 1 at a sample, outside
// the range or on a collapsed axis.
struct AxisWeights {
    int count = 0;
    std::array<int, 4> index{};
    std::array<double, 4> weight{};
    void add(int i, double w) {
        index[count] = i;
        weight[count] = w;
        ++count;
    }
};

// The Lagrange weights of the parabola through samples a, a+1, a+2, evaluated at x, scaled by s.
void addParabola(const std::vector<double>& x_s, int a, double x, double s, AxisWeights& out) {
    for (int i = a; i < a + 3; ++i) {
        double w = s;
        for (int j = a; j < a + 3; ++j)
            if (j != i) w *= (x - x_s[j]) / (x_s[i] - x_s[j]);
        // A sample both parabolas use is added twice; merge it so each sample appears once.
        int at = 0;
        while (at < out.count && out.index[at] != i) ++at;
        if (at < out.count)
            out.weight[at] += w;
        else
            out.add(i, w);
    }
}

// Between samples i and i+1 at t = (x - x_i) / (x_(i+1) - x_i): the parabola through i-1, i, i+1 blended
// linearly into the one through i, i+1, i+2 (an Overhauser spline, Catmull-Rom's construction on
// uneven samples), in the parameter itself. It is exact at the samples and for any quadratic in the
// parameter (so for the thin-smoke image, linear in k), continuous in value and slope across
// samples, and follows a saturating image (smoke that thickens as k grows) where linear
// interpolation cuts the curve and renders dark (docs/model.md, "Between grid points"). The end
// intervals use the one parabola they have; an axis of two samples is linear. Weights can be
// negative (down to -1/8 on even samples, -1/3 on samples that double), so a blend can undershoot
// zero: the runtime clamps the reconstructed colour and the fire lights' intensities at zero.
AxisWeights axisWeights(const std::vector<double>& x_s, double x) {
    AxisWeights out;
    const int last = static_cast<int>(x_s.size()) - 1;
    if (last <= 0 || !(x > x_s.front())) {  // also catches NaN
        out.add(0, 1.0);
        return out;
    }
    if (x >= x_s.back()) {
        out.add(last, 1.0);
        return out;
    }
    const int upper = static_cast<int>(std::upper_bound(x_s.begin(), x_s.end(), x) - x_s.begin());
    const int lower = upper - 1;
    const double t = (x - x_s[lower]) / (x_s[upper] - x_s[lower]);
    if (last == 1) {
        out.add(lower, 1.0 - t);
        out.add(upper, t);
        return out;
    }
    const bool has_left = lower >= 1, has_right = upper + 1 <= last;
    if (has_left) addParabola(x_s, lower - 1, x, has_right ? 1.0 - t : 1.0, out);
    if (has_right) addParabola(x_s, lower, x, has_left ? t : 1.0, out);
    return out;
}

void validateAxis(const std::vector<double>& samples, const char* name) {
    if (samples.empty()) throw std::invalid_argument(std::string("parameter axis ") + name + " has no samples");
    for (size_t i = 0; i < samples.size(); ++i) {
        if (!std::isfinite(samples[i]))
            throw std::invalid_argument(std::string("parameter axis ") + name + " has a non-finite sample");
        if (i > 0 && !(samples[i] > samples[i - 1]))
            throw std::invalid_argument(std::string("parameter axis ") + name + " is not strictly increasing");
    }
}

}  // namespace

ExtinctionParams ParameterAxes::point(int index) const {
    const int n_kf = static_cast<int>(flame_extinction.size());
    const int n_ks = static_cast<int>(smoke_extinction.size());
    const int i_kf = index % n_kf;
    const int i_ks = (index / n_kf) % n_ks;
    const int i_tc = index / (n_kf * n_ks);
    return {temperature_threshold[i_tc], smoke_extinction[i_ks], flame_extinction[i_kf]};
}

GridWeights interpolationWeights(const ParameterAxes& axes, const ExtinctionParams& theta) {
    const AxisWeights tc = axisWeights(axes.temperature_threshold, theta.temperature_threshold);
    const AxisWeights ks = axisWeights(axes.smoke_extinction, theta.smoke_extinction);
    const AxisWeights kf = axisWeights(axes.flame_extinction, theta.flame_extinction);
    GridWeights out;
    for (int a = 0; a < tc.count; ++a)
        for (int b = 0; b < ks.count; ++b)
            for (int c = 0; c < kf.count; ++c) {
                const float w = static_cast<float>(tc.weight[a] * ks.weight[b] * kf.weight[c]);
                if (w == 0.0f) continue;
                out.point[out.count] = axes.pointIndex(tc.index[a], ks.index[b], kf.index[c]);
                out.weight[out.count] = w;
                ++out.count;
            }
    return out;
}

void validateAxes(const ParameterAxes& axes) {
    validateAxis(axes.temperature_threshold, "temperature_threshold");
    validateAxis(axes.smoke_extinction, "smoke_extinction");
    validateAxis(axes.flame_extinction, "flame_extinction");
}

}  // namespace firelook::basis
