// QA measures between the real-time image and the reference, defined exactly as `firelook compare`
// does (render::relativeRmse and render::maxAlphaError, docs/testing.md):
//   relative RMSE = sqrt(sum over pixels and RGB of (I - R)^2 / sum of R^2), linear premultiplied;
//   max alpha error = max over pixels of |alpha_I - alpha_R|.
// The heat map shows where the error is: per pixel e = sqrt(mean over RGB of (I - R)^2) divided by
// the reference's RMS value sqrt(mean over all pixels and RGB of R^2), so the mean of e^2 over the
// image is the relative RMSE squared; e / scale is mapped black -> red -> yellow -> white.
#pragma once

#include <vector>

namespace firelook::viewer {

struct ErrorMeasures {
    double relative_rmse = 0.0;
    double max_alpha_error = 0.0;
};

// Throws std::runtime_error if the sizes differ.
ErrorMeasures compareImages(const std::vector<float>& image, const std::vector<float>& reference, int width,
                            int height);

// RGBA8 heat map of the per-pixel error (see above); `scale` is the error shown white.
void makeHeatMap(const std::vector<float>& image, const std::vector<float>& reference, int width, int height,
                 float scale, std::vector<unsigned char>& rgba8);

}  // namespace firelook::viewer
