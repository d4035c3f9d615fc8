#include "flipbook/atlas.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "common/error.h"

namespace firelook::flipbook {
namespace {

bool isLight(Layer layer) { return static_cast<int>(layer) <= static_cast<int>(Layer::Light5); }

}  // namespace

Normalisation normalisationFor(const std::vector<FrameLayers>& frames, bool to_unit_range) {
    Normalisation n;
    if (!to_unit_range) return n;
    float light = 0.0f, emission = 0.0f;
    for (const FrameLayers& f : frames) {
        for (const std::vector<float>& layer : f.light)
            for (float v : layer) light = std::max(light, v);
        for (float v : f.emission_rgb) emission = std::max(emission, v);
        for (float v : f.colour_rgb) emission = std::max(emission, v);
    }
    // A luminance never exceeds the largest of its channels, so one scale covers both.
    if (light > 0.0f) n.lightmap_scale = light;
    if (emission > 0.0f) n.emission_scale = emission;
    return n;
}

image::ImageRGBA packAtlas(const AtlasSpec& spec, const std::vector<FrameLayers>& frames, int columns, int rows,
                           const Normalisation& normalisation) {
    if (frames.empty()) throw Error(ErrorCode::InvalidArgument, "no frames to pack");
    if (columns < 1 || rows < 1 || static_cast<std::size_t>(columns) * rows < frames.size())
        throw Error(ErrorCode::InvalidArgument, std::to_string(frames.size()) + " frames do not fit a " +
                                                    std::to_string(columns) + "x" + std::to_string(rows) +
                                                    " grid");
    const int w = frames.front().width, h = frames.front().height;
    image::ImageRGBA atlas(w * columns, h * rows);
    for (std::size_t k = 0; k < frames.size(); ++k) {
        const FrameLayers& f = frames[k];
        if (f.width != w || f.height != h)
            throw Error(ErrorCode::InvalidArgument, "frames of different sizes");
        const int x0 = static_cast<int>(k % columns) * w, y0 = static_cast<int>(k / columns) * h;
        for (int c = 0; c < 4; ++c) {
            const Layer layer = spec.channels[c];
            const bool scaled = layer != Layer::Transparency;
            const float inverse = static_cast<float>(
                1.0 / (isLight(layer) ? normalisation.lightmap_scale : normalisation.emission_scale));
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const float v = f.value(layer, static_cast<std::size_t>(y) * w + x);
                    atlas.at(x0 + x, y0 + y)[c] = scaled ? v * inverse : v;
                }
        }
    }
    return atlas;
}

}  // namespace firelook::flipbook
