// The render module's error: firelook::Error with the render module's default code.
#pragma once

#include <string>

#include "common/error.h"

namespace firelook::render {

// Invalid input to the render module (a malformed volume, camera, look or image), with a message
// that names the problem: code InvalidArgument unless the site gives another (Cancelled).
class RenderError : public Error {
  public:
    explicit RenderError(const std::string& message) : Error(ErrorCode::InvalidArgument, message) {}
    RenderError(ErrorCode code, const std::string& message) : Error(code, message) {}
};

}  // namespace firelook::render
