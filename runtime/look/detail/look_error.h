// One message shape for every LookError: "<file>: key '<key>': <problem>".
#pragma once

#include <string>
#include <string_view>

#include "look/look.h"

namespace firelook::detail {

inline std::string lookDisplayName(const std::string& source_name) {
    return source_name.empty() ? std::string("(unnamed look)") : source_name;
}

[[noreturn]] inline void throwLookError(const std::string& source_name, std::string_view key,
                                        const std::string& problem) {
    std::string message = lookDisplayName(source_name) + ": ";
    if (!key.empty()) message += "key '" + std::string(key) + "': ";
    throw LookError(message + problem);
}

}  // namespace firelook::detail
