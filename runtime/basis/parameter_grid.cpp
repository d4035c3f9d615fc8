#include "basis/parameter_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace firelook::basis {
namespace {

struct AxisWeights {
    int lower = 0;
    int upper = 0;
    float t = 0.0f;  // weight of upper
};

AxisWeights axisWeights(const std::vector<double>& samples, double value) {
    const int last = static_cast<int>(samples.size()) - 1;
    if (last <= 0 || !(value > samples.front())) return {0, 0, 0.0f};  // also catches NaN
    if (value >= samples.back()) return {last, last, 0.0f};
    const auto it = std::upper_bound(samples.begin(), samples.end(), value);
    const int upper = static_cast<int>(it - samples.begin());
    const int lower = upper - 1;
    const double t = (value - samples[lower]) / (samples[upper] - samples[lower]);
    return {lower, upper, static_cast<float>(t)};
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
    for (int c = 0; c < 8; ++c) {
        const bool up_tc = c & 4, up_ks = c & 2, up_kf = c & 1;
        const float w = (up_tc ? tc.t : 1.0f - tc.t) * (up_ks ? ks.t : 1.0f - ks.t) * (up_kf ? kf.t : 1.0f - kf.t);
        if (w == 0.0f) continue;
        const int point = axes.pointIndex(up_tc ? tc.upper : tc.lower, up_ks ? ks.upper : ks.lower,
                                          up_kf ? kf.upper : kf.lower);
        out.point[out.count] = point;
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
