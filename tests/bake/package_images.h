// A baked package's frame rendered for a look, and two such images compared: what the bake tests
// check a package against another by (same data baked two ways).
#pragma once

#include <algorithm>
#include <cmath>
#include <memory_resource>
#include <vector>

#include "basis/basis_package.h"
#include "basis/look_renderer.h"
#include "look/look.h"

namespace firelook::bake::test {

// Frame `frame` of `package` for `look` (the runtime's resident form), premultiplied RGBA.
inline std::vector<float> renderFrame(const basis::BasisReader& package, int frame, const Look& look) {
    const basis::ResidentFrame f = package.loadResidentFrame(frame, std::pmr::get_default_resource());
    std::vector<float> rgba(static_cast<size_t>(package.description().pixelCount()) * 4);
    basis::renderLookImage(package.description(), f, look, rgba);
    return rgba;
}

struct ImageDifference {
    double relative_rmse = 0.0;   // of the RGB against the reference's RGB norm
    double worst_alpha = 0.0;     // largest |alpha difference| of any pixel
    double reference_norm = 0.0;  // sum of the reference's squared RGB: 0 means an empty image
};

// `image` against `reference`, both RGBA of the same size.
inline ImageDifference compareImages(const std::vector<float>& image, const std::vector<float>& reference) {
    double diff = 0.0, norm = 0.0, alpha = 0.0;
    for (size_t i = 0; i < image.size(); i += 4) {
        for (int ch = 0; ch < 3; ++ch) {
            diff += double(image[i + ch] - reference[i + ch]) * (image[i + ch] - reference[i + ch]);
            norm += double(reference[i + ch]) * reference[i + ch];
        }
        alpha = std::max(alpha, double(std::abs(image[i + 3] - reference[i + 3])));
    }
    return {norm > 0.0 ? std::sqrt(diff / norm) : 0.0, alpha, norm};
}

}  // namespace firelook::bake::test
