// The one implementation of z = S V^T w (docs/model.md): the weighted sum of the columns of S V^T,
// column weights w = grid weight x (c_i per bin, E_l per light), over the grid points that
// bracket the look's extinction. Unchecked and allocation-free: the runtime world calls it for
// all its instances after validating the shapes once; basis::computeCoefficients (recombine.h) is
// the checked form of it.
//
// Order of the sums: first the grid points' columns are blended, M = sum_p g_p (S V^T)_p (a
// columns-per-point x rank matrix, the points in increasing index), then z = sum_c M_c (c_c or
// E_l), the columns in order. That reads each point's columns once for all three channels (a
// third of the multiply-adds of weighting every column by its three channel weights) and lets
// instances that show the same frame share every read of S V^T (coefficientBatch): a batch gives
// each instance the bits a batch of one gives it (a point another instance brings in adds an exact
// 0, S V^T being finite as the decoder gives it). Against the exact sum a value is within
// (points + columns + 2) eps sum |term| (first order); a column whose weight is 0 in a channel
// adds nothing to it.
#pragma once

#include <span>

#include "basis/bake_description.h"
#include "look/look_model.h"

namespace firelook::basis {

// One instance's look as the kernel reads it, and where its z goes.
struct CoefficientJob {
    ExtinctionParams extinction;
    const Rgb* rbf = nullptr;     // model.bins.count entries
    const Rgb* lights = nullptr;  // one per model light
    float* z_out = nullptr;       // rank x 3, z_out[k * 3 + channel]
};

// svt: columns x rank, column-major (svt[column * rank + k]; FrameFactors::svt or
// ResidentFrame::svt), columns = model.columnCount(); every job's z from that one matrix.
// Up to 8 instances at a time share each read (AVX-512; 4 with AVX2 + FMA, the same bits either
// way; the baseline build rounds each product apart from its sum). Single-threaded; about 50 KiB
// of stack.
void coefficientBatch(const BasisModel& model, const float* svt, int rank, std::span<const CoefficientJob> jobs);

// coefficientBatch for one look. Any matrix stored that way works: B^T of a pixels x columns basis
// with rank = pixels gives the image's RGB per pixel.
void coefficientKernel(const BasisModel& model, const float* svt, int rank, const ExtinctionParams& extinction,
                       const Rgb* rbf, const Rgb* lights, float* z_out);

}  // namespace firelook::basis
