// Plain values in and out of an optional section's payload (the fire lights' FLIT, the fire probes'
// FPRB): raw bytes in the machine's order, which the package format fixes as little-endian
// (docs/package-format.md); the readers check a payload's size before they read it.
#pragma once

#include <cstddef>
#include <cstring>
#include <span>
#include <vector>

namespace firelook::basis {

template <typename T>
void putSectionValue(std::vector<std::byte>& out, T value) {
    const std::size_t at = out.size();
    out.resize(at + sizeof(T));
    std::memcpy(out.data() + at, &value, sizeof(T));
}

// Reads at `at` and moves it past the value.
template <typename T>
T getSectionValue(std::span<const std::byte> bytes, std::size_t& at) {
    T value;
    std::memcpy(&value, bytes.data() + at, sizeof(T));
    at += sizeof(T);
    return value;
}

}  // namespace firelook::basis
