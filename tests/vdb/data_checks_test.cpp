// Telling the truth about the data (issue 13 C): what loading cleans is reported per frame and grid,
// values beyond the plausible range are refused (or clamped and reported under clamp_extreme),
// gaps are reported when a sequence is opened, and `strict` turns each of these into an error.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "vdb/frame_grids.h"
#include "vdb/vdb_sequence.h"
#include "vdb_test_files.h"

namespace firelook::vdb {
namespace {

using namespace testing;  // vdb_test_files.h
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

// Options whose warnings land in `lines`.
ReadOptions collecting(std::vector<std::string>& lines, ReadOptions options = {}) {
    options.warn = [&lines](const std::string& line) { lines.push_back(line); };
    return options;
}

void writeGridFrame(const std::filesystem::path& file, const Voxels& density, const Voxels& temperature) {
    writeVdb(file, {makeGrid("density", density), makeGrid("temperature", temperature)});
}

// Density: 2 NaN, 1 Inf, 3 negative and a good voxel; temperature: 1 NaN, 2 Inf (one -Inf).
void writeDirtyGridFrame(const std::filesystem::path& file) {
    writeGridFrame(file,
               {{{0, 0, 0}, kNaN},
                {{1, 0, 0}, kNaN},
                {{2, 0, 0}, kInf},
                {{3, 0, 0}, -0.5f},
                {{4, 0, 0}, -1.0f},
                {{5, 0, 0}, -2.0f},
                {{6, 0, 0}, 0.5f}},
               {{{0, 0, 0}, kNaN}, {{1, 0, 0}, -kInf}, {{2, 0, 0}, kInf}, {{3, 0, 0}, 2.0f}});
}

TEST(DataChecks, CleanedValuesAreCountedPerGridAndReportedOnePerLine) {
    TempDir dir;
    writeDirtyGridFrame(dir / "f_1.vdb");
    std::vector<std::string> warnings;
    const VolumeFrame frame = VdbSequence::open(dir.path().string(), collecting(warnings)).load(1);
    EXPECT_EQ(frame.density_cleaned.nan, 2u);
    EXPECT_EQ(frame.density_cleaned.inf, 1u);
    EXPECT_EQ(frame.density_cleaned.negative, 3u);
    EXPECT_EQ(frame.density_cleaned.clamped, 0u);
    EXPECT_EQ(frame.temperature_cleaned.nan, 1u);
    EXPECT_EQ(frame.temperature_cleaned.inf, 2u);
    EXPECT_EQ(frame.cleaned_non_finite, 6u) << "the totals stay as they were";
    EXPECT_EQ(frame.cleaned_negative_density, 3u);
    const std::string file = (dir / "f_1.vdb").string();
    EXPECT_THAT(warnings, ElementsAre(file + ": density: 2 NaN, 1 Inf, 3 negative values set to 0",
                                      file + ": temperature: 1 NaN, 2 Inf values set to 0"));
    EXPECT_EQ(cleaningReport(frame), warnings);
    EXPECT_EQ(cleaningSummary(frame), "density: 2 NaN, 1 Inf, 3 negative values; temperature: 1 NaN, 2 Inf values");
}

TEST(DataChecks, ACleanFrameReportsNothing) {
    TempDir dir;
    writeGridFrame(dir / "f_1.vdb", kDensity, kTemperature);
    writeGridFrame(dir / "f_2.vdb", kDensity, kTemperature);
    std::vector<std::string> warnings;
    const VdbSequence sequence = VdbSequence::open(dir.path().string(), collecting(warnings));
    const VolumeFrame frame = sequence.load(1);
    EXPECT_FALSE(frame.density_cleaned.any());
    EXPECT_FALSE(frame.temperature_cleaned.any());
    EXPECT_THAT(cleaningReport(frame), IsEmpty());
    EXPECT_THAT(warnings, IsEmpty());
}

TEST(DataChecks, ExtremeDensityIsRefusedNamingTheFileTheGridAndTheValue) {
    TempDir dir;
    writeGridFrame(dir / "f_1.vdb", {{{0, 0, 0}, 0.5f}, {{4, -2, 7}, 1e30f}, {{5, 0, 0}, 2e7f}}, kTemperature);
    const std::string error = errorOf([&] { VdbSequence::open(dir.path().string()).load(1); });
    EXPECT_THAT(error, HasSubstr((dir / "f_1.vdb").string() + ": density: value 1e+30 at voxel (4, -2, 7)"));
    EXPECT_THAT(error, HasSubstr("above 1e+06"));
    EXPECT_THAT(error, HasSubstr("2 such voxels"));
    EXPECT_THAT(error, HasSubstr("--clamp-extreme"));
    EXPECT_EQ(error.find('\n'), std::string::npos) << "one line";
}

TEST(DataChecks, TheBoundItselfIsPlausible) {
    TempDir dir;
    writeGridFrame(dir / "f_1.vdb", {{{0, 0, 0}, 1e6f}},
               {{{0, 0, 0}, static_cast<float>(kMaxPlausibleTemperature)}, {{1, 0, 0}, -1e6f}});
    std::vector<std::string> warnings;
    const VolumeFrame frame = VdbSequence::open(dir.path().string(), collecting(warnings)).load(1);
    EXPECT_EQ(frame.density_stats.max, kMaxPlausibleDensity);
    EXPECT_THAT(warnings, IsEmpty());
}

TEST(DataChecks, ExtremeTemperatureIsRefusedAfterTheMapping) {
    TempDir dir;
    writeGridFrame(dir / "f_1.vdb", kDensity, {{{0, 0, 0}, 300.0f}, {{1, 1, 1}, -3e7f}});
    std::string error = errorOf([&] { VdbSequence::open(dir.path().string()).load(1); });
    EXPECT_THAT(error, HasSubstr("f_1.vdb: temperature: value -3e+07 at voxel (1, 1, 1)"));
    EXPECT_THAT(error, HasSubstr("|T| above 1e+06 in the data's units"));

    // 3000 (raw) is fine; the same data in millikelvin scaled by 1e4 is not.
    TempDir scaled;
    writeGridFrame(scaled / "f_1.vdb", kDensity, {{{0, 0, 0}, 300.0f}, {{2, 0, 0}, 3000.0f}});
    EXPECT_EQ(errorOf([&] { VdbSequence::open(scaled.path().string()).load(1); }), "no error");
    error = errorOf([&] { VdbSequence::open(scaled.path().string(), {.temperature_scale = 1e4}).load(1); });
    EXPECT_THAT(error, HasSubstr("temperature: value 3e+07 at voxel (2, 0, 0)"));
}

TEST(DataChecks, ClampExtremeClampsAndReportsLikeCleaning) {
    TempDir dir;
    writeGridFrame(dir / "f_1.vdb", {{{0, 0, 0}, 0.5f}, {{1, 0, 0}, 1e30f}, {{2, 0, 0}, kNaN}},
               {{{0, 0, 0}, 2.0f}, {{1, 0, 0}, -5e6f}, {{2, 0, 0}, 7e6f}, {{3, 0, 0}, 8e6f}});
    std::vector<std::string> warnings;
    ReadOptions options;
    options.clamp_extreme = true;
    const VolumeFrame frame = VdbSequence::open(dir.path().string(), collecting(warnings, options)).load(1);
    const auto density = frame.grids->density->getConstAccessor();
    const auto temperature = frame.grids->temperature->getConstAccessor();
    EXPECT_EQ(density.getValue({1, 0, 0}), 1e6f);
    EXPECT_EQ(temperature.getValue({1, 0, 0}), -1e6f);
    EXPECT_EQ(temperature.getValue({2, 0, 0}), 1e6f);
    EXPECT_EQ(frame.density_stats.max, 1e6);
    EXPECT_EQ(frame.temperature_stats.min, -1e6);
    EXPECT_EQ(frame.density_cleaned.clamped, 1u);
    EXPECT_EQ(frame.temperature_cleaned.clamped, 3u);
    const std::string file = (dir / "f_1.vdb").string();
    EXPECT_THAT(warnings,
                ElementsAre(file + ": density: 1 NaN, 0 Inf, 0 negative values set to 0; 1 value above 1e+06 "
                                   "clamped to 1e+06",
                            file + ": temperature: 3 values beyond +-1e+06 clamped to +-1e+06"));
}

TEST(DataChecks, StrictRefusesCleaningAndClamping) {
    TempDir dir;
    writeDirtyGridFrame(dir / "f_1.vdb");
    std::string error = errorOf([&] { VdbSequence::open(dir.path().string(), {.strict = true}).load(1); });
    EXPECT_THAT(error, HasSubstr((dir / "f_1.vdb").string() +
                                 ": density: 2 NaN, 1 Inf, 3 negative values; temperature: 1 NaN, 2 Inf values"));
    EXPECT_THAT(error, HasSubstr("refused by --strict"));

    TempDir extreme;
    writeGridFrame(extreme / "f_1.vdb", {{{0, 0, 0}, 1e30f}}, kTemperature);
    error = errorOf([&] { VdbSequence::open(extreme.path().string(), {.clamp_extreme = true, .strict = true}).load(1); });
    EXPECT_THAT(error, HasSubstr("density: 1 value above 1e+06 (refused by --strict"));

    // A clean frame reads as usual under strict.
    TempDir clean;
    writeGridFrame(clean / "f_1.vdb", kDensity, kTemperature);
    EXPECT_EQ(errorOf([&] { VdbSequence::open(clean.path().string(), {.strict = true}).load(1); }), "no error");
}

TEST(DataChecks, GapsAreReportedWhenTheSequenceIsOpened) {
    TempDir dir;
    for (int f : {1, 2, 4}) writeGridFrame(dir / ("f_" + std::to_string(f) + ".vdb"), kDensity, kTemperature);
    std::vector<std::string> warnings;
    const VdbSequence sequence = VdbSequence::open(dir.path().string(), collecting(warnings));
    EXPECT_THAT(warnings, ElementsAre(dir.path().string() + ": frame 3 missing"));
    sequence.load(4);
    EXPECT_EQ(warnings.size(), 1u) << "loading a clean frame adds nothing";

    TempDir wide;
    for (int f : {1, 3, 4, 5, 8}) writeGridFrame(wide / ("f_" + std::to_string(f) + ".vdb"), kDensity, kTemperature);
    warnings.clear();
    VdbSequence::open(wide.path().string(), collecting(warnings));
    EXPECT_THAT(warnings, ElementsAre(wide.path().string() + ": frames 2, 6-7 missing"));

    const std::string error = errorOf([&] { VdbSequence::open(wide.path().string(), {.strict = true}); });
    EXPECT_THAT(error, HasSubstr(wide.path().string() + ": frames 2, 6-7 missing (refused by --strict)"));
}

TEST(DataChecks, FrameNumbersAreWrittenAsRanges) {
    EXPECT_EQ(formatFrameNumbers({}), "");
    EXPECT_EQ(formatFrameNumbers({3}), "3");
    EXPECT_EQ(formatFrameNumbers({3, 5, 6, 7, 9, 10}), "3, 5-7, 9-10");
    EXPECT_EQ(describeMissingFrames({3}), "frame 3 missing");
    EXPECT_EQ(describeMissingFrames({3, 4}), "frames 3-4 missing");
}

}  // namespace
}  // namespace firelook::vdb
