// Conversions between FireLook's linear premultiplied floats and the 8-bit sRGB values of a PNG.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "image/image.h"

namespace firelook::image::detail {

struct Png8Pixels {
    int channels = 4;  // 4: RGBA with un-premultiplied colour; 3: opaque RGB
    std::vector<std::uint8_t> values;
};

// The policy documented in image_io.h: exposure, then either un-premultiplied RGBA or, with a
// background, an opaque RGB composite; then sRGB encoding and rounding to 8 bits.
Png8Pixels encodePng8(const ImageRGBA& image, double exposure_stops,
                      const std::optional<std::array<float, 3>>& background);

// In place: straight sRGB-encoded colour in [0, 1] with linear alpha becomes linear premultiplied.
void decodeSrgbStraightAlpha(ImageRGBA& image);

}  // namespace firelook::image::detail
