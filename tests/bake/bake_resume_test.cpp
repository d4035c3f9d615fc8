// Resuming an interrupted bake (bake/bake_checkpoint.h, BakeRunOptions::resume): the frames it
// finished are reused only when baked with the same settings from the same sequence (every frame's
// file unchanged) and undamaged, and the package ends with the bytes of a bake that was never stopped.
#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <string>
#include <vector>

#include "../support/temp_dir.h"
#include "bake/bake_checkpoint.h"
#include "bake/bake_pipeline.h"
#include "tiny_sample_bake.h"

namespace firelook::bake {
namespace {

using firelook::testing::TempDir;
using test::fileBytes;
using test::tinyConfig;

BakeConfig threeFrames(uint64_t seed = 1) {
    BakeConfig c = tinyConfig(seed);
    c.frames = "1-3";
    return c;
}

// Bakes and cancels at the start of frame 3: frames 1 and 2 are finished and kept.
void bakeTwoOfThree(const std::string& sequence, const std::filesystem::path& out, const BakeConfig& c) {
    const auto cancel_at_frame_3 = [](double, const std::string& detail) { return !detail.starts_with("frame 3 ("); };
    EXPECT_THROW(bakePackage(sequence, out, c, "test", cancel_at_frame_3), std::runtime_error);
    EXPECT_FALSE(std::filesystem::exists(out));
    EXPECT_EQ(BakeCheckpoint::keptFrames(out), 2u);
}

std::vector<bool> resumedFlags(const BakeReport& report) {
    std::vector<bool> flags;
    for (const FrameBakeReport& f : report.frames) flags.push_back(f.resumed);
    return flags;
}

TEST(BakeResume, ACancelledBakeResumesToTheSameBytes) {
    TempDir dir;
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / "whole.firelook", threeFrames(), "test");
    const auto out = dir / "out.firelook";
    bakeTwoOfThree(FIRELOOK_SAMPLE_DIR, out, threeFrames());
    const BakeReport report = bakePackage(FIRELOOK_SAMPLE_DIR, out, threeFrames(), "test", {}, {}, {.resume = true, .plan = {}, .plan_file = {}});
    EXPECT_EQ(resumedFlags(report), (std::vector<bool>{true, true, false}));
    EXPECT_GT(report.frames[0].rank, 0) << "a resumed frame reports what its bake recorded";
    EXPECT_TRUE(fileBytes(out) == fileBytes(dir / "whole.firelook"));
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"out.firelook", "whole.firelook"})) << "the parts are gone";
}

TEST(BakeResume, WithoutResumeEveryFrameIsBakedAgain) {
    TempDir dir;
    const auto out = dir / "out.firelook";
    bakeTwoOfThree(FIRELOOK_SAMPLE_DIR, out, threeFrames());
    const BakeReport report = bakePackage(FIRELOOK_SAMPLE_DIR, out, threeFrames(), "test");
    EXPECT_EQ(resumedFlags(report), (std::vector<bool>{false, false, false}));
}

TEST(BakeResume, FramesBakedWithOtherSettingsAreBakedAgain) {
    TempDir dir;
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / "whole.firelook", threeFrames(2), "test");
    const auto out = dir / "out.firelook";
    bakeTwoOfThree(FIRELOOK_SAMPLE_DIR, out, threeFrames(1));
    std::vector<std::string> notices;
    const BakeReport report = bakePackage(
        FIRELOOK_SAMPLE_DIR, out, threeFrames(2), "test", {}, [&](const std::string& line) { notices.push_back(line); },
        {.resume = true, .plan = {}, .plan_file = {}});
    EXPECT_EQ(resumedFlags(report), (std::vector<bool>{false, false, false}));
    ASSERT_EQ(notices.size(), 2u);
    EXPECT_NE(notices[0].find("frame 1: not resumed"), std::string::npos) << notices[0];
    EXPECT_NE(notices[0].find("other settings (provenance.settings.seed: 2 vs 1)"), std::string::npos) << notices[0];
    EXPECT_TRUE(fileBytes(out) == fileBytes(dir / "whole.firelook"));
}

TEST(BakeResume, AFrameWhoseFileChangedOrWhosePartIsDamagedIsBakedAgain) {
    TempDir dir;
    // A sequence of its own, so one of its files can change.
    std::filesystem::create_directory(dir / "seq");
    for (const char* name : {"fluid_data_0001.vdb", "fluid_data_0002.vdb", "fluid_data_0003.vdb"})
        std::filesystem::copy_file(std::filesystem::path(FIRELOOK_SAMPLE_DIR) / name, dir / "seq" / name);
    const std::string sequence = (dir / "seq").string();
    BakeConfig c = threeFrames();
    const auto out = dir / "out.firelook";
    bakeTwoOfThree(sequence, out, c);
    {  // A part damaged on disk: one byte of its first section flipped.
        std::fstream part(BakeCheckpoint::folderFor(out) / "frame_1.firelook", std::ios::in | std::ios::out | std::ios::binary);
        part.seekp(200);
        part.put('\x7f');
    }
    std::vector<std::string> notices;
    const auto note = [&](const std::string& line) { notices.push_back(line); };
    BakeReport report = bakePackage(sequence, out, c, "test", {}, note, {.resume = true, .plan = {}, .plan_file = {}});
    EXPECT_EQ(resumedFlags(report), (std::vector<bool>{false, true, false}));
    ASSERT_EQ(notices.size(), 1u);
    EXPECT_NE(notices[0].find("frame 1: not resumed"), std::string::npos) << notices[0];
    EXPECT_NE(notices[0].find("checksum"), std::string::npos) << notices[0];
    bakePackage(sequence, dir / "whole.firelook", c, "test");
    EXPECT_TRUE(fileBytes(out) == fileBytes(dir / "whole.firelook"));

    // Frame 2 becomes frame 1's file: the sequence is another (provenance.sequence_xxh3_64), so no
    // kept frame is reused, and the reason given is the most specific one.
    std::filesystem::remove(out);
    bakeTwoOfThree(sequence, out, c);
    std::filesystem::copy_file(std::filesystem::path(FIRELOOK_SAMPLE_DIR) / "fluid_data_0001.vdb",
                               dir / "seq" / "fluid_data_0002.vdb", std::filesystem::copy_options::overwrite_existing);
    notices.clear();
    report = bakePackage(sequence, out, c, "test", {}, note, {.resume = true, .plan = {}, .plan_file = {}});
    EXPECT_EQ(resumedFlags(report), (std::vector<bool>{false, false, false}));
    ASSERT_EQ(notices.size(), 2u);
    EXPECT_NE(notices[0].find("frame 1: not resumed"), std::string::npos) << notices[0];
    EXPECT_NE(notices[0].find("another frame of the sequence has changed since"), std::string::npos) << notices[0];
    EXPECT_NE(notices[1].find("frame 2: not resumed"), std::string::npos) << notices[1];
    EXPECT_NE(notices[1].find("input file has changed"), std::string::npos) << notices[1];
    bakePackage(sequence, dir / "whole2.firelook", c, "test");
    EXPECT_TRUE(fileBytes(out) == fileBytes(dir / "whole2.firelook"));
}

}  // namespace
}  // namespace firelook::bake
