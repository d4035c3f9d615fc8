// The GPU layouts of firelook.h (fl_*_get_frame_u, fl_*_get_frame_depths) written straight from a
// frame in the world's resident form (basis/resident_frame.h), so a host uploading the frame an
// instance shows needs no second decode; the fl_package_ variants load the frame in the same form
// and write it by the same code. U is the codec's grid value rounded to half, as basis::expandFrame
// gives it (tests/plugin_api rebuilds the world's image and alpha from these layers).
#pragma once

#include <cstddef>
#include <cstdint>

#include "basis/bake_description.h"
#include "basis/resident_frame.h"

namespace firelook::plugin {

// uint16_t elements of the U layers: ceil(rank / 4) RGBA layers of `pixels`.
size_t uLayerElements(int rank, size_t pixels);
// floats of the depth layers: footprint_samples x (1 + alpha thresholds) layers of `pixels`.
size_t depthLayerFloats(const basis::BakeDescription& description);

// U[p][k] as IEEE half at ((k / 4) * pixels + p) * 4 + k % 4, 0 beyond the rank; `out` holds
// uLayerElements(frame.rank, frame.pixels).
void writeULayers(const basis::ResidentFrame& frame, uint16_t* out);
// O_b(s) at layer s, O_a(s, j) at layer S + s T + j; `out` holds depthLayerFloats(description).
void writeDepthLayers(const basis::BakeDescription& description, const basis::ResidentFrame& frame, float* out);

}  // namespace firelook::plugin
