// The look model (look/look_model.h) prepared for evaluation at every collision of a random walk.
#pragma once

#include <cmath>
#include <glm/vec3.hpp>
#include <vector>

#include "look/look_model.h"

namespace firelook::render {

// Evaluates sigma_t and j of docs/model.md for interpolated (rho, T). The formulas are those
// of look_model.h; only the order of work differs (emission uses a recurrence so that all n basis
// functions cost two exponentials instead of n).
class LookEvaluator {
  public:
    // Throws RenderError if the look cannot be evaluated: no bins or an empty temperature range (in
    // look.bins or look.emission.basis.bins), negative or non-finite extinction, an albedo outside
    // [0, 1], or emission coefficients that are not finite and non-negative.
    explicit LookEvaluator(const LookModel& look);

    // sigma_t = kappa(T) * rho, 1 / world unit.
    double extinction(double density, double temperature) const {
        // tanh(x) = 1 - 2 / (exp(2x) + 1): one exp is cheaper than glibc's tanh (via expm1), and the
        // cancellation near 0 costs only ~1e-16 absolutely; saturates to +-1 without overflow.
        const double x = (bins_.clamp(temperature) - threshold_) * half_inverse_bin_width_;
        const double f = 1.0 - 2.0 / (std::exp(2.0 * x) + 1.0);
        return (a_ * f + b_) * density;
    }
    // L_e(T) = sum_i c_i phi((T - T_i) / dT); j = rho * L_e(T).
    glm::dvec3 emissionPerDensity(double temperature) const;
    bool hasEmission() const { return has_emission_; }
    double albedo() const { return albedo_; }

  private:
    TemperatureBins bins_;           // for kappa
    TemperatureBins emission_bins_;  // the emission basis's own bins (normally the same)
    EmissionBasis emission_basis_;   // its clamping rule
    double threshold_, half_inverse_bin_width_, a_, b_, albedo_;
    double inverse_width_squared_;  // 1 / w^2, w in bins
    double step_ratio_;             // exp(-2 / w^2): how neighbouring ratios of the Gaussians change
    std::vector<glm::dvec3> coefficients_;
    bool has_emission_ = false;
};

}  // namespace firelook::render
