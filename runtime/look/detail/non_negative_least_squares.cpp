#include "look/detail/non_negative_least_squares.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace firelook::detail {
namespace {

// w = a^T (b - a x): the negative gradient of the objective / 2.
std::vector<double> negativeGradient(const DenseMatrix& a, std::span<const double> b,
                                     const std::vector<double>& x) {
    std::vector<double> residual(b.begin(), b.end());
    for (int r = 0; r < a.rows; ++r)
        for (int c = 0; c < a.cols; ++c) residual[r] -= a(r, c) * x[c];
    std::vector<double> w(a.cols, 0.0);
    for (int r = 0; r < a.rows; ++r)
        for (int c = 0; c < a.cols; ++c) w[c] += a(r, c) * residual[r];
    return w;
}

// Least squares restricted to the passive columns; zero elsewhere.
std::vector<double> solveOnPassiveSet(const DenseMatrix& a, std::span<const double> b,
                                      const std::vector<bool>& passive) {
    std::vector<int> columns;
    for (int c = 0; c < a.cols; ++c)
        if (passive[c]) columns.push_back(c);
    DenseMatrix sub(a.rows, static_cast<int>(columns.size()));
    for (int r = 0; r < a.rows; ++r)
        for (size_t k = 0; k < columns.size(); ++k) sub(r, static_cast<int>(k)) = a(r, columns[k]);
    const std::vector<double> sub_x = solveLeastSquares(std::move(sub), b);
    std::vector<double> z(a.cols, 0.0);
    for (size_t k = 0; k < columns.size(); ++k) z[columns[k]] = sub_x[k];
    return z;
}

}  // namespace

std::vector<double> nonNegativeLeastSquares(const DenseMatrix& a, std::span<const double> b) {
    const int n = a.cols;
    std::vector<double> x(n, 0.0);
    std::vector<bool> passive(n, false);

    // The gradient scales with |a| |b|; below this it is rounding noise.
    double a_norm1 = 0.0;
    for (int c = 0; c < n; ++c) {
        double column_sum = 0.0;
        for (int r = 0; r < a.rows; ++r) column_sum += std::abs(a(r, c));
        a_norm1 = std::max(a_norm1, column_sum);
    }
    double b_norm_inf = 0.0;
    for (double value : b) b_norm_inf = std::max(b_norm_inf, std::abs(value));
    const double tolerance =
        10.0 * std::max(a.rows, n) * std::numeric_limits<double>::epsilon() * a_norm1 * b_norm_inf;

    const int max_passes = 3 * n;
    int passes = 0;
    std::vector<double> w = negativeGradient(a, b, x);
    while (passes < max_passes) {
        int entering = -1;
        for (int c = 0; c < n; ++c)
            if (!passive[c] && w[c] > tolerance && (entering < 0 || w[c] > w[entering])) entering = c;
        if (entering < 0) break;
        passive[entering] = true;

        while (passes++ < max_passes) {
            const std::vector<double> z = solveOnPassiveSet(a, b, passive);
            bool feasible = true;
            for (int c = 0; c < n; ++c) feasible = feasible && (!passive[c] || z[c] > 0.0);
            if (feasible) {
                x = z;
                break;
            }
            // Step from x towards z until the first passive variable reaches zero;
            // that one (the blocking variable) leaves the passive set.
            double step = 1.0;
            int blocking = -1;
            for (int c = 0; c < n; ++c) {
                if (!passive[c] || z[c] > 0.0) continue;
                const double ratio = x[c] > 0.0 ? x[c] / (x[c] - z[c]) : 0.0;
                if (blocking < 0 || ratio < step) {
                    step = ratio;
                    blocking = c;
                }
            }
            for (int c = 0; c < n; ++c) {
                if (!passive[c]) continue;
                x[c] += step * (z[c] - x[c]);
                if (c == blocking || x[c] <= 0.0) {
                    x[c] = 0.0;
                    passive[c] = false;
                }
            }
        }
        w = negativeGradient(a, b, x);
    }
    for (double& value : x) value = std::max(value, 0.0);  // guard against rounding after the cap
    return x;
}

}  // namespace firelook::detail
