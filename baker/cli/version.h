#pragma once

namespace firelook::cli {
// Recorded as provenance in every package this tool writes.
inline constexpr const char* kToolVersion = "0.1.0";
}  // namespace firelook::cli
