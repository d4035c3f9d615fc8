// A user look (look.h) applied to one baked frame: checks that the look fits
// the package, fits its emission to the package's RBFs, and reconstructs the
// premultiplied RGBA image. The CLI's render/animate and tests share it.
#pragma once

#include <span>
#include <string>

#include "basis/bake_description.h"
#include "basis/frame_factors.h"
#include "basis/resident_frame.h"
#include "look/look.h"

namespace firelook::basis {

// Throws LookError (naming look.source_name) when the albedo differs from the
// baked one or the number of lights or bins does not match.
void renderLookImage(const BakeDescription& description, const FrameFactors& factors, std::span<const float> u_float,
                     const Look& look, std::span<float> rgba_out);
// The same on the resident form (what the runtime world draws, bit for bit).
void renderLookImage(const BakeDescription& description, const ResidentFrame& frame, const Look& look,
                     std::span<float> rgba_out);

}  // namespace firelook::basis
