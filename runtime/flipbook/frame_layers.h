// The layers of one frame that flipbook atlases pack (flipbook_layout.h), recombined from the
// package with runtime/basis/look_renderer.h: the transfer is linear in the emission and in each
// light's irradiance (docs/model.md, "Basis images"), so each layer is the look with everything
// but one source turned off.
#pragma once

#include <array>
#include <vector>

#include "basis/bake_description.h"
#include "basis/resident_frame.h"
#include "flipbook/flipbook_layout.h"
#include "look/look.h"

namespace firelook::flipbook {

struct FrameLayers {
    int width = 0, height = 0;
    // Per pixel: each six-way light alone at unit irradiance with no emission (radiance per unit
    // irradiance; the same in R, G and B, as the basis is); empty without six-way lights.
    std::array<std::vector<float>, 6> light;
    std::vector<float> emission_rgb;  // 3 per pixel: the look's emission with every light off
    std::vector<float> colour_rgb;    // 3 per pixel: the look as given, with its own lights
    std::vector<float> alpha;         // 1 per pixel; the same in every layer

    float value(Layer layer, std::size_t pixel) const;
};

// Throws an InvalidArgument Error when `six_way` is asked of a package baked without six-way lights
// (BakeDescription::six_way_first_light < 0); look errors as renderLookImage.
FrameLayers renderFrameLayers(const basis::BakeDescription& description, const basis::ResidentFrame& frame,
                              const Look& look, bool six_way);

}  // namespace firelook::flipbook
