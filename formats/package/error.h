#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace firelook::package {

// Fixed-width so the values can cross the C plugin API unchanged.
enum class ErrorCode : int32_t {
    IoError = 1,             // the operating system refused: open, read, write, fsync, rename
    NotAPackage = 2,         // the file does not start with the FireLook identifier (or is empty)
    Truncated = 3,           // the file is shorter than its header says (or than the header)
    Corrupt = 4,             // a checksum mismatch or an inconsistent header, index or zstd frame
    NewerMajorVersion = 5,   // written by a newer, incompatible major version of the format
    UnsupportedFeature = 6,  // a required section of an unknown type or with an unknown codec
    InvalidArgument = 7,     // caller misuse: bad zstd level, duplicate section, foreign SectionInfo
    InvalidState = 8,        // a writer used after commit, after a failure, or after being moved from
    CompressionFailed = 9,   // zstd failed while compressing
    OutOfMemory = 10,        // an allocation (ours or zstd's) failed
};

// A short, stable English name ("truncated", "corrupt", ...); never null.
const char* toString(ErrorCode code);

// Every failure of the package reader and writer. what() reads "<file>: <code name>: <problem>".
class PackageError : public std::runtime_error {
  public:
    PackageError(ErrorCode code, std::filesystem::path file, const std::string& problem);

    ErrorCode code() const { return code_; }
    const std::filesystem::path& file() const { return file_; }

  private:
    ErrorCode code_;
    std::filesystem::path file_;
};

}  // namespace firelook::package
