#pragma once

#include <string>

#include "common/error.h"

namespace firelook::vdb {

// Every failure of the VDB input: a firelook::Error whose message names the file (or pattern) and
// the problem. Code BadVolume unless the site knows better (IoError, Cancelled, ...).
class VdbError : public Error {
  public:
    explicit VdbError(const std::string& message) : Error(ErrorCode::BadVolume, message) {}
    VdbError(ErrorCode code, const std::string& message) : Error(code, message) {}
};

}  // namespace firelook::vdb
