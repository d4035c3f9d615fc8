#include "bake/basis_compression.h"

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
#include "render/random.h"

namespace firelook::bake {
namespace {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::Map<const RowMatrix> basisMatrix(const FrameBasis& basis) {
    return {basis.matrix.data(), static_cast<Eigen::Index>(basis.width) * basis.height, basis.columns};
}

// Below this many columns, or where the pairs asked for are a third of the columns, the dense
// solver on the Gram matrix is as cheap as the subspace iteration (leadingSpectrum).
constexpr int kDenseColumns = 400;
// The subspace iteration first asks for this many pairs, then doubles them while the dropped energy
// is above what SpectrumNeeds asks for: a real frame's rank is 15-45 (the sample at 256x256).
constexpr int kFirstLeading = 32;

void denseSpectrum(const Eigen::MatrixXd& gram, FrameSpectrum& spectrum) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
    const Eigen::VectorXd lambda = eigen.eigenvalues().cwiseMax(0.0);
    spectrum.eigenvalues.assign(lambda.data(), lambda.data() + lambda.size());
    spectrum.eigenvectors.assign(eigen.eigenvectors().data(), eigen.eigenvectors().data() + eigen.eigenvectors().size());
    spectrum.total = lambda.sum();
}

// B's rows that hold anything (most pixels of a fire image see nothing), in order, found in one
// pass over the whole matrix, and their cut into kRowChunks runs of equal counts: each run is
// summed on a thread of its own and the runs' sums are added in order, so every product below
// gives the same bits with any number of threads. The compression runs between two frames' traces,
// so one core used to wait here.
constexpr int kRowChunks = 2;
// Rows a product takes at once: a block of 256 rows of 1632 columns (the bundled sample's) is
// 1.6 MB in float, read from B once and used while it is in cache.
constexpr Eigen::Index kBlockRows = 256;

struct NonEmptyRows {
    std::vector<Eigen::Index> rows;
    Eigen::Index begin(int chunk) const { return static_cast<Eigen::Index>(rows.size()) * chunk / kRowChunks; }
};

NonEmptyRows nonEmptyRows(const Eigen::Map<const RowMatrix>& b) {
    NonEmptyRows out;
    for (Eigen::Index p = 0; p < b.rows(); ++p)
        if (b.row(p).cwiseAbs().maxCoeff() != 0.0f) out.rows.push_back(p);
    return out;
}

// Calls visit(chunk, block, filled) for the chunk's rows of B D, kBlockRows at a time (the block's
// first `filled` rows are set), in `Scalar`, each chunk on a thread of its own.
template <typename Scalar, typename Visit>
void forEachRowBlock(const Eigen::Map<const RowMatrix>& b, const NonEmptyRows& nonempty,
                     const Eigen::VectorXd& balance, Visit&& visit) {
    using Block = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
    const Eigen::Matrix<Scalar, 1, Eigen::Dynamic> d = balance.transpose().cast<Scalar>();
    tbb::parallel_for(0, kRowChunks, [&](int chunk) {
        Block block(kBlockRows, b.cols());
        Eigen::Index filled = 0;
        for (Eigen::Index n = nonempty.begin(chunk), end = nonempty.begin(chunk + 1); n < end; ++n) {
            block.row(filled++) = b.row(nonempty.rows[static_cast<std::size_t>(n)]).template cast<Scalar>().cwiseProduct(d);
            if (filled == kBlockRows || n + 1 == end) {
                visit(chunk, block, filled);
                filled = 0;
            }
        }
    });
}

// The lower triangle of the Gram matrix (B D)^T (B D), in double: for the dense solver. Memory:
// kRowChunks Gram matrices while they are summed, within the three the bake's plan counts
// (bake_pipeline.cpp).
Eigen::MatrixXd gramOfRows(const Eigen::Map<const RowMatrix>& b, const NonEmptyRows& nonempty,
                           const Eigen::VectorXd& balance) {
    const Eigen::Index columns = b.cols();
    std::array<Eigen::MatrixXd, kRowChunks> part;
    for (Eigen::MatrixXd& gram : part) gram = Eigen::MatrixXd::Zero(columns, columns);
    forEachRowBlock<double>(b, nonempty, balance, [&](int chunk, const Eigen::MatrixXd& block, Eigen::Index filled) {
        part[static_cast<std::size_t>(chunk)].selfadjointView<Eigen::Lower>().rankUpdate(block.topRows(filled).transpose());
    });
    for (int chunk = 1; chunk < kRowChunks; ++chunk) part[0] += part[static_cast<std::size_t>(chunk)];
    return std::move(part[0]);
}

// G Q for the Gram matrix G = (B D)^T (B D) without forming it: (B D)^T ((B D) Q), a block of rows
// at a time, in float (the iteration only has to find the subspace; the Rayleigh-Ritz step below
// measures in double).
Eigen::MatrixXd gramTimes(const Eigen::Map<const RowMatrix>& b, const NonEmptyRows& nonempty,
                          const Eigen::VectorXd& balance, const Eigen::MatrixXd& q) {
    const Eigen::MatrixXf qf = q.cast<float>();
    std::array<Eigen::MatrixXf, kRowChunks> part;
    for (Eigen::MatrixXf& z : part) z = Eigen::MatrixXf::Zero(q.rows(), q.cols());
    forEachRowBlock<float>(b, nonempty, balance, [&](int chunk, const Eigen::MatrixXf& block, Eigen::Index filled) {
        const Eigen::MatrixXf y = block.topRows(filled) * qf;
        part[static_cast<std::size_t>(chunk)].noalias() += block.topRows(filled).transpose() * y;
    });
    Eigen::MatrixXd z = part[0].cast<double>();
    for (int chunk = 1; chunk < kRowChunks; ++chunk) z += part[static_cast<std::size_t>(chunk)].cast<double>();
    return z;
}

// Q^T G Q in double: the Rayleigh quotient whose eigenpairs are the Ritz pairs of G on span(Q).
Eigen::MatrixXd projectedGram(const Eigen::Map<const RowMatrix>& b, const NonEmptyRows& nonempty,
                              const Eigen::VectorXd& balance, const Eigen::MatrixXd& q) {
    std::array<Eigen::MatrixXd, kRowChunks> part;
    for (Eigen::MatrixXd& h : part) h = Eigen::MatrixXd::Zero(q.cols(), q.cols());
    forEachRowBlock<double>(b, nonempty, balance, [&](int chunk, const Eigen::MatrixXd& block, Eigen::Index filled) {
        const Eigen::MatrixXd w = block.topRows(filled) * q;
        part[static_cast<std::size_t>(chunk)].noalias() += w.transpose() * w;
    });
    for (int chunk = 1; chunk < kRowChunks; ++chunk) part[0] += part[static_cast<std::size_t>(chunk)];
    return std::move(part[0]);
}

Eigen::MatrixXd orthonormalColumns(const Eigen::MatrixXd& z) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(z);
    return qr.householderQ() * Eigen::MatrixXd::Identity(z.rows(), z.cols());
}

// The `count` largest eigenpairs of G = (B D)^T (B D) by block subspace iteration on B D itself
// (Halko, Martinsson and Tropp's randomized range finder with power iterations, then Rayleigh-
// Ritz), without the Gram matrix: forming it cost a frame's rows times columns^2 (frame 12 of the
// bundled sample at 256x256: 23860 rows of 1632 columns, most of the 4.7 s that SVD and storage
// took of its 16.6 s bake; 2.95 s without it), where an iteration costs rows times columns times
// 2 `count`. The subspace holds 2 `count` vectors and is
// iterated until the sum of its leading `count` Ritz values moves by at most `tolerance`. The Ritz
// values are at most the true eigenvalues (Cauchy interlacing), and for Ritz vectors v,
// ||B D v||^2 is exactly the Ritz value: the dropped energy total - sum of them is exactly the
// error of the truncation that compressFrameBasis stores with these vectors, so a rank chosen from
// them keeps its bound; only the rank can be larger than the exact spectrum's, where the
// iteration has not converged. By hand, not with a library: Spectra's Lanczos solver (which took
// the pairs from the Gram matrix before) multiplies by one vector at a time, which on B itself is
// two passes over the whole matrix (150-400 MB) per product and a hundred or more products; a
// block of 2 `count` vectors is one pass, and Eigen's products do the arithmetic.
// `subspace` holds the previous call's subspace (a smaller count's), which starts this one: its
// vectors are already near the leading ones. It returns with this call's.
void leadingSpectrum(const Eigen::Map<const RowMatrix>& b, const NonEmptyRows& nonempty,
                     const Eigen::VectorXd& balance, int count, double tolerance, FrameSpectrum& spectrum,
                     Eigen::MatrixXd& subspace) {
    const auto columns = static_cast<Eigen::Index>(b.cols());
    const Eigen::Index width = std::min<Eigen::Index>(columns, 2 * static_cast<Eigen::Index>(count));
    // A fixed start: the same pairs for the same matrix.
    render::Pcg32 rng(0x5eed5eedULL);
    Eigen::MatrixXd start(columns, width);
    const Eigen::Index kept = std::min(subspace.cols(), width);
    start.leftCols(kept) = subspace.leftCols(kept);
    for (Eigen::Index j = kept; j < width; ++j)
        for (Eigen::Index i = 0; i < columns; ++i) start(i, j) = 2.0 * rng.uniform() - 1.0;
    Eigen::MatrixXd q = orthonormalColumns(start);
    // At most this many products with G; frame 12 of the bundled sample and the same frame
    // upsampled 4x settled in 4 at 256x256.
    constexpr int kMaxIterations = 16;
    double previous = -1.0;
    for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
        const Eigen::MatrixXd z = gramTimes(b, nonempty, balance, q);
        // Q^T G Q from the product just made (in float): only to see the iteration settle.
        const Eigen::MatrixXd h = q.transpose() * z;
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz(0.5 * (h + h.transpose()), Eigen::EigenvaluesOnly);
        const double sum = ritz.eigenvalues().tail(count).sum();
        q = orthonormalColumns(z);
        if (previous >= 0.0 && std::fabs(sum - previous) <= tolerance) break;
        previous = sum;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz(projectedGram(b, nonempty, balance, q));
    subspace = q * ritz.eigenvectors().rowwise().reverse();  // the Ritz vectors, the largest first
    const Eigen::MatrixXd vectors = q * ritz.eigenvectors().rightCols(count);  // ascending
    spectrum.eigenvalues.resize(static_cast<std::size_t>(count));
    for (int m = 0; m < count; ++m)
        spectrum.eigenvalues[static_cast<std::size_t>(m)] = std::max(ritz.eigenvalues()[width - count + m], 0.0);
    spectrum.eigenvectors.assign(vectors.data(), vectors.data() + vectors.size());
}

}  // namespace

FrameSpectrum frameSpectrum(const FrameBasis& basis, const BasisSources& sources, const SpectrumNeeds& needs) {
    const int columns = basis.columns;
    const Eigen::Map<const RowMatrix> b = basisMatrix(basis);
    const NonEmptyRows nonempty = nonEmptyRows(b);

    // Each column's energy (the Gram matrix's diagonal), in double, over the non-empty rows.
    std::array<Eigen::VectorXd, kRowChunks> part;
    for (Eigen::VectorXd& e : part) e = Eigen::VectorXd::Zero(columns);
    forEachRowBlock<double>(b, nonempty, Eigen::VectorXd::Ones(columns),
                            [&](int chunk, const Eigen::MatrixXd& block, Eigen::Index filled) {
                                part[static_cast<std::size_t>(chunk)] +=
                                    block.topRows(filled).cwiseAbs2().colwise().sum().transpose();
                            });
    for (int chunk = 1; chunk < kRowChunks; ++chunk) part[0] += part[static_cast<std::size_t>(chunk)];
    const Eigen::VectorXd& column_energy = part[0];

    FrameSpectrum spectrum;
    spectrum.columns = columns;
    spectrum.balance.assign(columns, 1.0);
    if (sources.columns_per_point > 0 && columns % sources.columns_per_point == 0) {
        // The SVD is of B D, D the per-source factors (basis/source_balance.h).
        std::vector<double> energy(sources.columns_per_point, 0.0);
        for (int j = 0; j < columns; ++j) energy[j % sources.columns_per_point] += column_energy[j];
        const std::vector<double> factor = basis::sourceBalance(energy, sources.bins);
        for (int j = 0; j < columns; ++j) spectrum.balance[j] = factor[j % sources.columns_per_point];
    }
    const Eigen::Map<const Eigen::VectorXd> d(spectrum.balance.data(), columns);
    spectrum.total = column_energy.dot(d.cwiseAbs2());
    const bool all = needs.max_rank <= 0;
    const int cap = all ? columns : std::min(needs.max_rank, columns);
    // What the subspace iteration may leave of the dropped energy it is judged by: a hundredth, but
    // not below the float products' rounding of the Ritz values' sum (about 1e-8 of the total).
    const double tolerance = std::max(0.01 * needs.finest_error * needs.finest_error, 1e-7) * spectrum.total;
    Eigen::MatrixXd subspace;
    for (int count = std::min(kFirstLeading, cap);; count = std::min(2 * count, cap)) {
        if (all || columns <= kDenseColumns || 3 * count >= columns) {
            denseSpectrum(gramOfRows(b, nonempty, d), spectrum);
            break;
        }
        if (!(spectrum.total > 0.0)) {  // nothing to find: an empty frame
            spectrum.eigenvalues.assign(static_cast<std::size_t>(count), 0.0);
            spectrum.eigenvectors.assign(static_cast<std::size_t>(columns) * count, 0.0);
            break;
        }
        leadingSpectrum(b, nonempty, d, count, tolerance, spectrum, subspace);
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
