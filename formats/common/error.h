// The one coded error of FireLook's libraries: a code from one list plus a message naming the file
// and the problem. Every layer on the plugin's path (package reader, basis, runtime package, world,
// look) throws it or a subclass, and the C plugin maps the code to an fl_result by one table, so a
// failure's meaning never depends on which C++ exception type carried it.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace firelook {

// X(name, value, text). Values are fixed (1..10 were the package reader's codes and stay so).
#define FIRELOOK_ERROR_CODES(X)                                                                       \
    X(IoError, 1, "I/O error")                    /* the OS refused: open, read, write, fsync, rename */ \
    X(NotAPackage, 2, "not a FireLook package")   /* no FireLook identifier (or an empty file) */        \
    X(Truncated, 3, "truncated")                  /* shorter than its header says */                     \
    X(Corrupt, 4, "corrupt")                      /* checksum mismatch, inconsistent content */          \
    X(NewerMajorVersion, 5, "newer major version") /* written by a newer, incompatible format */         \
    X(UnsupportedFeature, 6, "unsupported feature") /* a required section or codec this build lacks */   \
    X(InvalidArgument, 7, "invalid argument")     /* caller misuse */                                    \
    X(InvalidState, 8, "invalid state")           /* an object used after commit/failure/move */         \
    X(CompressionFailed, 9, "compression failed") /* zstd failed while compressing */                    \
    X(OutOfMemory, 10, "out of memory")           /* an allocation failed */                             \
    X(InvalidHandle, 11, "invalid handle")        /* 0, stale, of another kind or another world */       \
    X(Look, 12, "look error")                     /* a bad look, or one that does not fit the package */ \
    X(Limit, 13, "limit reached")                 /* too many objects of one kind */

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
