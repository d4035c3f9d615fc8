// The one exception type of the render module.
#pragma once

#include <stdexcept>

namespace firelook::render {

// Invalid input to the render module (a malformed volume, camera, look or image), with a message
// that names the problem.
class RenderError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

}  // namespace firelook::render
