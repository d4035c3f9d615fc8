#include "look/detail/dense_linear_algebra.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace firelook::detail {

std::vector<double> solveLeastSquares(DenseMatrix a, std::span<const double> b_in) {
    const int m = a.rows;
    const int n = a.cols;
    std::vector<double> b(b_in.begin(), b_in.end());
    std::vector<double> v(m);

    for (int j = 0; j < n && j < m; ++j) {
        double norm2 = 0.0;
        for (int i = j; i < m; ++i) norm2 += a(i, j) * a(i, j);
        if (norm2 == 0.0) continue;
        // Reflect onto -sign(a_jj) * |column| so the subtraction below never cancels.
        const double alpha = a(j, j) > 0.0 ? -std::sqrt(norm2) : std::sqrt(norm2);
        for (int i = j; i < m; ++i) v[i] = a(i, j);
        v[j] -= alpha;
        double v_norm2 = 0.0;
        for (int i = j; i < m; ++i) v_norm2 += v[i] * v[i];
        if (v_norm2 == 0.0) continue;

        for (int c = j; c < n; ++c) {
            double dot = 0.0;
            for (int i = j; i < m; ++i) dot += v[i] * a(i, c);
            const double s = 2.0 * dot / v_norm2;
            for (int i = j; i < m; ++i) a(i, c) -= s * v[i];
        }
        double dot = 0.0;
        for (int i = j; i < m; ++i) dot += v[i] * b[i];
        const double s = 2.0 * dot / v_norm2;
        for (int i = j; i < m; ++i) b[i] -= s * v[i];
    }

    double largest_pivot = 0.0;
    for (int j = 0; j < std::min(m, n); ++j) largest_pivot = std::max(largest_pivot, std::abs(a(j, j)));
    const double pivot_floor = largest_pivot * std::max(m, n) * std::numeric_limits<double>::epsilon();

    std::vector<double> x(n, 0.0);
    for (int j = std::min(m, n) - 1; j >= 0; --j) {
        if (std::abs(a(j, j)) <= pivot_floor) continue;
        double sum = b[j];
        for (int c = j + 1; c < n; ++c) sum -= a(j, c) * x[c];
        x[j] = sum / a(j, j);
    }
    return x;
}

std::vector<double> symmetricEigenvalues(DenseMatrix a) {
    const int n = a.rows;
    double total = 0.0;
    for (double value : a.values) total += value * value;
    const double off_diagonal_goal = total * 1e-30;  // (1e-15 relative) squared

    for (int sweep = 0; sweep < 100; ++sweep) {
        double off = 0.0;
        for (int p = 0; p < n; ++p)
            for (int q = p + 1; q < n; ++q) off += 2.0 * a(p, q) * a(p, q);
        if (off <= off_diagonal_goal) break;

        for (int p = 0; p < n; ++p) {
            for (int q = p + 1; q < n; ++q) {
                if (a(p, q) == 0.0) continue;
                // Rotation that zeroes a(p,q) (Golub & Van Loan, Algorithm 8.5.1).
                const double tau = (a(q, q) - a(p, p)) / (2.0 * a(p, q));
                const double t = (tau >= 0.0 ? 1.0 : -1.0) / (std::abs(tau) + std::sqrt(1.0 + tau * tau));
                const double c = 1.0 / std::sqrt(1.0 + t * t);
                const double s = t * c;
                for (int k = 0; k < n; ++k) {
                    const double akp = a(k, p);
                    const double akq = a(k, q);
                    a(k, p) = c * akp - s * akq;
                    a(k, q) = s * akp + c * akq;
                }
                for (int k = 0; k < n; ++k) {
                    const double apk = a(p, k);
                    const double aqk = a(q, k);
                    a(p, k) = c * apk - s * aqk;
                    a(q, k) = s * apk + c * aqk;
                }
            }
        }
    }
    std::vector<double> eigenvalues(n);
    for (int i = 0; i < n; ++i) eigenvalues[i] = a(i, i);
    return eigenvalues;
}

}  // namespace firelook::detail
