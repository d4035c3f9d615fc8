// What a look is fitted to: one frame's target image, which pixels count and how alpha enters.
#pragma once

#include <vector>

#include "look/look_model.h"

namespace firelook::fit {

// A frame's target at the package's image size. Either the effect alone, premultiplied RGBA with
// its alpha (what `firelook render` writes to EXR): alpha is matched as well as the colour; or an
// opaque picture of the effect over a known background (match_alpha false): the colour compared
// is the composite rgb + (1 - alpha) * background (docs/model.md, "Light transport").
struct FrameTarget {
    int frame = 0;
    std::vector<float> rgba;    // pixels x 4, linear, premultiplied, top row first
    std::vector<float> weight;  // pixels, each >= 0 (0 leaves a pixel out); empty: 1 everywhere
    bool match_alpha = true;
    Rgb background{0.0f};       // used when match_alpha is false
};

}  // namespace firelook::fit
