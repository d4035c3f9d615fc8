// Non-negative least squares given only the normal equations: min x^T G x - 2 b^T x subject to
// x >= 0, for a small symmetric positive semi-definite G (the Gram matrix of a few basis images).
#pragma once

#include <span>
#include <vector>

namespace firelook::fit {

// G: n x n, row-major, symmetric; b: n. Factors G = R^T R (Cholesky; a column whose diagonal is
// below 1e-13 of the largest carries no signal and gets x = 0; a ridge of 1e-12 of the largest
// diagonal keeps the factor defined when G is only semi-definite), then solves
// min ||R x - d||, R^T d = b, with x >= 0 by the look library's Lawson-Hanson active-set method
// (look/detail/non_negative_least_squares.h), whose objective differs from the one above by a
// constant. Every entry of the result is finite and >= 0.
std::vector<double> solveGramNnls(std::span<const double> gram, std::span<const double> b, int n);

}  // namespace firelook::fit
