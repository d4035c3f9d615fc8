// Coefficients z = S V^T w, reconstruction U z and exact alpha as defined by the reference kernels
// (reference_kernels.h, what the runtime's resident kernels are checked against), on hand-built
// factors whose images can be computed by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/packing.hpp>
#include <limits>
#include <vector>

#include "../support/error_code.h"
#include "reference_kernels.h"

namespace firelook::basis {
namespace {

constexpr int kBins = 3;
constexpr int kLightCount = 1;
constexpr int kPerPoint = kBins + kLightCount;

// 3 bins, one light, T_c in {1, 2}, k_s collapsed at 1, k_f in {1, 3}: 4 grid points, 16 columns.
// A 4x4 image, so that pixels == columns and U can be the identity.
BakeDescription recombineDescription() {
    BakeDescription d;
    d.bins = {0.0, 3.0, kBins};
    d.albedo = 0.5;
    d.axes = {{1.0, 2.0}, {1.0}, {1.0, 3.0}};
    d.alpha_thresholds = {1.0, 1.5, 2.0};
    d.light_directions = {{0.0, -1.0, 0.0}};
    d.width = 4;
    d.height = 4;
    d.frames = {{1, 16}};
    return d;
}

double svtValue(int column, int k) { return 0.1 + 0.01 * column + 0.001 * k * (column % 3); }

// Rank = columns = pixels = 16, U = identity (exact in half precision): pixel p's image is the
// p-th coefficient, so every pixel checks one row of S V^T against the hand-computed sum.
FrameFactors identityFactors(const BakeDescription& d) {
    FrameFactors f;
    f.frame = 1;
    f.pixels = d.pixelCount();
    f.columns = d.columnCount();
    f.rank = f.columns;
    f.u_half.assign(static_cast<size_t>(f.pixels) * f.rank, glm::packHalf1x16(0.0f));
    for (int p = 0; p < f.pixels; ++p)
        f.u_half[static_cast<size_t>(p) * f.rank + p] = glm::packHalf1x16(1.0f);
    f.svt.resize(static_cast<size_t>(f.columns) * f.rank);
    for (int j = 0; j < f.columns; ++j)
        for (int k = 0; k < f.rank; ++k)
            f.svt[static_cast<size_t>(j) * f.rank + k] = static_cast<float>(svtValue(j, k));
    f.depth_b.resize(f.pixels);
    f.depth_a.resize(f.pixels * d.alpha_thresholds.size());
    for (int p = 0; p < f.pixels; ++p) {
        f.depth_b[p] = 0.1f * p;
        for (size_t a = 0; a < d.alpha_thresholds.size(); ++a)
            f.depth_a[a * f.pixels + p] = (static_cast<float>(a) - 1.0f) * 0.05f * p;
    }
    return f;
}

const std::vector<Rgb> kCoefficients = {{1.0f, 2.0f, 3.0f}, {0.5f, 0.0f, 0.25f}, {2.0f, 1.0f, 0.0f}};
const std::vector<Rgb> kIrradiance = {{0.3f, 0.6f, 0.9f}};

std::vector<float> recombineCoefficients(const BakeDescription& d, const FrameFactors& f,
                                const ExtinctionParams& theta, const std::vector<Rgb>& c,
                                const std::vector<Rgb>& e) {
    std::vector<float> z(static_cast<size_t>(f.rank) * 3);
    reference::computeCoefficients(d, f, {theta, c, e}, z);
    return z;
}

// Sums of at most 16 products of O(1) float values: well within 1e-5 relative.
constexpr double kFloatSumTolerance = 1e-5;

TEST(Recombine, ImageIsTheHandComputedWeightedSum) {
    const BakeDescription d = recombineDescription();
    const FrameFactors f = identityFactors(d);
    // T_c = 1.25 is a quarter of the way from 1 to 2; k_f = 2 halfway from 1 to 3.
    const ExtinctionParams theta{1.25, 1.0, 2.0};
    struct Corner {
        int point;
        double weight;
    };
    const Corner corners[4] = {{d.axes.pointIndex(0, 0, 0), 0.75 * 0.5},
                               {d.axes.pointIndex(0, 0, 1), 0.75 * 0.5},
                               {d.axes.pointIndex(1, 0, 0), 0.25 * 0.5},
                               {d.axes.pointIndex(1, 0, 1), 0.25 * 0.5}};
    const std::vector<float> z = recombineCoefficients(d, f, theta, kCoefficients, kIrradiance);
    std::vector<float> rgba(static_cast<size_t>(f.pixels) * 4);
    reference::reconstructImage(d, f, decodeU(f), z, theta, rgba);
    for (int p = 0; p < f.pixels; ++p) {
        for (int ch = 0; ch < 3; ++ch) {
            double expected = 0.0;
            for (const Corner& corner : corners)
                for (int c = 0; c < kPerPoint; ++c) {
                    const double weight = c < kBins ? kCoefficients[c][ch] : kIrradiance[c - kBins][ch];
                    expected += corner.weight * weight * svtValue(corner.point * kPerPoint + c, p);
                }
            EXPECT_NEAR(z[p * 3 + ch], expected, kFloatSumTolerance * expected)
                << "pixel " << p << " ch " << ch;
            EXPECT_NEAR(rgba[p * 4 + ch], expected, kFloatSumTolerance * expected)
                << "pixel " << p << " ch " << ch;
        }
    }
}

TEST(Recombine, CoefficientsAreLinearInEmissionAndIrradiance) {
    const BakeDescription d = recombineDescription();
    const FrameFactors f = identityFactors(d);
    const ExtinctionParams theta{1.7, 1.0, 1.4};
    const std::vector<Rgb> c1 = kCoefficients;
    const std::vector<Rgb> c2 = {{0.0f, 1.0f, 0.5f}, {4.0f, 0.0f, 1.0f}, {0.25f, 0.25f, 3.0f}};
    std::vector<Rgb> c_sum(kBins);
    for (int i = 0; i < kBins; ++i) c_sum[i] = c1[i] + 2.0f * c2[i];
    const std::vector<Rgb> no_light = {Rgb(0.0f)};
    const std::vector<Rgb> no_emission(kBins, Rgb(0.0f));

    const std::vector<float> z1 = recombineCoefficients(d, f, theta, c1, no_light);
    const std::vector<float> z2 = recombineCoefficients(d, f, theta, c2, no_light);
    const std::vector<float> z_sum = recombineCoefficients(d, f, theta, c_sum, no_light);
    const std::vector<float> z_light = recombineCoefficients(d, f, theta, no_emission, kIrradiance);
    const std::vector<float> z_light3 = recombineCoefficients(d, f, theta, no_emission, {3.0f * kIrradiance[0]});
    const std::vector<float> z_all = recombineCoefficients(d, f, theta, c1, kIrradiance);
    for (size_t k = 0; k < z1.size(); ++k) {
        const double lin = z1[k] + 2.0 * z2[k];
        EXPECT_NEAR(z_sum[k], lin, kFloatSumTolerance * std::abs(lin) + 1e-7) << k;
        EXPECT_NEAR(z_light3[k], 3.0 * z_light[k], kFloatSumTolerance * std::abs(z_light[k]) * 3 + 1e-7) << k;
        EXPECT_NEAR(z_all[k], z1[k] + z_light[k], kFloatSumTolerance * std::abs(z_all[k]) + 1e-7) << k;
    }
}

TEST(Recombine, ArgumentCountsAreChecked) {
    const BakeDescription d = recombineDescription();
    const FrameFactors f = identityFactors(d);
    std::vector<float> z(static_cast<size_t>(f.rank) * 3);
    const ExtinctionParams theta{1.0, 1.0, 1.0};
    const std::vector<Rgb> two_bins(2, Rgb(1.0f)), four_bins(4, Rgb(1.0f)), two_lights(2, Rgb(1.0f));
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      reference::computeCoefficients(d, f, {theta, two_bins, kIrradiance}, z));
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      reference::computeCoefficients(d, f, {theta, four_bins, kIrradiance}, z));
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      reference::computeCoefficients(d, f, {theta, kCoefficients, {}}, z));
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      reference::computeCoefficients(d, f, {theta, kCoefficients, two_lights}, z));
    std::vector<float> short_z(static_cast<size_t>(f.rank) * 3 - 1);
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      reference::computeCoefficients(d, f, {theta, kCoefficients, kIrradiance}, short_z));
    try {
        reference::computeCoefficients(d, f, {theta, two_bins, kIrradiance}, z);
    } catch (const firelook::Error& e) {
        EXPECT_EQ(e.code(), firelook::ErrorCode::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("bins"), std::string::npos) << e.what();
    }

    const std::vector<float> u = decodeU(f);
    std::vector<float> rgba(static_cast<size_t>(f.pixels) * 4);
    std::vector<float> short_rgba(rgba.size() - 1);
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      reference::reconstructImage(d, f, u, z, theta, short_rgba));
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      reference::reconstructImage(d, f, u, short_z, theta, rgba));
    EXPECT_ERROR_CODE(
        firelook::ErrorCode::InvalidArgument,
        reference::reconstructImage(d, f, std::span<const float>(u).first(u.size() - 1), z, theta, rgba));
}

TEST(Recombine, NegativeAndNonFiniteRadianceBecomesZero) {
    const BakeDescription d = recombineDescription();
    FrameFactors f = identityFactors(d);
    std::vector<float> u = decodeU(f);
    u[static_cast<size_t>(3) * f.rank + 3] = std::numeric_limits<float>::infinity();
    u[static_cast<size_t>(5) * f.rank + 5] = std::numeric_limits<float>::quiet_NaN();
    // S V^T is positive, so pixel 3 sums to +inf and pixel 5 to NaN.
    f.depth_b[7] = std::numeric_limits<float>::quiet_NaN();
    f.depth_b[8] = 1e30f;
    f.depth_b[9] = std::numeric_limits<float>::infinity();
    const ExtinctionParams theta{1.5, 1.0, 2.0};
    const std::vector<float> z = recombineCoefficients(d, f, theta, kCoefficients, kIrradiance);
    std::vector<float> rgba(static_cast<size_t>(f.pixels) * 4);
    reference::reconstructImage(d, f, u, z, theta, rgba);
    for (size_t i = 0; i < rgba.size(); ++i) {
        EXPECT_TRUE(std::isfinite(rgba[i])) << i;
        EXPECT_GE(rgba[i], 0.0f) << i;
    }
    for (int ch = 0; ch < 3; ++ch) {
        EXPECT_EQ(rgba[3 * 4 + ch], 0.0f);
        EXPECT_EQ(rgba[5 * 4 + ch], 0.0f);
    }
    EXPECT_EQ(rgba[7 * 4 + 3], 1.0f) << "NaN depth: opaque rather than NaN";
    EXPECT_EQ(rgba[8 * 4 + 3], 1.0f);
    EXPECT_EQ(rgba[9 * 4 + 3], 1.0f);

    // All-negative S V^T: every pixel clamps to black.
    FrameFactors negative = identityFactors(d);
    for (float& v : negative.svt) v = -v;
    const std::vector<float> zn = recombineCoefficients(d, negative, theta, kCoefficients, kIrradiance);
    reference::reconstructImage(d, negative, decodeU(negative), zn, theta, rgba);
    for (int p = 0; p < negative.pixels; ++p)
        for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(rgba[p * 4 + ch], 0.0f);
}

TEST(Recombine, PixelAlphaInterpolatesOpticalDepthInThreshold) {
    const BakeDescription d = recombineDescription();
    const FrameFactors f = identityFactors(d);
    std::vector<float> rgba(static_cast<size_t>(f.pixels) * 4);
    for (const ExtinctionParams& theta :
         {ExtinctionParams{1.25, 2.0, 0.5}, ExtinctionParams{1.9, 0.5, 4.0}, ExtinctionParams{1.5, 3.0, 3.0},
          ExtinctionParams{0.0, 1.0, 6.0}, ExtinctionParams{7.0, 5.0, 0.0}}) {
        // O_a by hand: alpha thresholds 1, 1.5, 2, clamped at the ends.
        const double tc = std::clamp(theta.temperature_threshold, 1.0, 2.0);
        const int lower = tc >= 1.5 ? 1 : 0;
        const double t = std::min((tc - d.alpha_thresholds[lower]) / 0.5, 1.0);
        const std::vector<float> z = recombineCoefficients(d, f, theta, kCoefficients, kIrradiance);
        reference::reconstructImage(d, f, decodeU(f), z, theta, rgba);
        for (int p = 0; p < f.pixels; ++p) {
            const double o_a = (1.0 - t) * f.depth_a[lower * f.pixels + p] +
                               t * f.depth_a[std::min(lower + 1, 2) * f.pixels + p];
            const double o_b = f.depth_b[p];
            const double expected = 1.0 - std::exp(-(theta.a() * o_a + theta.b() * o_b));
            // Float depths and exp: a few float ulps.
            EXPECT_NEAR(reference::pixelAlpha(d, f, p, theta), expected, 1e-6) << "pixel " << p << " T_c " << tc;
            EXPECT_EQ(rgba[p * 4 + 3], reference::pixelAlpha(d, f, p, theta)) << "reconstructImage and pixelAlpha agree";
        }
    }
}

TEST(Recombine, RankZeroIsBlackWithAlphaFromDepths) {
    const BakeDescription d = recombineDescription();
    FrameFactors f = identityFactors(d);
    f.rank = 0;
    f.u_half.clear();
    f.svt.clear();
    const ExtinctionParams theta{1.5, 1.0, 2.0};
    std::vector<float> z;
    reference::computeCoefficients(d, f, {theta, kCoefficients, kIrradiance}, z);
    std::vector<float> rgba(static_cast<size_t>(f.pixels) * 4, -1.0f);
    reference::reconstructImage(d, f, decodeU(f), z, theta, rgba);
    for (int p = 0; p < f.pixels; ++p) {
        for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(rgba[p * 4 + ch], 0.0f);
        EXPECT_EQ(rgba[p * 4 + 3], reference::pixelAlpha(d, f, p, theta));
    }
}

TEST(Recombine, AlphaIsTheMeanOverFootprintRays) {
    BakeDescription d = recombineDescription();
    d.footprint_samples = 2;
    FrameFactors f = identityFactors(d);
    // Ray 0 keeps the depths above; ray 1 is clear (alpha 0) for even pixels and opaque for odd ones.
    const size_t pixels = static_cast<size_t>(f.pixels), thresholds = d.alpha_thresholds.size();
    for (size_t p = 0; p < pixels; ++p) {
        f.depth_b.push_back(p % 2 == 0 ? 0.0f : 1e30f);
    }
    f.depth_a.resize(2 * thresholds * pixels, 0.0f);
    const ExtinctionParams theta{1.25, 2.0, 0.5};
    BakeDescription single = recombineDescription();
    FrameFactors first_ray = identityFactors(single);
    std::vector<float> rgba(pixels * 4);
    const std::vector<float> z = recombineCoefficients(d, f, theta, kCoefficients, kIrradiance);
    reference::reconstructImage(d, f, decodeU(f), z, theta, rgba);
    for (int p = 0; p < f.pixels; ++p) {
        const double expected = 0.5 * reference::pixelAlpha(single, first_ray, p, theta) + (p % 2 == 0 ? 0.0 : 0.5);
        // Float sums of two alphas.
        EXPECT_NEAR(reference::pixelAlpha(d, f, p, theta), expected, 1e-6) << "pixel " << p;
        EXPECT_NEAR(rgba[p * 4 + 3], expected, 1e-6) << "pixel " << p;
    }
}

}  // namespace
}  // namespace firelook::basis
