// Non-negative least squares: min ||a x - b||_2 subject to x >= 0.
#pragma once

#include <span>
#include <vector>

#include "look/detail/dense_linear_algebra.h"

namespace firelook::detail {

// Lawson & Hanson, "Solving Least Squares Problems" (1974), chapter 23: the
// active-set method. The result is always >= 0, even if the iteration cap
// (3 * cols passes, as in SciPy) stops it before the optimum.
std::vector<double> nonNegativeLeastSquares(const DenseMatrix& a, std::span<const double> b);

}  // namespace firelook::detail
