#include "basis/recombine.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "basis/coefficients.h"
#include "basis/parameter_grid.h"
#include "basis/simd.h"
#include "common/error.h"

namespace firelook::basis {

void computeCoefficients(const BakeDescription& description, const ResidentFrame& frame, const LookWeights& look,
                         std::span<float> z_out) {
    const int rank = frame.rank;
    const std::span<const float> svt = frame.svt;
    const int bins = description.bins.count;
    const int lights = static_cast<int>(description.light_directions.size());
    if (static_cast<int>(look.rbf_coefficients.size()) != bins)
        throw Error(ErrorCode::InvalidArgument, "look has " + std::to_string(look.rbf_coefficients.size()) +
                                                    " emission coefficients, the package has " +
                                                    std::to_string(bins) + " bins");
    if (static_cast<int>(look.light_irradiance.size()) != lights)
        throw Error(ErrorCode::InvalidArgument, "look has " + std::to_string(look.light_irradiance.size()) +
                                                    " light irradiances, the package has " +
                                                    std::to_string(lights) + " lights");
    if (static_cast<int>(z_out.size()) < rank * 3)
        throw Error(ErrorCode::InvalidArgument, "coefficient output too short");
    if (svt.size() < static_cast<size_t>(description.columnCount()) * std::max(rank, 0))
        throw Error(ErrorCode::InvalidArgument, "S V^T too short for the description");

    coefficientKernel(description, svt.data(), rank, look.extinction, look.rbf_coefficients.data(),
                      look.light_irradiance.data(), z_out.data());
}

namespace {

// ---------------------------------------------------------------------------------------------
// Reconstruction kernels, on the types of basis/simd.h (two builds each, AVX2 and the baseline),
// 8 float lanes, so the baseline build is the same code on pairs of SSE registers.
// ---------------------------------------------------------------------------------------------
using simd::v4f;
using simd::v8f;
using simd::v8i;
using simd::v8s;

FIRELOOK_ALWAYS_INLINE void store8(float* p, const v8f& v) { simd::store(p, v); }

// Optical depths are handled in units of log2: tau2 = tau / ln 2, clamped to [0, kMaxTau2]:
// 2^-125 = 2.4e-38 is still a normal float and 1 - 2^-125 rounds to exactly 1, so the clamp
// changes no alpha.
constexpr float kMaxTau2 = 125.0f;

// The threshold layers bracketing T_c and the weights of tau2 = (a (1 - t) O_a(lower) +
// a t O_a(upper) + b O_b) / ln 2; `two` is false when T_c is on or
// outside the samples (O_a = the lower layer alone).
struct AlphaWeights {
    SampleBracket lerp;  // parameter_grid.h: the one bracketing rule
    bool two = false;
    float w_lower = 0.0f, w_upper = 0.0f, w_density = 0.0f;
};

AlphaWeights alphaWeights(const BakeDescription& description, const ExtinctionParams& extinction) {
    AlphaWeights w;
    w.lerp = sampleBracket(description.alpha_thresholds, extinction.temperature_threshold);
    // The layer weight in float, as the GPU layers' writers and the plugin's state report it.
    const float t = static_cast<float>(w.lerp.t);
    w.two = w.lerp.upper != w.lerp.lower && t != 0.0f;
    const double log2e = 1.4426950408889634;
    w.w_lower = static_cast<float>(extinction.a() * (w.two ? 1.0 - t : 1.0) * log2e);
    w.w_upper = static_cast<float>(extinction.a() * (w.two ? t : 0.0) * log2e);
    w.w_density = static_cast<float>(extinction.b() * log2e);
    return w;
}

// sum += 1 - 2^-tau2 of 8 rays, tau2 = (a O_a + b O_b) / ln 2 as weighted by alphaWeights.
// tau2 < 0 counts as 0 (clear), NaN or above kMaxTau2 as opaque (alpha exactly 1), as the
// definition does (tests/basis/reference_kernels.h). 2^-tau2 = 2^-m 2^r with
// m = round(tau2), r = m - tau2 in [-1/2, 1/2] (exact in float), 2^r = 1 + r P(r) with the Cephes
// exp2f polynomial (P of degree 5, minimax on [-1/2, 1/2]; tau2 = 0 gives exactly alpha 0), 2^-m
// from the exponent bits. The polynomial's own relative error is 5e-9; in float arithmetic the
// alpha of one ray is within 7e-8 of 1 - exp(-tau) in double (largest difference over tau in
// [0, 90], tests/basis/recombine_kernel_test.cpp), far below the alpha error the stored depths
// already carry (FrameCodecSettings::alpha_error, frame_codec.h). Eigen's vectorised Array::exp would do too,
// but the runtime does not link Eigen, and Eigen picks its packet width at compile time (SSE2 in
// this build) rather than per target clone; the clamping and NaN rules here are ours either way.
FIRELOOK_ALWAYS_INLINE void addRayAlpha(v8f& sum, const v8f& tau_in) {
    const v8f zero = {};
    const v8f max_tau = zero + kMaxTau2;
    v8f tau = tau_in < max_tau ? tau_in : max_tau;  // NaN -> max_tau
    tau = tau > zero ? tau : zero;
    const v8i m = __builtin_convertvector(tau + 0.5f, v8i);  // tau >= 0: truncation rounds
    const v8f r = __builtin_convertvector(m, v8f) - tau;
    v8f p = r * 1.535336188319500e-4f + 1.339887440266574e-3f;
    p = p * r + 9.618437357674640e-3f;
    p = p * r + 5.550332471162809e-2f;
    p = p * r + 2.402264791363012e-1f;
    p = p * r + 6.931472028550421e-1f;
    p = p * r + 1.0f;
    sum += 1.0f - p * __builtin_bit_cast(v8f, (127 - m) << 23);
}

// Mean over the rays, in [0, 1].
FIRELOOK_ALWAYS_INLINE void finishAlpha(v8f& alpha, const v8f& sum, float samples) {
    const v8f zero = {};
    const v8f one = zero + 1.0f;
    const v8f mean = sum / samples;
    alpha = mean < one ? mean : one;
    alpha = alpha > zero ? alpha : zero;
}

constexpr int kMaxVectorRank = 1024;  // z blocks live on the stack (12 KiB)

// Horizontal sums of r, g, b into lanes 0..2 (lane 3 = b again).
FIRELOOK_ALWAYS_INLINE void sum3(v4f& out, const v8f& r, const v8f& g, const v8f& b) {
    const v8f rg = __builtin_shufflevector(r, g, 0, 2, 8, 10, 4, 6, 12, 14) +
                   __builtin_shufflevector(r, g, 1, 3, 9, 11, 5, 7, 13, 15);
    const v8f bb = __builtin_shufflevector(b, b, 0, 2, 8, 10, 4, 6, 12, 14) +
                   __builtin_shufflevector(b, b, 1, 3, 9, 11, 5, 7, 13, 15);
    const v8f rgb = __builtin_shufflevector(rg, bb, 0, 2, 8, 10, 4, 6, 12, 14) +
                    __builtin_shufflevector(rg, bb, 1, 3, 9, 11, 5, 7, 13, 15);
    out = __builtin_shufflevector(rgb, rgb, 0, 1, 2, 3) + __builtin_shufflevector(rgb, rgb, 4, 5, 6, 7);
}

// What alpha needs from a resident frame: the depth codes of the one or two threshold layers that
// bracket T_c, and the weights of tau2 (alphaWeights).
struct ResidentAlphaPlan {
    const float* depth = nullptr;  // DepthTable::depth
    int last = 0;                  // its last code
    int lower = 1, upper = 1;      // e_j lanes (1 + j)
    bool two = false;
    float w_lower = 0.0f, w_upper = 0.0f, w_density = 0.0f;
};

ResidentAlphaPlan residentAlphaPlan(const BakeDescription& description, const ResidentFrame& f,
                                    const ExtinctionParams& extinction) {
    const AlphaWeights w = alphaWeights(description, extinction);
    ResidentAlphaPlan plan;
    plan.depth = f.depth_table->depth.data();
    plan.last = static_cast<int>(f.depth_table->depth.size()) - 1;
    plan.lower = 1 + w.lerp.lower;
    plan.upper = 1 + w.lerp.upper;
    plan.two = w.two;
    plan.w_lower = w.w_lower;
    plan.w_upper = w.w_upper;
    plan.w_density = w.w_density;
    return plan;
}

// tau2 of one ray from its codes: O_b = D[q], O_a(j) = O_b - 2 D[q - e_j] (codes clamped to the
// table, so damaged values stay finite).
FIRELOOK_ALWAYS_INLINE float rayTau(const ResidentAlphaPlan& plan, const int16_t* v) {
    auto depth = [&](int q) { return plan.depth[std::clamp(q, 0, plan.last)]; };
    const float o_b = depth(v[0]);
    float tau = plan.w_density * o_b + plan.w_lower * (o_b - 2.0f * depth(int(v[0]) - int(v[plan.lower])));
    if (plan.two) tau += plan.w_upper * (o_b - 2.0f * depth(int(v[0]) - int(v[plan.upper])));
    return tau;
}

// Mean alpha of a detailed pixel's rays, 8 rays at a time (lanes past the last ray hold tau 0,
// alpha exactly 0), summed across lanes in a fixed order.
FIRELOOK_ALWAYS_INLINE float detailedAlpha(const ResidentAlphaPlan& plan, const int16_t* rays, int samples,
                                           int stride) {
    v8f sum = {};
    for (int first = 0; first < samples; first += 8) {
        v8f tau = {};
        for (int s = first; s < std::min(samples, first + 8); ++s)
            tau[s - first] = rayTau(plan, rays + static_cast<size_t>(s) * stride);
        addRayAlpha(sum, tau);
    }
    float total = 0.0f;
    for (int i = 0; i < 8; ++i) total += sum[i];
    return std::clamp(total / static_cast<float>(samples), 0.0f, 1.0f);
}

// Calls f(piece_first, piece_count) for each piece of [first, first + count) inside `runs`, in order.
template <typename F>
FIRELOOK_ALWAYS_INLINE void forRunPieces(std::span<const PixelRun> runs, size_t first, size_t count, F&& f) {
    const size_t end = first + count;
    auto it = std::upper_bound(runs.begin(), runs.end(), first,
                               [](size_t p, const PixelRun& r) { return p < static_cast<size_t>(r.first) + r.count; });
    for (; it != runs.end() && static_cast<size_t>(it->first) < end; ++it) {
        const size_t a = std::max(first, static_cast<size_t>(it->first));
        const size_t b = std::min(end, static_cast<size_t>(it->first) + it->count);
        f(a, b - a);
    }
}

// alpha_out[i] = alpha of the mean ray of pixel first + i, for i < count (alpha_out has room for
// count rounded up to 8; the lanes past count get 0). Elementwise in the lanes, so a pixel gets the
// same bits wherever its block starts (pixelAlpha evaluates it alone).
FIRELOOK_KERNEL_CLONES
void residentMeanAlpha(const ResidentAlphaPlan& plan, const ResidentFrame& f, size_t first, size_t count,
                       float* alpha_out) {
    const int stride = f.depth_stride;
    for (size_t block = 0; block < count; block += 8) {
        v8f tau = {};
        const size_t n = std::min<size_t>(8, count - block);
        for (size_t i = 0; i < n; ++i) tau[i] = rayTau(plan, f.mean_depth.data() + (first + block + i) * stride);
        v8f sum = {}, alpha;
        addRayAlpha(sum, tau);
        finishAlpha(alpha, sum, 1.0f);
        store8(alpha_out + block, alpha);
    }
}

// alpha_out[i] = alpha of pixel first + i, for i < count (alpha_out has room for count + 8): the
// mean rays of depth_runs (every other mean ray has codes 0, tau 0, alpha exactly 0, written
// as such), then each detailed pixel's rays.
FIRELOOK_KERNEL_CLONES
void residentAlphaSpan(const ResidentAlphaPlan& plan, const ResidentFrame& f, size_t first, size_t count,
                       float* alpha_out) {
    std::fill(alpha_out, alpha_out + count, 0.0f);
    forRunPieces(f.depth_runs, first, count, [&](size_t a, size_t n) {
        residentMeanAlpha(plan, f, a, n, alpha_out + (a - first));
    });
    const int stride = f.depth_stride;
    const auto begin = std::lower_bound(f.detailed_pixels.begin(), f.detailed_pixels.end(), static_cast<int32_t>(first));
    for (auto it = begin; it != f.detailed_pixels.end() && static_cast<size_t>(*it) < first + count; ++it) {
        const size_t index = static_cast<size_t>(it - f.detailed_pixels.begin());
        alpha_out[static_cast<size_t>(*it) - first] =
            detailedAlpha(plan, f.detailed_depth.data() + index * f.samples * stride, f.samples, stride);
    }
}

// rgb = U z for pixels [first, first + count): each pixel's W row (int16, rank_stride) against z
// scaled by u_scale, de-interleaved into 8-lane blocks per channel; alpha[i] is pixel first + i's.
FIRELOOK_KERNEL_CLONES
void residentRgbSpan(const ResidentFrame& f, const v8f* zr, const v8f* zg, const v8f* zb, size_t first, size_t count,
                     const float* alpha, float* rgba) {
    const int blocks = f.rank_stride / 8;
    for (size_t i = 0; i < count; ++i) {
        const size_t pixel = first + i;
        const int16_t* w = f.w.data() + pixel * f.rank_stride;
        v8f r = {}, g = {}, b = {};
        for (int k = 0; k < blocks; ++k) {
            v8s codes;
            simd::load(codes, w + 8 * k);
            const v8f x = __builtin_convertvector(codes, v8f);
            r += x * zr[k];
            g += x * zg[k];
            b += x * zb[k];
        }
        v4f out;
        sum3(out, r, g, b);
        const v4f zero = {};
        const v4f largest = zero + std::numeric_limits<float>::max();
        out = ((out > zero) & (out <= largest)) ? out : zero;  // NaN, +-inf and negatives -> 0
        out[3] = alpha[i];
        std::memcpy(rgba + pixel * 4, &out, sizeof out);
    }
}

// Increasing, disjoint, non-empty runs inside the image.
bool validRuns(std::span<const PixelRun> runs, size_t pixels) {
    size_t end = 0;
    for (const PixelRun& r : runs) {
        if (r.first < 0 || r.count <= 0 || static_cast<size_t>(r.first) < end ||
            static_cast<size_t>(r.count) > pixels - std::min(pixels, static_cast<size_t>(r.first)))
            return false;
        end = static_cast<size_t>(r.first) + r.count;
    }
    return true;
}

// rgba[i] = (0, 0, 0, alpha[i]) for i < count: pixels whose W row is 0, most of a frame. Streamed
// past the caches where the image is 16-byte aligned (x86): the image is written, not read, here,
// and a read for ownership of each line would double the memory traffic of these pixels.
FIRELOOK_KERNEL_CLONES
void clearRgb(const float* alpha, size_t count, float* rgba) {
#if defined(__SSE__)
    if (reinterpret_cast<uintptr_t>(rgba) % 16 == 0) {
        for (size_t i = 0; i < count; ++i) _mm_stream_ps(rgba + i * 4, _mm_set_ps(alpha[i], 0.0f, 0.0f, 0.0f));
        return;
    }
#endif
    for (size_t i = 0; i < count; ++i) {
        const v4f out = {0.0f, 0.0f, 0.0f, alpha[i]};
        simd::store(rgba + i * 4, out);
    }
}

void checkResident(const BakeDescription& description, const ResidentFrame& f) {
    const size_t pixels = static_cast<size_t>(std::max(f.pixels, 0));
    const size_t planes = 1 + description.alpha_thresholds.size();
    if (f.pixels != description.pixelCount() || f.rank_stride % 8 != 0 || f.rank_stride < f.rank ||
        f.w.size() < pixels * f.rank_stride || f.u_scale.size() < static_cast<size_t>(f.rank_stride) ||
        f.depth_stride < static_cast<int>(planes) || f.mean_depth.size() < pixels * f.depth_stride ||
        f.samples != description.footprint_samples ||
        f.detailed_depth.size() < f.detailed_pixels.size() * f.samples * f.depth_stride || !f.depth_table ||
        f.depth_table->depth.empty() || !validRuns(f.u_runs, pixels) || !validRuns(f.depth_runs, pixels))
        throw Error(ErrorCode::InvalidArgument, "resident frame does not match the description");
}

}  // namespace

float pixelAlpha(const BakeDescription& description, const ResidentFrame& frame, int pixel,
                 const ExtinctionParams& extinction) {
    checkResident(description, frame);
    if (pixel < 0 || pixel >= frame.pixels) throw Error(ErrorCode::InvalidArgument, "pixel out of range");
    float alpha[9];
    residentAlphaSpan(residentAlphaPlan(description, frame, extinction), frame, static_cast<size_t>(pixel), 1, alpha);
    return alpha[0];
}

void reconstructImage(const BakeDescription& description, const ResidentFrame& frame, std::span<const float> z,
                      const ExtinctionParams& extinction, std::span<float> rgba_out) {
    checkResident(description, frame);
    const size_t pixels = static_cast<size_t>(frame.pixels);
    const int rank = frame.rank;
    if (rgba_out.size() < pixels * 4) throw Error(ErrorCode::InvalidArgument, "image output too short");
    if (static_cast<int>(z.size()) < rank * 3)
        throw Error(ErrorCode::InvalidArgument, "coefficients too short");
    if (rank > kMaxVectorRank)
        throw Error(ErrorCode::InvalidArgument, "rank above " + std::to_string(kMaxVectorRank));
    const ResidentAlphaPlan alpha_plan = residentAlphaPlan(description, frame, extinction);
    // z scaled by U's column scales (U = W u_scale), in 8-lane blocks per channel; 0 past the rank.
    constexpr int kMaxBlocks = kMaxVectorRank / 8;
    v8f zblocks[3][kMaxBlocks];
    const int blocks = frame.rank_stride / 8;
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < blocks * 8; ++k)
            zblocks[c][k / 8][k % 8] = k < rank ? z[static_cast<size_t>(k) * 3 + c] * frame.u_scale[k] : 0.0f;
    // Pixels outside u_runs have W = 0: radiance 0, written without reading them.
    constexpr size_t kSpan = 4096;
    float alpha[kSpan + 8];
    for (size_t first = 0; first < pixels; first += kSpan) {
        const size_t count = std::min(kSpan, pixels - first);
        residentAlphaSpan(alpha_plan, frame, first, count, alpha);
        size_t done = first;
        const auto clear = [&](size_t end) { clearRgb(alpha + (done - first), end - done, rgba_out.data() + done * 4); done = end; };
        forRunPieces(frame.u_runs, first, count, [&](size_t a, size_t n) {
            clear(a);
            residentRgbSpan(frame, zblocks[0], zblocks[1], zblocks[2], a, n, alpha + (a - first), rgba_out.data());
            done = a + n;
        });
        clear(first + count);
    }
#if defined(__SSE__)
    _mm_sfence();  // the streamed stores (clearRgb) are seen before anything after this call
#endif
}

}  // namespace firelook::basis
