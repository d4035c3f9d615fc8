// Per-frame SVD of the basis matrix B (pixels x columns) and the quantised
// factors stored in the package (docs/model.md).
//
// Method: the Gram matrix B^T B is accumulated in double precision and
// eigen-decomposed (Eigen's SelfAdjointEigenSolver); V and S come from it and
// U = B V S^-1. Cost is linear in the number of pixels and quadratic in the
// number of columns (a few thousand at most), so it scales with image size; in
// double precision, singular values down to ~1e-7 of the largest are resolved,
// far below any truncation target we use.
#pragma once

#include <vector>

#include "bake/basis_tracer.h"
#include "basis/frame_factors.h"

namespace firelook::bake {

struct CompressionSettings {
    double target_relative_error = 0.003;  // Frobenius norm of the dropped part / norm of B
    int max_rank = 128;
};

struct CompressedFrame {
    basis::FrameFactors factors;
    double truncation_error = 0.0;    // relative Frobenius error of the rank-k truncation
    double quantisation_error = 0.0;  // relative Frobenius error added by storing U in half precision
    std::vector<double> singular_values;  // all of them, descending
};

CompressedFrame compressFrameBasis(const FrameBasis& basis, int frame, const CompressionSettings& settings);

}  // namespace firelook::bake
