// From a look to an image, on the resident form of a frame (resident_frame.h), the runtime's only
// frame form: the per-frame coefficient vectors z = S V^T w and the reconstruction image = U z,
// with alpha from the optical depths (docs/model.md). This is the runtime's hot path: no
// allocation here. tests/basis/reference_kernels.h writes the same definitions plainly, on the
// float layout of FrameFactors, for the tests to check these kernels against.
#pragma once

#include <span>

#include "basis/bake_description.h"
#include "basis/resident_frame.h"
#include "look/look_model.h"

namespace firelook::basis {

// Everything about a look that the recombination uses.
struct LookWeights {
    ExtinctionParams extinction;
    std::span<const Rgb> rbf_coefficients;  // c_i per bin (EmissionFunction::coefficients)
    std::span<const Rgb> light_irradiance;  // E_l per baked light
};

// z_out: rank x 3, z_out[k * 3 + channel]. Throws an InvalidArgument Error when the
// spans do not match the description (wrong bin or light count, short output).
void computeCoefficients(const BakeDescription& description, const ResidentFrame& frame, const LookWeights& look,
                         std::span<float> z_out);

// rgba_out: pixels x 4, premultiplied linear RGBA, top row first. U is read as its int16 grid
// values (z scaled by the column scales instead), alpha from the depth codes through the frame's
// DepthTable. Negative radiance (truncation ringing) is clamped to 0 and a non-finite value can
// never be written; alpha is in [0, 1]. Throws an InvalidArgument Error when the frame does not match
// the description, a span is too short or the rank is above 1024. Vectorised (AVX2 where the CPU
// has it), single-threaded; alpha's exp is a polynomial, alpha within 1e-7 of the exact value
// (see recombine.cpp).
void reconstructImage(const BakeDescription& description, const ResidentFrame& frame, std::span<const float> z,
                      const ExtinctionParams& extinction, std::span<float> rgba_out);

// alpha = mean over the footprint rays of 1 - exp(-(a O_a(T_c) + b O_b)) for one pixel; O_a
// interpolated linearly in T_c between the alpha threshold samples. Bit for bit the alpha
// reconstructImage writes. Throws an InvalidArgument Error for a pixel out of range or a frame that
// does not match the description.
float pixelAlpha(const BakeDescription& description, const ResidentFrame& frame, int pixel,
                 const ExtinctionParams& extinction);

}  // namespace firelook::basis
