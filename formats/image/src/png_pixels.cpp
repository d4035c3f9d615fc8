#include "png_pixels.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "image/srgb.h"

namespace firelook::image::detail {
namespace {

std::uint8_t quantise(double unit_value) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(unit_value, 0.0, 1.0) * 255.0));
}

}  // namespace

Png8Pixels encodePng8(const ImageRGBA& image, double exposure_stops,
                      const std::optional<std::array<float, 3>>& background) {
    const double exposure = std::exp2(exposure_stops);
    const std::size_t pixel_count = image.pixels.size() / 4;
    Png8Pixels out;
    out.channels = background ? 3 : 4;
    out.values.resize(pixel_count * static_cast<std::size_t>(out.channels));
    for (std::size_t p = 0; p < pixel_count; ++p) {
        const float* in = &image.pixels[4 * p];
        std::uint8_t* dst = &out.values[p * static_cast<std::size_t>(out.channels)];
        const double alpha = std::clamp(static_cast<double>(in[3]), 0.0, 1.0);
        if (background) {
            for (int c = 0; c < 3; ++c) {
                dst[c] = quantise(linearToSrgb(exposure * in[c] + (1.0 - alpha) * (*background)[c]));
            }
            continue;
        }
        // Divide by the alpha that will be stored, not the exact one, so that a reader multiplying
        // the stored colour by the stored alpha gets back the premultiplied value as closely as
        // 8 bits allow.
        dst[3] = quantise(alpha);
        const double stored_alpha = dst[3] / 255.0;
        for (int c = 0; c < 3; ++c) {
            dst[c] = stored_alpha > 0.0 ? quantise(linearToSrgb(exposure * in[c] / stored_alpha)) : 0;
        }
    }
    return out;
}

void decodeSrgbStraightAlpha(ImageRGBA& image) {
    for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
        const float alpha = image.pixels[i + 3];
        for (std::size_t c = 0; c < 3; ++c) {
            image.pixels[i + c] = static_cast<float>(srgbToLinear(image.pixels[i + c])) * alpha;
        }
    }
}

}  // namespace firelook::image::detail
