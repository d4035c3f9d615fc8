#include "world/coefficient_kernel.h"

#include <algorithm>

#include "basis/parameter_grid.h"
#include "basis/simd.h"

namespace firelook::runtime {
namespace {

// acc[k] += column[k] * w for the three channels; restrict lets the loop vectorise.
inline void axpy3(int rank, const float* __restrict column, float wr, float wg, float wb, float* __restrict r,
                  float* __restrict g, float* __restrict b) {
    for (int k = 0; k < rank; ++k) {
        const float c = column[k];
        r[k] += c * wr;
        g[k] += c * wg;
        b[k] += c * wb;
    }
}

}  // namespace

// Two builds of the kernel (basis/simd.h): AVX2 + FMA where available, the baseline elsewhere.
FIRELOOK_KERNEL_CLONES
void computeCoefficientsFast(const basis::BakeDescription& d, const float* svt, int rank,
                             const ExtinctionParams& extinction, const Rgb* rbf, const Rgb* lights, float* scratch,
                             float* z_out) {
    const int bins = d.bins.count;
    const int per_point = d.columnsPerPoint();
    float* r = scratch;
    float* g = scratch + rank;
    float* b = scratch + 2 * rank;
    std::fill(scratch, scratch + 3 * rank, 0.0f);
    const basis::GridWeights grid = basis::interpolationWeights(d.axes, extinction);
    for (int p = 0; p < grid.count; ++p) {
        const float gw = grid.weight[p];
        const float* columns = svt + static_cast<size_t>(grid.point[p]) * per_point * rank;
        for (int c = 0; c < per_point; ++c) {
            const Rgb w = gw * (c < bins ? rbf[c] : lights[c - bins]);
            if (w.r == 0.0f && w.g == 0.0f && w.b == 0.0f) continue;
            axpy3(rank, columns + static_cast<size_t>(c) * rank, w.r, w.g, w.b, r, g, b);
        }
    }
    for (int k = 0; k < rank; ++k) {
        z_out[3 * k + 0] = r[k];
        z_out[3 * k + 1] = g[k];
        z_out[3 * k + 2] = b[k];
    }
}

}  // namespace firelook::runtime
