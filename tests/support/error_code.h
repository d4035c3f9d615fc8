#pragma once
// Tests check a failure's meaning by its code (common/error.h), as the plugin and the CLI read it,
// never by the C++ type that carried it.

#include <optional>

#include "common/error.h"

namespace firelook::testing {

// The code of the firelook::Error that `action` throws; nullopt when it throws none (any other
// exception propagates, and fails the test).
template <typename F>
std::optional<ErrorCode> thrownCode(F&& action) {
    try {
        action();
    } catch (const Error& error) {
        return error.code();
    }
    return std::nullopt;
}

}  // namespace firelook::testing

// EXPECT_ERROR_CODE(ErrorCode::X, statement): the statement throws a firelook::Error of code X.
#define EXPECT_ERROR_CODE(code, ...) \
    EXPECT_EQ(::firelook::testing::thrownCode([&] { __VA_ARGS__; }), std::optional(code)) << #__VA_ARGS__
