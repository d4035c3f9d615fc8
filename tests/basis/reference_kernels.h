// The runtime's look kernels (runtime/basis/recombine.h) as plain definitions on the float layout
// of FrameFactors (runtime/basis/frame_factors.h): the runtime draws only the resident form, and
// tests check it, the frame codec and the bake against these. Scalar and unhurried; never a
// runtime path.
#pragma once

#include <span>

#include "basis/bake_description.h"
#include "basis/frame_factors.h"
#include "basis/recombine.h"

namespace firelook::reference {

// z = S V^T w: basis::computeCoefficients (its checks and its kernel) on the factors' S V^T.
void computeCoefficients(const basis::BakeDescription& description, const basis::FrameFactors& factors,
                         const basis::LookWeights& look, std::span<float> z_out);

// rgba_out: pixels x 4, premultiplied RGBA, as basis::reconstructImage defines it. rgb = U z summed
// in float, negative and non-finite sums 0; u_float is basis::decodeU(factors). Alpha is the mean
// over the footprint rays of 1 - e^-tau (in double), tau = a O_a + b O_b with O_a interpolated
// between the alpha threshold layers that bracket T_c (basis::sampleBracket, its weight in float as
// the runtime takes it); tau <= 0 is clear, NaN opaque. Throws an InvalidArgument Error when a span
// or the depth layers are too short.
void reconstructImage(const basis::BakeDescription& description, const basis::FrameFactors& factors,
                      std::span<const float> u_float, std::span<const float> z, const ExtinctionParams& extinction,
                      std::span<float> rgba_out);

// The alpha reconstructImage writes for `pixel` (the same code). Throws an InvalidArgument Error for
// a pixel out of range or depth layers too short.
float pixelAlpha(const basis::BakeDescription& description, const basis::FrameFactors& factors, int pixel,
                 const ExtinctionParams& extinction);

}  // namespace firelook::reference
