#include "common/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <utility>

#include "common/error.h"

namespace firelook {
namespace {

std::filesystem::path folderOf(const std::filesystem::path& target) {
    return target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
}

[[noreturn]] void throwIo(const std::filesystem::path& target, const std::string& problem, int error) {
    throw Error(ErrorCode::IoError, target.string() + ": " + problem + ": " + std::strerror(error));
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
    static std::atomic<unsigned long> counter{0};
    const std::filesystem::path folder = folderOf(target_);
    const std::string prefix = "." + target_.filename().string() + "." + std::to_string(::getpid()) + "-";
    // The counter makes names unique within the process and O_EXCL across processes; the retry
    // covers a stale temporary left by a killed process whose pid was reused.
    int error = EEXIST;
    for (int attempt = 0; attempt < 100; ++attempt) {
        temporary_ = folder / (prefix + std::to_string(counter.fetch_add(1)) + ".tmp");
        fd_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd_ >= 0) return;
        error = errno;
        if (error != EEXIST) break;
    }
    temporary_.clear();
    throwIo(target_, "cannot create a temporary file beside it", error);
}

AtomicFile::~AtomicFile() { discard(); }

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : target_(std::move(other.target_)),
      temporary_(std::exchange(other.temporary_, {})),
      fd_(std::exchange(other.fd_, -1)),
      committed_(other.committed_) {}

void AtomicFile::fail(const char* action) {
    const int error = errno;
    const std::string temporary = temporary_.string();
    discard();
    throwIo(target_, std::string("cannot ") + action + " (temporary file " + temporary + ")", error);
}

void AtomicFile::write(std::span<const std::byte> bytes) {
    if (fd_ < 0) {
        errno = EBADF;
        fail("write after commit or discard");
    }
    while (!bytes.empty()) {
        const ssize_t written = ::write(fd_, bytes.data(), bytes.size());
        if (written < 0 && errno == EINTR) continue;
        if (written < 0) fail("write");
        bytes = bytes.subspan(static_cast<std::size_t>(written));
    }
}

void AtomicFile::commit() {
    if (fd_ < 0) {
        errno = EBADF;
        fail("commit after commit or discard");
    }
    if (::fsync(fd_) != 0) fail("flush to disk");
    const int fd = std::exchange(fd_, -1);
    if (::close(fd) != 0) fail("close");
    if (::rename(temporary_.c_str(), target_.c_str()) != 0) fail("rename onto the target");
    committed_ = true;
    temporary_.clear();
    // Makes the rename itself durable. Best effort: the file is already published, and some file
    // systems refuse fsync on a folder.
    const int folder_fd = ::open(folderOf(target_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (folder_fd >= 0) {
        ::fsync(folder_fd);
        ::close(folder_fd);
    }
}

void AtomicFile::discard() noexcept {
    if (fd_ >= 0) ::close(std::exchange(fd_, -1));
    if (!committed_ && !temporary_.empty()) {
        ::unlink(temporary_.c_str());
        temporary_.clear();
    }
}

void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes) {
    AtomicFile file(target);
    file.write(bytes);
    file.commit();
}

void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path& temporary)>& write_to) {
    AtomicFile file(target);
    write_to(file.temporary());
    // The writer wrote the same file through its own descriptor (its callers truncate in place);
    // fsync through ours flushes that file's data.
    file.commit();
}

}  // namespace firelook
