#include "basis/parameter_grid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/error.h"

namespace firelook::basis {
namespace {

// weight[i - first] += the Lagrange weight of sample i in the polynomial through samples first ..
// first + degree, evaluated at x, scaled by s: one division a weight (the world computes these for
// every instance every update), and at a sample exactly s there and 0 elsewhere (the numerator and
// denominator are then the same products).
void addPolynomial(const std::vector<double>& x_s, int first, int degree, double x, double s, double* weight) {
    for (int i = first; i <= first + degree; ++i) {
        double num = 1.0, den = 1.0;
        for (int j = first; j <= first + degree; ++j)
            if (j != i) {
                num *= x - x_s[j];
                den *= x_s[i] - x_s[j];
            }
        weight[i - first] += s * (num / den);
    }
}

}  // namespace

SampleBracket sampleBracket(const std::vector<double>& samples, double x) {
    const int last = static_cast<int>(samples.size()) - 1;
    if (last <= 0 || !(x > samples.front())) return {0, 0, 0.0};  // also catches NaN
    if (x >= samples.back()) return {last, last, 0.0};
    const int upper = static_cast<int>(std::upper_bound(samples.begin(), samples.end(), x) - samples.begin());
    const int lower = upper - 1;
    return {lower, upper, (x - samples[lower]) / (samples[upper] - samples[lower])};
}

namespace {

void validateAxis(const std::vector<double>& samples, const char* name) {
    if (samples.empty())
        throw Error(ErrorCode::InvalidArgument, std::string("parameter axis ") + name + " has no samples");
    for (size_t i = 0; i < samples.size(); ++i) {
        if (!std::isfinite(samples[i]))
            throw Error(ErrorCode::InvalidArgument,
                        std::string("parameter axis ") + name + " has a non-finite sample");
        if (i > 0 && !(samples[i] > samples[i - 1]))
            throw Error(ErrorCode::InvalidArgument,
                        std::string("parameter axis ") + name + " is not strictly increasing");
    }
}

}  // namespace

// Between samples i and i+1 at t = (x - x_i) / (x_(i+1) - x_i): the cubic through i-2 .. i+1 blended
// linearly into the cubic through i-1 .. i+2, each window moved inside the axis where it would leave
// it (so an end interval, and every interval of a 4-sample axis, has one cubic). Interval i's right
// window is interval i+1's left one, so the blend is continuous in value and slope across samples;
// it is exact at the samples and for any cubic in the parameter (so for thin smoke, whose image is
// linear in k). On fewer samples the degree drops: parabolas on 3 (blended the same way), a line on
// 2. Cubic rather than parabolic because the image of smoke saturates as k grows and the parabolas
// through doubling samples overshoot it by up to 0.5 % in the last interval, the cubic by 0.14 %
// (docs/model.md, "Between grid points"). Weights can be negative, so a blend can undershoot zero:
// the runtime clamps the reconstructed colour and the fire lights' intensities at zero.
AxisWeights axisWeights(const std::vector<double>& x_s, double x) {
    AxisWeights out;
    const SampleBracket bracket = sampleBracket(x_s, x);
    if (bracket.lower == bracket.upper) {  // on or beyond an end
        out.count = 1;
        out.index[0] = bracket.lower;
        out.weight[0] = 1.0;
        return out;
    }
    const int last = static_cast<int>(x_s.size()) - 1;
    const int lower = bracket.lower;
    const double t = bracket.t;
    const int degree = std::min(3, last);
    const auto window = [&](int first) { return std::clamp(first, 0, last - degree); };
    // The windows are the same or one apart (`window` is monotone): samples left .. right + degree.
    const int left = window(lower - (degree - 1)), right = window(lower - (degree - 2));
    out.count = right - left + degree + 1;
    for (int k = 0; k < out.count; ++k) {
        out.index[k] = left + k;
        out.weight[k] = 0.0;
    }
    if (left == right) {
        addPolynomial(x_s, left, degree, x, 1.0, out.weight.data());
    } else {
        addPolynomial(x_s, left, degree, x, 1.0 - t, out.weight.data());
        addPolynomial(x_s, right, degree, x, t, out.weight.data() + (right - left));
    }
    return out;
}

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
                const float w = pointWeight(tc.weight[a], ks.weight[b], kf.weight[c]);
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
