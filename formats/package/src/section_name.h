#pragma once

#include <cstdint>
#include <string>

namespace firelook::package::detail {

// "section 'META'" or "section 'FACT' frame 12", for error messages. Non-printable fourcc bytes
// are shown as hex so a corrupt type cannot inject control characters.
std::string sectionName(uint32_t type, uint32_t frame);

}  // namespace firelook::package::detail
