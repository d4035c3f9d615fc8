#include "bake/basis_compression.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <glm/gtc/packing.hpp>

namespace firelook::bake {

CompressedFrame compressFrameBasis(const FrameBasis& basis, int frame, const CompressionSettings& settings) {
    const int pixels = basis.width * basis.height;
    const int columns = basis.columns;
    using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const Eigen::Map<const RowMatrix> b(basis.matrix.data(), pixels, columns);

    // Gram matrix over the non-empty rows (most pixels of a fire image see nothing).
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(columns, columns);
    constexpr int kBlockRows = 256;
    Eigen::MatrixXd block(kBlockRows, columns);
    int filled = 0;
    const auto flush = [&] {
        if (filled == 0) return;
        gram.selfadjointView<Eigen::Lower>().rankUpdate(block.topRows(filled).transpose());
        filled = 0;
    };
    for (int p = 0; p < pixels; ++p) {
        if (b.row(p).cwiseAbs().maxCoeff() == 0.0f) continue;
        block.row(filled++) = b.row(p).cast<double>();
        if (filled == kBlockRows) flush();
    }
    flush();

    CompressedFrame out;
    out.factors.frame = frame;
    out.factors.pixels = pixels;
    out.factors.columns = columns;
    out.factors.depth_density = basis.depth_density;
    out.factors.depth_sigmoid = basis.depth_sigmoid;

    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
    const Eigen::VectorXd lambda = eigen.eigenvalues().cwiseMax(0.0);  // ascending; rounding can dip below 0
    const double total = lambda.sum();
    for (int j = columns - 1; j >= 0; --j) out.singular_values.push_back(std::sqrt(lambda[j]));
    if (!(total > 0.0)) return out;  // an empty frame: rank 0, the image is black and transparent

    // Smallest rank whose dropped energy is within the target.
    int rank = 0;
    double dropped = total;
    while (rank < std::min(settings.max_rank, columns) &&
           std::sqrt(std::max(dropped, 0.0) / total) > settings.target_relative_error) {
        dropped -= lambda[columns - 1 - rank];
        ++rank;
    }
    out.truncation_error = std::sqrt(std::max(dropped, 0.0) / total);
    out.factors.rank = rank;

    Eigen::MatrixXf v(columns, rank);
    Eigen::VectorXf sigma(rank);
    for (int m = 0; m < rank; ++m) {
        v.col(m) = eigen.eigenvectors().col(columns - 1 - m).cast<float>();
        sigma[m] = static_cast<float>(std::sqrt(lambda[columns - 1 - m]));
    }
    // U = B V S^-1, pixel-major like B.
    RowMatrix u = b * v;
    for (int m = 0; m < rank; ++m) u.col(m) /= sigma[m];

    out.factors.svt.resize(static_cast<size_t>(columns) * rank);
    for (int j = 0; j < columns; ++j)
        for (int m = 0; m < rank; ++m) out.factors.svt[static_cast<size_t>(j) * rank + m] = sigma[m] * v(j, m);

    // Half precision U; its error in B is ||(U_half - U) S||_F because V is orthonormal.
    out.factors.u_half.resize(static_cast<size_t>(pixels) * rank);
    double quantisation = 0.0;
    for (int p = 0; p < pixels; ++p)
        for (int m = 0; m < rank; ++m) {
            const float value = u(p, m);
            const uint16_t half = glm::packHalf1x16(value);
            out.factors.u_half[static_cast<size_t>(p) * rank + m] = half;
            const double err = (double(glm::unpackHalf1x16(half)) - value) * sigma[m];
            quantisation += err * err;
        }
    out.quantisation_error = std::sqrt(quantisation / total);
    return out;
}

}  // namespace firelook::bake
