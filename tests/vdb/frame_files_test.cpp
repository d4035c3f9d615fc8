// File discovery: folders, patterns, numbering, gaps and the errors for bad sequences.
#include "vdb/frame_files.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "vdb/vdb_error.h"
#include "vdb_test_files.h"

namespace firelook::vdb {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using testing::TempDir;
using testing::touch;

std::vector<int> numbersOf(const std::vector<FrameFile>& frames) {
    std::vector<int> numbers;
    for (const FrameFile& frame : frames) numbers.push_back(frame.number);
    return numbers;
}

std::string frameFilesErrorOf(const std::string& folder_or_pattern) {
    try {
        findFrameFiles(folder_or_pattern);
    } catch (const VdbError& error) {
        return error.what();
    }
    return "no error";
}

TEST(FrameFiles, FolderIsSortedNumericallyNotAlphabetically) {
    TempDir dir;
    for (const char* name : {"fire_100.vdb", "fire_9.vdb", "fire_10.vdb", "notes.txt"}) touch(dir / name);
    const std::vector<FrameFile> frames = findFrameFiles(dir.path().string());
    EXPECT_THAT(numbersOf(frames), ElementsAre(9, 10, 100));
    EXPECT_EQ(frames[0].path, dir / "fire_9.vdb");
}

TEST(FrameFiles, HashPatternMatchesItsPaddingAndLargerNumbers) {
    TempDir dir;
    for (const char* name : {"fire_0001.vdb", "fire_0012.vdb", "fire_12345.vdb", "fire_01.vdb",
                             "fire_00012.vdb", "fire_0002.vdb.bak", "smoke_0003.vdb"}) {
        touch(dir / name);
    }
    const std::vector<FrameFile> frames = findFrameFiles((dir / "fire_####.vdb").string());
    EXPECT_THAT(numbersOf(frames), ElementsAre(1, 12, 12345));
}

TEST(FrameFiles, PrintfPatternsAgreeWithHashes) {
    TempDir dir;
    for (const char* name : {"fire_0003.vdb", "fire_0001.vdb", "fire_0002.vdb"}) touch(dir / name);
    EXPECT_THAT(numbersOf(findFrameFiles((dir / "fire_%04d.vdb").string())), ElementsAre(1, 2, 3));
    EXPECT_THAT(numbersOf(findFrameFiles((dir / "fire_####.vdb").string())), ElementsAre(1, 2, 3));
    EXPECT_THAT(numbersOf(findFrameFiles((dir / "fire_%d.vdb").string())), ElementsAre(1, 2, 3));
}

TEST(FrameFiles, GapsAreListed) {
    TempDir dir;
    for (const char* name : {"f_1.vdb", "f_2.vdb", "f_5.vdb", "f_7.vdb"}) touch(dir / name);
    EXPECT_THAT(missingFrameNumbers(findFrameFiles(dir.path().string())), ElementsAre(3, 4, 6));
}

TEST(FrameFiles, OneFileIsAOneFrameSequence) {
    TempDir dir;
    touch(dir / "fire_0042.vdb");
    const std::vector<FrameFile> frames = findFrameFiles((dir / "fire_0042.vdb").string());
    ASSERT_EQ(frames.size(), 1u);
    EXPECT_EQ(frames[0].number, 42);
}

TEST(FrameFiles, MixedPrefixesAreRefusedAndNamed) {
    TempDir dir;
    for (const char* name : {"fire_0001.vdb", "fire_0002.vdb", "smoke_0001.vdb"}) touch(dir / name);
    const std::string error = frameFilesErrorOf(dir.path().string());
    EXPECT_THAT(error, HasSubstr(dir.path().string()));
    EXPECT_THAT(error, HasSubstr("'fire_'"));
    EXPECT_THAT(error, HasSubstr("'smoke_'"));
}

TEST(FrameFiles, FileWithoutFrameNumberInFolderIsRefused) {
    TempDir dir;
    for (const char* name : {"fire_0001.vdb", "cache.vdb"}) touch(dir / name);
    EXPECT_THAT(frameFilesErrorOf(dir.path().string()), HasSubstr("cache.vdb"));
}

TEST(FrameFiles, DuplicateFrameNumbersAreRefused) {
    TempDir dir;
    for (const char* name : {"fire_01.vdb", "fire_001.vdb"}) touch(dir / name);
    const std::string error = frameFilesErrorOf(dir.path().string());
    EXPECT_THAT(error, HasSubstr("fire_01.vdb"));
    EXPECT_THAT(error, HasSubstr("fire_001.vdb"));
}

TEST(FrameFiles, EmptyFolderAndNoMatchAreErrors) {
    TempDir dir;
    EXPECT_THAT(frameFilesErrorOf(dir.path().string()), HasSubstr("no .vdb file"));
    touch(dir / "fire_0001.vdb");
    const std::string pattern = (dir / "smoke_####.vdb").string();
    EXPECT_THAT(frameFilesErrorOf(pattern), HasSubstr(pattern));
    EXPECT_THAT(frameFilesErrorOf(pattern), HasSubstr("no file matches"));
    EXPECT_THAT(frameFilesErrorOf((dir / "missing").string()), HasSubstr("no such folder or file"));
    EXPECT_THAT(frameFilesErrorOf((dir / "missing" / "f_####.vdb").string()), HasSubstr("does not exist"));
}

TEST(FrameFiles, PatternWithTwoFrameFieldsIsRefused) {
    TempDir dir;
    EXPECT_THAT(frameFilesErrorOf((dir / "f_##_%04d.vdb").string()), HasSubstr("more than one frame field"));
}

}  // namespace
}  // namespace firelook::vdb
