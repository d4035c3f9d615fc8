// The one coded error of FireLook: a code from one list plus a message naming the file and the
// problem. Every layer (formats/, runtime/, baker/, plugin_api/src) throws it; the few named
// subclasses (PackageError, VdbError, ImageError, GltfError, RenderError, LookError, ...) only
// construct it with their default code. Callers that need the meaning read code(), never the C++
// type, and the C plugin maps the code to an fl_result by one table (plugin_api/src/result_table.h).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace firelook {

// X(name, value, text). Values are fixed (1..10 were the package reader's codes and stay so).
#define FIRELOOK_ERROR_CODES(X)                                                                             \
    X(IoError, 1, "I/O error")                      /* the OS refused: open, read, write, fsync, rename */  \
    X(NotAPackage, 2, "not a FireLook package")     /* no FireLook identifier (or an empty file) */         \
    X(Truncated, 3, "truncated")                    /* shorter than its header says */                      \
    X(Corrupt, 4, "corrupt")                        /* checksum mismatch, inconsistent content */           \
    X(NewerMajorVersion, 5, "newer major version")  /* written by a newer, incompatible format */           \
    X(UnsupportedFeature, 6, "unsupported feature") /* a required section or codec this build lacks */      \
    X(InvalidArgument, 7, "invalid argument")       /* caller misuse */                                     \
    X(InvalidState, 8, "invalid state")             /* an object used after commit/failure/move */          \
    X(CompressionFailed, 9, "compression failed")   /* zstd failed while compressing */                     \
    X(OutOfMemory, 10, "out of memory")             /* an allocation failed */                              \
    X(InvalidHandle, 11, "invalid handle")          /* 0, stale, of another kind or another world */        \
    X(Look, 12, "look error")                       /* a bad look, or one that does not fit the package */  \
    X(Limit, 13, "limit reached")                   /* too many objects of one kind */                      \
    X(Cancelled, 14, "cancelled")                   /* stopped on request: a progress callback, a signal */ \
    X(NotFound, 15, "not found")                    /* no such frame, camera or lights in the package */    \
    X(BadVolume, 16, "bad volume")                  /* a VDB input that cannot be read or used */           \
    X(BadImage, 17, "bad image")                    /* an image that cannot be read, written or used */     \
    X(BadScene, 18, "bad scene")                    /* a glTF scene that cannot be read or used */          \
    /* The C API's own failures (plugin_api/src), in this list so that the plugin has one error. */         \
    X(StructSize, 19, "struct size")                /* a caller's struct_size below the first published */  \
    X(VersionMismatch, 20, "version mismatch")      /* header and library disagree */                       \
    X(NotInitialized, 21, "not initialized")                                                                \
    X(AlreadyInitialized, 22, "already initialized")                                                        \
    X(BufferTooSmall, 23, "buffer too small")                                                               \
    X(NoData, 24, "no data")                        /* an output not enabled or not computed yet */         \
    X(Internal, 25, "internal error")               /* a bug */

enum class ErrorCode : int32_t {
#define FIRELOOK_ERROR_ENUM(name, value, text) name = value,
    FIRELOOK_ERROR_CODES(FIRELOOK_ERROR_ENUM)
#undef FIRELOOK_ERROR_ENUM
};

// A short, stable English name ("truncated", "corrupt", ...); "unknown error" for other values.
inline const char* toString(ErrorCode code) {
    switch (code) {
#define FIRELOOK_ERROR_TEXT(name, value, text) \
    case ErrorCode::name: return text;
        FIRELOOK_ERROR_CODES(FIRELOOK_ERROR_TEXT)
#undef FIRELOOK_ERROR_TEXT
    }
    return "unknown error";
}

class Error : public std::runtime_error {
  public:
    // message names the file (or source) and the problem: "<file>: <problem>".
    Error(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
    ErrorCode code() const { return code_; }

  private:
    ErrorCode code_;
};

}  // namespace firelook
