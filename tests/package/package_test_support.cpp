#include "package_test_support.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>

#define XXH_INLINE_ALL
#include <xxhash.h>

namespace firelook::package::test {

std::vector<std::byte> readFile(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error("test: cannot read " + file.string());
    std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::byte> bytes(chars.size());
    std::memcpy(bytes.data(), chars.data(), chars.size());
    return bytes;
}

void writeFile(const std::filesystem::path& file, std::span<const std::byte> bytes) {
    // A fresh file rather than truncating the old one: ext4 flushes a truncated-and-rewritten file
    // to disk (auto_da_alloc), which made the truncation sweep a hundred times slower.
    std::filesystem::remove(file);
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("test: cannot write " + file.string());
}

std::vector<float> smoothFloats(std::size_t count, uint32_t seed) {
    std::mt19937 random(seed);
    std::normal_distribution<float> noise(0.0f, 0.01f);
    std::vector<float> values(count);
    for (std::size_t i = 0; i < count; ++i) {
        const float x = static_cast<float>(i % 1024) / 1024.0f;
        const float y = static_cast<float>(i / 1024) / 1024.0f;
        values[i] = std::sin(6.0f * x + static_cast<float>(seed)) * std::cos(4.0f * y) + noise(random);
    }
    return values;
}

FileHeader headerOf(std::span<const std::byte> file) {
    FileHeader header;
    std::memcpy(&header, file.data(), sizeof header);
    return header;
}

IndexEntry indexEntryOf(std::span<const std::byte> file, uint32_t index) {
    IndexEntry entry;
    std::memcpy(&entry, file.data() + headerOf(file).index_offset + index * sizeof(IndexEntry), sizeof entry);
    return entry;
}

void setHeader(std::vector<std::byte>& file, const FileHeader& header) {
    std::memcpy(file.data(), &header, sizeof header);
}

void setIndexEntry(std::vector<std::byte>& file, uint32_t index, const IndexEntry& entry) {
    std::memcpy(file.data() + headerOf(file).index_offset + index * sizeof(IndexEntry), &entry, sizeof entry);
}

uint64_t xxh3(std::span<const std::byte> bytes) { return XXH3_64bits(bytes.data(), bytes.size()); }

void reseal(std::vector<std::byte>& file) {
    FileHeader header = headerOf(file);
    header.index_checksum =
        xxh3(std::span(file).subspan(header.index_offset, header.section_count * sizeof(IndexEntry)));
    setHeader(file, header);
    header.header_checksum = xxh3(std::span(file).first(offsetof(FileHeader, header_checksum)));
    setHeader(file, header);
}

AlignedBytes::AlignedBytes(std::span<const std::byte> bytes, std::size_t misalignment)
    : storage_(bytes.size() + 2 * kSectionAlignment), size_(bytes.size()) {
    const auto address = reinterpret_cast<std::uintptr_t>(storage_.data());
    start_ = (kSectionAlignment - address % kSectionAlignment) % kSectionAlignment + misalignment % kSectionAlignment;
    if (!bytes.empty()) std::memcpy(storage_.data() + start_, bytes.data(), bytes.size());
}

void expectPackageError(const std::function<void()>& action, ErrorCode code,
                        const std::filesystem::path& file) {
    try {
        action();
        ADD_FAILURE() << "expected PackageError " << toString(code) << " for " << file << ", got success";
    } catch (const PackageError& error) {
        EXPECT_EQ(error.code(), code) << "got " << toString(error.code()) << ": " << error.what();
        EXPECT_EQ(error.file(), file);
        EXPECT_NE(std::string(error.what()).find(file.string()), std::string::npos) << error.what();
    }
}

}  // namespace firelook::package::test
