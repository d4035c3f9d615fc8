// Small dense linear algebra for the emission fit (n <= a few dozen bins).
//
// Hand-written rather than Eigen so that the runtime, which a game engine links,
// pulls in no linear-algebra library for a handful of 16x16 solves at load time.
#pragma once

#include <span>
#include <vector>

namespace firelook::detail {

// Row-major rows x cols matrix of doubles.
struct DenseMatrix {
    int rows = 0;
    int cols = 0;
    std::vector<double> values;

    DenseMatrix(int row_count, int col_count)
        : rows(row_count), cols(col_count), values(static_cast<size_t>(row_count) * col_count, 0.0) {}

    double& operator()(int r, int c) { return values[static_cast<size_t>(r) * cols + c]; }
    double operator()(int r, int c) const { return values[static_cast<size_t>(r) * cols + c]; }
};

// Minimises ||a x - b||_2 for rows >= cols by Householder QR. Columns that are
// numerically dependent on earlier ones get x = 0 (a basic solution).
std::vector<double> solveLeastSquares(DenseMatrix a, std::span<const double> b);

// All eigenvalues of a symmetric matrix (cyclic Jacobi rotations), unsorted.
std::vector<double> symmetricEigenvalues(DenseMatrix a);

}  // namespace firelook::detail
