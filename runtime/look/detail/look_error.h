// One message shape for every LookError: "<file>: key '<key>': <problem>".
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "look/look.h"

namespace firelook::detail {

inline std::string lookDisplayName(const std::string& source_name) {
    return source_name.empty() ? std::string("(unnamed look)") : source_name;
}

// The key of an array element in a message: indexedKey("emission.stops", 2) = "emission.stops[2]".
inline std::string indexedKey(std::string_view key, size_t index) {
    return std::string(key) + "[" + std::to_string(index) + "]";
}

[[noreturn]] inline void throwLookError(const std::string& source_name, std::string_view key,
                                        const std::string& problem) {
    std::string message = lookDisplayName(source_name) + ": ";
    if (!key.empty()) message += "key '" + std::string(key) + "': ";
    throw LookError(message + problem);
}

}  // namespace firelook::detail
