// The one coefficient kernel (runtime/basis/coefficients.h, z = S V^T w) against the definition in
// double, at ranks on both sides of its 128-wide blocks, and the checked computeCoefficients
// (recombine.h) as exactly the kernel after its checks.
#include "basis/coefficients.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <vector>

#include "basis/parameter_grid.h"
#include "basis/recombine.h"

namespace firelook::basis {
namespace {

// 3 bins, 2 lights, a 3 x 2 x 2 grid.
BasisModel model() {
    BasisModel m;
    m.bins = {0.0, 3.0, 3};
    m.axes = {{1.0, 1.5, 2.0}, {1.0, 4.0}, {0.5, 2.0}};
    m.light_directions = {{0.0, -1.0, 0.0}, {1.0, 0.0, 0.0}};
    return m;
}

std::vector<float> randomSvt(const BasisModel& m, int rank, unsigned seed) {
    std::vector<float> svt(static_cast<size_t>(m.columnCount()) * rank);
    unsigned state = seed;
    for (float& v : svt) {
        state = state * 1664525u + 1013904223u;
        v = static_cast<float>(state >> 8) / 16777216.0f * 4.0f - 2.0f;
    }
    return svt;
}

const std::vector<Rgb> kRbf = {{1.0f, 0.5f, 0.25f}, {0.0f, 0.0f, 0.0f}, {3.0f, 2.0f, 0.1f}};  // bin 1 skipped
const std::vector<Rgb> kLights = {{0.7f, 0.8f, 0.9f}, {2.0f, 0.0f, 1.0f}};

TEST(CoefficientKernel, MatchesTheDefinitionAcrossRankBlocks) {
    const BasisModel m = model();
    const int per_point = m.columnsPerPoint();
    for (const int rank : {1, 7, 128, 129, 300}) {
        const std::vector<float> svt = randomSvt(m, rank, 17u + rank);
        for (const ExtinctionParams e : {ExtinctionParams{1.2, 2.5, 1.1}, ExtinctionParams{2.0, 1.0, 0.5},
                                         ExtinctionParams{0.5, 9.0, 3.0}}) {
            std::vector<float> z(static_cast<size_t>(rank) * 3, -1.0f);
            coefficientKernel(m, svt.data(), rank, e, kRbf.data(), kLights.data(), z.data());
            const GridWeights grid = interpolationWeights(m.axes, e);
            for (int k = 0; k < rank; ++k)
                for (int ch = 0; ch < 3; ++ch) {
                    double sum = 0.0, magnitude = 0.0;
                    int terms = 0;
                    for (int g = 0; g < grid.count; ++g)
                        for (int c = 0; c < per_point; ++c) {
                            const Rgb coef = c < m.bins.count ? kRbf[c] : kLights[c - m.bins.count];
                            const double term = static_cast<double>(grid.weight[g]) * coef[ch] *
                                                svt[(static_cast<size_t>(grid.point[g]) * per_point + c) * rank + k];
                            sum += term;
                            magnitude += std::fabs(term);
                            ++terms;
                        }
                    // A float sum of n terms is within (n - 1) eps sum|term| of the exact one
                    // (first order); + 2 for the rounding of the weight and of each product.
                    const double bound = (terms + 2) * static_cast<double>(FLT_EPSILON) * magnitude;
                    ASSERT_NEAR(z[k * 3 + ch], sum, bound) << "rank " << rank << " k " << k << " ch " << ch;
                }
        }
    }
}

TEST(CoefficientKernel, ComputeCoefficientsIsTheKernelAfterItsChecks) {
    BakeDescription d;
    static_cast<BasisModel&>(d) = model();
    ResidentFrame f;
    f.rank = 129;
    const std::vector<float> svt = randomSvt(d, f.rank, 5u);
    f.svt.assign(svt.begin(), svt.end());
    const ExtinctionParams e{1.7, 3.0, 1.5};
    std::vector<float> checked(static_cast<size_t>(f.rank) * 3), kernel(checked.size());
    computeCoefficients(d, f, {e, kRbf, kLights}, checked);
    coefficientKernel(d, f.svt.data(), f.rank, e, kRbf.data(), kLights.data(), kernel.data());
    for (size_t i = 0; i < checked.size(); ++i) ASSERT_EQ(checked[i], kernel[i]) << i;
}

}  // namespace
}  // namespace firelook::basis
