#include "look/emission_fit.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "look/detail/dense_linear_algebra.h"
#include "look/detail/non_negative_least_squares.h"

namespace firelook {
namespace {

void checkBasis(const EmissionBasis& basis) {
    const TemperatureBins& bins = basis.bins;
    if (bins.count < 1)
        throw EmissionFitError("emission fit: need at least one temperature bin, got " +
                               std::to_string(bins.count));
    if (!std::isfinite(bins.t_lo) || !std::isfinite(bins.t_hi) || !(bins.t_hi > bins.t_lo) ||
        !(bins.width() > 0.0))
        throw EmissionFitError("emission fit: temperature range [" + std::to_string(bins.t_lo) + ", " +
                               std::to_string(bins.t_hi) + "] is empty or not finite");
    if (!std::isfinite(basis.width_in_bins) || !(basis.width_in_bins > 0.0))
        throw EmissionFitError("emission fit: RBF width must be positive and finite, got " +
                               std::to_string(basis.width_in_bins));
}

// A_ji = phi_i(T_j): row j is the bin centre, column i the basis function.
detail::DenseMatrix collocationMatrix(const EmissionBasis& basis) {
    const int n = basis.bins.count;
    detail::DenseMatrix a(n, n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) a(j, i) = basis.evaluate(i, basis.bins.center(j));
    return a;
}

std::vector<double> fitChannel(const detail::DenseMatrix& a, const std::vector<double>& emissivity) {
    std::vector<double> exact = detail::solveLeastSquares(a, emissivity);
    if (std::all_of(exact.begin(), exact.end(), [](double c) { return c >= 0.0; })) return exact;
    return detail::nonNegativeLeastSquares(a, emissivity);
}

double evaluateScalar(const EmissionBasis& basis, const std::vector<double>& coefficients, double t) {
    double sum = 0.0;
    for (int i = 0; i < basis.bins.count; ++i) sum += coefficients[i] * basis.evaluate(i, t);
    return sum;
}

// Fine sampling of [lo, hi]: enough points per bin to catch the extremes of
// Gaussians whose width is about one bin.
constexpr int kSamplesPerBin = 64;

template <typename Visit>
void sampleRange(const EmissionBasis& basis, double lo, double hi, Visit visit) {
    const int samples =
        std::max(1, static_cast<int>(std::ceil((hi - lo) / basis.bins.width() * kSamplesPerBin)));
    for (int s = 0; s <= samples; ++s) visit(lo + (hi - lo) * s / samples);
}

}  // namespace

std::vector<Rgb> fitEmissionCoefficients(const EmissionBasis& basis,
                                         std::span<const Rgb> per_bin_emissivity) {
    checkBasis(basis);
    const int n = basis.bins.count;
    if (static_cast<int>(per_bin_emissivity.size()) != n)
        throw EmissionFitError("emission fit: " + std::to_string(per_bin_emissivity.size()) +
                               " emissivity values for " + std::to_string(n) + " temperature bins");
    for (int i = 0; i < n; ++i)
        for (int channel = 0; channel < 3; ++channel)
            if (!std::isfinite(per_bin_emissivity[i][channel]))
                throw EmissionFitError("emission fit: emissivity of bin " + std::to_string(i) +
                                       " is not finite");

    const detail::DenseMatrix a = collocationMatrix(basis);
    std::vector<Rgb> coefficients(n, Rgb(0.0f));
    for (int channel = 0; channel < 3; ++channel) {
        std::vector<double> emissivity(n);
        for (int i = 0; i < n; ++i) emissivity[i] = per_bin_emissivity[i][channel];
        const std::vector<double> c = fitChannel(a, emissivity);
        // Rounding to float can only move a coefficient towards zero, never below it.
        for (int i = 0; i < n; ++i) coefficients[i][channel] = static_cast<float>(c[i]);
    }
    return coefficients;
}

EmissionFitReport analyzeEmissionFit(int bin_count, double width_in_bins) {
    EmissionBasis basis;
    basis.bins = TemperatureBins{0.0, 1.0, bin_count};
    basis.width_in_bins = width_in_bins;
    checkBasis(basis);
    const TemperatureBins& bins = basis.bins;
    const int n = bins.count;

    EmissionFitReport report;
    report.bins = n;
    report.width_in_bins = width_in_bins;

    const detail::DenseMatrix a = collocationMatrix(basis);
    const std::vector<double> eigenvalues = detail::symmetricEigenvalues(a);
    double largest = 0.0;
    double smallest = INFINITY;
    for (double lambda : eigenvalues) {
        largest = std::max(largest, std::abs(lambda));
        smallest = std::min(smallest, std::abs(lambda));
    }
    report.condition_number = smallest > 0.0 ? largest / smallest : INFINITY;

    const std::vector<double> constant_coefficients =
        detail::solveLeastSquares(a, std::vector<double>(n, 1.0));
    auto constant_deviation = [&](double lo, double hi) {
        double deviation = 0.0;
        sampleRange(basis, lo, hi, [&](double t) {
            deviation = std::max(deviation, std::abs(evaluateScalar(basis, constant_coefficients, t) - 1.0));
        });
        return deviation;
    };
    report.constant_ripple = constant_deviation(bins.center(0), bins.center(n - 1));
    report.constant_ripple_middle =
        n < 2 ? 0.0 : constant_deviation(bins.center(n / 2 - 1), bins.center(n / 2));
    report.constant_end_deviation = std::max(constant_deviation(bins.t_lo, bins.center(0)),
                                             constant_deviation(bins.center(n - 1), bins.t_hi));

    if (n < 2) return report;  // a step needs two bins
    std::vector<double> step(n, 0.0);
    std::fill(step.begin() + n / 2, step.end(), 1.0);

    auto measure_step = [&](const std::vector<double>& coefficients, double& undershoot, double& overshoot) {
        double low = 0.0;
        double high = 1.0;
        sampleRange(basis, bins.t_lo, bins.t_hi, [&](double t) {
            const double value = evaluateScalar(basis, coefficients, t);
            low = std::min(low, value);
            high = std::max(high, value);
        });
        undershoot = std::max(0.0, -low);
        overshoot = high - 1.0;
    };
    measure_step(detail::solveLeastSquares(a, step), report.step_undershoot_exact,
                 report.step_overshoot_exact);

    std::vector<Rgb> step_rgb(n);
    for (int i = 0; i < n; ++i) step_rgb[i] = Rgb(static_cast<float>(step[i]));
    const std::vector<Rgb> fitted_rgb = fitEmissionCoefficients(basis, step_rgb);
    std::vector<double> fitted(n);
    for (int i = 0; i < n; ++i) fitted[i] = fitted_rgb[i].r;
    measure_step(fitted, report.step_undershoot_fitted, report.step_overshoot_fitted);
    for (int j = 0; j < n; ++j)
        report.step_center_error_fitted =
            std::max(report.step_center_error_fitted,
                     std::abs(evaluateScalar(basis, fitted, bins.center(j)) - step[j]));
    return report;
}

}  // namespace firelook
