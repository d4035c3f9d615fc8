#include "image/image.h"

#include <string>

namespace firelook::image {

ImageRGBA::ImageRGBA(int width_in, int height_in) : width(width_in), height(height_in) {
    if (width_in < 0 || height_in < 0) {
        throw ImageError("image size " + std::to_string(width_in) + "x" + std::to_string(height_in) +
                         " is negative");
    }
    pixels.assign(4 * static_cast<std::size_t>(width_in) * static_cast<std::size_t>(height_in), 0.0f);
}

}  // namespace firelook::image
