#include "basis/coefficients.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include "basis/parameter_grid.h"
#include "basis/simd.h"

namespace firelook::basis {
namespace {

// Instances blended together, at most: every vector of S V^T read serves this many (8 on
// AVX-512's 32 registers, 4 on AVX2's 16).
constexpr int kBatch = 8;
// z is summed per rank block of this many on the stack (per instance and channel).
constexpr int kRankBlock = 128;
// The blended columns M of a stretch of this many values per instance stay on the stack (in L1).
constexpr int kStage = 512;
// Grid points a batch can bring in: a batch whose box of samples (batchPoints) holds more, or spans
// more than kMaxExtent samples of an axis, is done one instance at a time (a grid of at most this
// many points never is). With the above, a batch's stack is about 50 KiB.
constexpr int kMaxUnion = 2 * GridWeights::kMaxPoints;

// The grid points of a batch (increasing) and each instance's weight at each (0 where it has none).
struct BatchPoints {
    int count = 0;
    int point[kMaxUnion];
    float weight[kMaxUnion][kBatch];
};

// Samples of one axis a batch's box may span.
constexpr int kMaxExtent = 16;

// The grid points with a weight for any of the NB instances: each instance's weights per axis
// (axisWeights), laid out over the box of samples the batch spans, and at each point of the box
// the product interpolationWeights takes (pointWeight), so the same float; the points in
// increasing index (k_f fastest), those where every weight is 0 left out. False when the box spans
// more than kMaxExtent samples of an axis or kMaxUnion points.
template <int NB>
bool batchPoints(const ParameterAxes& axes, std::span<const CoefficientJob> jobs, BatchPoints& out) {
    const std::vector<double>* samples[3] = {&axes.temperature_threshold, &axes.smoke_extinction,
                                             &axes.flame_extinction};
    AxisWeights w[NB][3];
    int lo[3], extent[3];
    for (int axis = 0; axis < 3; ++axis) {
        int low = std::numeric_limits<int>::max(), high = -1;
        for (int i = 0; i < NB; ++i) {
            const ExtinctionParams& e = jobs[i].extinction;
            const double x = axis == 0 ? e.temperature_threshold : axis == 1 ? e.smoke_extinction : e.flame_extinction;
            w[i][axis] = axisWeights(*samples[axis], x);
            for (int k = 0; k < w[i][axis].count; ++k) {
                low = std::min(low, w[i][axis].index[k]);
                high = std::max(high, w[i][axis].index[k]);
            }
        }
        lo[axis] = low;
        extent[axis] = high - low + 1;
        if (extent[axis] > kMaxExtent) return false;
    }
    if (extent[0] * extent[1] * extent[2] > kMaxUnion) return false;
    double dense[3][kMaxExtent][NB] = {};
    for (int axis = 0; axis < 3; ++axis)
        for (int i = 0; i < NB; ++i)
            for (int k = 0; k < w[i][axis].count; ++k) dense[axis][w[i][axis].index[k] - lo[axis]][i] = w[i][axis].weight[k];
    out.count = 0;
    for (int a = 0; a < extent[0]; ++a)
        for (int b = 0; b < extent[1]; ++b)
            for (int c = 0; c < extent[2]; ++c) {
                float* weight = out.weight[out.count];
                bool any = false;
                for (int i = 0; i < NB; ++i) {
                    weight[i] = pointWeight(dense[0][a][i], dense[1][b][i], dense[2][c][i]);
                    any |= weight[i] != 0.0f;
                }
                if (!any) continue;
                out.point[out.count++] = axes.pointIndex(lo[0] + a, lo[1] + b, lo[2] + c);
            }
    return true;
}

// V: a float vector of W lanes; NV vectors a step. M[i][j] = sum over the batch's points of
// weight[i] x row[j] for j in [first, first + count) of every point's row (its columns x rank
// values, `row_length`), written to m[i][j - first]. Each instance's sum runs over the points in
// order, one fused multiply-add each; from +0 a sum never becomes -0, so an instance's weight 0
// adds nothing at all. Reads up to NV W - 1 values past a row's stretch: from the rows after it,
// or, where that would pass the end of S V^T, from a zero-padded copy.
template <typename V, int NV, int NB>
FIRELOOK_ALWAYS_INLINE void blendColumns(const float* svt, size_t row_length, int points, const BatchPoints& b,
                                         size_t first, size_t count, float (*m)[kStage + 128]) {
    constexpr int W = sizeof(V) / sizeof(float);
    constexpr int kStep = NV * W;
    const size_t total = static_cast<size_t>(points) * row_length;
    for (size_t j = 0; j < count; j += kStep) {
        V acc[NB][NV] = {};
        for (int u = 0; u < b.count; ++u) {
            const size_t at = static_cast<size_t>(b.point[u]) * row_length + first + j;
            const float* src = svt + at;
            float padded[kStep];
            if (at + kStep > total) {
                std::memset(padded, 0, sizeof padded);
                std::memcpy(padded, src, (total - at) * sizeof(float));
                src = padded;
            }
            V s[NV];
#pragma GCC unroll 8
            for (int v = 0; v < NV; ++v) simd::load(s[v], src + v * W);
#pragma GCC unroll 8
            for (int i = 0; i < NB; ++i) {
                const float w = b.weight[u][i];
#pragma GCC unroll 8
                for (int v = 0; v < NV; ++v) acc[i][v] += w * s[v];
            }
        }
#pragma GCC unroll 8
        for (int i = 0; i < NB; ++i)
#pragma GCC unroll 8
            for (int v = 0; v < NV; ++v) simd::store(m[i] + j + v * W, acc[i][v]);
    }
}

// sums[channel][t] += weight[channel] x m[t] for t < count, W lanes at a time (the last vector's
// lanes past count keep their value); a channel of weight 0 is left alone (as a term it would add
// nothing, or NaN from an infinite value).
template <typename V>
FIRELOOK_ALWAYS_INLINE void addColumn(float* const sums[3], const float* m, int count, const Rgb& weight) {
    constexpr int W = sizeof(V) / sizeof(float);
    using I = decltype(V{} < V{});
    I lane;
    for (int l = 0; l < W; ++l) lane[l] = l;
    for (int t = 0; t < count; t += W) {
        V x;
        simd::load(x, m + t);
        const I keep = lane < count - t;
        for (int channel = 0; channel < 3; ++channel) {
            if (weight[channel] == 0.0f) continue;
            V z;
            simd::load(z, sums[channel] + t);
            const V added = z + weight[channel] * x;
            z = keep ? added : z;
            simd::store(sums[channel] + t, z);
        }
    }
}

// NB = jobs.size() instances; `Regs` vector registers hold their sums (NV vectors each, at most 8,
// so that a batch of one still has independent sums to overlap).
template <typename V, int Regs, int NB>
FIRELOOK_ALWAYS_INLINE void batchKernel(const BasisModel& model, const float* svt, int rank,
                                        std::span<const CoefficientJob> jobs) {
    constexpr int NV = std::clamp(Regs / NB, 1, 8);
    const int bins = model.bins.count;
    const int per_point = model.columnsPerPoint();
    const int points = model.axes.pointCount();
    const size_t row_length = static_cast<size_t>(per_point) * rank;
    BatchPoints b;
    if constexpr (NB > 1) {
        if (!batchPoints<NB>(model.axes, jobs, b)) {  // one by one (each instance's bits do not change)
            for (size_t i = 0; i < jobs.size(); ++i) batchKernel<V, Regs, 1>(model, svt, rank, jobs.subspan(i, 1));
            return;
        }
    } else {
        batchPoints<1>(model.axes, jobs, b);  // one instance: at most 5 samples an axis
    }
    alignas(64) float m[kBatch][kStage + 128];
    alignas(64) float sums[kBatch][3][kRankBlock + 16];
    for (int k0 = 0; k0 < rank; k0 += kRankBlock) {
        const int n = std::min(kRankBlock, rank - k0);
        for (int i = 0; i < NB; ++i)
            for (float* channel : sums[i]) std::fill(channel, channel + n + 16, 0.0f);
        // The values of rank block [k0, k0 + n) of every column: one stretch of each point's row
        // when the block is the whole rank, else one per column.
        const int stretches = n == rank ? 1 : per_point;
        const size_t stretch_length = n == rank ? row_length : static_cast<size_t>(n);
        for (int s = 0; s < stretches; ++s) {
            const size_t stretch = n == rank ? 0 : static_cast<size_t>(s) * rank + k0;
            for (size_t first = 0; first < stretch_length; first += kStage) {
                const size_t count = std::min<size_t>(kStage, stretch_length - first);
                blendColumns<V, NV, NB>(svt, row_length, points, b, stretch + first, count, m);
                // Each column's part of the stage into the sums: value e of the row is column e / rank, k = e % rank.
                const size_t stage = stretch + first;
                int c = static_cast<int>(stage / rank), k = static_cast<int>(stage % rank);
                for (size_t e = stage; e < stage + count; ++c, k = 0) {
                    const int length = static_cast<int>(std::min<size_t>(stage + count - e, rank - k));
                    for (int i = 0; i < NB; ++i) {
                        float* const at[3] = {sums[i][0] + (k - k0), sums[i][1] + (k - k0), sums[i][2] + (k - k0)};
                        addColumn<V>(at, m[i] + (e - stage), length, c < bins ? jobs[i].rbf[c] : jobs[i].lights[c - bins]);
                    }
                    e += static_cast<size_t>(length);
                }
            }
        }
        for (size_t i = 0; i < jobs.size(); ++i) {
            float* z = jobs[i].z_out + 3 * static_cast<size_t>(k0);
            for (int k = 0; k < n; ++k)
                for (int channel = 0; channel < 3; ++channel) z[3 * k + channel] = sums[i][channel][k];
        }
    }
}

// Every job, NB at a time (the rest in batches of half as many, and so on).
template <typename V, int Regs, int NB>
FIRELOOK_ALWAYS_INLINE void batches(const BasisModel& model, const float* svt, int rank,
                                    std::span<const CoefficientJob> jobs) {
    size_t first = 0;
    for (; first + NB <= jobs.size(); first += NB) batchKernel<V, Regs, NB>(model, svt, rank, jobs.subspan(first, NB));
    const std::span<const CoefficientJob> rest = jobs.subspan(first);
    if constexpr (NB > 1) {
        if (rest.size() >= NB / 2) {
            batchKernel<V, Regs, NB / 2>(model, svt, rank, rest.first(NB / 2));
            batches<V, Regs, NB / 2>(model, svt, rank, rest.subspan(NB / 2));
        } else {
            batches<V, Regs, NB / 2>(model, svt, rank, rest);
        }
    }
}

// Three builds by the CPU (function multi-versioning): AVX-512 on 16 lanes, AVX2 + FMA and the
// baseline on 8; the sums are lane by lane, so the AVX builds give the same bits and the baseline
// rounds each product apart. Not under ThreadSanitizer: a multi-versioned function's resolver
// runs while the loader relocates, before TSan's runtime is up, and the program crashes there
// (plugin_api_thread_tests, SIGSEGV in _dl_relocate_object).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
__attribute__((target("default"))) void runBatches(const BasisModel& model, const float* svt, int rank,
                                                   std::span<const CoefficientJob> jobs) {
    batches<simd::v8f, 12, 4>(model, svt, rank, jobs);
}
__attribute__((target("arch=x86-64-v3"))) void runBatches(const BasisModel& model, const float* svt, int rank,
                                                          std::span<const CoefficientJob> jobs) {
    batches<simd::v8f, 12, 4>(model, svt, rank, jobs);
}
__attribute__((target("arch=x86-64-v4"))) void runBatches(const BasisModel& model, const float* svt, int rank,
                                                          std::span<const CoefficientJob> jobs) {
    batches<simd::v16f, 24, 8>(model, svt, rank, jobs);
}
#else
void runBatches(const BasisModel& model, const float* svt, int rank, std::span<const CoefficientJob> jobs) {
    batches<simd::v8f, 12, 4>(model, svt, rank, jobs);
}
#endif

}  // namespace

void coefficientBatch(const BasisModel& model, const float* svt, int rank, std::span<const CoefficientJob> jobs) {
    if (rank > 0) runBatches(model, svt, rank, jobs);
}

void coefficientKernel(const BasisModel& model, const float* svt, int rank, const ExtinctionParams& extinction,
                       const Rgb* rbf, const Rgb* lights, float* z_out) {
    const CoefficientJob job{extinction, rbf, lights, z_out};
    coefficientBatch(model, svt, rank, std::span(&job, 1));
}

}  // namespace firelook::basis
