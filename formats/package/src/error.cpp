#include "package/error.h"

namespace firelook::package {

PackageError::PackageError(ErrorCode code, std::filesystem::path file, const std::string& problem)
    : firelook::Error(code, file.string() + ": " + toString(code) + ": " + problem), file_(std::move(file)) {}

}  // namespace firelook::package
