// The frame codec (runtime/basis/frame_codec.h): the error bounds it promises hold for any look in
// the axes' range, its bytes are deterministic, and damaged payloads are refused by name.
#include "basis/frame_codec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <glm/gtc/packing.hpp>
#include <random>

#include "../support/error_code.h"
#include "basis/source_balance.h"
#include "codec_test_frames.h"
#include "reference_kernels.h"

namespace firelook::basis {
namespace {

TEST(DepthCompanding, InverseAndSlopeBound) {
    const DepthCompanding g = DepthCompanding::forAxes({{1.0}, {2.0, 16.0}, {0.5, 4.0}});
    EXPECT_DOUBLE_EQ(g.k_lo, 0.5);
    EXPECT_DOUBLE_EQ(g.k_hi, 16.0);
    EXPECT_DOUBLE_EQ(g.alphaFactor(), 2.0);  // max k_f / min k_s
    double previous = -1.0;
    for (double o = 0.0; o < 200.0; o = o * 1.07 + 1e-4) {
        const double y = g.forward(o);
        EXPECT_GE(y, previous) << o;  // strictly increasing, but saturating in double past ~70 / k_lo
        EXPECT_LE(y, g.limit());
        if (o < 60.0) {
            EXPECT_GT(y, previous) << o;
        }
        previous = y;
        // g' >= k e^(-k o) for every k in [k_lo, k_hi] (what the alpha bound rests on), from the
        // closed form of the maximum; checked where double resolves g (g' above 1e-7).
        double slope_bound = 0.0;
        for (double k = g.k_lo; k <= g.k_hi * (1 + 1e-9); k += (g.k_hi - g.k_lo) / 1000)
            slope_bound = std::max(slope_bound, k * std::exp(-k * o));
        if (slope_bound < 1e-7) continue;
        EXPECT_NEAR(g.inverse(y), o, 1e-13 / slope_bound + 1e-12 * o) << o;
        const double h = 1e-5 * (1.0 + o);
        const double slope = (g.forward(o + h) - g.forward(o - std::min(o, h))) / (h + std::min(o, h));
        EXPECT_GE(slope * (1.0 + 1e-3), slope_bound) << o;
    }
    EXPECT_EQ(g.inverse(g.limit()), INFINITY);
}

// For every look on and between the grid points, the alpha of every pixel moves by at most the
// bound the codec reports (quantisation plus the footprint's mean-ray test), and the bound is the
// one asked for. Without a footprint tolerance every ray that differs is kept.
TEST(FrameCodec, AlphaWithinTheBoundForAnyLook) {
    for (const int samples : {1, 4, 9, 6})  // 6: not a square, stored as stacked images
    for (const double footprint_error : {0.0, 0.001}) {
        const BakeDescription d = codecDescription(13, 7, samples);
        const FrameFactors original = codecFactors(d, 4, 11 + samples);
        FrameCodecSettings settings;
        settings.alpha_error = 0.002;
        settings.footprint_error = footprint_error;
        const EncodedFrame encoded = encodeFrame(d, original, settings);
        EXPECT_DOUBLE_EQ(encoded.alpha_bound, 0.002 + footprint_error);
        if (footprint_error == 0.0 && samples > 1) {
            EXPECT_GT(encoded.detailed_pixels, size_t(d.pixelCount() / 2));
        }
        const FrameFactors decoded = decodeFrame(d, 3, 4, encoded.u, encoded.svt, encoded.depths, "test");
        for (const float ks : {2.0f, 3.0f, 16.0f})
            for (const float kf : {0.5f, 1.7f, 4.0f})
                for (const float tc : {1.0f, 1.1f, 1.6f, 2.0f}) {
                    const ExtinctionParams e{tc, ks, kf};
                    double worst = 0.0;
                    for (int p = 0; p < d.pixelCount(); ++p)
                        worst = std::max(worst, double(std::abs(reference::pixelAlpha(d, original, p, e) -
                                                                reference::pixelAlpha(d, decoded, p, e))));
                    // 1e-6: float rounding of the two alpha evaluations.
                    EXPECT_LE(worst, encoded.alpha_bound + 1e-6) << samples << " " << ks << " " << kf << " " << tc;
                }
        for (float v : decoded.depth_b) EXPECT_TRUE(std::isfinite(v));
        for (float v : decoded.depth_a) EXPECT_TRUE(std::isfinite(v));
    }
}

// U: every value of W = U S within half a grid step (plus the half rounding of the decoded U);
// S V^T within half of its own step; the measured Frobenius errors near their targets.
TEST(FrameCodec, UOnItsGridAndSvtExact) {
    const BakeDescription d = codecDescription(32, 24, 1);
    const FrameFactors original = codecFactors(d, 6, 5);
    FrameCodecSettings settings;
    settings.basis_error = 0.001;
    const EncodedFrame encoded = encodeFrame(d, original, settings);
    const FrameFactors decoded = decodeFrame(d, 3, 6, encoded.u, encoded.svt, encoded.depths, "test");
    ASSERT_EQ(decoded.u_half.size(), original.u_half.size());
    std::vector<double> sigma(6, 0.0);
    for (int j = 0; j < d.columnCount(); ++j)
        for (int k = 0; k < 6; ++k) sigma[k] += double(original.svt[j * 6 + k]) * original.svt[j * 6 + k];
    for (double& s : sigma) s = std::sqrt(s);
    for (size_t i = 0; i < original.u_half.size(); ++i) {
        const double a = glm::unpackHalf1x16(original.u_half[i]), b = glm::unpackHalf1x16(decoded.u_half[i]);
        EXPECT_LE(std::abs(a - b) * sigma[i % 6], 0.5 * encoded.u_step * (1 + 1e-6) + std::abs(b) * 0x1p-11 * sigma[i % 6]) << i;
    }
    // The step is chosen for the expected error of rounding every value; a fifth of U is 0 here
    // and rounds exactly, so the measured error lies below the target (and not far below).
    // U and S V^T share the basis error, half its square each.
    EXPECT_LE(encoded.u_error, settings.basis_error / std::sqrt(2.0));
    EXPECT_GE(encoded.u_error, 0.5 * settings.basis_error / std::sqrt(2.0));
    EXPECT_LE(std::hypot(encoded.u_error, encoded.svt_error), settings.basis_error);
    for (size_t i = 0; i < original.svt.size(); ++i)
        EXPECT_LE(std::abs(decoded.svt[i] - original.svt[i]), 0.5 * encoded.svt_step * (1 + 1e-6)) << i;
}

TEST(FrameCodec, EverySourceKeepsItsShareOfTheBound) {
    // The light's columns 1e-6 of the emission's (issue 28: clamped extreme densities made the
    // emission 1e5 times the sun). One S V^T step for all columns rounded every light coefficient
    // to 0; one step per column kind (basis/source_balance.h) keeps the light within
    // kMaxSourceRatio times the bound, and the emission within the bound.
    const BakeDescription d = codecDescription(32, 24, 1);
    FrameFactors original = codecFactors(d, 6, 5);
    const int kinds = d.columnsPerPoint(), light = d.bins.count;  // the one light's column kind
    for (int j = 0; j < d.columnCount(); ++j)
        if (j % kinds == light)
            for (int k = 0; k < 6; ++k) original.svt[j * 6 + k] *= 1e-6f;
    FrameCodecSettings settings;
    settings.basis_error = 0.001;
    const EncodedFrame encoded = encodeFrame(d, original, settings);
    const FrameFactors decoded = decodeFrame(d, 3, 6, encoded.u, encoded.svt, encoded.depths, "test");
    double error2[2] = {}, norm2[2] = {};
    for (int j = 0; j < d.columnCount(); ++j)
        for (int k = 0; k < 6; ++k) {
            const int source = j % kinds == light ? 1 : 0;
            const double a = original.svt[j * 6 + k], b = decoded.svt[j * 6 + k];
            error2[source] += (a - b) * (a - b);
            norm2[source] += a * a;
        }
    ASSERT_GT(norm2[1], 0.0);
    EXPECT_LE(std::sqrt(error2[0] / norm2[0]), settings.basis_error) << "emission";
    EXPECT_LE(std::sqrt(error2[1] / norm2[1]), kMaxSourceRatio * settings.basis_error) << "light";
    EXPECT_LE(std::hypot(encoded.u_error, encoded.svt_error), settings.basis_error);
}

TEST(FrameCodec, SameBytesAndDamageRefused) {
    const BakeDescription d = codecDescription(9, 5, 4);
    const FrameFactors f = codecFactors(d, 3, 2);
    const EncodedFrame a = encodeFrame(d, f, {}), b = encodeFrame(d, f, {});
    EXPECT_EQ(a.u, b.u);
    EXPECT_EQ(a.svt, b.svt);
    EXPECT_EQ(a.depths, b.depths);
    auto error = [&](std::vector<std::byte> u, std::vector<std::byte> svt, std::vector<std::byte> depths, int rank) {
        try {
            decodeFrame(d, 3, rank, u, svt, depths, "pkg.firelook");
        } catch (const std::runtime_error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(error(a.u, a.svt, a.depths, 3), "");
    std::vector<std::byte> short_u(a.u.begin(), a.u.end() - 1);
    EXPECT_NE(error(short_u, a.svt, a.depths, 3).find("pkg.firelook: frame 3 UFAC section ends early"), std::string::npos);
    EXPECT_NE(error(a.u, a.svt, a.depths, 2).find("another rank"), std::string::npos);
    std::vector<std::byte> long_svt = a.svt;
    long_svt.push_back(std::byte{0});
    EXPECT_NE(error(a.u, long_svt, a.depths, 3).find("SVTF section has 1 bytes too many"), std::string::npos);
    std::vector<std::byte> bad_depths = a.depths;
    bad_depths[0] = std::byte{9};
    EXPECT_NE(error(a.u, a.svt, bad_depths, 3).find("ODEP section has an unknown codec version"), std::string::npos);
    std::vector<std::byte> bad_step = a.depths;
    const double zero = 0.0;
    std::memcpy(bad_step.data() + 8, &zero, 8);
    EXPECT_NE(error(a.u, a.svt, bad_step, 3).find("invalid depth quantisation"), std::string::npos);
}

// A bound finer than 2^15 levels can give is not promised: the codec takes its finest grid and
// reports the bound that grid gives, which the alpha of every pixel still keeps.
TEST(FrameCodec, ReportsTheBoundItCanKeep) {
    BakeDescription d = codecDescription(6, 5, 4);
    d.axes.smoke_extinction = {0.0, 2.0};  // k_s = 0 beside k_f = 4
    const FrameFactors original = codecFactors(d, 1, 3);
    FrameCodecSettings tight;
    tight.alpha_error = 1e-7;
    tight.footprint_error = 0.0;
    const EncodedFrame encoded = encodeFrame(d, original, tight);
    EXPECT_GT(encoded.alpha_bound, 1e-7);
    const FrameFactors decoded = decodeFrame(d, 3, 1, encoded.u, encoded.svt, encoded.depths, "test");
    for (const float ks : {0.0f, 1.0f, 2.0f})
        for (const float kf : {0.5f, 4.0f})
            for (int p = 0; p < d.pixelCount(); ++p) {
                const ExtinctionParams e{1.3, ks, kf};
                EXPECT_LE(std::abs(reference::pixelAlpha(d, original, p, e) - reference::pixelAlpha(d, decoded, p, e)),
                          encoded.alpha_bound + 1e-6);
            }
    FrameCodecSettings zero;
    zero.basis_error = 0.0;
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, encodeFrame(d, original, zero));
}

}  // namespace
}  // namespace firelook::basis
