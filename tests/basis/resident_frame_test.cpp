// The resident form (runtime/basis/resident_frame.h): what the runtime draws from agrees with the
// float layout the tools and the GPU upload use, payloads of codec version 1 still decode to the
// same values, a reused frame decodes like a fresh one, and damage is refused by name.
#include "basis/resident_frame.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <glm/gtc/packing.hpp>
#include <string>

#include "../support/error_code.h"
#include "basis/frame_codec.h"
#include "basis/recombine.h"
#include "codec_test_frames.h"
#include "reference_kernels.h"

namespace firelook::basis {
namespace {

// codecFactors() with every other pixel's rays made equal, so a frame has both detailed pixels and
// pixels that keep their mean ray only.
FrameFactors mixedFactors(const BakeDescription& d, int rank, uint32_t seed) {
    FrameFactors f = codecFactors(d, rank, seed);
    const size_t pixels = static_cast<size_t>(f.pixels), thresholds = d.alpha_thresholds.size();
    for (size_t p = 0; p < pixels; p += 2)
        for (int s = 1; s < d.footprint_samples; ++s) {
            f.depth_b[s * pixels + p] = f.depth_b[p];
            for (size_t j = 0; j < thresholds; ++j)
                f.depth_a[(s * thresholds + j) * pixels + p] = f.depth_a[j * pixels + p];
        }
    return f;
}

ResidentFrame decode(const BakeDescription& d, const EncodedFrame& e, int rank) {
    return decodeResidentFrame(d, 3, rank, e.u, e.svt, e.depths, "test", std::pmr::get_default_resource(), nullptr);
}

std::vector<float> residentCoefficients(const BakeDescription& d, const ResidentFrame& f, const ExtinctionParams& e) {
    const std::vector<Rgb> rbf = {{1.0f, 0.5f, 0.2f}, {0.3f, 2.0f, 0.1f}, {0.0f, 0.4f, 1.5f}};
    const std::vector<Rgb> lights = {{0.7f, 0.7f, 0.9f}};
    std::vector<float> z(static_cast<size_t>(f.rank) * 3);
    computeCoefficients(d, f, LookWeights{e, rbf, lights}, z);
    return z;
}

TEST(ResidentFrame, ReconstructsAsTheExpandedFrame) {
    for (const int samples : {1, 4, 9, 6}) {
        const BakeDescription d = codecDescription(13, 7, samples);
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
            const std::vector<float> z = residentCoefficients(d, resident, e);
            std::vector<float> a(size_t(d.pixelCount()) * 4), b(a.size());
            reconstructImage(d, resident, z, e, a);
            reference::reconstructImage(d, expanded, u, z, e, b);
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

// tests/data/basis/codec1_frames.bin, codec2_frames.bin and codec3_frames.bin hold the three
// payloads the encoders of codec versions 1 (plane after plane), 2 (each item's codes together, as
// two byte planes) and 3 (one S V^T step; written by commit b66cc3c's encodeFrame) wrote for
// codecFactors(codecDescription(13, 7, S), 4, 11 + S) at alpha_error 0.002, footprint_error 0.001,
// for S = 9 and 6: u32 S, u32 rank, then each payload as u32 size and bytes. The quantisation is
// unchanged since for factors whose sources lie within kMaxSourceRatio (these do), so today's
// payloads of the same factors must decode to exactly the same values.
void expectOldPayloadsDecode(const char* name, uint32_t version) {
    std::ifstream in(std::string(FIRELOOK_TEST_DATA_DIR "/basis/") + name, std::ios::binary);
    ASSERT_TRUE(in) << name;
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
    auto versionOf = [](const std::vector<std::byte>& payload) {
        uint32_t v = 0;
        if (payload.size() >= 4) std::memcpy(&v, payload.data(), 4);
        return v;
    };
    int cases = 0;
    while (at < file.size()) {
        const int samples = static_cast<int>(u32()), rank = static_cast<int>(u32());
        const std::vector<std::byte> u = payload(), svt = payload(), depths = payload();
        ASSERT_LE(at, file.size());
        EXPECT_EQ(versionOf(u), version) << name;
        EXPECT_EQ(versionOf(depths), version) << name;
        const BakeDescription d = codecDescription(13, 7, samples);
        FrameCodecSettings settings;
        settings.alpha_error = 0.002;
        settings.footprint_error = 0.001;
        const EncodedFrame today = encodeFrame(d, codecFactors(d, rank, 11 + samples), settings);
        EXPECT_NE(today.u, u) << name << " should differ from today's bytes";
        const ResidentFrame old_frame =
            decodeResidentFrame(d, 3, rank, u, svt, depths, name, std::pmr::get_default_resource(), nullptr);
        const ResidentFrame new_frame = decode(d, today, rank);
        EXPECT_TRUE(std::equal(old_frame.w.begin(), old_frame.w.end(), new_frame.w.begin(), new_frame.w.end()));
        EXPECT_TRUE(std::equal(old_frame.svt.begin(), old_frame.svt.end(), new_frame.svt.begin(), new_frame.svt.end()));
        EXPECT_TRUE(std::equal(old_frame.mean_depth.begin(), old_frame.mean_depth.end(), new_frame.mean_depth.begin(),
                               new_frame.mean_depth.end()));
        EXPECT_TRUE(std::equal(old_frame.detailed_depth.begin(), old_frame.detailed_depth.end(),
                               new_frame.detailed_depth.begin(), new_frame.detailed_depth.end()));
        EXPECT_TRUE(std::equal(old_frame.detailed_pixels.begin(), old_frame.detailed_pixels.end(),
                               new_frame.detailed_pixels.begin(), new_frame.detailed_pixels.end()));
        EXPECT_GT(old_frame.detailed_pixels.size(), 0u);
        ++cases;
    }
    EXPECT_EQ(cases, 2) << name;
}

TEST(ResidentFrame, DecodesCodec1Payloads) { expectOldPayloadsDecode("codec1_frames.bin", 1); }
TEST(ResidentFrame, DecodesCodec2Payloads) { expectOldPayloadsDecode("codec2_frames.bin", 2); }
TEST(ResidentFrame, DecodesCodec3Payloads) { expectOldPayloadsDecode("codec3_frames.bin", 3); }

TEST(ResidentFrame, AReusedFrameDecodesLikeAFreshOne) {
    const BakeDescription d = codecDescription(16, 9, 4);
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
    reconstructImage(d, reused, residentCoefficients(d, reused, e), e, a);
    reconstructImage(d, fresh, residentCoefficients(d, fresh, e), e, b);
    EXPECT_EQ(a, b);
}

// codecFactors() inside a disc only, all 0 outside (no U, no depth), as a fire's footprint leaves most
// of a frame; `radius` 0 leaves nothing, a large one everything.
FrameFactors discFactors(const BakeDescription& d, int rank, uint32_t seed, double radius) {
    FrameFactors f = mixedFactors(d, rank, seed);
    const size_t pixels = static_cast<size_t>(f.pixels), thresholds = d.alpha_thresholds.size();
    for (size_t p = 0; p < pixels; ++p) {
        const double x = double(p % d.width) - 0.4 * d.width, y = double(p / d.width) - 0.5 * d.height;
        if (std::hypot(x, y) <= radius) continue;
        for (int k = 0; k < rank; ++k) f.u_half[p * rank + k] = 0;
        for (int s = 0; s < d.footprint_samples; ++s) {
            f.depth_b[s * pixels + p] = 0.0f;
            for (size_t j = 0; j < thresholds; ++j) f.depth_a[(s * thresholds + j) * pixels + p] = 0.0f;
        }
    }
    return f;
}

// Version 3 codes only the occupied pixels (a W row or a mean ray not all 0); the others decode
// to 0 even over a frame that held values there, and the frame reconstructs as its expansion.
TEST(ResidentFrame, EmptyPixelsAreLeftOutAndDecodeToZero) {
    const BakeDescription d = codecDescription(23, 17, 4);
    const int rank = 9;
    const EncodedFrame full = encodeFrame(d, mixedFactors(d, rank, 3), {});
    for (const double radius : {0.0, 2.0, 6.5, 100.0}) {
        const FrameFactors original = discFactors(d, rank, 3, radius);
        const EncodedFrame encoded = encodeFrame(d, original, {});
        ResidentFrame f = decode(d, full, rank);  // non-zero everywhere before
        decodeResidentFrame(d, 3, rank, encoded.u, encoded.svt, encoded.depths, "test", f);
        const ResidentFrame fresh = decode(d, encoded, rank);
        EXPECT_TRUE(std::equal(f.w.begin(), f.w.end(), fresh.w.begin(), fresh.w.end())) << radius;
        EXPECT_TRUE(std::equal(f.mean_depth.begin(), f.mean_depth.end(), fresh.mean_depth.begin(),
                               fresh.mean_depth.end())) << radius;
        size_t occupied_u = 0, occupied_depth = 0;
        for (int p = 0; p < d.pixelCount(); ++p) {
            bool any_u = false, any_depth = false;
            for (int k = 0; k < rank; ++k) {
                const int16_t w = f.w[size_t(p) * f.rank_stride + k];
                any_u |= w != 0;
                if (original.u_half[size_t(p) * rank + k] == 0) {
                    EXPECT_EQ(w, 0) << radius << " " << p;
                }
            }
            for (int j = 0; j < f.depth_stride; ++j) any_depth |= f.mean_depth[size_t(p) * f.depth_stride + j] != 0;
            occupied_u += any_u;
            occupied_depth += any_depth;
        }
        // The payloads hold one code (2 bytes) per plane of each occupied item, and no more:
        // header, runs, codes; depths also the detailed pixels and their rays.
        const size_t runs_u = [&] {
            uint32_t n;
            std::memcpy(&n, encoded.u.data() + 16 + 4 * rank, 4);
            return n;
        }();
        EXPECT_EQ(encoded.u.size(), 16 + 4 * size_t(rank) + 4 + 8 * runs_u + 2 * size_t(rank) * occupied_u) << radius;
        uint32_t runs_depth;
        std::memcpy(&runs_depth, encoded.depths.data() + 32, 4);
        const size_t planes = 1 + d.alpha_thresholds.size(), detailed = f.detailed_pixels.size();
        EXPECT_EQ(encoded.depths.size(), 32 + 4 + 8 * size_t(runs_depth) + 4 + 4 * detailed +
                                             2 * planes * (occupied_depth + detailed * d.footprint_samples))
            << radius;
        if (radius == 0.0) {
            EXPECT_EQ(occupied_u + occupied_depth + runs_u + runs_depth, 0u);
        }
        if (radius == 100.0) {  // codecFactors() leaves U 0 left of x = 0.2 only: a run per row
            EXPECT_EQ(runs_u, size_t(d.height));
        }
        if (radius == 6.5) {
            EXPECT_GT(occupied_u, 0u);
            EXPECT_LT(occupied_u, size_t(d.pixelCount()) / 2);
            EXPECT_GT(detailed, 0u);
        }
        const FrameFactors expanded = expandFrame(d, f);
        const ExtinctionParams e{1.3f, 4.0f, 2.0f};
        std::vector<float> a(size_t(d.pixelCount()) * 4), b(a.size());
        const std::vector<float> z = residentCoefficients(d, f, e);
        reconstructImage(d, f, z, e, a);
        reference::reconstructImage(d, expanded, decodeU(expanded), z, e, b);
        for (int p = 0; p < d.pixelCount(); ++p) {
            EXPECT_NEAR(a[p * 4 + 3], b[p * 4 + 3], 1e-6) << radius << " " << p;  // as in ReconstructsAsTheExpandedFrame
            const auto row = f.w.begin() + ptrdiff_t(p) * f.rank_stride;
            if (std::all_of(row, row + f.rank_stride, [](int16_t v) { return v == 0; })) {
                for (int c = 0; c < 3; ++c) EXPECT_EQ(a[p * 4 + c], 0.0f) << radius << " " << p;
            }
        }
    }
}

// The decoder keeps the payload's runs (resident_frame.h): every W row and mean ray outside them is
// 0, and reconstructImage, which reads only the runs, writes the same bits as with runs of every
// pixel (which reads everything), whatever the look: an empty pixel's radiance and alpha are
// exactly 0. Runs that are not increasing, overlap or leave the image are refused.
TEST(ResidentFrame, ReconstructionReadsOnlyTheRuns) {
    const BakeDescription d = codecDescription(23, 17, 4);
    const int rank = 9;
    const ExtinctionParams looks[] = {{1.3f, 4.0f, 2.0f}, {1.05f, 16.0f, 0.5f}, {2.0f, 2.0f, 4.0f}};
    for (const double radius : {0.0, 2.0, 6.5, 100.0}) {
        const EncodedFrame encoded = encodeFrame(d, discFactors(d, rank, 3, radius), {});
        const ResidentFrame f = decode(d, encoded, rank);
        std::vector<uint8_t> in_u(size_t(d.pixelCount()), 0), in_depth(in_u.size(), 0);
        for (const PixelRun& r : f.u_runs) std::fill_n(in_u.begin() + r.first, r.count, 1);
        for (const PixelRun& r : f.depth_runs) std::fill_n(in_depth.begin() + r.first, r.count, 1);
        size_t outside = 0;
        for (int p = 0; p < d.pixelCount(); ++p) {
            const auto w = f.w.begin() + ptrdiff_t(p) * f.rank_stride;
            const auto q = f.mean_depth.begin() + ptrdiff_t(p) * f.depth_stride;
            if (!in_u[p]) {
                EXPECT_TRUE(std::all_of(w, w + f.rank_stride, [](int16_t v) { return v == 0; })) << radius << " " << p;
            }
            if (!in_depth[p]) {
                EXPECT_TRUE(std::all_of(q, q + f.depth_stride, [](int16_t v) { return v == 0; })) << radius << " " << p;
            }
            outside += !in_u[p] && !in_depth[p];
        }
        if (radius == 6.5) {
            EXPECT_GT(outside, size_t(d.pixelCount()) / 2);
        }
        ResidentFrame every = f;
        every.u_runs.assign(1, PixelRun{0, d.pixelCount()});
        every.depth_runs.assign(1, PixelRun{0, d.pixelCount()});
        for (const ExtinctionParams& e : looks) {
            const std::vector<float> z = residentCoefficients(d, f, e);
            std::vector<float> a(size_t(d.pixelCount()) * 4, -1.0f), b(a.size(), -2.0f);
            reconstructImage(d, f, z, e, a);
            reconstructImage(d, every, z, e, b);
            for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << radius << " value " << i;
            for (int p = 0; p < d.pixelCount(); p += 5) {
                ASSERT_EQ(pixelAlpha(d, f, p, e), a[size_t(p) * 4 + 3]) << radius << " " << p;
            }
        }
    }
    const ResidentFrame f = decode(d, encodeFrame(d, discFactors(d, rank, 3, 6.5), {}), rank);
    const std::vector<float> z(size_t(rank) * 3, 1.0f);
    std::vector<float> rgba(size_t(d.pixelCount()) * 4);
    const ExtinctionParams e = looks[0];
    for (const std::vector<PixelRun>& bad : {std::vector<PixelRun>{{5, 3}, {7, 2}}, std::vector<PixelRun>{{4, 0}},
                                             std::vector<PixelRun>{{-1, 3}},
                                             std::vector<PixelRun>{{d.pixelCount() - 2, 3}}}) {
        ResidentFrame damaged = f;
        damaged.u_runs.assign(bad.begin(), bad.end());
        EXPECT_ERROR_CODE(ErrorCode::InvalidArgument, reconstructImage(d, damaged, z, e, rgba));
        damaged = f;
        damaged.depth_runs.assign(bad.begin(), bad.end());
        EXPECT_ERROR_CODE(ErrorCode::InvalidArgument, reconstructImage(d, damaged, z, e, rgba));
    }
}

// The decoder keeps a row's neighbours in registers for strides of 8 to 64 lanes (one kernel per
// stride) and goes item by item beyond: every stride decodes W to the grid values of U S (within
// half a step of the original U, which is half-rounded), zero where U is 0, the padding 0, and
// S V^T (the same kernels, its columns as items) within half of its step.
TEST(ResidentFrame, EveryStrideDecodesToTheGrid) {
    const BakeDescription d = codecDescription(19, 6, 4);
    for (const int rank : {1, 8, 9, 16, 17, 24, 31, 40, 47, 56, 63, 64, 65, 72, 80}) {
        const FrameFactors original = discFactors(d, rank, 40 + rank, 5.0);
        const EncodedFrame encoded = encodeFrame(d, original, {});
        ResidentFrame f = decode(d, encodeFrame(d, mixedFactors(d, rank, 1), {}), rank);  // stale values first
        decodeResidentFrame(d, 3, rank, encoded.u, encoded.svt, encoded.depths, "test", f);
        ASSERT_EQ(f.rank_stride % 8, 0);
        ASSERT_EQ(f.w.size(), size_t(d.pixelCount()) * f.rank_stride);
        double worst = 0.0;
        for (int p = 0; p < d.pixelCount(); ++p)
            for (int k = 0; k < f.rank_stride; ++k) {
                const int16_t w = f.w[size_t(p) * f.rank_stride + k];
                if (k >= rank || original.u_half[size_t(p) * rank + k] == 0) {
                    EXPECT_EQ(w, 0) << rank << " " << p << " " << k;
                    continue;
                }
                // u_scale = step / sigma_k: W / step = u / u_scale, rounded to the nearest level.
                const double u = glm::unpackHalf1x16(original.u_half[size_t(p) * rank + k]);
                worst = std::max(worst, std::abs(w - u / f.u_scale[k]));
            }
        EXPECT_LE(worst, 0.5 + 1e-3) << rank;  // 1e-3: float rounding of u / u_scale
        for (size_t i = 0; i < original.svt.size(); ++i)
            EXPECT_LE(std::abs(f.svt[i] - original.svt[i]), 0.5 * encoded.svt_step * (1 + 1e-6) + 1e-6) << rank << " " << i;
    }
}

TEST(ResidentFrame, DamageIsRefusedByName) {
    const BakeDescription d = codecDescription(8, 5, 4);
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
    // Version 3's depth header (32 bytes), then u32 runs, a u32 gap and length per run, then the
    // u32 count of detailed pixels and a u32 gap each.
    auto u32At = [](const std::vector<std::byte>& bytes, size_t at) {
        uint32_t v;
        std::memcpy(&v, bytes.data() + at, 4);
        return v;
    };
    auto setU32 = [](std::vector<std::byte>& bytes, size_t at, uint32_t v) { std::memcpy(bytes.data() + at, &v, 4); };
    constexpr size_t kRuns = 4 + 4 + 8 + 8 + 8;
    ASSERT_GT(u32At(e.depths, kRuns), 0u);
    std::vector<std::byte> overrun = e.depths;
    setU32(overrun, kRuns + 4, uint32_t(d.pixelCount()));  // the first run's gap
    EXPECT_NE(failure(e.u, overrun).find("pkg.firelook: frame 3 ODEP section has an invalid run of occupied items"),
              std::string::npos);
    std::vector<std::byte> empty_run = e.depths;
    setU32(empty_run, kRuns + 8, 0);  // the first run's length
    EXPECT_NE(failure(e.u, empty_run).find("invalid run of occupied items"), std::string::npos);
    std::vector<std::byte> many_runs = e.depths;
    setU32(many_runs, kRuns, 0x7FFFFFFF);
    EXPECT_NE(failure(e.u, many_runs).find("ODEP section ends early"), std::string::npos);
    const size_t detailed_at = kRuns + 4 + 8 * size_t(u32At(e.depths, kRuns));
    ASSERT_GT(u32At(e.depths, detailed_at), 0u);
    std::vector<std::byte> far_pixel = e.depths;
    setU32(far_pixel, detailed_at + 4, uint32_t(d.pixelCount()));
    EXPECT_NE(failure(e.u, far_pixel).find("invalid detailed pixel"), std::string::npos);
    std::vector<std::byte> bad_u_run = e.u;
    setU32(bad_u_run, 4 + 4 + 8 + 4 * 3 + 8, 0);  // after version, rank, step, 3 scales: the first run's length
    EXPECT_NE(failure(bad_u_run, e.depths).find("UFAC section has an invalid run of occupied items"),
              std::string::npos);
    std::vector<std::byte> versioned = e.u;
    versioned[0] = std::byte{9};
    EXPECT_NE(failure(versioned, e.depths).find("unknown codec version"), std::string::npos);
}

}  // namespace
}  // namespace firelook::basis
