// Rendered RGBA images and the error measures of docs/testing.md.
#pragma once

#include <vector>

namespace firelook::render {

// Premultiplied linear RGBA, 4 floats per pixel, row-major with the top row first.
// alpha = 1 - transmittance along the pixel's ray, so final = rgb + (1 - alpha) * background.
struct RenderImage {
    int width = 0;
    int height = 0;
    std::vector<float> rgba;
};

// sqrt(sum |a - r|^2 / sum |r|^2) over the RGB channels of every pixel. 0 when both are black;
// infinity when only the reference is. Throws RenderError if the sizes differ.
double relativeRmse(const RenderImage& a, const RenderImage& reference);

// max |alpha_a - alpha_r| over pixels. Throws RenderError if the sizes differ.
double maxAlphaError(const RenderImage& a, const RenderImage& reference);

}  // namespace firelook::render
