// Turning C API results into exceptions inside the viewer: every fl_* call goes through check(), so
// a failure surfaces as one message that names the call and, via fl_last_error(), the file.
#pragma once

#include <stdexcept>
#include <string>

#include "firelook/firelook.h"

namespace firelook::viewer {

class ViewerError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

inline void check(fl_result result, const char* call) {
    if (result == FL_OK) return;
    const std::string detail = fl_last_error();
    // The library's message already names the call and the file.
    throw ViewerError(detail.empty() ? std::string(call) + " failed (" + fl_result_string(result) + ")"
                                     : detail + " (" + fl_result_string(result) + ")");
}

}  // namespace firelook::viewer
