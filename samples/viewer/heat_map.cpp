#include "heat_map.h"

#include <algorithm>
#include <cmath>

#include "render/render_image.h"

namespace firelook::viewer {

ErrorMeasures compareImages(const std::vector<float>& image, const std::vector<float>& reference, int width,
                            int height) {
    const render::RenderImage a{width, height, image}, r{width, height, reference};
    return {render::relativeRmse(a, r), render::maxAlphaError(a, r)};
}

void makeHeatMap(const std::vector<float>& image, const std::vector<float>& reference, int width, int height,
                 float scale, std::vector<unsigned char>& rgba8) {
    const size_t pixels = static_cast<size_t>(width) * height;
    rgba8.assign(pixels * 4, 255);
    if (image.size() < pixels * 4 || reference.size() < pixels * 4) return;
    double reference_square = 0.0;
    for (size_t i = 0; i < pixels * 4; ++i)
        if (i % 4 != 3) reference_square += static_cast<double>(reference[i]) * reference[i];
    const double rms = std::sqrt(reference_square / (3.0 * static_cast<double>(pixels)));
    // black -> red -> yellow -> white at t = 0, 1/3, 2/3, 1.
    static const float ramp[4][3] = {{0, 0, 0}, {0.8f, 0.05f, 0.0f}, {1.0f, 0.85f, 0.0f}, {1, 1, 1}};
    for (size_t p = 0; p < pixels; ++p) {
        double square = 0.0;
        for (int c = 0; c < 3; ++c) {
            const double d = static_cast<double>(image[p * 4 + c]) - reference[p * 4 + c];
            square += d * d;
        }
        const double e = rms > 0.0 ? std::sqrt(square / 3.0) / rms : 0.0;
        const float t = std::clamp(static_cast<float>(e / std::max(scale, 1e-12f)), 0.0f, 1.0f) * 3.0f;
        const int i = std::min(static_cast<int>(t), 2);
        const float f = t - static_cast<float>(i);
        for (int c = 0; c < 3; ++c)
            rgba8[p * 4 + c] =
                static_cast<unsigned char>(std::lround(255.0f * (ramp[i][c] + f * (ramp[i + 1][c] - ramp[i][c]))));
    }
}

}  // namespace firelook::viewer
