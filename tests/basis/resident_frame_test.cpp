// The resident form (runtime/basis/resident_frame.h): what the runtime draws from agrees with the
// float layout the tools and the GPU upload use, payloads of codec version 1 still decode to the
// same values, a reused frame decodes like a fresh one, and damage is refused by name.
#include "basis/resident_frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "basis/frame_codec.h"
#include "basis/recombine.h"
#include "codec_test_frames.h"

namespace firelook::basis {
namespace {

// factors() with every other pixel's rays made equal, so a frame has both detailed pixels and
// pixels that keep their mean ray only.
FrameFactors mixedFactors(const BakeDescription& d, int rank, uint32_t seed) {
    FrameFactors f = factors(d, rank, seed);
    const size_t pixels = static_cast<size_t>(f.pixels), thresholds = d.alpha_thresholds.size();
    for (size_t p = 0; p < pixels; p += 2)
        for (int s = 1; s < d.footprint_samples; ++s) {
            f.depth_density[s * pixels + p] = f.depth_density[p];
            for (size_t j = 0; j < thresholds; ++j)
                f.depth_sigmoid[(s * thresholds + j) * pixels + p] = f.depth_sigmoid[j * pixels + p];
        }
    return f;
}

ResidentFrame decode(const BakeDescription& d, const EncodedFrame& e, int rank) {
    return decodeResidentFrame(d, 3, rank, e.u, e.svt, e.depths, "test", std::pmr::get_default_resource(), nullptr);
}

std::vector<float> coefficients(const BakeDescription& d, const ResidentFrame& f, const ExtinctionParams& e) {
    const std::vector<Rgb> rbf = {{1.0f, 0.5f, 0.2f}, {0.3f, 2.0f, 0.1f}, {0.0f, 0.4f, 1.5f}};
    const std::vector<Rgb> lights = {{0.7f, 0.7f, 0.9f}};
    std::vector<float> z(static_cast<size_t>(f.rank) * 3);
    computeCoefficients(d, f, LookWeights{e, rbf, lights}, z);
    return z;
}

TEST(ResidentFrame, ReconstructsAsTheExpandedFrame) {
    for (const int samples : {1, 4, 9, 6}) {
        const BakeDescription d = description(13, 7, samples);
        const int rank = 11;  // two 8-lane blocks, the second partial
        const EncodedFrame encoded = encodeFrame(d, mixedFactors(d, rank, 5 + samples), {});
        const ResidentFrame resident = decode(d, encoded, rank);
        if (samples > 1) {
            EXPECT_GT(resident.detailed_pixels.size(), 0u) << samples;
            EXPECT_LT(resident.detailed_pixels.size(), size_t(d.pixelCount())) << samples;
        }
        const FrameFactors expanded = expandFrame(d, resident);
        const std::vector<float> u = decodeU(expanded);
        for (const ExtinctionParams e : {ExtinctionParams{1.1f, 3.0f, 1.7f}, ExtinctionParams{2.0f, 16.0f, 0.5f},
                                         ExtinctionParams{0.5f, 2.0f, 4.0f}, ExtinctionParams{1.6f, 5.0f, 2.0f}}) {
            const std::vector<float> z = coefficients(d, resident, e);
            std::vector<float> a(size_t(d.pixelCount()) * 4), b(a.size());
            reconstructImage(d, resident, z, e, a);
            reconstructImage(d, expanded, u, z, e, b);
            for (int p = 0; p < d.pixelCount(); ++p) {
                // The expanded U is the resident one rounded to half (relative 2^-11 per value),
                // so each channel may differ by 2^-11 sum_k |U z_k|, plus float rounding.
                for (int c = 0; c < 3; ++c) {
                    double bound = 0.0;
                    for (int k = 0; k < rank; ++k) bound += std::abs(u[size_t(p) * rank + k] * z[size_t(k) * 3 + c]);
                    EXPECT_NEAR(a[p * 4 + c], b[p * 4 + c], bound * (1.0 / 2048) + 1e-6) << samples << " " << p;
                }
                // Alpha from the same codes and table; the FrameFactors path averages a
                // mean-ray pixel's identical rays, so float rounding of that mean only.
                EXPECT_NEAR(a[p * 4 + 3], b[p * 4 + 3], 1e-6) << samples << " " << p;
                EXPECT_EQ(pixelAlpha(d, resident, p, e), a[p * 4 + 3]) << samples << " " << p;  // bit for bit
                EXPECT_TRUE(std::isfinite(a[p * 4 + 0]) && std::isfinite(a[p * 4 + 3]));
            }
        }
    }
}

// tests/data/basis/codec1_frames.bin holds the three payloads the codec-1 encoder (before the
// payloads stored each item's codes together) wrote for factors(description(13, 7, S), 4, 11 + S)
// at alpha_error 0.002, footprint_error 0.001, for S = 9 and 6. The quantisation is unchanged
// since, so today's payloads of the same factors must decode to exactly the same values.
TEST(ResidentFrame, DecodesCodec1Payloads) {
    std::ifstream in(FIRELOOK_TEST_DATA_DIR "/basis/codec1_frames.bin", std::ios::binary);
    ASSERT_TRUE(in) << "tests/data/basis/codec1_frames.bin";
    const std::vector<char> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    size_t at = 0;
    auto u32 = [&] {
        uint32_t v = 0;
        EXPECT_LE(at + 4, file.size());
        std::memcpy(&v, file.data() + at, 4);
        at += 4;
        return v;
    };
    auto payload = [&] {
        const uint32_t n = u32();
        const auto* p = reinterpret_cast<const std::byte*>(file.data() + at);
        at += n;
        return std::vector<std::byte>(p, p + n);
    };
    int cases = 0;
    while (at < file.size()) {
        const int samples = static_cast<int>(u32()), rank = static_cast<int>(u32());
        const std::vector<std::byte> u = payload(), svt = payload(), depths = payload();
        ASSERT_LE(at, file.size());
        const BakeDescription d = description(13, 7, samples);
        FrameCodecSettings settings;
        settings.alpha_error = 0.002;
        settings.footprint_error = 0.001;
        const EncodedFrame today = encodeFrame(d, factors(d, rank, 11 + samples), settings);
        EXPECT_NE(today.u, u) << "the codec-1 fixture should differ from today's bytes";
        const ResidentFrame old_frame =
            decodeResidentFrame(d, 3, rank, u, svt, depths, "codec1", std::pmr::get_default_resource(), nullptr);
        const ResidentFrame new_frame = decode(d, today, rank);
        EXPECT_TRUE(std::equal(old_frame.w.begin(), old_frame.w.end(), new_frame.w.begin(), new_frame.w.end()));
        EXPECT_TRUE(std::equal(old_frame.svt.begin(), old_frame.svt.end(), new_frame.svt.begin(), new_frame.svt.end()));
        EXPECT_TRUE(std::equal(old_frame.mean_depth.begin(), old_frame.mean_depth.end(), new_frame.mean_depth.begin(),
                               new_frame.mean_depth.end()));
        EXPECT_TRUE(std::equal(old_frame.detailed_depth.begin(), old_frame.detailed_depth.end(),
                               new_frame.detailed_depth.begin(), new_frame.detailed_depth.end()));
        EXPECT_EQ(old_frame.detailed_pixels.size(), new_frame.detailed_pixels.size());
        EXPECT_GT(old_frame.detailed_pixels.size(), 0u);
        ++cases;
    }
    EXPECT_EQ(cases, 2);
}

TEST(ResidentFrame, AReusedFrameDecodesLikeAFreshOne) {
    const BakeDescription d = description(16, 9, 4);
    const EncodedFrame big = encodeFrame(d, mixedFactors(d, 13, 1), {});
    const EncodedFrame small = encodeFrame(d, mixedFactors(d, 5, 2), {});
    ResidentFrame reused = decode(d, big, 13);
    const std::shared_ptr<const DepthTable> table = reused.depth_table;
    const int16_t* w = reused.w.data();
    decodeResidentFrame(d, 4, 5, small.u, small.svt, small.depths, "test", reused);
    const ResidentFrame fresh = decode(d, small, 5);
    EXPECT_EQ(reused.w.data(), w);                // the buffers were reused
    EXPECT_EQ(reused.depth_table.get(), table.get());  // and the depth table (the same grid)
    EXPECT_EQ(reused.rank, 5);
    EXPECT_EQ(reused.rank_stride, fresh.rank_stride);
    EXPECT_TRUE(std::equal(reused.w.begin(), reused.w.end(), fresh.w.begin(), fresh.w.end()));
    EXPECT_TRUE(std::equal(reused.mean_depth.begin(), reused.mean_depth.end(), fresh.mean_depth.begin(),
                           fresh.mean_depth.end()));
    EXPECT_TRUE(std::equal(reused.detailed_pixels.begin(), reused.detailed_pixels.end(),
                           fresh.detailed_pixels.begin(), fresh.detailed_pixels.end()));
    EXPECT_TRUE(std::equal(reused.detailed_depth.begin(), reused.detailed_depth.end(), fresh.detailed_depth.begin(),
                           fresh.detailed_depth.end()));
    const ExtinctionParams e{1.3f, 4.0f, 2.0f};
    std::vector<float> a(size_t(d.pixelCount()) * 4), b(a.size());
    reconstructImage(d, reused, coefficients(d, reused, e), e, a);
    reconstructImage(d, fresh, coefficients(d, fresh, e), e, b);
    EXPECT_EQ(a, b);
}

TEST(ResidentFrame, DamageIsRefusedByName) {
    const BakeDescription d = description(8, 5, 4);
    const EncodedFrame e = encodeFrame(d, mixedFactors(d, 3, 9), {});
    auto failure = [&](std::vector<std::byte> u, std::vector<std::byte> depths) {
        try {
            decodeResidentFrame(d, 3, 3, u, e.svt, depths, "pkg.firelook", std::pmr::get_default_resource(), nullptr);
        } catch (const std::runtime_error& error) {
            return std::string(error.what());
        }
        return std::string("no error");
    };
    std::vector<std::byte> short_u(e.u.begin(), e.u.end() - 1);
    EXPECT_NE(failure(short_u, e.depths).find("pkg.firelook: frame 3 UFAC section ends early"), std::string::npos);
    std::vector<std::byte> flagged = e.depths;
    flagged[4 + 4 + 8 + 8 + 8] = std::byte{7};  // the first pixel flag, after the header
    EXPECT_NE(failure(e.u, flagged).find("invalid pixel flag"), std::string::npos);
    std::vector<std::byte> versioned = e.u;
    versioned[0] = std::byte{9};
    EXPECT_NE(failure(versioned, e.depths).find("unknown codec version"), std::string::npos);
}

}  // namespace
}  // namespace firelook::basis
