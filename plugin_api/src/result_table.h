// The one table from the runtime's coded errors (common/error.h) to the C API's results. A switch
// without default: -Wswitch (with -Werror) fails the build when a code is added without a row.
#pragma once

#include "common/error.h"
#include "firelook/firelook.h"

namespace firelook::plugin {

constexpr fl_result toResult(ErrorCode code) {
    switch (code) {
        case ErrorCode::IoError: return FL_ERROR_IO;
        case ErrorCode::NotAPackage: return FL_ERROR_NOT_A_PACKAGE;
        case ErrorCode::Truncated: return FL_ERROR_CORRUPT;
        case ErrorCode::Corrupt: return FL_ERROR_CORRUPT;
        case ErrorCode::NewerMajorVersion: return FL_ERROR_UNSUPPORTED;
        case ErrorCode::UnsupportedFeature: return FL_ERROR_UNSUPPORTED;
        case ErrorCode::InvalidArgument: return FL_ERROR_INVALID_ARGUMENT;
        case ErrorCode::InvalidState: return FL_ERROR_INTERNAL;       // the plugin misused a reader/writer
        case ErrorCode::CompressionFailed: return FL_ERROR_INTERNAL;  // the runtime never compresses
        case ErrorCode::OutOfMemory: return FL_ERROR_OUT_OF_MEMORY;
        case ErrorCode::InvalidHandle: return FL_ERROR_INVALID_HANDLE;
        case ErrorCode::Look: return FL_ERROR_LOOK;
        case ErrorCode::Limit: return FL_ERROR_LIMIT;
    }
    return FL_ERROR_INTERNAL;  // a value outside the list
}

}  // namespace firelook::plugin
