#include "reference_kernels.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "basis/parameter_grid.h"
#include "basis/resident_frame.h"
#include "common/error.h"

namespace firelook::reference {
namespace {

// Throws an InvalidArgument Error unless the factors hold every depth layer the description implies.
void checkDepthLayers(const basis::BakeDescription& description, const basis::FrameFactors& factors) {
    const size_t rays = static_cast<size_t>(std::max(description.footprint_samples, 0)) *
                        static_cast<size_t>(std::max(factors.pixels, 0));
    if (description.footprint_samples < 1 || description.alpha_thresholds.empty() ||
        factors.depth_b.size() < rays || factors.depth_a.size() < rays * description.alpha_thresholds.size())
        throw Error(ErrorCode::InvalidArgument, "optical depth layers do not match the description");
}

// The alpha of one pixel (the depth layers checked).
float alphaOf(const basis::BakeDescription& description, const basis::FrameFactors& factors, size_t pixel,
              const ExtinctionParams& extinction) {
    const basis::SampleBracket bracket =
        basis::sampleBracket(description.alpha_thresholds, extinction.temperature_threshold);
    const double t = static_cast<float>(bracket.t);
    // A layer with weight 0 is not read (it may hold anything).
    const bool two = bracket.upper != bracket.lower && t != 0.0;
    const size_t pixels = static_cast<size_t>(factors.pixels), thresholds = description.alpha_thresholds.size();
    double sum = 0.0;
    for (int s = 0; s < description.footprint_samples; ++s) {
        const float* layers = factors.depth_a.data() + static_cast<size_t>(s) * thresholds * pixels + pixel;
        const double lower = layers[static_cast<size_t>(bracket.lower) * pixels];
        const double o_a = two ? (1.0 - t) * lower + t * layers[static_cast<size_t>(bracket.upper) * pixels] : lower;
        const double tau = extinction.a() * o_a + extinction.b() * factors.depth_b[s * pixels + pixel];
        sum += std::isnan(tau) ? 1.0 : tau <= 0.0 ? 0.0 : -std::expm1(-tau);
    }
    return static_cast<float>(std::clamp(sum / description.footprint_samples, 0.0, 1.0));
}

}  // namespace

void computeCoefficients(const basis::BakeDescription& description, const basis::FrameFactors& factors,
                         const basis::LookWeights& look, std::span<float> z_out) {
    // The resident form's S V^T is the float layout's; nothing else of it is read.
    basis::ResidentFrame frame;
    frame.rank = factors.rank;
    frame.svt.assign(factors.svt.begin(), factors.svt.end());
    basis::computeCoefficients(description, frame, look, z_out);
}

void reconstructImage(const basis::BakeDescription& description, const basis::FrameFactors& factors,
                      std::span<const float> u_float, std::span<const float> z, const ExtinctionParams& extinction,
                      std::span<float> rgba_out) {
    const size_t pixels = static_cast<size_t>(std::max(factors.pixels, 0));
    const size_t rank = static_cast<size_t>(std::max(factors.rank, 0));
    if (rgba_out.size() < pixels * 4) throw Error(ErrorCode::InvalidArgument, "image output too short");
    if (z.size() < rank * 3) throw Error(ErrorCode::InvalidArgument, "coefficients too short");
    if (u_float.size() < pixels * rank) throw Error(ErrorCode::InvalidArgument, "U too short");
    checkDepthLayers(description, factors);
    for (size_t p = 0; p < pixels; ++p) {
        for (size_t c = 0; c < 3; ++c) {
            float sum = 0.0f;
            for (size_t k = 0; k < rank; ++k) sum += u_float[p * rank + k] * z[k * 3 + c];
            rgba_out[p * 4 + c] = sum > 0.0f && std::isfinite(sum) ? sum : 0.0f;
        }
        rgba_out[p * 4 + 3] = alphaOf(description, factors, p, extinction);
    }
}

float pixelAlpha(const basis::BakeDescription& description, const basis::FrameFactors& factors, int pixel,
                 const ExtinctionParams& extinction) {
    checkDepthLayers(description, factors);
    if (pixel < 0 || pixel >= factors.pixels) throw Error(ErrorCode::InvalidArgument, "pixel out of range");
    return alphaOf(description, factors, static_cast<size_t>(pixel), extinction);
}

}  // namespace firelook::reference
