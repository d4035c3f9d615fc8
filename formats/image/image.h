// The in-memory image every FireLook tool exchanges: linear HDR, premultiplied RGBA.
#pragma once

#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/error.h"

namespace firelook::image {

// Thrown for every image failure; the message names the file (when there is one) and the problem.
class ImageError : public Error {
  public:
    explicit ImageError(const std::string& message) : Error(ErrorCode::BadImage, message) {}
    ImageError(ErrorCode code, const std::string& message) : Error(code, message) {}
};

// Linear HDR radiance with premultiplied alpha (alpha = 1 - transmittance), row-major, top row first:
// pixel (x, y) occupies pixels[4 * (y * width + x) + 0..3] as R, G, B, A.
struct ImageRGBA {
    int width = 0;
    int height = 0;
    std::vector<float> pixels;

    ImageRGBA() = default;
    // Every pixel transparent black. Throws ImageError for a negative size.
    ImageRGBA(int width, int height);

    std::span<float, 4> at(int x, int y) { return std::span<float, 4>(pixels.data() + offset(x, y), 4); }
    std::span<const float, 4> at(int x, int y) const {
        return std::span<const float, 4>(pixels.data() + offset(x, y), 4);
    }

  private:
    std::size_t offset(int x, int y) const {
        return 4 *
               (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x));
    }
};

}  // namespace firelook::image
