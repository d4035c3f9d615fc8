// The one table from FireLook's coded errors (common/error.h) to the C API's results: the plugin
// gets every failure, its own and the runtime's, as firelook::Error and maps its code here, never
// by the C++ type. A switch without default: -Wswitch (with -Werror) fails the build when a code is
// added without a row.
//
// Every FL_ERROR_* is reached by at least one code. Many-to-one rows, on purpose (and checked by
// PluginApiInit.EveryErrorCodeMapsToADocumentedResult):
//   Truncated, Corrupt -> FL_ERROR_CORRUPT; NewerMajorVersion, UnsupportedFeature -> FL_ERROR_UNSUPPORTED;
//   the fallback FL_ERROR_INTERNAL for Internal, InvalidState and CompressionFailed (the plugin misused
//   a reader or writer; the runtime never compresses) and for BadVolume, BadImage, BadScene (the
//   baker's inputs: the plugin reads no VDB, image file or glTF, so reaching it is a bug).
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
        case ErrorCode::InvalidState:
            return FL_ERROR_INTERNAL;
        case ErrorCode::CompressionFailed:
            return FL_ERROR_INTERNAL;
        case ErrorCode::OutOfMemory: return FL_ERROR_OUT_OF_MEMORY;
        case ErrorCode::InvalidHandle: return FL_ERROR_INVALID_HANDLE;
        case ErrorCode::Look: return FL_ERROR_LOOK;
        case ErrorCode::Limit: return FL_ERROR_LIMIT;
        case ErrorCode::Cancelled:
            return FL_ERROR_CANCELLED;
        case ErrorCode::NotFound:
            return FL_ERROR_NOT_FOUND;
        case ErrorCode::BadVolume:
            return FL_ERROR_INTERNAL;
        case ErrorCode::BadImage:
            return FL_ERROR_INTERNAL;
        case ErrorCode::BadScene:
            return FL_ERROR_INTERNAL;
        case ErrorCode::StructSize:
            return FL_ERROR_STRUCT_SIZE;
        case ErrorCode::VersionMismatch:
            return FL_ERROR_VERSION_MISMATCH;
        case ErrorCode::NotInitialized:
            return FL_ERROR_NOT_INITIALIZED;
        case ErrorCode::AlreadyInitialized:
            return FL_ERROR_ALREADY_INITIALIZED;
        case ErrorCode::BufferTooSmall:
            return FL_ERROR_BUFFER_TOO_SMALL;
        case ErrorCode::NoData:
            return FL_ERROR_NO_DATA;
        case ErrorCode::Internal:
            return FL_ERROR_INTERNAL;
    }
    return FL_ERROR_INTERNAL;  // a value outside the list
}

}  // namespace firelook::plugin
