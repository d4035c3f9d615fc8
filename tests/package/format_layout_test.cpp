// Pins the on-disk layout: every field's byte offset as documented in format.h and
// docs/package-format.md. A change here is a format change and needs a major version bump.

#include <gtest/gtest.h>

#include <cstddef>
#include <set>
#include <string>

#include "package/error.h"
#include "package/format.h"

namespace firelook::package {
namespace {

TEST(PackageFormatLayout, HeaderFieldOffsets) {
    EXPECT_EQ(sizeof(FileHeader), 64u);
    EXPECT_EQ(offsetof(FileHeader, identifier), 0u);
    EXPECT_EQ(offsetof(FileHeader, version_major), 8u);
    EXPECT_EQ(offsetof(FileHeader, version_minor), 10u);
    EXPECT_EQ(offsetof(FileHeader, header_size), 12u);
    EXPECT_EQ(offsetof(FileHeader, index_entry_size), 16u);
    EXPECT_EQ(offsetof(FileHeader, section_count), 20u);
    EXPECT_EQ(offsetof(FileHeader, index_offset), 24u);
    EXPECT_EQ(offsetof(FileHeader, file_size), 32u);
    EXPECT_EQ(offsetof(FileHeader, index_checksum), 40u);
    EXPECT_EQ(offsetof(FileHeader, reserved), 48u);
    EXPECT_EQ(offsetof(FileHeader, header_checksum), 56u);
}

TEST(PackageFormatLayout, IndexEntryFieldOffsets) {
    EXPECT_EQ(sizeof(IndexEntry), 64u);
    EXPECT_EQ(offsetof(IndexEntry, type), 0u);
    EXPECT_EQ(offsetof(IndexEntry, frame), 4u);
    EXPECT_EQ(offsetof(IndexEntry, flags), 8u);
    EXPECT_EQ(offsetof(IndexEntry, codec), 12u);
    EXPECT_EQ(offsetof(IndexEntry, offset), 16u);
    EXPECT_EQ(offsetof(IndexEntry, stored_size), 24u);
    EXPECT_EQ(offsetof(IndexEntry, raw_size), 32u);
    EXPECT_EQ(offsetof(IndexEntry, checksum), 40u);
    EXPECT_EQ(offsetof(IndexEntry, reserved), 48u);
}

TEST(PackageFormatLayout, ConstantsMatchTheSpecification) {
    const unsigned char identifier[8] = {0x89, 'F', 'L', 'K', 0x0D, 0x0A, 0x1A, 0x0A};
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(kIdentifier), 8),
              std::string(reinterpret_cast<const char*>(identifier), 8));
    EXPECT_EQ(kFormatMajor, 1);
    EXPECT_EQ(kSectionAlignment, 64u);
    EXPECT_EQ(kNoFrame, 0xFFFFFFFFu);
    EXPECT_EQ(kSectionRequired, 1u);
    EXPECT_EQ(static_cast<uint32_t>(Codec::Raw), 0u);
    EXPECT_EQ(static_cast<uint32_t>(Codec::Zstd), 1u);
    // Stored little-endian, the fourcc's bytes spell the name in file order.
    EXPECT_EQ(kMetadataType, 0x4154454Du);
    EXPECT_EQ(makeFourCC('F', 'A', 'C', 'T'), 0x54434146u);
}

TEST(PackageFormatLayout, EveryErrorCodeHasItsOwnName) {
    std::set<std::string> names;
    for (int32_t value = 1; value <= 10; ++value) {
        const char* name = toString(static_cast<ErrorCode>(value));
        ASSERT_NE(name, nullptr);
        EXPECT_STRNE(name, "unknown error") << value;
        names.insert(name);
    }
    EXPECT_EQ(names.size(), 10u);
    EXPECT_STREQ(toString(static_cast<ErrorCode>(999)), "unknown error");
}

TEST(PackageFormatLayout, ErrorMessageNamesFileAndProblem) {
    const PackageError error(ErrorCode::Truncated, "/data/fire.firelook", "the file has 10 bytes");
    EXPECT_EQ(error.code(), ErrorCode::Truncated);
    EXPECT_EQ(error.file(), "/data/fire.firelook");
    EXPECT_STREQ(error.what(), "/data/fire.firelook: truncated: the file has 10 bytes");
}

}  // namespace
}  // namespace firelook::package
