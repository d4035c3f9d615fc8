// A user look (look.h) applied to one baked frame in its resident form (resident_frame.h): checks
// that the look fits the package, fits its emission to the package's RBFs, and reconstructs the
// premultiplied RGBA image, as the runtime world draws it (bit for bit). The CLI's render/animate,
// the fit and tests share it.
#pragma once

#include <span>
#include <string>

#include "basis/bake_description.h"
#include "basis/resident_frame.h"
#include "look/look.h"

namespace firelook::basis {

// Throws LookError (naming look.source_name) when the look's albedo differs from the baked one
// (albedo is fixed at bake time).
void checkBakedAlbedo(const BakeDescription& description, const Look& look);

// Throws LookError (naming look.source_name) when the albedo differs from the
// baked one or the number of lights or bins does not match.
void renderLookImage(const BakeDescription& description, const ResidentFrame& frame, const Look& look,
                     std::span<float> rgba_out);

}  // namespace firelook::basis
