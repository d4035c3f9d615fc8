#include "render/look_evaluator.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "render/render_error.h"

namespace firelook::render {

namespace {

void checkBins(const TemperatureBins& bins, const char* what) {
    if (bins.count < 1) throw RenderError(std::string("look: ") + what + " need at least one bin");
    if (!(std::isfinite(bins.t_lo) && std::isfinite(bins.t_hi) && bins.t_hi > bins.t_lo))
        throw RenderError(std::string("look: ") + what + " have an empty or non-finite range [" +
                          std::to_string(bins.t_lo) + ", " + std::to_string(bins.t_hi) + "]");
}

}  // namespace

LookEvaluator::LookEvaluator(const LookModel& look)
    : bins_(look.bins), emission_bins_(look.emission.basis.bins), emission_basis_(look.emission.basis) {
    checkBins(bins_, "the temperature bins");
    checkBins(emission_bins_, "the emission basis's bins");
    const ExtinctionParams& e = look.extinction;
    if (!(std::isfinite(e.smoke_extinction) && std::isfinite(e.flame_extinction) &&
          e.smoke_extinction >= 0.0 && e.flame_extinction >= 0.0 && std::isfinite(e.temperature_threshold)))
        throw RenderError("look: extinctions must be finite and non-negative and the threshold finite");
    if (!(look.albedo >= 0.0 && look.albedo <= 1.0))
        throw RenderError("look: albedo " + std::to_string(look.albedo) + " is outside [0, 1]");
    const double w = look.emission.basis.width_in_bins;
    if (!(std::isfinite(w) && w > 0.0)) throw RenderError("look: the RBF width must be positive");
    if (!look.emission.coefficients.empty() &&
        static_cast<int>(look.emission.coefficients.size()) != emission_bins_.count)
        throw RenderError("look: " + std::to_string(look.emission.coefficients.size()) +
                          " emission coefficients for " + std::to_string(emission_bins_.count) + " bins");

    threshold_ = e.temperature_threshold;
    half_inverse_bin_width_ = 0.5 / bins_.width();
    a_ = e.a();
    b_ = e.b();
    albedo_ = look.albedo;
    inverse_width_squared_ = 1.0 / (w * w);
    step_ratio_ = std::exp(-2.0 * inverse_width_squared_);
    for (const Rgb& c : look.emission.coefficients) {
        for (int ch = 0; ch < 3; ++ch)
            if (!(std::isfinite(c[ch]) && c[ch] >= 0.0f))
                throw RenderError("look: emission coefficients must be finite and non-negative");
        coefficients_.emplace_back(c);
        has_emission_ = has_emission_ || c.r > 0.0f || c.g > 0.0f || c.b > 0.0f;
    }
}

glm::dvec3 LookEvaluator::emissionPerDensity(double temperature) const {
    if (!has_emission_) return glm::dvec3(0.0);
    // x: the temperature in bin units, bin centre i at x = i. phi_i = exp(-(x - i)^2 / w^2).
    // Neighbours differ by g_{i+1} / g_i = exp((2 (x - i) - 1) / w^2), a ratio that itself shrinks
    // by exp(-2 / w^2) per step; walking away from the nearest centre the terms only decrease.
    // The basis's clamping rule (EmissionBasis::emissionTemperature), so this equals look_model.h.
    const double x =
        (emission_basis_.emissionTemperature(temperature) - emission_bins_.t_lo) / emission_bins_.width() - 0.5;
    const int n = static_cast<int>(coefficients_.size());
    const int nearest = std::clamp(static_cast<int>(std::lround(x)), 0, n - 1);
    const double d = x - nearest;
    const double g_nearest = std::exp(-d * d * inverse_width_squared_);
    glm::dvec3 sum = coefficients_[nearest] * g_nearest;

    double g = g_nearest;
    double ratio = std::exp((2.0 * d - 1.0) * inverse_width_squared_);
    for (int i = nearest + 1; i < n && g > 0.0; ++i) {
        g *= ratio;
        ratio *= step_ratio_;
        sum += coefficients_[i] * g;
    }
    g = g_nearest;
    ratio = std::exp(-(2.0 * d + 1.0) * inverse_width_squared_);
    for (int i = nearest - 1; i >= 0 && g > 0.0; --i) {
        g *= ratio;
        ratio *= step_ratio_;
        sum += coefficients_[i] * g;
    }
    return sum;
}

}  // namespace firelook::render
