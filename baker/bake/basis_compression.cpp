#include "bake/basis_compression.h"

#include <Spectra/MatOp/DenseSymMatProd.h>
#include <Spectra/SymEigsSolver.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <glm/gtc/packing.hpp>
#include <stdexcept>
#include <vector>

#include "basis/source_balance.h"
#include "common/error.h"

namespace firelook::bake {
namespace {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::Map<const RowMatrix> basisMatrix(const FrameBasis& basis) {
    return {basis.matrix.data(), static_cast<Eigen::Index>(basis.width) * basis.height, basis.columns};
}

// Below this many columns, or where the pairs asked for are a third of the columns, the dense
// solver is as cheap as the Lanczos one (1632 columns, the bundled sample's: 2.6 s dense).
constexpr int kDenseColumns = 400;
// The Lanczos solver first asks for this many pairs, then doubles them while the dropped energy is
// above what SpectrumNeeds asks for: a real frame's rank is 15-45 (the sample at 256x256).
constexpr int kFirstLeading = 32;

void denseSpectrum(const Eigen::MatrixXd& gram, FrameSpectrum& spectrum) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
    const Eigen::VectorXd lambda = eigen.eigenvalues().cwiseMax(0.0);
    spectrum.eigenvalues.assign(lambda.data(), lambda.data() + lambda.size());
    spectrum.eigenvectors.assign(eigen.eigenvectors().data(), eigen.eigenvectors().data() + eigen.eigenvectors().size());
    spectrum.total = lambda.sum();
}

// The `count` largest eigenpairs (Spectra's implicitly restarted Lanczos on the lower triangle);
// false where it did not converge.
bool leadingSpectrum(const Eigen::MatrixXd& gram, int count, FrameSpectrum& spectrum) {
    const auto n = static_cast<int>(gram.rows());
    Spectra::DenseSymMatProd<double> product(gram);
    Spectra::SymEigsSolver<Spectra::DenseSymMatProd<double>> solver(product, count, std::min(n, 2 * count + 1));
    solver.init();  // a fixed start vector: the same pairs for the same matrix
    solver.compute(Spectra::SortRule::LargestAlge, 1000, 1e-10);
    if (solver.info() != Spectra::CompInfo::Successful) return false;
    const Eigen::VectorXd lambda = solver.eigenvalues();  // descending
    const Eigen::MatrixXd vectors = solver.eigenvectors();
    spectrum.eigenvalues.resize(count);
    spectrum.eigenvectors.resize(static_cast<std::size_t>(n) * count);
    for (int m = 0; m < count; ++m) {  // ascending, as the dense solver gives them
        spectrum.eigenvalues[count - 1 - m] = std::max(lambda[m], 0.0);
        std::copy_n(vectors.col(m).data(), n, spectrum.eigenvectors.begin() + static_cast<std::size_t>(count - 1 - m) * n);
    }
    return true;
}

// The lower triangle of the Gram matrix B^T B over B's non-empty rows (most pixels of a fire image
// see nothing), in double. The rows are cut into kGramChunks runs with equal shares of the
// non-empty ones, each summed on a thread of its own, and the runs' matrices added in order: the
// same bits with any number of threads. The compression runs between two frames' traces, so one
// core used to wait here, and the Gram is most of the SVD's seconds (frame 12 of the bundled sample
// at 256x256: 23860 non-empty rows of 1632 columns). Memory: kGramChunks Gram matrices while they
// are summed, within the three the bake's plan counts (bake_pipeline.cpp).
constexpr int kGramChunks = 2;

Eigen::MatrixXd gramOfNonEmptyRows(const Eigen::Map<const RowMatrix>& b) {
    const Eigen::Index columns = b.cols();
    // Which rows hold anything, found once (a pass over the whole matrix) for the split and the sums.
    std::vector<std::uint8_t> non_empty(static_cast<std::size_t>(b.rows()));
    Eigen::Index count = 0;
    for (Eigen::Index p = 0; p < b.rows(); ++p) {
        non_empty[static_cast<std::size_t>(p)] = b.row(p).cwiseAbs().maxCoeff() != 0.0f;
        count += non_empty[static_cast<std::size_t>(p)];
    }
    // start[c]: the first row of run c, the first where the non-empty rows before it reach
    // count * c / kGramChunks (p runs to b.rows() inclusive, where they reach count).
    std::array<Eigen::Index, kGramChunks + 1> start{};
    start[kGramChunks] = b.rows();
    std::size_t c = 1;
    for (Eigen::Index p = 0, seen = 0; p <= b.rows() && c < kGramChunks; ++p) {
        while (c < kGramChunks && seen >= count * static_cast<Eigen::Index>(c) / kGramChunks) start[c++] = p;
        if (p < b.rows()) seen += non_empty[static_cast<std::size_t>(p)];
    }
    std::array<Eigen::MatrixXd, kGramChunks> part;
    tbb::parallel_for(0, kGramChunks, [&](int chunk) {
        Eigen::MatrixXd& gram = part[static_cast<std::size_t>(chunk)];
        gram = Eigen::MatrixXd::Zero(columns, columns);
        constexpr int kBlockRows = 256;
        Eigen::MatrixXd block(kBlockRows, columns);
        int filled = 0;
        const auto flush = [&] {
            if (filled == 0) return;
            gram.selfadjointView<Eigen::Lower>().rankUpdate(block.topRows(filled).transpose());
            filled = 0;
        };
        for (Eigen::Index p = start[static_cast<std::size_t>(chunk)];
             p < start[static_cast<std::size_t>(chunk) + 1]; ++p) {
            if (!non_empty[static_cast<std::size_t>(p)]) continue;
            block.row(filled++) = b.row(p).cast<double>();
            if (filled == kBlockRows) flush();
        }
        flush();
    });
    for (int chunk = 1; chunk < kGramChunks; ++chunk) part[0] += part[static_cast<std::size_t>(chunk)];
    return std::move(part[0]);
}

}  // namespace

FrameSpectrum frameSpectrum(const FrameBasis& basis, const BasisSources& sources, const SpectrumNeeds& needs) {
    const int columns = basis.columns;
    const Eigen::Map<const RowMatrix> b = basisMatrix(basis);

    Eigen::MatrixXd gram = gramOfNonEmptyRows(b);

    FrameSpectrum spectrum;
    spectrum.columns = columns;
    spectrum.balance.assign(columns, 1.0);
    if (sources.columns_per_point > 0 && columns % sources.columns_per_point == 0) {
        // The Gram matrix of B D, D the per-source factors (basis/source_balance.h): D G D.
        std::vector<double> energy(sources.columns_per_point, 0.0);
        for (int j = 0; j < columns; ++j) energy[j % sources.columns_per_point] += gram(j, j);
        const std::vector<double> factor = basis::sourceBalance(energy, sources.bins);
        for (int j = 0; j < columns; ++j) spectrum.balance[j] = factor[j % sources.columns_per_point];
        const Eigen::Map<const Eigen::VectorXd> d(spectrum.balance.data(), columns);
        const Eigen::MatrixXd full = gram.selfadjointView<Eigen::Lower>();
        gram = d.asDiagonal() * full * d.asDiagonal();
    }
    spectrum.total = std::max(gram.trace(), 0.0);
    const bool all = needs.max_rank <= 0;
    const int cap = all ? columns : std::min(needs.max_rank, columns);
    for (int count = std::min(kFirstLeading, cap);; count = std::min(2 * count, cap)) {
        if (all || columns <= kDenseColumns || 3 * count >= columns || !leadingSpectrum(gram, count, spectrum)) {
            denseSpectrum(gram, spectrum);
            break;
        }
        double dropped = spectrum.total;
        for (double lambda : spectrum.eigenvalues) dropped -= lambda;
        if (count == cap || dropped <= needs.finest_error * needs.finest_error * spectrum.total) break;
    }
    return spectrum;
}

int truncationRank(const FrameSpectrum& spectrum, const CompressionSettings& settings) {
    const auto columns = static_cast<int>(spectrum.eigenvalues.size());
    if (!(spectrum.total > 0.0)) return 0;  // an empty frame: rank 0, the image is black and transparent
    int rank = 0;
    double dropped = spectrum.total;
    while (rank < std::min(settings.max_rank, columns) &&
           std::sqrt(std::max(dropped, 0.0) / spectrum.total) > settings.target_relative_error) {
        dropped -= spectrum.eigenvalues[columns - 1 - rank];
        ++rank;
    }
    return rank;
}

CompressedFrame compressFrameBasis(const FrameBasis& basis, int frame, const FrameSpectrum& spectrum, int rank) {
    const int pixels = basis.width * basis.height;
    const int columns = basis.columns;
    const Eigen::Map<const RowMatrix> b = basisMatrix(basis);
    const std::vector<double>& lambda = spectrum.eigenvalues;
    const auto held = static_cast<int>(lambda.size());
    if (rank > held) throw Error(ErrorCode::InvalidArgument, "compressFrameBasis: rank beyond the spectrum's pairs");
    const Eigen::Map<const Eigen::MatrixXd> vectors(spectrum.eigenvectors.data(), columns, held);

    CompressedFrame out;
    out.factors.frame = frame;
    out.factors.pixels = pixels;
    out.factors.columns = columns;
    out.factors.depth_b = basis.depth_b;
    out.factors.depth_a = basis.depth_a;
    double rest = spectrum.total;
    for (int j = held - 1; j >= 0; --j) {
        out.singular_values.push_back(std::sqrt(lambda[j]));
        rest -= lambda[j];
    }
    if (held < columns) out.singular_values.push_back(std::sqrt(std::max(rest, 0.0)));
    if (!(spectrum.total > 0.0)) return out;

    double dropped = spectrum.total;
    for (int m = 0; m < rank; ++m) dropped -= lambda[held - 1 - m];
    out.truncation_error = std::sqrt(std::max(dropped, 0.0) / spectrum.total);
    out.factors.rank = rank;

    Eigen::MatrixXf v(columns, rank);
    Eigen::VectorXf sigma(rank);
    for (int m = 0; m < rank; ++m) {
        v.col(m) = vectors.col(held - 1 - m).cast<float>();
        sigma[m] = static_cast<float>(std::sqrt(lambda[held - 1 - m]));
    }
    // The SVD is of B D (D = spectrum.balance): U = B D V S^-1, pixel-major like B, and the stored
    // S V^T D^-1, so that U S V^T D^-1 is B's truncation.
    Eigen::VectorXf d(columns);
    for (int j = 0; j < columns; ++j) d[j] = static_cast<float>(spectrum.balance.empty() ? 1.0 : spectrum.balance[j]);
    RowMatrix u = b * (d.asDiagonal() * v);
    for (int m = 0; m < rank; ++m) u.col(m) /= sigma[m];

    out.factors.svt.resize(static_cast<size_t>(columns) * rank);
    for (int j = 0; j < columns; ++j)
        for (int m = 0; m < rank; ++m)
            out.factors.svt[static_cast<size_t>(j) * rank + m] = static_cast<float>(double(sigma[m]) * v(j, m) / d[j]);

    // Half precision U; its error in B D is ||(U_half - U) S||_F because V is orthonormal.
    out.factors.u_half.resize(static_cast<size_t>(pixels) * rank);
    double quantisation = 0.0;
    out.column_quantisation.assign(rank, 0.0);
    for (int p = 0; p < pixels; ++p)
        for (int m = 0; m < rank; ++m) {
            const float value = u(p, m);
            const uint16_t half = glm::packHalf1x16(value);
            out.factors.u_half[static_cast<size_t>(p) * rank + m] = half;
            const double err = (double(glm::unpackHalf1x16(half)) - value) * sigma[m];
            quantisation += err * err;
            out.column_quantisation[m] += err * err / spectrum.total;
        }
    out.quantisation_error = std::sqrt(quantisation / spectrum.total);
    return out;
}

CompressedFrame leadingColumns(const CompressedFrame& frame, int rank) {
    const int full = frame.factors.rank;
    if (rank < 0 || rank > full) throw Error(ErrorCode::InvalidArgument, "leadingColumns: rank out of range");
    CompressedFrame out;
    out.factors.frame = frame.factors.frame;
    out.factors.pixels = frame.factors.pixels;
    out.factors.columns = frame.factors.columns;
    out.factors.depth_b = frame.factors.depth_b;
    out.factors.depth_a = frame.factors.depth_a;
    out.factors.rank = rank;
    out.singular_values = frame.singular_values;
    double total = 0.0, kept = 0.0, quantisation = 0.0;
    for (size_t m = 0; m < frame.singular_values.size(); ++m) {
        const double s2 = frame.singular_values[m] * frame.singular_values[m];
        total += s2;
        if (static_cast<int>(m) < rank) kept += s2;
    }
    if (!(total > 0.0)) return out;
    out.truncation_error = std::sqrt(std::max(total - kept, 0.0) / total);
    out.column_quantisation.assign(frame.column_quantisation.begin(), frame.column_quantisation.begin() + rank);
    for (double q : out.column_quantisation) quantisation += q;
    out.quantisation_error = std::sqrt(quantisation);
    const auto pixels = static_cast<size_t>(frame.factors.pixels);
    out.factors.u_half.resize(pixels * rank);
    for (size_t p = 0; p < pixels; ++p)
        std::copy_n(frame.factors.u_half.begin() + p * full, rank, out.factors.u_half.begin() + p * rank);
    out.factors.svt.resize(static_cast<size_t>(frame.factors.columns) * rank);
    for (size_t j = 0; j < static_cast<size_t>(frame.factors.columns); ++j)
        std::copy_n(frame.factors.svt.begin() + j * full, rank, out.factors.svt.begin() + j * rank);
    return out;
}

CompressedFrame compressFrameBasis(const FrameBasis& basis, int frame, const CompressionSettings& settings,
                                   const BasisSources& sources) {
    const FrameSpectrum spectrum = frameSpectrum(basis, sources);
    return compressFrameBasis(basis, frame, spectrum, truncationRank(spectrum, settings));
}

}  // namespace firelook::bake
