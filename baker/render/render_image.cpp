#include "render/render_image.h"

#include <cmath>
#include <limits>
#include <string>

#include "render/render_error.h"

namespace firelook::render {
namespace {

void checkComparable(const RenderImage& a, const RenderImage& reference) {
    const auto expected =
        static_cast<std::size_t>(reference.width) * static_cast<std::size_t>(reference.height) * 4;
    if (a.width != reference.width || a.height != reference.height ||
        a.rgba.size() != reference.rgba.size() || reference.rgba.size() != expected)
        throw RenderError("image comparison: sizes differ (" + std::to_string(a.width) + "x" +
                          std::to_string(a.height) + " against " + std::to_string(reference.width) + "x" +
                          std::to_string(reference.height) + ") or do not match the pixel data");
}

}  // namespace

double relativeRmse(const RenderImage& a, const RenderImage& reference) {
    checkComparable(a, reference);
    double error = 0.0, norm = 0.0;
    for (std::size_t i = 0; i < reference.rgba.size(); i += 4)
        for (std::size_t ch = 0; ch < 3; ++ch) {
            const double r = reference.rgba[i + ch];
            const double d = static_cast<double>(a.rgba[i + ch]) - r;
            error += d * d;
            norm += r * r;
        }
    if (norm == 0.0) return error == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
    return std::sqrt(error / norm);
}

double maxAlphaError(const RenderImage& a, const RenderImage& reference) {
    checkComparable(a, reference);
    double worst = 0.0;
    for (std::size_t i = 3; i < reference.rgba.size(); i += 4) {
        const double e = std::abs(static_cast<double>(a.rgba[i]) - reference.rgba[i]);
        if (!(e <= worst)) worst = e;  // written so that a NaN propagates instead of being skipped
    }
    return worst;
}

}  // namespace firelook::render
