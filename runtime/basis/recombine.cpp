#include "basis/recombine.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace firelook::basis {
namespace {

struct ThresholdLerp {
    int lower = 0;
    int upper = 0;
    float t = 0.0f;
};

ThresholdLerp thresholdLerp(const std::vector<double>& samples, double t_c) {
    const int last = static_cast<int>(samples.size()) - 1;
    if (last <= 0 || !(t_c > samples.front())) return {0, 0, 0.0f};
    if (t_c >= samples.back()) return {last, last, 0.0f};
    const int upper =
        static_cast<int>(std::upper_bound(samples.begin(), samples.end(), t_c) - samples.begin());
    const int lower = upper - 1;
    return {lower, upper, static_cast<float>((t_c - samples[lower]) / (samples[upper] - samples[lower]))};
}

float alphaFromDepths(float depth_density, float depth_sigmoid, const ExtinctionParams& e) {
    const double tau = e.a() * depth_sigmoid + e.b() * depth_density;
    const double alpha = 1.0 - std::exp(-std::max(tau, 0.0));
    return std::isfinite(alpha) ? static_cast<float>(alpha) : 1.0f;
}

}  // namespace

void computeCoefficients(const BakeDescription& description, const FrameFactors& factors,
                         const LookWeights& look, std::span<float> z_out) {
    const int bins = description.bins.count;
    const int lights = static_cast<int>(description.light_directions.size());
    if (static_cast<int>(look.rbf_coefficients.size()) != bins)
        throw std::invalid_argument("look has " + std::to_string(look.rbf_coefficients.size()) +
                                    " emission coefficients, the package has " + std::to_string(bins) +
                                    " bins");
    if (static_cast<int>(look.light_irradiance.size()) != lights)
        throw std::invalid_argument("look has " + std::to_string(look.light_irradiance.size()) +
                                    " light irradiances, the package has " + std::to_string(lights) +
                                    " lights");
    const int rank = factors.rank;
    if (static_cast<int>(z_out.size()) < rank * 3)
        throw std::invalid_argument("coefficient output too short");

    std::fill(z_out.begin(), z_out.begin() + rank * 3, 0.0f);
    const GridWeights grid = interpolationWeights(description.axes, look.extinction);
    const int per_point = description.columnsPerPoint();
    for (int g = 0; g < grid.count; ++g) {
        const int first_column = grid.point[g] * per_point;
        for (int c = 0; c < per_point; ++c) {
            const Rgb weight =
                grid.weight[g] * (c < bins ? look.rbf_coefficients[c] : look.light_irradiance[c - bins]);
            if (weight.r == 0.0f && weight.g == 0.0f && weight.b == 0.0f) continue;
            const float* column = factors.svt.data() + static_cast<size_t>(first_column + c) * rank;
            for (int k = 0; k < rank; ++k) {
                z_out[k * 3 + 0] += column[k] * weight.r;
                z_out[k * 3 + 1] += column[k] * weight.g;
                z_out[k * 3 + 2] += column[k] * weight.b;
            }
        }
    }
}

namespace {

// Mean over the pixel's footprint rays of 1 - exp(-tau); O_a is linear in T_c between samples.
float footprintAlpha(const BakeDescription& description, const FrameFactors& factors,
                     const ThresholdLerp& lerp, size_t pixel, const ExtinctionParams& extinction) {
    const size_t pixels = static_cast<size_t>(factors.pixels);
    const size_t thresholds = description.alpha_thresholds.size();
    const int samples = description.footprint_samples;
    float sum = 0.0f;
    for (int s = 0; s < samples; ++s) {
        const float* sigmoid = factors.depth_sigmoid.data() + static_cast<size_t>(s) * thresholds * pixels;
        const float o_a = (1.0f - lerp.t) * sigmoid[lerp.lower * pixels + pixel] +
                          lerp.t * sigmoid[lerp.upper * pixels + pixel];
        sum +=
            alphaFromDepths(factors.depth_density[static_cast<size_t>(s) * pixels + pixel], o_a, extinction);
    }
    return sum / static_cast<float>(samples);
}

}  // namespace

float pixelAlpha(const BakeDescription& description, const FrameFactors& factors, int pixel,
                 const ExtinctionParams& extinction) {
    const ThresholdLerp lerp = thresholdLerp(description.alpha_thresholds, extinction.temperature_threshold);
    return footprintAlpha(description, factors, lerp, static_cast<size_t>(pixel), extinction);
}

void reconstructImage(const BakeDescription& description, const FrameFactors& factors,
                      std::span<const float> u_float, std::span<const float> z,
                      const ExtinctionParams& extinction, std::span<float> rgba_out) {
    const int pixels = factors.pixels;
    const int rank = factors.rank;
    if (static_cast<int>(rgba_out.size()) < pixels * 4) throw std::invalid_argument("image output too short");
    if (static_cast<int>(z.size()) < rank * 3) throw std::invalid_argument("coefficients too short");
    if (u_float.size() < static_cast<size_t>(pixels) * rank) throw std::invalid_argument("U too short");

    const ThresholdLerp lerp = thresholdLerp(description.alpha_thresholds, extinction.temperature_threshold);
    for (int p = 0; p < pixels; ++p) {
        const float* u = u_float.data() + static_cast<size_t>(p) * rank;
        float r = 0.0f, g = 0.0f, b = 0.0f;
        for (int k = 0; k < rank; ++k) {
            r += u[k] * z[k * 3 + 0];
            g += u[k] * z[k * 3 + 1];
            b += u[k] * z[k * 3 + 2];
        }
        float* out = rgba_out.data() + static_cast<size_t>(p) * 4;
        out[0] = r > 0.0f && std::isfinite(r) ? r : 0.0f;
        out[1] = g > 0.0f && std::isfinite(g) ? g : 0.0f;
        out[2] = b > 0.0f && std::isfinite(b) ? b : 0.0f;
        out[3] = footprintAlpha(description, factors, lerp, static_cast<size_t>(p), extinction);
    }
}

}  // namespace firelook::basis
