#include "package/mapped_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>

#include "package/error.h"
#include "package/format.h"

namespace firelook::package::detail {
namespace {

class FileDescriptor {
  public:
    explicit FileDescriptor(int fd) : fd_(fd) {}
    ~FileDescriptor() {
        if (fd_ >= 0) ::close(fd_);
    }
    FileDescriptor(const FileDescriptor&) = delete;
    FileDescriptor& operator=(const FileDescriptor&) = delete;
    int get() const { return fd_; }

  private:
    int fd_;
};

[[noreturn]] void throwIo(const std::filesystem::path& file, const std::string& action, int error) {
    throw PackageError(ErrorCode::IoError, file, "cannot " + action + ": " + std::strerror(error));
}

// A 64-byte aligned buffer of at least `size` bytes for the heap copy of a file or a caller's buffer
// (aligned_alloc wants a multiple of the alignment).
std::byte* allocateAligned(std::size_t size, const std::filesystem::path& name) {
    const std::size_t capacity = (size + kSectionAlignment - 1) / kSectionAlignment * kSectionAlignment;
    auto* buffer = static_cast<std::byte*>(std::aligned_alloc(kSectionAlignment, capacity));
    if (buffer == nullptr) {
        throw PackageError(ErrorCode::OutOfMemory, name, "no memory to hold " + std::to_string(size) + " bytes");
    }
    return buffer;
}

}  // namespace

MappedFile MappedFile::open(const std::filesystem::path& file, bool memory_map) {
    const FileDescriptor fd(::open(file.c_str(), O_RDONLY | O_CLOEXEC));
    if (fd.get() < 0) throwIo(file, "open", errno);
    struct stat status {};
    if (::fstat(fd.get(), &status) != 0) throwIo(file, "stat", errno);
    if (!S_ISREG(status.st_mode)) throw PackageError(ErrorCode::IoError, file, "not a regular file");

    MappedFile mapped;
    mapped.size_ = static_cast<std::size_t>(status.st_size);
    if (mapped.size_ == 0) return mapped;

    if (memory_map) {
        void* address = ::mmap(nullptr, mapped.size_, PROT_READ, MAP_PRIVATE, fd.get(), 0);
        if (address != MAP_FAILED) {
            mapped.data_ = static_cast<const std::byte*>(address);
            mapped.storage_ = Storage::Mapped;
            return mapped;
        }
        // Some file systems cannot map; reading works everywhere.
    }

    std::byte* buffer = allocateAligned(mapped.size_, file);
    mapped.data_ = buffer;
    std::size_t done = 0;
    while (done < mapped.size_) {
        const ssize_t got = ::pread(fd.get(), buffer + done, mapped.size_ - done, static_cast<off_t>(done));
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throwIo(file, "read", errno);  // `mapped` frees the buffer
        if (got == 0) {
            throw PackageError(ErrorCode::IoError, file, "the file shrank while it was being read");
        }
        done += static_cast<std::size_t>(got);
    }
    return mapped;
}

MappedFile MappedFile::fromMemory(std::span<const std::byte> bytes, MemoryOwnership ownership,
                                  const std::filesystem::path& name) {
    MappedFile held;
    held.size_ = bytes.size();
    if (ownership == MemoryOwnership::Borrow) {
        const auto misalignment = reinterpret_cast<std::uintptr_t>(bytes.data()) % kSectionAlignment;
        if (misalignment != 0) {
            throw PackageError(ErrorCode::InvalidArgument, name,
                               "a borrowed buffer must be 64-byte aligned (section data is used in place), "
                               "this one is " + std::to_string(misalignment) +
                                   " bytes past a 64-byte boundary: align it or have it copied");
        }
        held.data_ = bytes.data();
        held.storage_ = Storage::Borrowed;
        return held;
    }
    if (bytes.empty()) return held;
    std::byte* buffer = allocateAligned(bytes.size(), name);
    std::memcpy(buffer, bytes.data(), bytes.size());
    held.data_ = buffer;
    return held;
}

MappedFile::~MappedFile() { release(); }

MappedFile::MappedFile(MappedFile&& other) noexcept
    : data_(std::exchange(other.data_, nullptr)),
      size_(std::exchange(other.size_, 0)),
      storage_(std::exchange(other.storage_, Storage::Heap)) {}

MappedFile& MappedFile::operator=(MappedFile&& other) noexcept {
    if (this != &other) {
        release();
        data_ = std::exchange(other.data_, nullptr);
        size_ = std::exchange(other.size_, 0);
        storage_ = std::exchange(other.storage_, Storage::Heap);
    }
    return *this;
}

void MappedFile::release() noexcept {
    switch (storage_) {
        case Storage::Mapped: ::munmap(const_cast<std::byte*>(data_), size_); break;
        case Storage::Heap: std::free(const_cast<std::byte*>(data_)); break;
        case Storage::Borrowed: break;  // the caller's
    }
    data_ = nullptr;
    size_ = 0;
    storage_ = Storage::Heap;
}

}  // namespace firelook::package::detail
