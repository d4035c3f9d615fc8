// Fitting the emission coefficients c_i of L_e(T) = sum_i c_i phi((T - T_i)/dT)
// to the user's per-bin emissivity (docs/model.md), and measuring how
// well a given RBF width behaves.
#pragma once

#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/error.h"
#include "look/look_model.h"

namespace firelook {

// Code ErrorCode::Look: per-bin emissivity that cannot be fitted is a bad look.
class EmissionFitError : public Error {
  public:
    explicit EmissionFitError(const std::string& message) : Error(ErrorCode::Look, message) {}
};

// Coefficients (one per bin) such that L_e(T_j) ~= e_j at every bin centre and
// L_e(T) >= 0 for every T. Per channel: if the exact interpolant's coefficients
// are all >= 0 they are returned (L_e(T_j) = e_j to rounding); otherwise the
// non-negative least-squares fit of the same collocation system. Since every
// phi_i > 0, c >= 0 makes L_e >= 0 everywhere, whatever the input.
// Throws EmissionFitError if the count differs from the basis' bins, a value is
// not finite, or the bins are degenerate.
std::vector<Rgb> fitEmissionCoefficients(const EmissionBasis& basis, std::span<const Rgb> per_bin_emissivity);

// How a width behaves for a given bin count; all deviations are relative to
// the interpolated value (1 for the constant, the step height for the step).
struct EmissionFitReport {
    int bins = 0;
    double width_in_bins = 0.0;
    // 2-norm condition number of A_ji = phi_i(T_j), the collocation matrix.
    double condition_number = 0.0;
    // Exact interpolation of a constant, max |L_e - 1| sampled between the first
    // and last bin centres, where every point has basis functions on both sides.
    double constant_ripple = 0.0;
    // The same between the two middle bin centres only, away from the ends: the
    // ripple of the Gaussian lattice itself, ~2 exp(-(pi w)^2) by Poisson summation.
    double constant_ripple_middle = 0.0;
    // The same over the two outer half-bins [T_lo, T_0] and [T_{n-1}, T_hi],
    // where the sum of Gaussians rolls off for lack of a neighbour beyond.
    double constant_end_deviation = 0.0;
    // Exact interpolation of a 0 -> 1 step between the middle two bins: how far
    // L_e dips below 0 and rises above 1 anywhere in [T_lo, T_hi].
    double step_undershoot_exact = 0.0;
    double step_overshoot_exact = 0.0;
    // The same step through fitEmissionCoefficients(): the undershoot is 0 by
    // construction; the price is a miss at the bin centres next to the step.
    double step_undershoot_fitted = 0.0;
    double step_overshoot_fitted = 0.0;
    double step_center_error_fitted = 0.0;  // max |L_e(T_j) - e_j|
};

// Measures the figures above on [0, 1] with `bins` bins (the figures do not
// depend on the temperature unit, since the width is in units of dT).
EmissionFitReport analyzeEmissionFit(int bins, double width_in_bins);

}  // namespace firelook
