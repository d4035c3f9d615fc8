// Per-frame SVD of the basis matrix B (pixels x columns) and the quantised
// factors stored in the package (docs/model.md).
//
// Method: V and S are eigenpairs of the Gram matrix B^T B and U = B V S^-1. A
// frame keeps at most max_rank (128) of its columns' 1000-6000 singular vectors,
// so where the columns are many only the leading eigenpairs are computed, by
// block subspace iteration on B itself (basis_compression.cpp): each iteration
// costs rows x columns x 2 pairs, where forming the Gram matrix cost rows x
// columns^2 and a dense solver columns^3 (a 5664-column frame with sphere
// lights: minutes). The Ritz values it gives are at most the eigenvalues, and
// the dropped energy is B's squared norm (in double) less them: exactly the
// error of the truncation stored with those vectors, so the truncation error
// stays exact; where the iteration has not settled, the rank can only be larger.
// With few columns, or every pair asked for, the Gram matrix is accumulated in
// double and eigen-decomposed whole.
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
    double truncation_error = 0.0;    // relative Frobenius error of the rank-k truncation (of B D)
    double quantisation_error = 0.0;  // relative Frobenius error added by storing U in half precision
    // Descending: the leading ones the spectrum holds, then (where it holds fewer than the columns)
    // one value whose square is the energy of all the others, so the total is still their sum.
    std::vector<double> singular_values;
    std::vector<double> column_quantisation;  // per kept column, its share of quantisation_error^2
};

// Which columns belong to which light source (column = point * columns_per_point + c; c < bins
// is emission bin c, then one per light). With columns_per_point 0 every column weighs the same.
struct BasisSources {
    int columns_per_point = 0;
    int bins = 0;
};

// The eigen-decomposition of (B D)^T (B D), made once per frame so that several truncations of one
// traced basis can be tried (storage_target.h) without decomposing again. D scales each source's
// columns to the same energy (basis/source_balance.h), so the truncation error bounds every
// source's share, not only the brightest source's.
struct FrameSpectrum {
    int columns = 0;
    std::vector<double> balance;       // D, one factor per column (1 without sources)
    std::vector<double> eigenvectors;  // columns x eigenvalues.size(), column-major, in the eigenvalues' order
    // The leading eigenvalues (all of them where SpectrumNeeds asks for all), ascending: the
    // largest is the last. Clamped at 0 (rounding can dip below).
    std::vector<double> eigenvalues;
    double total = 0.0;                // ||B D||_F^2, the trace of the Gram matrix
};
// Which eigenpairs a spectrum must hold: those of every truncation to at most max_rank columns
// whose relative error is at least finest_error. max_rank 0: all of them.
struct SpectrumNeeds {
    double finest_error = 0.0;
    int max_rank = 0;
};
FrameSpectrum frameSpectrum(const FrameBasis& basis, const BasisSources& sources = {}, const SpectrumNeeds& needs = {});

// The smallest rank (at most max_rank) whose dropped energy is within the target relative error.
int truncationRank(const FrameSpectrum& spectrum, const CompressionSettings& settings);

// The factors of the rank-`rank` truncation.
CompressedFrame compressFrameBasis(const FrameBasis& basis, int frame, const FrameSpectrum& spectrum, int rank);

// The leading `rank` columns of `frame` (rank <= frame's): the rank-`rank` truncation, without
// computing U again.
CompressedFrame leadingColumns(const CompressedFrame& frame, int rank);

// The same with the rank from `settings` (truncationRank).
CompressedFrame compressFrameBasis(const FrameBasis& basis, int frame, const CompressionSettings& settings,
                                   const BasisSources& sources = {});

}  // namespace firelook::bake
