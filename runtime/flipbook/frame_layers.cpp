#include "flipbook/frame_layers.h"

#include <algorithm>
#include <stdexcept>

#include "basis/look_renderer.h"
#include "basis/six_way_lights.h"
#include "common/error.h"

namespace firelook::flipbook {

float FrameLayers::value(Layer layer, std::size_t pixel) const {
    const int index = static_cast<int>(layer);
    if (index < basis::kSixWayLightCount) return light[index][pixel];
    switch (layer) {
        case Layer::Transparency: return alpha[pixel];
        case Layer::Emission: {
            const float* e = &emission_rgb[3 * pixel];
            return 0.2126f * e[0] + 0.7152f * e[1] + 0.0722f * e[2];
        }
        case Layer::EmissionR: return emission_rgb[3 * pixel];
        case Layer::EmissionG: return emission_rgb[3 * pixel + 1];
        case Layer::EmissionB: return emission_rgb[3 * pixel + 2];
        case Layer::ColourR: return colour_rgb[3 * pixel];
        case Layer::ColourG: return colour_rgb[3 * pixel + 1];
        case Layer::ColourB: return colour_rgb[3 * pixel + 2];
        default: return 0.0f;
    }
}

FrameLayers renderFrameLayers(const basis::BakeDescription& d, const basis::ResidentFrame& frame, const Look& look,
                              bool six_way) {
    if (six_way && d.six_way_first_light < 0)
        throw Error(ErrorCode::InvalidArgument,
                    "the package was baked without six-way lights (firelook bake --lights six-way)");
    FrameLayers out;
    out.width = d.width;
    out.height = d.height;
    const std::size_t pixels = static_cast<std::size_t>(d.pixelCount());
    std::vector<float> rgba(pixels * 4);
    const auto keep = [&](std::vector<float>& rgb) {
        rgb.resize(pixels * 3);
        for (std::size_t p = 0; p < pixels; ++p)
            for (int c = 0; c < 3; ++c) rgb[3 * p + c] = rgba[4 * p + c];
    };
    basis::renderLookImage(d, frame, look, rgba);
    keep(out.colour_rgb);
    out.alpha.resize(pixels);
    for (std::size_t p = 0; p < pixels; ++p) out.alpha[p] = rgba[4 * p + 3];
    if (!six_way) return out;

    Look dark = look;
    std::fill(dark.light_irradiance.begin(), dark.light_irradiance.end(), Rgb(0.0f));
    basis::renderLookImage(d, frame, dark, rgba);
    keep(out.emission_rgb);
    dark.emission = EmissionBins{std::vector<Rgb>(static_cast<std::size_t>(d.bins.count), Rgb(0.0f))};
    for (int l = 0; l < basis::kSixWayLightCount; ++l) {
        Look one = dark;
        one.light_irradiance[static_cast<std::size_t>(d.six_way_first_light + l)] = Rgb(1.0f);
        basis::renderLookImage(d, frame, one, rgba);
        out.light[l].resize(pixels);
        for (std::size_t p = 0; p < pixels; ++p) out.light[l][p] = rgba[4 * p];
    }
    return out;
}

}  // namespace firelook::flipbook
