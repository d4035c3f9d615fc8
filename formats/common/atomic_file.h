// The one way FireLook writes a file: readers see the previous file or the complete new one, never
// a part, and concurrent writers of one target never share a temporary.
//
// The bytes go to ".<name>.<pid>-<n>.tmp" beside the target (created exclusively, mode 0666 less
// the umask, like any new file; n counts within the process), which is fsync'ed, renamed over the
// target, and the folder fsync'ed (best effort: some file systems refuse it). On any failure or
// exception before the rename, the temporary is removed and the target is left as it was. A
// process killed outright leaves the temporary (hidden, and never under the target's name).
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <span>
#include <string_view>

namespace firelook {

// A file being written: write into it (write() or the descriptor), then commit(). Destroyed or
// discarded without commit(), it removes its temporary. Errors are firelook::Error (IoError) whose
// message names the target, the action, the temporary and the OS's reason.
class AtomicFile {
  public:
    explicit AtomicFile(std::filesystem::path target);
    ~AtomicFile();
    AtomicFile(AtomicFile&& other) noexcept;
    AtomicFile& operator=(AtomicFile&&) = delete;
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    const std::filesystem::path& target() const { return target_; }
    const std::filesystem::path& temporary() const { return temporary_; }
    // The temporary's descriptor (write-only, O_CLOEXEC) until commit() or discard(); then -1.
    int fd() const { return fd_; }

    // Writes all the bytes at the current offset (retrying short writes and EINTR).
    void write(std::span<const std::byte> bytes);
    void write(std::string_view text) { write(std::as_bytes(std::span(text.data(), text.size()))); }

    // fsync, close, rename over the target, fsync the folder. Throws (and removes the temporary)
    // when any step before the rename fails; the file is then discarded.
    void commit();
    // Closes and removes the temporary (no-op after commit()).
    void discard() noexcept;
    bool committed() const { return committed_; }

  private:
    [[noreturn]] void fail(const char* action);

    std::filesystem::path target_;
    std::filesystem::path temporary_;
    int fd_ = -1;
    bool committed_ = false;
};

// The bytes as the whole new content of `target`.
void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes);

// For writers that open a path themselves (OpenImageIO, OpenVDB): write_to(temporary) writes the
// complete file at the temporary path it is given (an empty file that already exists), then it is
// fsync'ed and renamed as above. An exception from write_to propagates after the cleanup.
void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path& temporary)>& write_to);

}  // namespace firelook
