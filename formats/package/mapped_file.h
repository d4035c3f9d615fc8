#pragma once

#include <cstddef>
#include <filesystem>
#include <span>

namespace firelook::package::detail {

// A whole file's bytes, read-only: a POSIX memory mapping, or a 64-byte aligned heap copy when
// mapping is not wanted or fails. Either way bytes().data() is at least 64-byte aligned, so a
// 64-aligned file offset gives a 64-aligned pointer.
class MappedFile {
  public:
    // Throws PackageError(IoError or OutOfMemory) naming `file`.
    static MappedFile open(const std::filesystem::path& file, bool memory_map);

    MappedFile() = default;
    ~MappedFile();
    MappedFile(MappedFile&& other) noexcept;
    MappedFile& operator=(MappedFile&& other) noexcept;
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;

    std::span<const std::byte> bytes() const { return {data_, size_}; }
    bool isMemoryMapped() const { return memory_mapped_; }

  private:
    void release() noexcept;

    const std::byte* data_ = nullptr;
    std::size_t size_ = 0;
    bool memory_mapped_ = false;  // else data_ came from std::aligned_alloc (or is null when empty)
};

}  // namespace firelook::package::detail
