// What each flipbook layout puts in which channel of which atlas (docs/cli.md, "firelook
// flipbook"). A layout is a list of RGBA atlases; each channel takes one layer of a frame
// (frame_layers.h). Shared by `firelook flipbook` and anything that reads its atlases.
//
// six-way-unity (Unity VFX Graph's six-way lighting, com.unity.visualeffectgraph 17.2 manual, "Lightmap
// channel mapping"): lightmap A = right, top, back, transparency; lightmap B = left, bottom, front,
// emission (one channel); the emission's colour in a third atlas (RGB + transparency).
// six-way-rlt-bbf (the RLT / BBF naming of Unreal and EmberGen exports): RLT = right, left, top,
// transparency; BBF = bottom, back, front, emission; the emission's colour in a third atlas.
// rgba: the look's own image (its own lights), premultiplied RGB and alpha, in one atlas.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace firelook::flipbook {

enum class Layout { SixWayUnity, SixWayRltBbf, Rgba };

// A layer of one frame. Light0..Light5 are the six-way lights in basis/six_way_lights.h's order
// (right, top, back, left, bottom, front).
enum class Layer {
    Light0, Light1, Light2, Light3, Light4, Light5,
    Transparency,    // alpha = 1 - transmittance
    Emission,        // the emission image's luminance (Rec. 709 weights), one channel
    EmissionR, EmissionG, EmissionB,
    ColourR, ColourG, ColourB,  // the look's image with its own lights
};

struct AtlasSpec {
    std::string name;               // the file's stem: "six_way_a", ...
    std::array<Layer, 4> channels;  // R, G, B, A
};

// Throws an InvalidArgument Error naming the text for an unknown layout.
Layout parseLayout(std::string_view name);
std::string_view layoutName(Layout layout);
std::vector<AtlasSpec> atlasesOf(Layout layout);
bool usesSixWayLights(Layout layout);
// "right", "transparency", "emission", "emission_r", "colour_r", ...
std::string_view layerName(Layer layer);

}  // namespace firelook::flipbook
