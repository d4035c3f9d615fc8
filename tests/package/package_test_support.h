#pragma once

// Helpers shared by the package tests (the temporary folder is tests/support/temp_dir.h): whole-file I/O, test
// data, and re-sealing a deliberately edited package (recomputing its checksums) so a test can
// craft an inconsistent file that is not caught by a checksum first.

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "../support/temp_dir.h"
#include "package/error.h"
#include "package/format.h"

namespace firelook::package::test {

using firelook::testing::TempDir;

// The section type the tests write their factors under.
inline constexpr uint32_t kFactors = makeFourCC('F', 'A', 'C', 'T');

std::vector<std::byte> readFile(const std::filesystem::path& file);
void writeFile(const std::filesystem::path& file, std::span<const std::byte> bytes);

// Floats that look like an image factor: a smooth field plus a little noise (seeded, reproducible).
std::vector<float> smoothFloats(std::size_t count, uint32_t seed);

template <typename T>
std::span<const std::byte> asBytes(const std::vector<T>& values) {
    return std::as_bytes(std::span(values));
}

FileHeader headerOf(std::span<const std::byte> file);
IndexEntry indexEntryOf(std::span<const std::byte> file, uint32_t index);
void setHeader(std::vector<std::byte>& file, const FileHeader& header);
void setIndexEntry(std::vector<std::byte>& file, uint32_t index, const IndexEntry& entry);
// Recomputes the index and header checksums after an edit.
void reseal(std::vector<std::byte>& file);
// XXH3-64 as the format uses it.
uint64_t xxh3(std::span<const std::byte> bytes);

// A copy of some bytes that starts `misalignment` bytes past a 64-byte boundary (0: aligned), for
// borrowed memory sources. Not copyable: a borrowed view points into it.
class AlignedBytes {
  public:
    explicit AlignedBytes(std::span<const std::byte> bytes, std::size_t misalignment = 0);
    AlignedBytes(const AlignedBytes&) = delete;
    AlignedBytes& operator=(const AlignedBytes&) = delete;
    std::span<std::byte> bytes() { return std::span(storage_).subspan(start_, size_); }
    std::span<const std::byte> view() const { return std::span(storage_).subspan(start_, size_); }

  private:
    std::vector<std::byte> storage_;
    std::size_t start_ = 0, size_ = 0;
};

// Runs `action` and expects a PackageError with `code` whose message names `file`.
void expectPackageError(const std::function<void()>& action, ErrorCode code,
                        const std::filesystem::path& file);

}  // namespace firelook::package::test
