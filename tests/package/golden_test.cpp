// Golden packages under tests/data/package pin the byte layout: the writer must reproduce
// tiny_raw.firelook exactly, and the reader must decode both files to the values they were made
// from. tiny_raw holds only Raw sections so its bytes do not depend on the zstd version;
// tiny_zstd is only read (zstd output may change between zstd versions, decoding may not).
// To regenerate after a deliberate format change (with a version bump), run this test with
// FIRELOOK_REGENERATE_GOLDEN=1.

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "package/container_reader.h"
#include "package/container_writer.h"
#include "package_test_support.h"

namespace firelook::package {
namespace {

using test::asBytes;

const std::filesystem::path kGoldenDir = std::filesystem::path(FIRELOOK_TEST_DATA_DIR) / "package";
using test::kFactors;
constexpr uint32_t kOptional = makeFourCC('O', 'P', 'T', 'L');
constexpr std::string_view kRawMetadata = R"({"tool":"firelook golden","version":1})";
constexpr std::string_view kZstdMetadata = R"({"tool":"firelook golden","codec":"zstd"})";
const std::vector<float> kRawFactors{1.0f, -2.5f, 0.125f, 3.0e6f};

std::vector<float> zstdFactors() {
    std::vector<float> values(1000);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<float>(i) * 0.5f;
    return values;
}

// The golden files are examples of version 1.0 (docs/package-format.md), whatever minor this build writes.
void writeTinyRaw(const std::filesystem::path& path) {
    ContainerWriter writer(path, WriterOptions{.zstd_level = 10, .format_minor = 0});
    writer.addSection(kMetadataType, kNoFrame, std::as_bytes(std::span(kRawMetadata)), Codec::Raw);
    writer.addSection(kFactors, 1, asBytes(kRawFactors), Codec::Raw);
    writer.addSection(kOptional, 2, {}, Codec::Raw, false);
    writer.commit();
}

void writeTinyZstd(const std::filesystem::path& path) {
    ContainerWriter writer(path, WriterOptions{.zstd_level = 19, .format_minor = 0});
    writer.addMetadata(kZstdMetadata);
    writer.addSection(kFactors, 0, asBytes(zstdFactors()), Codec::Zstd);
    writer.commit();
}

class PackageGolden : public ::testing::Test {
  protected:
    void SetUp() override {
        if (std::getenv("FIRELOOK_REGENERATE_GOLDEN") != nullptr) {
            writeTinyRaw(kGoldenDir / "tiny_raw.firelook");
            writeTinyZstd(kGoldenDir / "tiny_zstd.firelook");
            GTEST_SKIP() << "regenerated the golden packages in " << kGoldenDir;
        }
    }
};

TEST_F(PackageGolden, WriterReproducesTheGoldenBytes) {
    test::TempDir dir;
    writeTinyRaw(dir / "tiny_raw.firelook");
    EXPECT_EQ(test::readFile(dir / "tiny_raw.firelook"), test::readFile(kGoldenDir / "tiny_raw.firelook"));
}

TEST_F(PackageGolden, HeaderAndIndexHoldTheDocumentedValues) {
    const std::vector<std::byte> file = test::readFile(kGoldenDir / "tiny_raw.firelook");
    ASSERT_EQ(file.size(),
              384u);  // 64 header + META padded to 64 + FACT padded to 64 + empty OPTL + 3 * 64 index
    const FileHeader header = test::headerOf(file);
    EXPECT_EQ(std::memcmp(header.identifier,
                          "\x89"
                          "FLK\r\n\x1A\n",
                          8),
              0);
    EXPECT_EQ(header.version_major, 1);
    EXPECT_EQ(header.version_minor, 0);
    EXPECT_EQ(header.header_size, 64u);
    EXPECT_EQ(header.index_entry_size, 64u);
    EXPECT_EQ(header.section_count, 3u);
    EXPECT_EQ(header.index_offset, 192u);
    EXPECT_EQ(header.file_size, 384u);
    EXPECT_EQ(header.reserved, 0u);
    EXPECT_EQ(header.index_checksum, test::xxh3(std::span(file).subspan(192, 192)));
    EXPECT_EQ(header.header_checksum, test::xxh3(std::span(file).first(56)));

    const IndexEntry meta = test::indexEntryOf(file, 0);
    EXPECT_EQ(meta.type, kMetadataType);
    EXPECT_EQ(meta.frame, kNoFrame);
    EXPECT_EQ(meta.flags, 1u);
    EXPECT_EQ(meta.codec, 0u);
    EXPECT_EQ(meta.offset, 64u);
    EXPECT_EQ(meta.stored_size, kRawMetadata.size());
    EXPECT_EQ(meta.raw_size, kRawMetadata.size());
    EXPECT_EQ(meta.checksum, test::xxh3(std::span(file).subspan(64, kRawMetadata.size())));

    const IndexEntry factors = test::indexEntryOf(file, 1);
    EXPECT_EQ(factors.type, kFactors);
    EXPECT_EQ(factors.frame, 1u);
    EXPECT_EQ(factors.offset, 128u);
    EXPECT_EQ(factors.stored_size, 16u);

    const IndexEntry optional = test::indexEntryOf(file, 2);
    EXPECT_EQ(optional.type, kOptional);
    EXPECT_EQ(optional.frame, 2u);
    EXPECT_EQ(optional.flags, 0u);
    EXPECT_EQ(optional.offset, 192u);  // an empty section sits where the next data would start
    EXPECT_EQ(optional.stored_size, 0u);
    EXPECT_EQ(optional.reserved[0], 0u);
    EXPECT_EQ(optional.reserved[1], 0u);
}

TEST_F(PackageGolden, ReaderDecodesTheRawGolden) {
    const ContainerReader reader = ContainerReader::open(kGoldenDir / "tiny_raw.firelook");
    EXPECT_EQ(reader.version(), (FormatVersion{1, 0}));
    EXPECT_EQ(reader.metadata(), std::string(kRawMetadata));
    const std::span<const std::byte> factors = reader.mapped(*reader.find(kFactors, 1));
    ASSERT_EQ(factors.size(), 16u);
    std::vector<float> values(4);
    std::memcpy(values.data(), factors.data(), 16);
    EXPECT_EQ(values, kRawFactors);
    ASSERT_NE(reader.find(kOptional, 2), nullptr);
    EXPECT_FALSE(reader.find(kOptional, 2)->required());
}

TEST_F(PackageGolden, ReaderDecodesTheZstdGolden) {
    const ContainerReader reader = ContainerReader::open(kGoldenDir / "tiny_zstd.firelook");
    EXPECT_EQ(reader.metadata(), std::string(kZstdMetadata));
    const SectionInfo* section = reader.find(kFactors, 0);
    ASSERT_NE(section, nullptr);
    EXPECT_EQ(section->codec, Codec::Zstd);
    const std::vector<std::byte> decoded = reader.read(*section);
    std::vector<float> values(decoded.size() / sizeof(float));
    std::memcpy(values.data(), decoded.data(), decoded.size());
    EXPECT_EQ(values, zstdFactors());
}

}  // namespace
}  // namespace firelook::package
