// The one coefficient kernel (runtime/basis/coefficients.h, z = S V^T w) against the definition in
// double, at ranks on both sides of its 128-wide blocks; a batch giving every instance the bits it
// gets alone, whatever its neighbours (the world batches the instances that show one frame); and
// the checked computeCoefficients (recombine.h) as exactly the kernel after its checks.
#include "basis/coefficients.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <set>
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

// Looks spread over the grid and beyond it (clamped), some on samples, some sharing a neighbourhood.
std::vector<ExtinctionParams> spreadLooks(int count) {
    std::vector<ExtinctionParams> looks;
    for (int i = 0; i < count; ++i)
        looks.push_back({0.9 + 0.09 * i, 0.5 + 0.7 * ((i * 7) % 13), i % 5 == 0 ? 2.0 : 0.4 + 0.3 * ((i * 3) % 11)});
    return looks;
}

// Batches of 1 to 21 (the kernel takes up to 8 together, then halves) on ranks across its 16-lane
// vectors, stages and rank blocks: every z the same value as that instance's kernel alone. Exact,
// not a tolerance: each value's sums run over the same terms in the same order in both, and a point
// only another instance uses adds an exact 0 (coefficients.h).
TEST(CoefficientKernel, ABatchGivesEachInstanceItsOwnBits) {
    const BasisModel m = model();
    for (const int rank : {1, 7, 21, 64, 129, 300}) {
        const std::vector<float> svt = randomSvt(m, rank, 90u + rank);
        for (const int count : {1, 3, 8, 13, 21}) {
            const std::vector<ExtinctionParams> looks = spreadLooks(count);
            std::vector<float> batch(static_cast<size_t>(count) * rank * 3, -1.0f), alone(batch.size(), -2.0f);
            std::vector<CoefficientJob> jobs;
            for (int i = 0; i < count; ++i)
                jobs.push_back({looks[i], kRbf.data(), kLights.data(), batch.data() + static_cast<size_t>(i) * rank * 3});
            coefficientBatch(m, svt.data(), rank, jobs);
            for (int i = 0; i < count; ++i)
                coefficientKernel(m, svt.data(), rank, looks[i], kRbf.data(), kLights.data(),
                                  alone.data() + static_cast<size_t>(i) * rank * 3);
            for (size_t v = 0; v < batch.size(); ++v)
                ASSERT_EQ(batch[v], alone[v]) << "rank " << rank << " batch " << count << " value " << v;
        }
    }
}

// A grid larger than a batch may bring in (10 x 10 x 10 points, looks far apart): the batch is done
// one instance at a time, with the same bits.
TEST(CoefficientKernel, ABatchOverAWideGridGivesTheSameBits) {
    BasisModel m = model();
    m.axes = {{}, {}, {}};
    for (int i = 0; i < 10; ++i) {
        m.axes.temperature_threshold.push_back(1.0 + 0.1 * i);
        m.axes.smoke_extinction.push_back(1.0 + i);
        m.axes.flame_extinction.push_back(0.5 + 0.5 * i);
    }
    const int rank = 19;
    const std::vector<float> svt = randomSvt(m, rank, 7u);
    std::vector<ExtinctionParams> looks;
    for (int i = 0; i < 8; ++i) looks.push_back({1.05 + 0.11 * i, 1.5 + 1.1 * i, 0.75 + 0.55 * i});
    std::vector<float> batch(looks.size() * rank * 3), alone(batch.size());
    std::vector<CoefficientJob> jobs;
    for (size_t i = 0; i < looks.size(); ++i) {
        jobs.push_back({looks[i], kRbf.data(), kLights.data(), batch.data() + i * rank * 3});
        coefficientKernel(m, svt.data(), rank, looks[i], kRbf.data(), kLights.data(), alone.data() + i * rank * 3);
    }
    std::set<int> points;
    for (const ExtinctionParams& e : looks) {
        const GridWeights g = interpolationWeights(m.axes, e);
        points.insert(g.point.begin(), g.point.begin() + g.count);
    }
    ASSERT_GT(points.size(), 2u * GridWeights::kMaxPoints) << "the looks must bring in more points than one batch holds";
    coefficientBatch(m, svt.data(), rank, jobs);
    for (size_t v = 0; v < batch.size(); ++v) ASSERT_EQ(batch[v], alone[v]) << "value " << v;
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
