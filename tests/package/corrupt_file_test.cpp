// Every reader error code from a crafted file: truncation at every length, a flipped byte in
// every region, version and feature checks, and files that are not packages at all. Every crafted
// file given to expectOpenError is also opened from memory, borrowed and copied, for the same error.

#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "package/container_reader.h"
#include "package/container_writer.h"
#include "package_test_support.h"

namespace firelook::package {
namespace {

using test::asBytes;
using test::expectPackageError;

using test::kFactors;
constexpr uint32_t kNewFeature = makeFourCC('N', 'E', 'W', 'X');

// A small package with every kind of section: zstd metadata, raw and zstd data, an empty one.
class CorruptPackage : public ::testing::Test {
  protected:
    void SetUp() override {
        {
            ContainerWriter writer(dir_ / "good.firelook");
            writer.addMetadata(R"({"tool":"corruption test"})");
            writer.addSection(kFactors, 0, asBytes(test::smoothFloats(100, 1)), Codec::Raw);
            writer.addSection(kFactors, 1, asBytes(test::smoothFloats(100, 2)), Codec::Zstd);
            writer.addSection(kFactors, 2, {}, Codec::Raw);
            writer.commit();
        }
        good_ = test::readFile(dir_ / "good.firelook");
        header_ = test::headerOf(good_);
        ASSERT_EQ(header_.section_count, 4u);
    }

    // Writes `bytes` as a package file and returns its path.
    std::filesystem::path craft(std::span<const std::byte> bytes, bool memory_map = true) {
        const auto path = dir_ / (memory_map ? "crafted.firelook" : "crafted-read.firelook");
        test::writeFile(path, bytes);
        return path;
    }

    void expectOpenError(const std::vector<std::byte>& bytes, ErrorCode code, const std::string& context) {
        SCOPED_TRACE(context);
        for (bool memory_map : {true, false}) {
            const auto path = craft(bytes, memory_map);
            expectPackageError(
                [&] {
                    ContainerReader::open(path,
                                        ReaderOptions{.memory_map = memory_map, .understood_types = {}});
                },
                code, path);
        }
        // The same bytes held in memory go through exactly the same checks (memory_source_test.cpp).
        const std::filesystem::path name = "archive.pak:crafted.firelook";
        const test::AlignedBytes held(bytes);
        for (const auto ownership : {ContainerReader::MemoryOwnership::Borrow, ContainerReader::MemoryOwnership::Copy})
            expectPackageError([&] { ContainerReader::openMemory(held.view(), ownership, name); }, code, name);
    }

    // Opens the crafted file and reads every section; returns the frames whose read failed as Corrupt.
    std::vector<uint32_t> corruptSections(const std::vector<std::byte>& bytes) {
        const auto path = craft(bytes);
        const ContainerReader reader = ContainerReader::open(path);
        std::vector<uint32_t> failed;
        for (const SectionInfo& section : reader.sections()) {
            try {
                reader.read(section);
                if (section.codec == Codec::Raw) reader.mapped(section);
            } catch (const PackageError& error) {
                EXPECT_EQ(error.code(), ErrorCode::Corrupt) << error.what();
                failed.push_back(section.type == kMetadataType ? kNoFrame : section.frame);
            }
        }
        return failed;
    }

    test::TempDir dir_;
    std::vector<std::byte> good_;
    FileHeader header_{};
};

TEST_F(CorruptPackage, TruncatedAtEveryLengthIsTruncated) {
    // Every length from 1 byte to one byte short: inside the identifier, the header, every section,
    // at every section boundary and padding, and inside the index.
    for (std::size_t length = 1; length < good_.size(); ++length) {
        const auto path = craft(std::span(good_).first(length));
        expectPackageError([&] { ContainerReader::open(path); }, ErrorCode::Truncated, path);
        if (::testing::Test::HasFailure()) {
            ADD_FAILURE() << "first failing length " << length;
            return;
        }
    }
}

TEST_F(CorruptPackage, TruncatedAtSectionBoundariesWithoutMapping) {
    std::vector<uint64_t> boundaries{sizeof(FileHeader), header_.index_offset};
    for (uint32_t i = 0; i < header_.section_count; ++i) {
        const IndexEntry entry = test::indexEntryOf(good_, i);
        boundaries.push_back(entry.offset);
        boundaries.push_back(entry.offset + entry.stored_size);
    }
    for (uint64_t length : boundaries) {
        expectOpenError(
            std::vector<std::byte>(good_.begin(), good_.begin() + static_cast<std::ptrdiff_t>(length)),
            ErrorCode::Truncated, "length " + std::to_string(length));
    }
}

TEST_F(CorruptPackage, FlippedHeaderByteIsDetected) {
    for (std::size_t offset = 0; offset < sizeof(FileHeader); ++offset) {
        std::vector<std::byte> bytes = good_;
        bytes[offset] ^= std::byte{0xFF};
        // The identifier says "not ours"; a flipped major byte reads as major 0xFE or 0xFF01, which
        // cannot be told from a real newer major (its header may be laid out differently, so its
        // checksum cannot be checked); any other byte breaks the header checksum.
        const ErrorCode expected = offset < 8    ? ErrorCode::NotAPackage
                                   : offset < 10 ? ErrorCode::NewerMajorVersion
                                                 : ErrorCode::Corrupt;
        expectOpenError(bytes, expected, "header byte " + std::to_string(offset));
    }
}

TEST_F(CorruptPackage, FlippedIndexByteIsCorrupt) {
    for (std::size_t offset = header_.index_offset; offset < good_.size(); ++offset) {
        std::vector<std::byte> bytes = good_;
        bytes[offset] ^= std::byte{0x01};
        const auto path = craft(bytes);
        expectPackageError([&] { ContainerReader::open(path); }, ErrorCode::Corrupt, path);
    }
}

TEST_F(CorruptPackage, FlippedSectionByteFailsOnlyThatSection) {
    for (uint32_t i = 0; i < header_.section_count; ++i) {
        const IndexEntry entry = test::indexEntryOf(good_, i);
        const uint32_t frame = entry.type == kMetadataType ? kNoFrame : entry.frame;
        // First, middle and last stored byte of every non-empty section.
        for (uint64_t within : {uint64_t{0}, entry.stored_size / 2, entry.stored_size - 1}) {
            if (entry.stored_size == 0) continue;
            std::vector<std::byte> bytes = good_;
            bytes[entry.offset + within] ^= std::byte{0x10};
            EXPECT_EQ(corruptSections(bytes), std::vector<uint32_t>{frame})
                << "section " << i << " byte " << within;
        }
    }
}

TEST_F(CorruptPackage, FlippedPaddingByteChangesNoData) {
    // Padding carries no data (docs/package-format.md): a reader never uses it.
    const IndexEntry first = test::indexEntryOf(good_, 0);
    const uint64_t padding = first.offset + first.stored_size;
    ASSERT_LT(padding, test::indexEntryOf(good_, 1).offset);
    std::vector<std::byte> bytes = good_;
    bytes[padding] ^= std::byte{0xFF};
    EXPECT_TRUE(corruptSections(bytes).empty());
}

TEST_F(CorruptPackage, AppendedBytesAreCorrupt) {
    std::vector<std::byte> bytes = good_;
    bytes.push_back(std::byte{0});
    expectOpenError(bytes, ErrorCode::Corrupt, "one byte appended");
}

TEST_F(CorruptPackage, NewerMajorVersionIsRefusedBeforeAnythingElse) {
    std::vector<std::byte> bytes = good_;
    const uint16_t major = 2;
    std::memcpy(bytes.data() + offsetof(FileHeader, version_major), &major, sizeof major);
    expectOpenError(bytes, ErrorCode::NewerMajorVersion, "major 2, old checksum");
    // A newer major may have a shorter header: the version is judged from the first 10 bytes.
    expectOpenError(std::vector<std::byte>(bytes.begin(), bytes.begin() + 10), ErrorCode::NewerMajorVersion,
                    "major 2, 10 bytes");
}

TEST_F(CorruptPackage, MajorVersionZeroIsCorrupt) {
    std::vector<std::byte> bytes = good_;
    const uint16_t major = 0;
    std::memcpy(bytes.data() + offsetof(FileHeader, version_major), &major, sizeof major);
    test::reseal(bytes);
    expectOpenError(bytes, ErrorCode::Corrupt, "major 0");
}

TEST_F(CorruptPackage, NewerMinorWithUnknownOptionalSectionIsReadable) {
    const auto path = dir_ / "newer-minor.firelook";
    const std::vector<float> factors = test::smoothFloats(64, 3);
    {
        ContainerWriter writer(path, WriterOptions{.zstd_level = 10, .format_minor = 7});
        writer.addSection(kFactors, 0, asBytes(factors), Codec::Raw);
        writer.addSection(kNewFeature, kNoFrame, asBytes(factors), Codec::Zstd, false);
        writer.commit();
    }
    const ContainerReader reader =
        ContainerReader::open(path, ReaderOptions{.memory_map = true, .understood_types = {kFactors}});
    EXPECT_EQ(reader.version(), (FormatVersion{1, 7}));
    ASSERT_EQ(reader.sections().size(), 1u);
    EXPECT_EQ(reader.skippedSectionCount(), 1u);
    EXPECT_EQ(reader.find(kNewFeature), nullptr);
    EXPECT_EQ(reader.read(*reader.find(kFactors, 0)).size(), factors.size() * sizeof(float));

    // An inspection tool that names no types sees everything.
    EXPECT_EQ(ContainerReader::open(path).sections().size(), 2u);
}

TEST_F(CorruptPackage, UnknownRequiredSectionIsUnsupported) {
    const auto path = dir_ / "unknown-required.firelook";
    {
        ContainerWriter writer(path, WriterOptions{.zstd_level = 10, .format_minor = 7});
        writer.addSection(kFactors, 0, {}, Codec::Raw);
        writer.addSection(kNewFeature, 3, {}, Codec::Raw, true);
        writer.commit();
    }
    expectPackageError(
        [&] { ContainerReader::open(path, ReaderOptions{.memory_map = true, .understood_types = {kFactors}}); },
        ErrorCode::UnsupportedFeature, path);
}

TEST_F(CorruptPackage, UnknownCodecIsUnsupportedWhenRequiredAndSkippedWhenOptional) {
    std::vector<std::byte> bytes = good_;
    IndexEntry entry = test::indexEntryOf(bytes, 2);  // FACT frame 1, zstd, required
    entry.codec = 9;
    test::setIndexEntry(bytes, 2, entry);
    test::reseal(bytes);
    expectOpenError(bytes, ErrorCode::UnsupportedFeature, "required section with codec 9");

    entry.flags = 0;
    test::setIndexEntry(bytes, 2, entry);
    test::reseal(bytes);
    const ContainerReader reader = ContainerReader::open(craft(bytes));
    EXPECT_EQ(reader.skippedSectionCount(), 1u);
    EXPECT_EQ(reader.find(kFactors, 1), nullptr);
    EXPECT_NE(reader.find(kFactors, 0), nullptr);
}

// Inconsistent files whose checksums were recomputed, as a buggy or hostile writer would make them.
TEST_F(CorruptPackage, InconsistentIndexIsCorruptEvenWithValidChecksums) {
    const auto edited = [&](uint32_t index, const auto& edit) {
        std::vector<std::byte> bytes = good_;
        IndexEntry entry = test::indexEntryOf(bytes, index);
        edit(entry);
        test::setIndexEntry(bytes, index, entry);
        test::reseal(bytes);
        return bytes;
    };
    expectOpenError(edited(1, [](IndexEntry& e) { e.offset += 8; }), ErrorCode::Corrupt,
                    "misaligned section");
    expectOpenError(edited(1, [](IndexEntry& e) { e.offset = 0; }), ErrorCode::Corrupt,
                    "section over the header");
    expectOpenError(edited(2, [&](IndexEntry& e) { e.offset = test::indexEntryOf(good_, 1).offset; }),
                    ErrorCode::Corrupt, "overlapping sections");
    expectOpenError(edited(1, [](IndexEntry& e) { e.stored_size = UINT64_MAX - 10; }), ErrorCode::Corrupt,
                    "section past the end");
    expectOpenError(edited(1, [](IndexEntry& e) { e.raw_size += 1; }), ErrorCode::Corrupt,
                    "raw section with raw size != stored size");
    expectOpenError(edited(2, [](IndexEntry& e) { e.raw_size = UINT64_MAX; }), ErrorCode::Corrupt,
                    "zstd section claiming an impossible raw size");
    expectOpenError(edited(2, [](IndexEntry& e) { e.frame = 0; }), ErrorCode::Corrupt,
                    "duplicate (type, frame)");
}

TEST_F(CorruptPackage, InconsistentHeaderIsCorruptEvenWithValidChecksums) {
    const auto edited = [&](const auto& edit) {
        std::vector<std::byte> bytes = good_;
        FileHeader header = test::headerOf(bytes);
        edit(header);
        test::setHeader(bytes, header);
        test::reseal(bytes);
        return bytes;
    };
    expectOpenError(edited([](FileHeader& h) { h.header_size = 128; }), ErrorCode::Corrupt, "header size");
    expectOpenError(edited([](FileHeader& h) { h.index_entry_size = 32; }), ErrorCode::Corrupt, "entry size");
    expectOpenError(edited([](FileHeader& h) { h.section_count -= 1; }), ErrorCode::Corrupt,
                    "index not at end");
    expectOpenError(edited([](FileHeader& h) { h.file_size -= 1; }), ErrorCode::Corrupt,
                    "file larger than declared");
}

TEST_F(CorruptPackage, ZstdFrameThatDisagreesWithTheIndexIsCorrupt) {
    const IndexEntry zstd_entry = test::indexEntryOf(good_, 2);
    ASSERT_EQ(zstd_entry.codec, static_cast<uint32_t>(Codec::Zstd));

    // Garbage inside the frame with a matching checksum: zstd itself must catch it.
    std::vector<std::byte> bytes = good_;
    for (uint64_t i = 6; i < zstd_entry.stored_size; ++i) bytes[zstd_entry.offset + i] = std::byte{0xA5};
    IndexEntry entry = zstd_entry;
    entry.checksum = test::xxh3(std::span(bytes).subspan(entry.offset, entry.stored_size));
    test::setIndexEntry(bytes, 2, entry);
    test::reseal(bytes);
    EXPECT_EQ(corruptSections(bytes), std::vector<uint32_t>{1});

    // A raw size that differs from the size the frame records.
    bytes = good_;
    entry = zstd_entry;
    entry.raw_size -= 4;
    test::setIndexEntry(bytes, 2, entry);
    test::reseal(bytes);
    EXPECT_EQ(corruptSections(bytes), std::vector<uint32_t>{1});
}

TEST_F(CorruptPackage, FilesThatAreNotPackages) {
    expectOpenError({}, ErrorCode::NotAPackage, "empty file");

    std::mt19937 random(42);
    std::vector<std::byte> noise(1000);
    for (auto& byte : noise) byte = static_cast<std::byte>(random() & 0xFF);
    noise[0] = std::byte{0x00};  // a seeded file, but make sure it cannot start like ours
    expectOpenError(noise, ErrorCode::NotAPackage, "random bytes");

    const unsigned char png[] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A, 0, 0, 0, 13, 'I', 'H', 'D',
                                 'R',  0,   0,   0,   1,    0,    0,    0,    1, 8, 6, 0,  0,   0};
    expectOpenError(std::vector<std::byte>(reinterpret_cast<const std::byte*>(png),
                                           reinterpret_cast<const std::byte*>(png) + sizeof png),
                    ErrorCode::NotAPackage, "PNG header");

    const std::string text = "{\"format\": \"firelook-look\", \"version\": 1}\n";
    expectOpenError(std::vector<std::byte>(reinterpret_cast<const std::byte*>(text.data()),
                                           reinterpret_cast<const std::byte*>(text.data()) + text.size()),
                    ErrorCode::NotAPackage, "a JSON look file");
}

TEST_F(CorruptPackage, MissingFileAndFolderAreIoErrors) {
    const auto missing = dir_ / "missing.firelook";
    expectPackageError([&] { ContainerReader::open(missing); }, ErrorCode::IoError, missing);
    expectPackageError([&] { ContainerReader::open(dir_.path()); }, ErrorCode::IoError, dir_.path());
}

}  // namespace
}  // namespace firelook::package
