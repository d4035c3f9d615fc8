// The writer publishes atomically, cleans up after itself, streams instead of buffering, and is
// deterministic.

#include <gtest/gtest.h>

#include <stdexcept>

#include "package/container_reader.h"
#include "package/container_writer.h"
#include "package_test_support.h"

namespace firelook::package {
namespace {

using test::asBytes;
using test::TempDir;

using test::kFactors;

void writeSample(const std::filesystem::path& path, WriterOptions options = {}) {
    ContainerWriter writer(path, options);
    writer.addMetadata(R"({"tool":"test"})");
    for (uint32_t frame = 1; frame <= 3; ++frame) {
        writer.addSection(kFactors, frame, asBytes(test::smoothFloats(5000, frame)),
                          frame == 2 ? Codec::Raw : Codec::Zstd);
    }
    writer.commit();
}

TEST(ContainerWriter, CommitLeavesOnlyTheDestination) {
    TempDir dir;
    writeSample(dir / "fire.firelook");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"fire.firelook"});
    EXPECT_NO_THROW(ContainerReader::open(dir / "fire.firelook"));
}

TEST(ContainerWriter, TemporaryFileSitsBesideTheDestinationUntilCommit) {
    TempDir dir;
    ContainerWriter writer(dir / "fire.firelook");
    EXPECT_EQ(writer.temporaryPath().parent_path(), dir.path());
    EXPECT_TRUE(std::filesystem::exists(writer.temporaryPath()));
    EXPECT_FALSE(std::filesystem::exists(dir / "fire.firelook"));
    // Until commit the temporary file is not a package, so nothing can mistake it for one.
    test::expectPackageError([&] { ContainerReader::open(writer.temporaryPath()); }, ErrorCode::NotAPackage,
                             writer.temporaryPath());
}

TEST(ContainerWriter, SectionsStreamToDiskInsteadOfStayingInMemory) {
    TempDir dir;
    ContainerWriter writer(dir / "fire.firelook");
    const std::vector<float> frame = test::smoothFloats(1 << 18, 1);  // 1 MiB per frame
    for (uint32_t i = 0; i < 4; ++i) {
        writer.addSection(kFactors, i, asBytes(frame), Codec::Raw);
        // Each added frame is already in the temporary file, so the writer need not hold it.
        EXPECT_GE(std::filesystem::file_size(writer.temporaryPath()),
                  sizeof(FileHeader) + (i + 1) * (1u << 20));
    }
}

TEST(ContainerWriter, DestroyedWithoutCommitLeavesDestinationUntouched) {
    TempDir dir;
    const auto path = dir / "fire.firelook";
    writeSample(path);
    const std::vector<std::byte> before = test::readFile(path);
    {
        ContainerWriter writer(path);
        writer.addSection(kFactors, 9, asBytes(test::smoothFloats(100, 9)));
    }
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"fire.firelook"});
    EXPECT_EQ(test::readFile(path), before);
}

TEST(ContainerWriter, ExceptionDuringBakeRemovesTemporaryAndCreatesNothing) {
    TempDir dir;
    EXPECT_THROW(
        {
            ContainerWriter writer(dir / "fire.firelook");
            writer.addSection(kFactors, 1, asBytes(test::smoothFloats(100, 1)));
            throw std::runtime_error("bake failed");
        },
        std::runtime_error);
    EXPECT_TRUE(dir.entries().empty());
}

TEST(ContainerWriter, CommitReplacesAnExistingPackage) {
    TempDir dir;
    const auto path = dir / "fire.firelook";
    writeSample(path);
    {
        ContainerWriter writer(path);
        writer.addMetadata(R"({"tool":"second"})");
        writer.commit();
    }
    EXPECT_EQ(ContainerReader::open(path).metadata(), R"({"tool":"second"})");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"fire.firelook"});
}

TEST(ContainerWriter, SameInputGivesIdenticalBytes) {
    TempDir dir;
    writeSample(dir / "a.firelook");
    writeSample(dir / "b.firelook");
    EXPECT_EQ(test::readFile(dir / "a.firelook"), test::readFile(dir / "b.firelook"));
}

TEST(ContainerWriter, MoveTransfersTheUncommittedFile) {
    TempDir dir;
    ContainerWriter first(dir / "a.firelook");
    first.addSection(kFactors, 0, asBytes(test::smoothFloats(10, 0)));
    ContainerWriter second = std::move(first);
    test::expectPackageError([&] { first.commit(); }, ErrorCode::InvalidState, {});

    ContainerWriter other(dir / "b.firelook");
    const auto other_temporary = other.temporaryPath();
    other = std::move(second);  // discards b's uncommitted file
    EXPECT_FALSE(std::filesystem::exists(other_temporary));
    other.commit();
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"a.firelook"});
}

TEST(ContainerWriter, RejectsMisuse) {
    TempDir dir;
    const auto path = dir / "fire.firelook";
    test::expectPackageError(
        [&] { ContainerWriter(path, WriterOptions{.zstd_level = 1000, .format_minor = kFormatMinor}); },
        ErrorCode::InvalidArgument, path);
    EXPECT_TRUE(dir.entries().empty());

    ContainerWriter writer(path);
    writer.addSection(kFactors, 1, asBytes(test::smoothFloats(10, 1)));
    test::expectPackageError([&] { writer.addSection(kFactors, 1, {}); }, ErrorCode::InvalidArgument, path);
    test::expectPackageError([&] { writer.addSection(kFactors, 2, {}, static_cast<Codec>(7)); },
                             ErrorCode::InvalidArgument, path);
    writer.addSection(kFactors, 2, {});  // the writer is still usable after rejected calls
    writer.commit();
    test::expectPackageError([&] { writer.addSection(kFactors, 3, {}); }, ErrorCode::InvalidState, path);
    test::expectPackageError([&] { writer.commit(); }, ErrorCode::InvalidState, path);
    EXPECT_EQ(ContainerReader::open(path).sections().size(), 2u);
}

TEST(ContainerWriter, MissingFolderIsAnIoErrorNamingTheDestination) {
    TempDir dir;
    const auto path = dir / "no such folder" / "fire.firelook";
    test::expectPackageError([&] { ContainerWriter writer(path); }, ErrorCode::IoError, path);
}

}  // namespace
}  // namespace firelook::package
