// --target-size and --target-error (baker/bake/storage_target.h) on the tiny sample bake: what a
// target promises is checked on the package written, not on the chooser's own figures.
#include "bake/storage_target.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "../basis/codec_test_frames.h"
#include "../support/error_code.h"
#include "../support/temp_dir.h"
#include "bake/bake_config.h"
#include "bake/bake_pipeline.h"
#include "basis/basis_package.h"
#include "basis/frame_factors.h"
#include "common/error.h"
#include "package/container_writer.h"
#include "tiny_sample_bake.h"

namespace firelook::bake {
namespace {

using firelook::testing::TempDir;
using test::fileBytes;
using test::tinyConfig;

BakeConfig twoFrames() {
    BakeConfig c = tinyConfig();
    c.frames = "6-7";
    c.scene.width = c.scene.height = 32;
    return c;
}

TEST(StorageTarget, TargetErrorBoundsEveryFramesPredictedError) {
    TempDir dir;
    for (double target : {0.003, 0.02}) {
        BakeConfig c = twoFrames();
        c.target.basis_error = target;
        const BakeReport r = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "e.firelook", c, "test");
        for (const FrameBakeReport& f : r.frames) {
            EXPECT_TRUE(f.target_met) << f.frame;
            // The promise: truncation and storage together, as measured on the stored grids.
            EXPECT_LE(std::hypot(f.truncation_error, f.quantisation_error), target * (1 + 1e-9)) << f.frame;
        }
    }
}

TEST(StorageTarget, LooserErrorStoresFewerBytes) {
    TempDir dir;
    uint64_t bytes[2];
    int i = 0;
    for (double target : {0.002, 0.03}) {
        BakeConfig c = twoFrames();
        c.target.basis_error = target;
        bytes[i++] = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "e.firelook", c, "test").package_bytes;
    }
    EXPECT_LT(bytes[1], bytes[0]);
}

TEST(StorageTarget, TargetSizeKeepsThePackageOfTheSequenceWithinIt) {
    TempDir dir;
    const BakeConfig plain = twoFrames();
    const BakeReport base = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "p.firelook", plain, "test");
    const uint64_t frame_bytes = (base.package_bytes) / 2;
    // A target whose per-frame share (of the 12-frame sequence) is about half of what the defaults
    // store: the bake must shrink the frames to fit.
    BakeConfig c = twoFrames();
    c.target.package_bytes = 12 * frame_bytes / 2 + 12 * 4096 + 64 * 1024;
    const BakeReport r = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "s.firelook", c, "test");
    ASSERT_EQ(r.frames.size(), 2u);
    for (const FrameBakeReport& f : r.frames) {
        EXPECT_TRUE(f.target_met) << f.frame;
        EXPECT_LE(f.u_bytes + f.svt_bytes + f.depth_bytes, f.share_bytes) << f.frame;
        EXPECT_GT(f.quality_scale, 0.0);
    }
    // Two frames of twelve: their share of the target, and the package's actual bytes within it
    // once the metadata is counted.
    EXPECT_LE(r.package_bytes * 6, c.target.package_bytes);
    EXPECT_EQ(r.package_bytes, std::filesystem::file_size(dir / "s.firelook"));
    // The same inputs give the same bytes.
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / "s2.firelook", c, "test");
    EXPECT_EQ(fileBytes(dir / "s.firelook"), fileBytes(dir / "s2.firelook"));
}

TEST(StorageTarget, BothTargetsOrABadErrorAreRefused) {
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      checkStorageTarget({.package_bytes = 1 << 20, .basis_error = 0.01}));
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, checkStorageTarget({.basis_error = 1.5}));
    EXPECT_NO_THROW(checkStorageTarget({.basis_error = 0.01}));
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      frameShareBytes({.package_bytes = 1000}, 12, 500));
}

TEST(StorageTarget, BakeConfigFileTakesTheTargetsAndTheMemoryBudget) {
    TempDir dir;
    const auto file = dir / "bake.json";
    {
        std::ofstream(file) << R"({"compression": {"target_size": "2M"}, "memory_budget": "3G"})";
    }
    BakeConfig c;
    applyConfigFile(c, file);
    EXPECT_EQ(c.target.package_bytes, uint64_t(2) << 20);
    EXPECT_EQ(c.memory_budget_bytes, uint64_t(3) << 30);
    // Recorded in the settings only when given, so that packages baked without one keep theirs.
    EXPECT_NE(configToJson(c).find("\"target_size\""), std::string::npos);
    EXPECT_EQ(configToJson(BakeConfig{}).find("\"target_size\""), std::string::npos);
    EXPECT_EQ(configToJson(BakeConfig{}).find("\"target_error\""), std::string::npos);
    {
        std::ofstream(file) << R"({"compression": {"target_size": "2M", "target_error": 0.01}})";
    }
    BakeConfig both;
    EXPECT_THROW(applyConfigFile(both, file), std::runtime_error);
}

// U S V^T of a frame (pixels x columns, pixel-major).
std::vector<double> basisOf(const basis::FrameFactors& f) {
    const std::vector<float> u = basis::decodeU(f);
    std::vector<double> b(static_cast<size_t>(f.pixels) * f.columns, 0.0);
    for (int p = 0; p < f.pixels; ++p)
        for (int j = 0; j < f.columns; ++j)
            for (int m = 0; m < f.rank; ++m)
                b[size_t(p) * f.columns + j] += double(u[size_t(p) * f.rank + m]) * f.svt[size_t(j) * f.rank + m];
    return b;
}

// firelook repack's targets (chooseStoredFramePrecision): a frame stored at the defaults, stored
// again within a looser error or a smaller share. Checked on the frame read back from the package
// written: its basis within the target of the stored one, fewer bytes, no higher rank. A target
// below the errors the package already records cannot be met, and says so.
TEST(StorageTarget, StoredFrameMeetsALooserTargetAndNeverATighterOne) {
    TempDir dir;
    const BakeReport base = bakePackage(FIRELOOK_SAMPLE_DIR, dir / "p.firelook", twoFrames(), "test");
    const basis::BasisReader package = basis::BasisReader::open(dir / "p.firelook");
    const FrameBakeReport& fr = base.frames.at(0);
    const basis::FrameFactors original = package.loadFrame(fr.frame);
    const StoredFrameErrors stored = storedFrameErrors(original, fr.truncation_error, fr.quantisation_error);
    const uint64_t original_bytes = fr.u_bytes + fr.svt_bytes + fr.depth_bytes;
    const std::vector<double> b0 = basisOf(original);
    double norm = 0.0;
    for (double v : b0) norm += v * v;

    const double target = 0.03;
    const std::vector<std::pair<StorageTarget, uint64_t>> targets = {{{.basis_error = target}, 0},
                                                                      {{.package_bytes = 1}, original_bytes / 2}};
    for (const auto& [t, share] : targets) {
        const FramePrecision chosen =
            chooseStoredFramePrecision(stored, package.description(), CompressionSettings{}, {}, t, share);
        EXPECT_TRUE(chosen.target_met);
        EXPECT_LE(chosen.compressed.factors.rank, original.rank);
        const auto file = dir / "r.firelook";
        {
            package::ContainerWriter writer(file);
            const basis::StoredFrame written = basis::writeEncodedFrame(writer, fr.frame, chosen.encoded);
            basis::BakeDescription d = package.description();
            d.frames = {{fr.frame, chosen.compressed.factors.rank}};
            writer.addMetadata(basis::makeMetadata(d, "{}"));
            writer.commit();
            EXPECT_LT(written.bytes(), original_bytes);
            if (share > 0) {
                EXPECT_LE(written.bytes(), share);
            }
        }
        const std::vector<double> b1 = basisOf(basis::BasisReader::open(file).loadFrame(fr.frame));
        double diff = 0.0;
        for (size_t i = 0; i < b0.size(); ++i) diff += (b1[i] - b0[i]) * (b1[i] - b0[i]);
        if (t.basis_error > 0.0) {
            // Against the stored frame, the new error alone: within the target, which holds it and
            // the recorded errors together (they add in squares).
            EXPECT_LE(std::sqrt(diff / norm), target);
            EXPECT_LE(chosen.predicted_error, target * (1 + 1e-9));
        }
    }
    // Half the error the package already holds: not met, whatever is chosen.
    const double held = std::hypot(fr.truncation_error, fr.quantisation_error);
    ASSERT_GT(held, 0.0);
    const FramePrecision tighter = chooseStoredFramePrecision(stored, package.description(), CompressionSettings{}, {},
                                                              {.basis_error = held / 2}, 0);
    EXPECT_FALSE(tighter.target_met);
    EXPECT_GE(tighter.predicted_error, held * 0.9) << "the recorded errors stay in the prediction";
}

TEST(StorageTarget, AFrameBeyondTheCodecsRangeFailsNamingIt) {
    // One value of U at the largest half beside values ~0.01: the 16-bit grid's step is then set by
    // the range, every other value rounds to 0, and the stored error is ~100% of the basis.
    const basis::BakeDescription d = basis::codecDescription(32, 24, 1);
    basis::FrameFactors factors = basis::codecFactors(d, 4, 7);
    const basis::FrameCodecSettings settings;
    basis::EncodedFrame encoded = basis::encodeFrame(d, factors, settings);
    EXPECT_NO_THROW(checkStoredError(3, encoded, settings)) << "an ordinary frame is within its bound";
    // A bound the 16-bit grids cannot reach on any frame is the target chooser's "not met", not a failure.
    basis::FrameCodecSettings finest = settings;
    finest.basis_error = 1e-9;
    const basis::EncodedFrame fine = basis::encodeFrame(d, factors, finest);
    ASSERT_GT(std::hypot(fine.u_error, fine.svt_error), 2.0 * finest.basis_error) << "the grids reached 1e-9";
    EXPECT_NO_THROW(checkStoredError(3, fine, finest));
    factors.u_half[d.width * 10 + 20] = glm::packHalf1x16(65504.0f);
    encoded = basis::encodeFrame(d, factors, settings);
    try {
        checkStoredError(3, encoded, settings);
        ADD_FAILURE() << "stored error " << encoded.u_error << " passed";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::Limit);
        EXPECT_NE(std::string(e.what()).find("frame 3:"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace firelook::bake
