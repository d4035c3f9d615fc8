// Frames packed into flipbook atlases: frame k of n in cell (k % columns, k / columns) of a
// columns x rows grid, top-left first (the order Unity's and Unreal's flipbook players step
// through), each cell one frame at the package's size; cells past the last frame are zero.
#pragma once

#include <vector>

#include "flipbook/flipbook_layout.h"
#include "flipbook/frame_layers.h"
#include "image/image.h"

namespace firelook::flipbook {

// Atlas texel = value / scale per kind of layer; the sidecar records both, so value = texel * scale.
struct Normalisation {
    double lightmap_scale = 1.0;  // the six lights' layers
    double emission_scale = 1.0;  // emission, its luminance and the look's colour
};

// 1 for float files; for 8-bit files the largest value of each kind over every frame, so the
// brightest texel is 1 (a kind that is zero everywhere keeps 1).
Normalisation normalisationFor(const std::vector<FrameLayers>& frames, bool to_unit_range);

// Throws an InvalidArgument Error when the frames do not fit the grid or differ in size.
image::ImageRGBA packAtlas(const AtlasSpec& spec, const std::vector<FrameLayers>& frames, int columns, int rows,
                           const Normalisation& normalisation);

}  // namespace firelook::flipbook
