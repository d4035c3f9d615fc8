#include "basis/recombine.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "basis/coefficients.h"
#include "basis/parameter_grid.h"
#include "basis/simd.h"

namespace firelook::basis {
namespace {

void coefficientsOf(const BakeDescription& description, std::span<const float> svt, int rank, const LookWeights& look,
                    std::span<float> z_out) {
    const int bins = description.bins.count;
    const int lights = static_cast<int>(description.light_directions.size());
    if (static_cast<int>(look.rbf_coefficients.size()) != bins)
        throw std::invalid_argument("look has " + std::to_string(look.rbf_coefficients.size()) +
                                    " emission coefficients, the package has " + std::to_string(bins) +
                                    " bins");
    if (static_cast<int>(look.light_irradiance.size()) != lights)
        throw std::invalid_argument("look has " + std::to_string(look.light_irradiance.size()) +
                                    " light irradiances, the package has " + std::to_string(lights) +
                                    " lights");
    if (static_cast<int>(z_out.size()) < rank * 3)
        throw std::invalid_argument("coefficient output too short");
    if (svt.size() < static_cast<size_t>(description.columnCount()) * std::max(rank, 0))
        throw std::invalid_argument("S V^T too short for the description");

    coefficientKernel(description, svt.data(), rank, look.extinction, look.rbf_coefficients.data(),
                      look.light_irradiance.data(), z_out.data());
}

}  // namespace

void computeCoefficients(const BakeDescription& description, const FrameFactors& factors, const LookWeights& look,
                         std::span<float> z_out) {
    coefficientsOf(description, factors.svt, factors.rank, look, z_out);
}

void computeCoefficients(const BakeDescription& description, const ResidentFrame& frame, const LookWeights& look,
                         std::span<float> z_out) {
    coefficientsOf(description, frame.svt, frame.rank, look, z_out);
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

FIRELOOK_ALWAYS_INLINE void load8(v8f& v, const float* p) { simd::load(v, p); }
FIRELOOK_ALWAYS_INLINE void store8(float* p, const v8f& v) { simd::store(p, v); }

// Optical depths are handled in units of log2: tau2 = tau / ln 2, clamped to [0, kMaxTau2]:
// 2^-125 = 2.4e-38 is still a normal float and 1 - 2^-125 rounds to exactly 1, so the clamp
// changes no alpha.
constexpr float kMaxTau2 = 125.0f;

// What alpha needs: per footprint ray s, O_b(s) and the one or two alpha-threshold layers of
// O_a(s) that bracket T_c (pointers to pixel 0 of ray 0; ray s is `ray_stride` floats further),
// and the weights of tau2 = (a (1 - t) O_a(lower) + a t O_a(upper) + b O_b) / ln 2.
struct AlphaPlan {
    const float* density = nullptr;  // ray s at density + s * pixels
    const float* lower = nullptr;    // ray s at lower + s * ray_stride
    const float* upper = nullptr;    // nullptr when T_c is on or outside the samples: O_a = lower
    size_t pixels = 0;
    size_t ray_stride = 0;  // thresholds * pixels
    int samples = 1;
    float w_lower = 0.0f, w_upper = 0.0f, w_density = 0.0f;
};

// The threshold layers bracketing T_c and the weights of tau2 = (a (1 - t) O_a(lower) +
// a t O_a(upper) + b O_b) / ln 2, for both forms of a frame; `two` is false when T_c is on or
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

AlphaPlan alphaPlan(const BakeDescription& description, const FrameFactors& factors,
                    const ExtinctionParams& extinction) {
    const AlphaWeights w = alphaWeights(description, extinction);
    const SampleBracket& lerp = w.lerp;
    AlphaPlan plan;
    plan.pixels = static_cast<size_t>(factors.pixels);
    plan.ray_stride = description.alpha_thresholds.size() * plan.pixels;
    plan.samples = description.footprint_samples;
    plan.density = factors.depth_b.data();
    plan.lower = factors.depth_a.data() + static_cast<size_t>(lerp.lower) * plan.pixels;
    plan.upper = w.two ? factors.depth_a.data() + static_cast<size_t>(lerp.upper) * plan.pixels : nullptr;
    plan.w_lower = w.w_lower;
    plan.w_upper = w.w_upper;
    plan.w_density = w.w_density;
    return plan;
}

// sum += 1 - 2^-tau2 of one ray for 8 pixels, tau2 = (a O_a + b O_b) / ln 2 as weighted by the
// plan. tau2 < 0 counts as 0 (clear), NaN or above kMaxTau2
// as opaque (alpha exactly 1), as the scalar definition did. 2^-tau2 = 2^-m 2^r with
// m = round(tau2), r = m - tau2 in [-1/2, 1/2] (exact in float), 2^r = 1 + r P(r) with the Cephes
// exp2f polynomial (P of degree 5, minimax on [-1/2, 1/2]; tau2 = 0 gives exactly alpha 0), 2^-m
// from the exponent bits. The polynomial's own relative error is 5e-9; in float arithmetic the
// alpha of one ray is within 7e-8 of 1 - exp(-tau) in double (largest difference over tau in
// [0, 90], tests/basis/recombine_kernel_test.cpp), far below what the half-precision depths already
// carry (relative 2^-11 in tau, up to 2e-4 in alpha). Eigen's vectorised Array::exp would do too,
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

// Throws std::invalid_argument unless the factors hold every depth layer the description implies.
void checkDepths(const BakeDescription& description, const FrameFactors& factors) {
    const size_t rays = static_cast<size_t>(std::max(description.footprint_samples, 0)) *
                        static_cast<size_t>(std::max(factors.pixels, 0));
    if (description.footprint_samples < 1 || description.alpha_thresholds.empty() ||
        factors.depth_b.size() < rays || factors.depth_a.size() < rays * description.alpha_thresholds.size())
        throw std::invalid_argument("optical depth layers do not match the description");
}

// alpha_out[i] = alpha of pixel first + i for i < count; `first` a multiple of 8 and alpha_out
// with room for count rounded up to 8 (it holds the running sums). Ray after ray, each depth layer
// is read in one run over the whole span (a few streams at a time, which the memory system serves
// far better than the 3 x footprint_samples streams of reading all rays of a pixel at once: with
// 16 rays and spans of 4096 pixels the image took 20% less time than with groups of 64 pixels).
// Whole blocks of 8 pixels and the last, partial block (zero-padded copies) each have their own
// copy of the arithmetic, and a pixel always goes through the same one: pixelAlpha evaluates the
// pixel's block of 8 and agrees with reconstructImage bit for bit (with fused multiply-adds in
// the AVX2 build, which copy of the code runs matters).
template <bool kTwoLayers>
FIRELOOK_ALWAYS_INLINE void alphaSpanOf(const AlphaPlan& plan, size_t first, size_t count, float* alpha_out) {
    const v8f zero = {};
    const v8f w_density = zero + plan.w_density, w_lower = zero + plan.w_lower, w_upper = zero + plan.w_upper;
    const size_t whole = count / 8, rest = count % 8;
    std::fill(alpha_out, alpha_out + (whole + (rest ? 1 : 0)) * 8, 0.0f);
    for (int s = 0; s < plan.samples; ++s) {
        const float* density = plan.density + static_cast<size_t>(s) * plan.pixels + first;
        const float* lower = plan.lower + static_cast<size_t>(s) * plan.ray_stride + first;
        const float* upper = kTwoLayers ? plan.upper + static_cast<size_t>(s) * plan.ray_stride + first : lower;
        for (size_t i = 0; i < whole; ++i) {
            v8f d, lo, sum;
            load8(d, density + 8 * i);
            load8(lo, lower + 8 * i);
            load8(sum, alpha_out + 8 * i);
            v8f tau = w_density * d + w_lower * lo;
            if constexpr (kTwoLayers) {
                v8f hi;
                load8(hi, upper + 8 * i);
                tau = tau + w_upper * hi;
            }
            addRayAlpha(sum, tau);
            store8(alpha_out + 8 * i, sum);
        }
        if (rest) {
            float padded[3][8] = {};
            std::copy(density + 8 * whole, density + count, padded[0]);
            std::copy(lower + 8 * whole, lower + count, padded[1]);
            if constexpr (kTwoLayers) std::copy(upper + 8 * whole, upper + count, padded[2]);
            v8f d, lo, sum;
            load8(d, padded[0]);
            load8(lo, padded[1]);
            load8(sum, alpha_out + 8 * whole);
            v8f tau = w_density * d + w_lower * lo;
            if constexpr (kTwoLayers) {
                v8f hi;
                load8(hi, padded[2]);
                tau = tau + w_upper * hi;
            }
            addRayAlpha(sum, tau);
            store8(alpha_out + 8 * whole, sum);
        }
    }
    for (size_t i = 0; i < whole + (rest ? 1 : 0); ++i) {
        v8f sum, alpha;
        load8(sum, alpha_out + 8 * i);
        finishAlpha(alpha, sum, static_cast<float>(plan.samples));
        store8(alpha_out + 8 * i, alpha);
    }
}

// One or two O_a layers per ray, chosen once per call (the one-layer build skips the third stream).
FIRELOOK_KERNEL_CLONES
void alphaSpan(const AlphaPlan& plan, size_t first, size_t count, float* alpha_out) {
    if (plan.upper)
        alphaSpanOf<true>(plan, first, count, alpha_out);
    else
        alphaSpanOf<false>(plan, first, count, alpha_out);
}

// What rgb needs: U (pixel-major float) and z de-interleaved into 8-lane blocks per channel.
// Ranks that are not a multiple of 8 end with one more block: the last 8 values of the U row
// (overlapping the previous block; for rank < 8, the row zero-padded on the left) against z
// blocks whose overlapping lanes are 0, so no value is counted twice.
constexpr int kMaxVectorRank = 1024;  // z blocks live on the stack (12 KiB); larger ranks: scalar

struct RgbPlan {
    const float* u = nullptr;
    int rank = 0;
    int blocks = 0;     // whole 8-lane blocks
    bool tail = false;  // one more, overlapping block
    const v8f* zr = nullptr;  // blocks + tail entries each
    const v8f* zg = nullptr;
    const v8f* zb = nullptr;
};

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

// rgba of one pixel: rgb = U z clamped (negative and non-finite -> 0), then alpha.
FIRELOOK_ALWAYS_INLINE void rgbPixel(const RgbPlan& plan, size_t pixel, float alpha, float* rgba) {
    const size_t rank = static_cast<size_t>(plan.rank);
    const float* u = plan.u + pixel * rank;
    v8f r = {}, g = {}, b = {};
    for (int k = 0; k < plan.blocks; ++k) {
        v8f x;
        load8(x, u + static_cast<size_t>(k) * 8);
        r += x * plan.zr[k];
        g += x * plan.zg[k];
        b += x * plan.zb[k];
    }
    if (plan.tail) {
        v8f x = {};
        if (rank >= 8) {
            load8(x, u + rank - 8);
        } else {
            for (size_t k = 0; k < rank; ++k) x[8 - rank + k] = u[k];
        }
        r += x * plan.zr[plan.blocks];
        g += x * plan.zg[plan.blocks];
        b += x * plan.zb[plan.blocks];
    }
    v4f out;
    sum3(out, r, g, b);
    const v4f zero = {};
    const v4f largest = zero + std::numeric_limits<float>::max();
    out = ((out > zero) & (out <= largest)) ? out : zero;  // NaN, +-inf and negatives -> 0
    out[3] = alpha;
    std::memcpy(rgba + pixel * 4, &out, sizeof out);
}

// rgba for pixels [first, first + count) with their alphas: rgb = U z, clamped.
FIRELOOK_KERNEL_CLONES
void rgbSpan(const RgbPlan& plan, size_t first, size_t count, const float* alpha, float* rgba) {
    const RgbPlan local = plan;
    for (size_t i = 0; i < count; ++i) rgbPixel(local, first + i, alpha[i], rgba);
}

}  // namespace

float pixelAlpha(const BakeDescription& description, const FrameFactors& factors, int pixel,
                 const ExtinctionParams& extinction) {
    checkDepths(description, factors);
    if (pixel < 0 || pixel >= factors.pixels) throw std::invalid_argument("pixel out of range");
    const AlphaPlan plan = alphaPlan(description, factors, extinction);
    // The pixel's block of 8, as reconstructImage evaluates it (see alphaSpanOf).
    const size_t first = static_cast<size_t>(pixel) / 8 * 8;
    float alpha[8];
    alphaSpan(plan, first, std::min<size_t>(8, static_cast<size_t>(factors.pixels) - first), alpha);
    return alpha[static_cast<size_t>(pixel) - first];
}

void reconstructImage(const BakeDescription& description, const FrameFactors& factors,
                      std::span<const float> u_float, std::span<const float> z,
                      const ExtinctionParams& extinction, std::span<float> rgba_out) {
    const int pixels = factors.pixels;
    const int rank = factors.rank;
    if (static_cast<int>(rgba_out.size()) < pixels * 4) throw std::invalid_argument("image output too short");
    if (static_cast<int>(z.size()) < rank * 3) throw std::invalid_argument("coefficients too short");
    if (u_float.size() < static_cast<size_t>(pixels) * rank) throw std::invalid_argument("U too short");
    checkDepths(description, factors);
    if (pixels <= 0) return;

    const AlphaPlan alpha_plan = alphaPlan(description, factors, extinction);

    // z de-interleaved per channel into 8-lane blocks (see RgbPlan).
    constexpr int kMaxBlocks = kMaxVectorRank / 8 + 1;
    v8f zblocks[3][kMaxBlocks];
    RgbPlan plan;
    plan.u = u_float.data();
    plan.rank = rank;
    const bool vector_rank = rank <= kMaxVectorRank;
    if (vector_rank) {
        plan.blocks = rank / 8;
        plan.tail = rank % 8 != 0;
        for (int c = 0; c < 3; ++c) {
            for (int k = 0; k < plan.blocks * 8; ++k) zblocks[c][k / 8][k % 8] = z[k * 3 + c];
            if (plan.tail)
                for (int j = 0; j < 8; ++j)
                    zblocks[c][plan.blocks][j] = j >= 8 - rank % 8 ? z[(rank - 8 + j) * 3 + c] : 0.0f;
        }
        plan.zr = zblocks[0];
        plan.zg = zblocks[1];
        plan.zb = zblocks[2];
    }

    // Spans of kSpan pixels: alpha first (each depth layer read in one run over the span), then
    // rgb (a stream of U). Single-threaded, no allocation; 16 KiB of alpha on the stack.
    // (Interleaving the two in groups of 64 pixels, to overlap the arithmetic of alpha with the
    // stream of U, measured slower here.)
    constexpr size_t kSpan = 4096;
    float alpha[kSpan];
    for (size_t first = 0; first < static_cast<size_t>(pixels); first += kSpan) {
        const size_t count = std::min(kSpan, static_cast<size_t>(pixels) - first);
        alphaSpan(alpha_plan, first, count, alpha);
        if (vector_rank) {
            rgbSpan(plan, first, count, alpha, rgba_out.data());
            continue;
        }
        for (size_t i = 0; i < count; ++i) {  // rank above kMaxVectorRank: the plain sum
            const float* u = u_float.data() + (first + i) * rank;
            float r = 0.0f, g = 0.0f, b = 0.0f;
            for (int k = 0; k < rank; ++k) {
                r += u[k] * z[k * 3 + 0];
                g += u[k] * z[k * 3 + 1];
                b += u[k] * z[k * 3 + 2];
            }
            float* out = rgba_out.data() + (first + i) * 4;
            out[0] = r > 0.0f && std::isfinite(r) ? r : 0.0f;
            out[1] = g > 0.0f && std::isfinite(g) ? g : 0.0f;
            out[2] = b > 0.0f && std::isfinite(b) ? b : 0.0f;
            out[3] = alpha[i];
        }
    }
}

// ---- The resident form (resident_frame.h) ----------------------------------------------------
namespace {

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

// alpha_out[i] = alpha of pixel first + i, for i < count (alpha_out has room for count rounded up
// to 8). Elementwise in the lanes, so a pixel gets the same bits wherever its block starts
// (pixelAlpha evaluates it alone).
FIRELOOK_KERNEL_CLONES
void residentAlphaSpan(const ResidentAlphaPlan& plan, const ResidentFrame& f, size_t first, size_t count,
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
    const auto begin = std::lower_bound(f.detailed_pixels.begin(), f.detailed_pixels.end(), static_cast<int32_t>(first));
    for (auto it = begin; it != f.detailed_pixels.end() && static_cast<size_t>(*it) < first + count; ++it) {
        const size_t index = static_cast<size_t>(it - f.detailed_pixels.begin());
        alpha_out[static_cast<size_t>(*it) - first] =
            detailedAlpha(plan, f.detailed_depth.data() + index * f.samples * stride, f.samples, stride);
    }
}

// rgb = U z for pixels [first, first + count): each pixel's W row (int16, rank_stride) against z
// scaled by u_scale, de-interleaved into 8-lane blocks per channel.
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

void checkResident(const BakeDescription& description, const ResidentFrame& f) {
    const size_t pixels = static_cast<size_t>(std::max(f.pixels, 0));
    const size_t planes = 1 + description.alpha_thresholds.size();
    if (f.pixels != description.pixelCount() || f.rank_stride % 8 != 0 || f.rank_stride < f.rank ||
        f.w.size() < pixels * f.rank_stride || f.u_scale.size() < static_cast<size_t>(f.rank_stride) ||
        f.depth_stride < static_cast<int>(planes) || f.mean_depth.size() < pixels * f.depth_stride ||
        f.samples != description.footprint_samples ||
        f.detailed_depth.size() < f.detailed_pixels.size() * f.samples * f.depth_stride || !f.depth_table ||
        f.depth_table->depth.empty())
        throw std::invalid_argument("resident frame does not match the description");
}

}  // namespace

float pixelAlpha(const BakeDescription& description, const ResidentFrame& frame, int pixel,
                 const ExtinctionParams& extinction) {
    checkResident(description, frame);
    if (pixel < 0 || pixel >= frame.pixels) throw std::invalid_argument("pixel out of range");
    float alpha[8];
    residentAlphaSpan(residentAlphaPlan(description, frame, extinction), frame, static_cast<size_t>(pixel), 1, alpha);
    return alpha[0];
}

void reconstructImage(const BakeDescription& description, const ResidentFrame& frame, std::span<const float> z,
                      const ExtinctionParams& extinction, std::span<float> rgba_out) {
    checkResident(description, frame);
    const size_t pixels = static_cast<size_t>(frame.pixels);
    const int rank = frame.rank;
    if (rgba_out.size() < pixels * 4) throw std::invalid_argument("image output too short");
    if (static_cast<int>(z.size()) < rank * 3) throw std::invalid_argument("coefficients too short");
    if (rank > kMaxVectorRank) throw std::invalid_argument("rank above " + std::to_string(kMaxVectorRank));
    const ResidentAlphaPlan alpha_plan = residentAlphaPlan(description, frame, extinction);
    // z scaled by U's column scales (U = W u_scale), in 8-lane blocks per channel; 0 past the rank.
    constexpr int kMaxBlocks = kMaxVectorRank / 8;
    v8f zblocks[3][kMaxBlocks];
    const int blocks = frame.rank_stride / 8;
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < blocks * 8; ++k)
            zblocks[c][k / 8][k % 8] = k < rank ? z[static_cast<size_t>(k) * 3 + c] * frame.u_scale[k] : 0.0f;
    constexpr size_t kSpan = 4096;
    float alpha[kSpan];
    for (size_t first = 0; first < pixels; first += kSpan) {
        const size_t count = std::min(kSpan, pixels - first);
        residentAlphaSpan(alpha_plan, frame, first, count, alpha);
        residentRgbSpan(frame, zblocks[0], zblocks[1], zblocks[2], first, count, alpha, rgba_out.data());
    }
}

}  // namespace firelook::basis
