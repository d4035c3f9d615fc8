#pragma once

#include <cstddef>
#include <filesystem>
#include <span>

namespace firelook::package::detail {

// How a package held in memory is taken: used in place (the caller keeps the bytes alive and
// unchanged for as long as the reader), or copied at open (the caller may free them at once).
enum class MemoryOwnership { Borrow, Copy };

// A whole package's bytes, read-only: a POSIX memory mapping, a 64-byte aligned heap copy (of a
// file, when mapping is not wanted or fails, or of a caller's buffer), or a borrowed view of a
// caller's buffer. Every kind has bytes().data() at least 64-byte aligned, so a 64-aligned offset
// gives a 64-aligned pointer: a borrowed buffer that is not 64-byte aligned is refused rather than
// quietly copied, since borrowing is chosen to avoid a second copy.
class MappedFile {
  public:
    // Throws PackageError(IoError or OutOfMemory) naming `file`.
    static MappedFile open(const std::filesystem::path& file, bool memory_map);
    // Throws PackageError naming `name`: InvalidArgument for a borrowed buffer not 64-byte aligned,
    // OutOfMemory when a copy cannot be made. An empty span is accepted (the reader then refuses it).
    static MappedFile fromMemory(std::span<const std::byte> bytes, MemoryOwnership ownership,
                                 const std::filesystem::path& name);

    MappedFile() = default;
    ~MappedFile();
    MappedFile(MappedFile&& other) noexcept;
    MappedFile& operator=(MappedFile&& other) noexcept;
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;

    std::span<const std::byte> bytes() const { return {data_, size_}; }
    bool isMemoryMapped() const { return storage_ == Storage::Mapped; }
    bool isBorrowed() const { return storage_ == Storage::Borrowed; }

  private:
    enum class Storage {
        Heap,      // std::aligned_alloc (or null when empty): freed here
        Mapped,    // mmap: unmapped here
        Borrowed,  // the caller's: never freed here
    };
    void release() noexcept;

    const std::byte* data_ = nullptr;
    std::size_t size_ = 0;
    Storage storage_ = Storage::Heap;
};

}  // namespace firelook::package::detail
