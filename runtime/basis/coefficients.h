// The one implementation of z = S V^T w (docs/model.md): the weighted sum of the columns of S V^T,
// column weights w = grid weight x (c_i per bin, E_l per light), over the grid points that
// bracket the look's extinction. Unchecked and allocation-free: the runtime world calls it per
// instance after validating the shapes once; basis::computeCoefficients (recombine.h) is the
// checked form of it.
#pragma once

#include "basis/bake_description.h"
#include "look/look_model.h"

namespace firelook::basis {

// svt: columns x rank, column-major (svt[column * rank + k]; FrameFactors::svt or
// ResidentFrame::svt), columns = model.columnCount(); rbf: model.bins.count entries, lights: one
// per model light; z_out: rank x 3, z_out[k * 3 + channel]. Any matrix stored that way works:
// B^T of a pixels x columns basis with rank = pixels gives the image's RGB per pixel.
void coefficientKernel(const BasisModel& model, const float* svt, int rank, const ExtinctionParams& extinction,
                       const Rgb* rbf, const Rgb* lights, float* z_out);

}  // namespace firelook::basis
