#include "package/error.h"

namespace firelook::package {

const char* toString(ErrorCode code) {
    switch (code) {
        case ErrorCode::IoError:
            return "I/O error";
        case ErrorCode::NotAPackage:
            return "not a FireLook package";
        case ErrorCode::Truncated:
            return "truncated";
        case ErrorCode::Corrupt:
            return "corrupt";
        case ErrorCode::NewerMajorVersion:
            return "newer major version";
        case ErrorCode::UnsupportedFeature:
            return "unsupported feature";
        case ErrorCode::InvalidArgument:
            return "invalid argument";
        case ErrorCode::InvalidState:
            return "invalid state";
        case ErrorCode::CompressionFailed:
            return "compression failed";
        case ErrorCode::OutOfMemory:
            return "out of memory";
    }
    return "unknown error";
}

PackageError::PackageError(ErrorCode code, std::filesystem::path file, const std::string& problem)
    : std::runtime_error(file.string() + ": " + toString(code) + ": " + problem),
      code_(code),
      file_(std::move(file)) {}

}  // namespace firelook::package
