// What the viewer needs about looks that the C API does not offer, done with the look library
// (firelook::look, the same code the runtime runs) and confined to this file:
//  - the emissivity at each bin centre of a preset or colour-stop emission, which the per-bin
//    editor starts from (the C API has no way to resolve a look's emission);
//  - the look in effect at a frame position while keyframes play, for the QA reference (the C API
//    reports the interpolated T_c, k_s, k_f in fl_instance_state but not the emission or lights).
// The real-time path itself stays on the C API.
#pragma once

#include <string>
#include <vector>

#include "firelook/firelook.h"
#include "keyframes_file.h"
#include "look_edit.h"

namespace firelook::viewer {

// The emissivity e_i at each bin centre of `info`'s bins. Throws ViewerError for a bad look.
std::vector<Rgb3> resolveBins(const LookEdit& look, const fl_package_info& info);

// The temperature at the centre of bin i.
double binCentre(const fl_package_info& info, int bin);

// Look-file JSON of the keyed look at `frame_position`: the keys and weight the runtime's
// keyframes use (runtime/world/keyframe_bracket.h: held before the first key, from the last on and
// exactly on a key), linear in every parameter and each bin's emissivity between keys (the runtime
// blends the fitted RBF weights, equal to blending the emissivity wherever the fit interpolates
// exactly). keys must be non-empty and sorted.
std::string keyedLookJson(const std::vector<Keyframe>& keys, double frame_position, const fl_package_info& info);

}  // namespace firelook::viewer
