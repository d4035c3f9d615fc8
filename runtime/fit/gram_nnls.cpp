#include "fit/gram_nnls.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/error.h"
#include "look/detail/non_negative_least_squares.h"

namespace firelook::fit {

std::vector<double> solveGramNnls(std::span<const double> gram, std::span<const double> b, int n) {
    if (n < 0 || gram.size() < static_cast<size_t>(n) * n || b.size() < static_cast<size_t>(n))
        throw Error(ErrorCode::InvalidArgument, "solveGramNnls: spans shorter than n");
    std::vector<double> x(n, 0.0);
    double max_diagonal = 0.0;
    for (int i = 0; i < n; ++i) max_diagonal = std::max(max_diagonal, gram[i * n + i]);
    if (!(max_diagonal > 0.0) || !std::isfinite(max_diagonal)) return x;

    std::vector<int> kept;
    for (int i = 0; i < n; ++i)
        if (gram[i * n + i] > 1e-13 * max_diagonal) kept.push_back(i);
    const int m = static_cast<int>(kept.size());
    const double ridge = 1e-12 * max_diagonal;

    // Cholesky G_kk = R^T R, R upper triangular (row-major in a DenseMatrix for the NNLS).
    detail::DenseMatrix r(m, m);
    for (int i = 0; i < m; ++i) {
        for (int j = i; j < m; ++j) {
            double sum = gram[kept[i] * n + kept[j]] + (i == j ? ridge : 0.0);
            for (int k = 0; k < i; ++k) sum -= r(k, i) * r(k, j);
            if (i == j) {
                // Semi-definite to rounding: the ridge's square root is the smallest pivot.
                r(i, i) = std::sqrt(std::max(sum, ridge));
            } else {
                r(i, j) = sum / r(i, i);
            }
        }
    }
    // R^T d = b (forward substitution).
    std::vector<double> d(m, 0.0);
    for (int i = 0; i < m; ++i) {
        double sum = b[kept[i]];
        for (int k = 0; k < i; ++k) sum -= r(k, i) * d[k];
        d[i] = sum / r(i, i);
    }
    const std::vector<double> solution = detail::nonNegativeLeastSquares(r, d);
    for (int i = 0; i < m; ++i) x[kept[i]] = std::isfinite(solution[i]) ? std::max(solution[i], 0.0) : 0.0;
    return x;
}

}  // namespace firelook::fit
