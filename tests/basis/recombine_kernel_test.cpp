// The reconstruction against a plain double-precision implementation of its definition, written
// here: the reference kernels (reference_kernels.h, plain float sums and exp, what the runtime's
// resident kernels are checked against elsewhere) on random data with negative, huge, infinite
// and NaN values, ranks that are not multiples of 8, 1 to 16 footprint rays, and pixel counts that
// leave partial blocks; and the resident kernel's polynomial exp (runtime/basis/recombine.cpp)
// over every code of a depth grid.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "../support/error_code.h"
#include "reference_kernels.h"

namespace firelook::basis {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

struct Random {  // splitmix64 -> [0, 1)
    uint64_t state;
    double next() {
        state += 0x9E3779B97F4A7C15ull;
        uint64_t z = state;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return static_cast<double>((z ^ (z >> 31)) >> 11) * (1.0 / 9007199254740992.0);
    }
    float uniform(float lo, float hi) { return lo + static_cast<float>(next()) * (hi - lo); }
};

struct Case {
    BakeDescription d;
    FrameFactors f;
    std::vector<float> u, z;
};

// width x height pixels, `samples` footprint rays, 5 alpha thresholds (1, 1.25, ..., 2). A few
// pixels get special values: U with +-inf, NaN and 1e20; depths with NaN, +-inf, 1e30 and negatives.
Case makeCase(int width, int height, int rank, int samples, uint64_t seed) {
    Case c;
    Random rng{seed};
    c.d.width = width;
    c.d.height = height;
    c.d.footprint_samples = samples;
    c.d.alpha_thresholds = {1.0, 1.25, 1.5, 1.75, 2.0};
    const size_t pixels = static_cast<size_t>(width) * height, thresholds = c.d.alpha_thresholds.size();
    c.f.pixels = static_cast<int>(pixels);
    c.f.rank = rank;
    c.u.resize(pixels * rank);
    for (float& v : c.u) v = rng.uniform(-0.5f, 0.5f);
    c.z.resize(static_cast<size_t>(rank) * 3);
    for (float& v : c.z) v = rng.uniform(-1.0f, 1.5f);
    c.f.depth_b.resize(pixels * samples);
    c.f.depth_a.resize(pixels * samples * thresholds);
    for (int s = 0; s < samples; ++s)
        for (size_t p = 0; p < pixels; ++p) {
            const float density = rng.uniform(0.0f, 4.0f);
            c.f.depth_b[s * pixels + p] = density;
            for (size_t t = 0; t < thresholds; ++t)  // in [-O_b, O_b], decreasing in T_c
                c.f.depth_a[(s * thresholds + t) * pixels + p] =
                    density * (1.0f - 2.0f * (static_cast<float>(t) + rng.uniform(0.2f, 0.8f)) / thresholds);
        }
    const auto u_at = [&](size_t p, int k) -> float& { return c.u[p * rank + k]; };
    const size_t last = pixels - 1;
    u_at(last, rank - 1) = 1e20f;  // huge but finite: the sum stays finite
    u_at(last / 2, 0) = -1e20f;
    u_at(3 % pixels, 0) = kInf;  // (written last: on tiny images these pixels coincide)
    u_at(5 % pixels, rank - 1) = -kInf;
    u_at(7 % pixels, rank / 2) = kNaN;
    const auto depth = [&](size_t p, int s) -> float& { return c.f.depth_b[s * pixels + p]; };
    depth(11 % pixels, 0) = kNaN;
    depth(13 % pixels, samples - 1) = kInf;
    depth(17 % pixels, 0) = -kInf;
    depth(19 % pixels, samples / 2) = 1e30f;
    depth(23 % pixels, 0) = -3.0f;
    c.f.depth_a[(0 * thresholds + 2) * pixels + (29 % pixels)] = kNaN;
    c.f.depth_a[((samples - 1) * thresholds + 1) * pixels + (31 % pixels)] = -kInf;
    c.f.depth_a[(0 * thresholds + 3) * pixels + last] = 1e30f;
    return c;
}

// The definition, in double. O_a is interpolated between the two threshold layers around T_c, from
// the one layer when T_c is on or outside the samples (a layer with weight 0 is not read).
struct Reference {
    std::vector<double> rgba;
    std::vector<double> rgb_bound;  // |computed - exact| allowed per channel (rounding of the float sum)
};

Reference exactImage(const Case& c, const ExtinctionParams& e) {
    const size_t pixels = static_cast<size_t>(c.f.pixels), thresholds = c.d.alpha_thresholds.size();
    const int rank = c.f.rank, samples = c.d.footprint_samples;
    Reference out{std::vector<double>(pixels * 4), std::vector<double>(pixels * 3)};
    const std::vector<double>& ts = c.d.alpha_thresholds;
    size_t lower = 0, upper = 0;
    double t = 0.0;
    const double tc = e.temperature_threshold;
    if (tc >= ts.back()) {
        lower = upper = thresholds - 1;
    } else if (tc > ts.front()) {
        upper = static_cast<size_t>(std::upper_bound(ts.begin(), ts.end(), tc) - ts.begin());
        lower = upper - 1;
        t = (tc - ts[lower]) / (ts[upper] - ts[lower]);
    }
    for (size_t p = 0; p < pixels; ++p) {
        for (int ch = 0; ch < 3; ++ch) {
            double sum = 0.0, magnitude = 0.0;
            for (int k = 0; k < rank; ++k) {
                const double term = static_cast<double>(c.u[p * rank + k]) * c.z[k * 3 + ch];
                sum += term;
                magnitude += std::fabs(term);
            }
            // A float sum of n terms in any order is within (n - 1) eps sum|term| of the exact one
            // (first-order bound); + 1 for the products' own rounding.
            out.rgb_bound[p * 3 + ch] = (rank + 1) * static_cast<double>(FLT_EPSILON) * magnitude;
            const bool finite = std::isfinite(sum) && std::fabs(sum) <= FLT_MAX;
            out.rgba[p * 4 + ch] = finite && sum > 0.0 ? sum : 0.0;
        }
        double alpha = 0.0;
        for (int s = 0; s < samples; ++s) {
            const float* sigmoid = c.f.depth_a.data() + s * thresholds * pixels;
            const double o_b = c.f.depth_b[s * pixels + p];
            const double o_a = t == 0.0 ? sigmoid[lower * pixels + p]
                                        : (1.0 - t) * sigmoid[lower * pixels + p] + t * sigmoid[upper * pixels + p];
            const double tau = e.a() * o_a + e.b() * o_b;
            alpha += std::isnan(tau) ? 1.0 : tau <= 0.0 ? 0.0 : 1.0 - std::exp(-tau);
        }
        out.rgba[p * 4 + 3] = alpha / samples;
    }
    return out;
}

// The float rounding of the depths' weights and of alpha (the reference sums in double): the
// tolerance the vectorised float kernel once met here with its polynomial exp2 (1.8e-7 measured);
// the resident kernel's polynomial is measured below (ResidentAlphaAccuracyOverTheWholeRange).
constexpr double kAlphaTolerance = 5e-7;

double g_worst_alpha = 0.0, g_worst_rgb = 0.0;  // largest |error| (alpha) and |error| / bound (rgb)

void expectMatchesReference(const Case& c, const ExtinctionParams& e, const char* what) {
    std::vector<float> rgba(static_cast<size_t>(c.f.pixels) * 4, -1.0f);
    reference::reconstructImage(c.d, c.f, c.u, c.z, e, rgba);
    const Reference ref = exactImage(c, e);
    int rgb_failures = 0, alpha_failures = 0;
    for (int p = 0; p < c.f.pixels; ++p) {
        for (int ch = 0; ch < 4; ++ch) {
            const float v = rgba[p * 4 + ch];
            ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << what << " pixel " << p << " ch " << ch << " = " << v;
        }
        ASSERT_LE(rgba[p * 4 + 3], 1.0f) << what << " pixel " << p;
        for (int ch = 0; ch < 3; ++ch) {
            const double expected = ref.rgba[p * 4 + ch];
            // A non-finite sum is 0 in both; a finite one within the rounding bound (clamping at 0
            // can only bring the two closer).
            if (ref.rgb_bound[p * 3 + ch] > 0.0)
                g_worst_rgb = std::max(g_worst_rgb, std::fabs(rgba[p * 4 + ch] - expected) / ref.rgb_bound[p * 3 + ch]);
            if (std::fabs(rgba[p * 4 + ch] - expected) > ref.rgb_bound[p * 3 + ch] + 1e-30 && rgb_failures++ < 5)
                ADD_FAILURE() << what << " pixel " << p << " ch " << ch << ": " << rgba[p * 4 + ch] << " vs "
                              << expected << " (bound " << ref.rgb_bound[p * 3 + ch] << ")";
        }
        g_worst_alpha = std::max(g_worst_alpha, std::fabs(rgba[p * 4 + 3] - ref.rgba[p * 4 + 3]));
        if (std::fabs(rgba[p * 4 + 3] - ref.rgba[p * 4 + 3]) > kAlphaTolerance && alpha_failures++ < 5)
            ADD_FAILURE() << what << " pixel " << p << " alpha " << rgba[p * 4 + 3] << " vs " << ref.rgba[p * 4 + 3];
        // pixelAlpha is the same computation, bit for bit.
        if (rgba[p * 4 + 3] != reference::pixelAlpha(c.d, c.f, p, e) && alpha_failures++ < 5)
            ADD_FAILURE() << what << " pixel " << p << ": pixelAlpha " << reference::pixelAlpha(c.d, c.f, p, e)
                          << " != image alpha " << rgba[p * 4 + 3];
    }
    // The special pixels behave as defined.
    const size_t pixels = static_cast<size_t>(c.f.pixels);
    for (int ch = 0; ch < 3; ++ch) {
        EXPECT_EQ(rgba[(3 % pixels) * 4 + ch], 0.0f) << what << ": +inf in U";
        EXPECT_EQ(rgba[(5 % pixels) * 4 + ch], 0.0f) << what << ": -inf in U";
        EXPECT_EQ(rgba[(7 % pixels) * 4 + ch], 0.0f) << what << ": NaN in U";
    }
}

const ExtinctionParams kLooks[] = {
    {1.375, 3.0, 1.0},   // T_c between samples, k_f < k_s (a < 0)
    {1.5, 0.5, 4.0},     // T_c on a sample
    {0.5, 2.0, 2.0},     // below the samples, a = 0
    {2.5, 10.0, 0.2},    // above the samples
    {1.8, 0.0, 0.0},     // no extinction at all: alpha 0 (or 1 for NaN depths)
};

TEST(RecombineKernel, MatchesScalarReference) {
    // 29 x 11 = 319 pixels: four whole groups of 64, a partial group of 63 (seven blocks of 8 and 7).
    for (const int rank : {1, 7, 8, 13, 64}) {
        for (const int samples : {1, 4, 9, 16}) {
            const Case c = makeCase(29, 11, rank, samples, 1000u * rank + samples);
            for (const ExtinctionParams& e : kLooks) {
                const std::string what = "rank " + std::to_string(rank) + " S " + std::to_string(samples) +
                                         " T_c " + std::to_string(e.temperature_threshold);
                expectMatchesReference(c, e, what.c_str());
            }
        }
    }
    std::printf("largest alpha error %.3g (tolerance %.3g); largest rgb error %.3g of its rounding bound\n",
                g_worst_alpha, kAlphaTolerance, g_worst_rgb);
}

TEST(RecombineKernel, SmallImagesAndLargeRanks) {
    // Fewer pixels than one block; and a rank above the vectorised limit (the plain-sum fallback).
    for (auto [w, h, rank] : {std::tuple{1, 1, 3}, std::tuple{3, 2, 9}, std::tuple{8, 8, 1}, std::tuple{9, 7, 1100}}) {
        const Case c = makeCase(w, h, rank, 4, 7u * rank + w);
        for (const ExtinctionParams& e : kLooks) {
            const std::string what = std::to_string(w) + "x" + std::to_string(h) + " rank " + std::to_string(rank);
            expectMatchesReference(c, e, what.c_str());
        }
    }
}

TEST(RecombineKernel, RankZeroIsBlack) {
    Case c = makeCase(13, 5, 1, 9, 5);
    c.f.rank = 0;
    c.u.clear();
    c.z.clear();
    std::vector<float> rgba(static_cast<size_t>(c.f.pixels) * 4, -1.0f);
    reference::reconstructImage(c.d, c.f, c.u, c.z, kLooks[0], rgba);
    for (int p = 0; p < c.f.pixels; ++p) {
        for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(rgba[p * 4 + ch], 0.0f);
        EXPECT_EQ(rgba[p * 4 + 3], reference::pixelAlpha(c.d, c.f, p, kLooks[0]));
    }
}

// The reference's alpha over the whole range of optical depth, one ray per pixel, against double:
// tau = b O_b swept from 0 to 90 (past the point where alpha is exactly 1 in float).
TEST(RecombineKernel, AlphaAccuracyOverTheWholeRange) {
    const int pixels = 200000;
    Case c;
    c.d.width = pixels;
    c.d.height = 1;
    c.d.alpha_thresholds = {1.0};
    c.f.pixels = pixels;
    c.f.rank = 0;
    c.f.depth_b.resize(pixels);
    c.f.depth_a.assign(pixels, 0.0f);
    const ExtinctionParams e{1.0, 1.0, 1.0};  // a = 0, b = 1: tau = O_b
    for (int p = 0; p < pixels; ++p) c.f.depth_b[p] = 90.0f * static_cast<float>(p) / (pixels - 1);
    std::vector<float> rgba(static_cast<size_t>(pixels) * 4);
    reference::reconstructImage(c.d, c.f, c.u, c.z, e, rgba);
    double worst = 0.0;
    for (int p = 0; p < pixels; ++p) {
        const double tau = c.f.depth_b[p];
        worst = std::max(worst, std::fabs(rgba[p * 4 + 3] - (1.0 - std::exp(-tau))));
    }
    EXPECT_EQ(rgba[3], 0.0f) << "tau = 0 is exactly clear";
    EXPECT_EQ(rgba[(pixels - 1) * 4 + 3], 1.0f);
    // The bound the resident kernel's polynomial meets too (below).
    EXPECT_LT(worst, 1.5e-7) << "largest alpha error " << worst;
    std::printf("alpha: largest error against double 1 - exp(-tau) over tau in [0, 90]: %.3g\n", worst);
}

// The resident kernel's exp approximation over the whole range of optical depth, one ray per
// pixel, against double: every code of a depth grid that reaches far past tau = 90 (where alpha is
// exactly 1 in float), tau = b D[q].
TEST(RecombineKernel, ResidentAlphaAccuracyOverTheWholeRange) {
    const std::shared_ptr<const DepthTable> table = DepthTable::build(1.0 / 4096, 0.01, 1.0);
    const int pixels = static_cast<int>(table->depth.size());
    ASSERT_GT(table->depth.back(), 90.0f);
    BakeDescription d;
    d.width = pixels;
    d.height = 1;
    d.alpha_thresholds = {1.0};
    ResidentFrame f;
    f.pixels = pixels;
    f.depth_stride = 8;
    f.mean_depth.assign(static_cast<size_t>(pixels) * f.depth_stride, 0);
    for (int q = 0; q < pixels; ++q) f.mean_depth[static_cast<size_t>(q) * f.depth_stride] = static_cast<int16_t>(q);
    f.depth_runs.assign(1, PixelRun{0, pixels});
    f.depth_table = table;
    const ExtinctionParams e{1.0, 1.0, 1.0};  // a = 0, b = 1: tau = O_b
    std::vector<float> rgba(static_cast<size_t>(pixels) * 4);
    reconstructImage(d, f, {}, e, rgba);
    double worst = 0.0;
    for (int q = 0; q < pixels; ++q)
        worst = std::max(worst, std::fabs(rgba[q * 4 + 3] - (1.0 - std::exp(-double(table->depth[q])))));
    EXPECT_EQ(rgba[3], 0.0f) << "tau = 0 is exactly clear";
    EXPECT_EQ(rgba[(pixels - 1) * 4 + 3], 1.0f);
    // recombine.cpp documents 7e-8; the same room as above for the baseline build.
    EXPECT_LT(worst, 1.5e-7) << "largest alpha error " << worst;
    std::printf("resident alpha: largest error against double 1 - exp(-tau) over %d depth codes: %.3g\n", pixels,
                worst);
}

TEST(RecombineKernel, DepthLayersAreChecked) {
    Case c = makeCase(8, 4, 8, 4, 3);
    std::vector<float> rgba(static_cast<size_t>(c.f.pixels) * 4);
    Case short_density = c;
    short_density.f.depth_b.pop_back();
    EXPECT_ERROR_CODE(
        firelook::ErrorCode::InvalidArgument,
        reference::reconstructImage(short_density.d, short_density.f, c.u, c.z, kLooks[0], rgba));
    Case short_sigmoid = c;
    short_sigmoid.f.depth_a.pop_back();
    EXPECT_ERROR_CODE(
        firelook::ErrorCode::InvalidArgument,
        reference::reconstructImage(short_sigmoid.d, short_sigmoid.f, c.u, c.z, kLooks[0], rgba));
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      reference::pixelAlpha(short_sigmoid.d, short_sigmoid.f, 0, kLooks[0]));
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, reference::pixelAlpha(c.d, c.f, -1, kLooks[0]));
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      reference::pixelAlpha(c.d, c.f, c.f.pixels, kLooks[0]));
}

}  // namespace
}  // namespace firelook::basis
