#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace firelook::package::detail {

// XXH3-64 with seed 0: the checksum of every checksummed region of the format.
uint64_t checksum64(std::span<const std::byte> bytes);

}  // namespace firelook::package::detail
