#include "section_name.h"

#include <cstdio>

#include "package/format.h"

namespace firelook::package::detail {

std::string sectionName(uint32_t type, uint32_t frame) {
    std::string name = "section '";
    for (int byte = 0; byte < 4; ++byte) {
        const auto c = static_cast<unsigned char>((type >> (8 * byte)) & 0xFFu);
        if (c >= 0x20 && c < 0x7F) {
            name += static_cast<char>(c);
        } else {
            char hex[5];
            std::snprintf(hex, sizeof hex, "\\x%02X", c);
            name += hex;
        }
    }
    name += '\'';
    if (frame != kNoFrame) name += " frame " + std::to_string(frame);
    return name;
}

}  // namespace firelook::package::detail
