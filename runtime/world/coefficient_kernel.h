// The per-instance hot path: z = S V^T w (docs/model.md), the same
// result as basis::computeCoefficients() (summation order aside: the sums run
// per channel into separate arrays so the loop over the rank vectorises), with
// no checks and no allocation. The caller (World) validated the shapes once.
#pragma once

#include "basis/bake_description.h"
#include "look/look_model.h"

namespace firelook::runtime {

// svt: S V^T of the frame (columns x rank, column-major, FrameFactors::svt or ResidentFrame::svt);
// rbf: bins entries, lights: one per baked light; scratch: >= 3 * rank floats;
// z_out: rank x 3, z_out[k * 3 + channel].
void computeCoefficientsFast(const basis::BakeDescription& description, const float* svt, int rank,
                             const ExtinctionParams& extinction, const Rgb* rbf, const Rgb* lights, float* scratch,
                             float* z_out);

}  // namespace firelook::runtime
