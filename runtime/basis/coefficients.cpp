#include "basis/coefficients.h"

#include <algorithm>

#include "basis/parameter_grid.h"
#include "basis/simd.h"

namespace firelook::basis {
namespace {

// Ranks are summed in blocks of this many so the per-channel sums live on the stack (no scratch
// from the caller) and stay in L1.
constexpr int kBlock = 128;

// acc[k] += column[k] * w for the three channels; restrict lets the loop vectorise.
FIRELOOK_ALWAYS_INLINE void axpy3(int n, const float* __restrict column, float wr, float wg, float wb,
                                  float* __restrict r, float* __restrict g, float* __restrict b) {
    for (int k = 0; k < n; ++k) {
        const float c = column[k];
        r[k] += c * wr;
        g[k] += c * wg;
        b[k] += c * wb;
    }
}

}  // namespace

// Two builds (basis/simd.h): AVX2 + FMA where available, the baseline elsewhere. Both sum each
// z[k] over the grid points and columns in the same order; the AVX2 build fuses each multiply-add
// (GCC contracts in C++ modes), so the builds differ by at most one rounding of each product.
FIRELOOK_KERNEL_CLONES
void coefficientKernel(const BasisModel& model, const float* svt, int rank, const ExtinctionParams& extinction,
                       const Rgb* rbf, const Rgb* lights, float* z_out) {
    const int bins = model.bins.count;
    const int per_point = model.columnsPerPoint();
    const GridWeights grid = interpolationWeights(model.axes, extinction);
    float r[kBlock], g[kBlock], b[kBlock];
    for (int k0 = 0; k0 < rank; k0 += kBlock) {
        const int n = std::min(kBlock, rank - k0);
        std::fill(r, r + n, 0.0f);
        std::fill(g, g + n, 0.0f);
        std::fill(b, b + n, 0.0f);
        for (int p = 0; p < grid.count; ++p) {
            const float gw = grid.weight[p];
            const float* columns = svt + static_cast<size_t>(grid.point[p]) * per_point * rank + k0;
            for (int c = 0; c < per_point; ++c) {
                const Rgb w = gw * (c < bins ? rbf[c] : lights[c - bins]);
                if (w.r == 0.0f && w.g == 0.0f && w.b == 0.0f) continue;
                axpy3(n, columns + static_cast<size_t>(c) * rank, w.r, w.g, w.b, r, g, b);
            }
        }
        float* z = z_out + 3 * static_cast<size_t>(k0);
        for (int k = 0; k < n; ++k) {
            z[3 * k + 0] = r[k];
            z[3 * k + 1] = g[k];
            z[3 * k + 2] = b[k];
        }
    }
}

}  // namespace firelook::basis
