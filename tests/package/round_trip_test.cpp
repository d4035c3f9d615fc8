// Whatever goes into a ContainerWriter comes out of a ContainerReader bit-exact, in both codecs,
// through the mapping and through the read-into-memory fallback.

#include <gtest/gtest.h>

#include <cstring>
#include <thread>

#include "package/container_reader.h"
#include "package/container_writer.h"
#include "package_test_support.h"

namespace firelook::package {
namespace {

using test::asBytes;
using test::smoothFloats;
using test::TempDir;

using test::kFactors;
constexpr uint32_t kEmpty = makeFourCC('E', 'M', 'P', 'T');

std::vector<std::byte> bytesOf(std::string_view text) {
    const auto bytes = std::as_bytes(std::span(text.data(), text.size()));
    return {bytes.begin(), bytes.end()};
}

class PackageRoundTrip : public ::testing::TestWithParam<bool> {};  // parameter: memory_map

TEST_P(PackageRoundTrip, RawAndZstdSectionsComeBackBitExact) {
    TempDir dir;
    const auto path = dir / "fire.firelook";
    const std::vector<float> raw_floats = smoothFloats(3000, 1);
    const std::vector<float> zstd_floats = smoothFloats(3000, 2);
    const std::string json = R"({"tool":"firelook test","settings":{"bins":16}})";
    {
        ContainerWriter writer(path);
        writer.addMetadata(json);
        writer.addSection(kFactors, 0, asBytes(raw_floats), Codec::Raw);
        writer.addSection(kFactors, 1, asBytes(zstd_floats), Codec::Zstd);
        writer.addSection(kEmpty, 0, {}, Codec::Raw, false);
        writer.addSection(kEmpty, 1, {}, Codec::Zstd, false);
        writer.commit();
    }
    ReaderOptions options;
    options.memory_map = GetParam();
    const ContainerReader reader = ContainerReader::open(path, options);
    EXPECT_EQ(reader.version(), (FormatVersion{kFormatMajor, kFormatMinor}));
    EXPECT_EQ(reader.isMemoryMapped(), GetParam());
    ASSERT_EQ(reader.sections().size(), 5u);
    EXPECT_EQ(reader.skippedSectionCount(), 0u);
    EXPECT_EQ(reader.fileSize(), std::filesystem::file_size(path));
    EXPECT_EQ(reader.metadata(), json);

    const SectionInfo* raw = reader.find(kFactors, 0);
    ASSERT_NE(raw, nullptr);
    EXPECT_EQ(raw->codec, Codec::Raw);
    EXPECT_TRUE(raw->required());
    EXPECT_EQ(raw->raw_size, raw_floats.size() * sizeof(float));
    const std::span<const std::byte> view = reader.mapped(*raw);
    ASSERT_EQ(view.size(), raw_floats.size() * sizeof(float));
    EXPECT_EQ(reinterpret_cast<uintptr_t>(view.data()) % kSectionAlignment, 0u);
    EXPECT_EQ(std::memcmp(view.data(), raw_floats.data(), view.size()), 0);
    EXPECT_EQ(reader.read(*raw), std::vector<std::byte>(view.begin(), view.end()));

    const SectionInfo* compressed = reader.find(kFactors, 1);
    ASSERT_NE(compressed, nullptr);
    EXPECT_EQ(compressed->codec, Codec::Zstd);
    EXPECT_LT(compressed->stored_size, compressed->raw_size);
    const std::vector<std::byte> decoded = reader.read(*compressed);
    ASSERT_EQ(decoded.size(), zstd_floats.size() * sizeof(float));
    EXPECT_EQ(std::memcmp(decoded.data(), zstd_floats.data(), decoded.size()), 0);

    for (uint32_t frame : {0u, 1u}) {
        const SectionInfo* empty = reader.find(kEmpty, frame);
        ASSERT_NE(empty, nullptr);
        EXPECT_FALSE(empty->required());
        EXPECT_EQ(empty->raw_size, 0u);
        EXPECT_TRUE(reader.read(*empty).empty());
    }
    EXPECT_TRUE(reader.mapped(*reader.find(kEmpty, 0)).empty());
    EXPECT_EQ(reader.find(kFactors, 2), nullptr);
    EXPECT_EQ(reader.find(kFactors), nullptr);
}

INSTANTIATE_TEST_SUITE_P(MappedAndRead, PackageRoundTrip, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "Mapped" : "ReadIntoMemory"; });

TEST(PackageRoundTrip, SectionsAreAlignedAndInWritingOrder) {
    TempDir dir;
    const auto path = dir / "aligned.firelook";
    {
        ContainerWriter writer(path);
        for (uint32_t frame = 0; frame < 20; ++frame) {
            // Lengths that are not multiples of 64 force padding after every section.
            const std::vector<std::byte> odd(frame * 7 + 1, std::byte{static_cast<unsigned char>(frame)});
            writer.addSection(kFactors, frame, odd, frame % 2 == 0 ? Codec::Raw : Codec::Zstd);
        }
        writer.commit();
    }
    const ContainerReader reader = ContainerReader::open(path);
    ASSERT_EQ(reader.sections().size(), 20u);
    uint64_t previous_end = sizeof(FileHeader);
    for (uint32_t i = 0; i < 20; ++i) {
        const SectionInfo& section = reader.sections()[i];
        EXPECT_EQ(section.frame, i);
        EXPECT_EQ(section.offset % kSectionAlignment, 0u);
        EXPECT_GE(section.offset, previous_end);
        previous_end = section.offset + section.stored_size;
        EXPECT_EQ(reader.read(section),
                  std::vector<std::byte>(i * 7 + 1, std::byte{static_cast<unsigned char>(i)}));
    }
}

TEST(PackageRoundTrip, LargeSectionsSpanManyZstdBlocksAndPages) {
    TempDir dir;
    const auto path = dir / "large.firelook";
    // 3 M floats = 12 MB: far more than zstd's 128 KiB block and many pages of the mapping.
    const std::vector<float> values = smoothFloats(3u << 20, 7);
    {
        ContainerWriter writer(path, WriterOptions{.zstd_level = 3, .format_minor = kFormatMinor});
        writer.addSection(kFactors, 0, asBytes(values), Codec::Raw);
        writer.addSection(kFactors, 1, asBytes(values), Codec::Zstd);
        writer.commit();
    }
    const ContainerReader reader = ContainerReader::open(path);
    const std::span<const std::byte> view = reader.mapped(*reader.find(kFactors, 0));
    ASSERT_EQ(view.size(), values.size() * sizeof(float));
    EXPECT_EQ(std::memcmp(view.data(), values.data(), view.size()), 0);
    const std::vector<std::byte> decoded = reader.read(*reader.find(kFactors, 1));
    ASSERT_EQ(decoded.size(), values.size() * sizeof(float));
    EXPECT_EQ(std::memcmp(decoded.data(), values.data(), decoded.size()), 0);
}

TEST(PackageRoundTrip, ManyFramesAreFoundByTypeAndFrame) {
    TempDir dir;
    const auto path = dir / "frames.firelook";
    constexpr uint32_t kFrameCount = 400;
    constexpr uint32_t kAlpha = makeFourCC('A', 'L', 'P', 'H');
    {
        ContainerWriter writer(path);
        writer.addMetadata("{}");
        // Frames written out of numeric order: lookup must not depend on the order in the file.
        for (uint32_t i = 0; i < kFrameCount; ++i) {
            const uint32_t frame = (i * 7919u) % kFrameCount + 1;
            const std::vector<uint32_t> factor{frame, frame * 2, frame * 3};
            const std::vector<uint32_t> alpha{frame + 1000};
            writer.addSection(kFactors, frame, asBytes(factor), Codec::Zstd);
            writer.addSection(kAlpha, frame, asBytes(alpha), Codec::Raw);
        }
        writer.commit();
    }
    const ContainerReader reader = ContainerReader::open(path);
    ASSERT_EQ(reader.sections().size(), 2 * kFrameCount + 1);
    for (uint32_t frame = 1; frame <= kFrameCount; ++frame) {
        const SectionInfo* factor = reader.find(kFactors, frame);
        const SectionInfo* alpha = reader.find(kAlpha, frame);
        ASSERT_NE(factor, nullptr) << frame;
        ASSERT_NE(alpha, nullptr) << frame;
        const std::vector<uint32_t> expected{frame, frame * 2, frame * 3};
        EXPECT_EQ(reader.read(*factor),
                  std::vector<std::byte>(asBytes(expected).begin(), asBytes(expected).end()));
        uint32_t alpha_value = 0;
        std::memcpy(&alpha_value, reader.mapped(*alpha).data(), sizeof alpha_value);
        EXPECT_EQ(alpha_value, frame + 1000);
    }
    EXPECT_EQ(reader.find(kFactors, 0), nullptr);
    EXPECT_EQ(reader.find(kFactors, kFrameCount + 1), nullptr);
}

TEST(PackageRoundTrip, PackageWithoutSectionsIsValid) {
    TempDir dir;
    const auto path = dir / "empty.firelook";
    {
        ContainerWriter writer(path);
        writer.commit();
    }
    EXPECT_EQ(std::filesystem::file_size(path), sizeof(FileHeader));
    const ContainerReader reader = ContainerReader::open(path);
    EXPECT_TRUE(reader.sections().empty());
    EXPECT_EQ(reader.metadata(), std::nullopt);
    EXPECT_EQ(reader.find(kFactors, 0), nullptr);
}

TEST(PackageRoundTrip, ZstdLevelsAllDecodeToTheSameBytes) {
    TempDir dir;
    const std::vector<float> values = smoothFloats(20000, 3);
    for (int level : {-5, 1, 19}) {
        const auto path = dir / ("level" + std::to_string(level) + ".firelook");
        {
            ContainerWriter writer(path, WriterOptions{.zstd_level = level, .format_minor = kFormatMinor});
            writer.addSection(kFactors, 0, asBytes(values));
            writer.commit();
        }
        const ContainerReader reader = ContainerReader::open(path);
        const std::vector<std::byte> decoded = reader.read(reader.sections()[0]);
        ASSERT_EQ(decoded.size(), values.size() * sizeof(float)) << level;
        EXPECT_EQ(std::memcmp(decoded.data(), values.data(), decoded.size()), 0) << level;
    }
}

TEST(PackageRoundTrip, OnlySectionsOfThisReaderAreAccepted) {
    TempDir dir;
    const auto path = dir / "foreign.firelook";
    {
        ContainerWriter writer(path);
        writer.addSection(kFactors, 0, bytesOf("payload"), Codec::Zstd);
        writer.commit();
    }
    const ContainerReader reader = ContainerReader::open(path);
    const SectionInfo copy = reader.sections()[0];
    EXPECT_EQ(reader.read(copy), bytesOf("payload"));  // an equal copy is as good as the original

    SectionInfo forged = copy;
    forged.offset = 0;  // would read the header as section data
    test::expectPackageError([&] { reader.read(forged); }, ErrorCode::InvalidArgument, path);
    SectionInfo missing = copy;
    missing.frame = 5;
    test::expectPackageError([&] { reader.read(missing); }, ErrorCode::InvalidArgument, path);
    test::expectPackageError([&] { reader.mapped(copy); }, ErrorCode::InvalidArgument,
                             path);  // zstd, not raw
}

TEST(PackageRoundTrip, ConcurrentReadersOfOneSectionAgree) {
    TempDir dir;
    const auto path = dir / "threads.firelook";
    const std::vector<float> values = smoothFloats(50000, 4);
    {
        ContainerWriter writer(path);
        writer.addSection(kFactors, 0, asBytes(values), Codec::Raw);
        writer.addSection(kFactors, 1, asBytes(values), Codec::Zstd);
        writer.commit();
    }
    const ContainerReader reader = ContainerReader::open(path);
    std::vector<int> matches(8, 0);
    std::vector<std::thread> threads;
    for (std::size_t t = 0; t < matches.size(); ++t) {
        threads.emplace_back([&, t] {
            const auto view = reader.mapped(*reader.find(kFactors, 0));
            const auto decoded = reader.read(*reader.find(kFactors, 1));
            matches[t] = std::memcmp(view.data(), values.data(), view.size()) == 0 &&
                         std::memcmp(decoded.data(), values.data(), decoded.size()) == 0;
        });
    }
    for (auto& thread : threads) thread.join();
    EXPECT_EQ(matches, std::vector<int>(matches.size(), 1));
}

TEST(PackageRoundTrip, MovedReaderKeepsItsMapping) {
    TempDir dir;
    const auto path = dir / "moved.firelook";
    {
        ContainerWriter writer(path);
        writer.addSection(kFactors, 0, bytesOf("abc"), Codec::Raw);
        writer.commit();
    }
    ContainerReader first = ContainerReader::open(path);
    const std::span<const std::byte> view = first.mapped(first.sections()[0]);
    const ContainerReader second = std::move(first);
    // The view belongs to the mapping, which moved with the reader.
    EXPECT_EQ(std::vector<std::byte>(view.begin(), view.end()), bytesOf("abc"));
    EXPECT_EQ(second.read(second.sections()[0]), bytesOf("abc"));
}

}  // namespace
}  // namespace firelook::package
