#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "common/error.h"

namespace firelook::package {

// The package reader and writer use codes 1..10 of the one list (common/error.h): IoError,
// NotAPackage, Truncated, Corrupt, NewerMajorVersion, UnsupportedFeature, InvalidArgument,
// InvalidState, CompressionFailed, OutOfMemory.
using ErrorCode = firelook::ErrorCode;
using firelook::toString;

// Every failure of the package reader and writer. what() reads "<file>: <code name>: <problem>".
class PackageError : public firelook::Error {
  public:
    PackageError(ErrorCode code, std::filesystem::path file, const std::string& problem);

    const std::filesystem::path& file() const { return file_; }

  private:
    std::filesystem::path file_;
};

}  // namespace firelook::package
