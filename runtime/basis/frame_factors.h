// The compressed basis of one frame in float (docs/model.md): the frame codec's input (the bake
// and repack encode it, frame_codec.h) and what layout-1 packages store. The runtime draws the
// resident form (resident_frame.h) only.
//   B ~= U (S V^T)   with B = pixels x columns, U = pixels x rank,
// plus the per-pixel optical depths that give exact alpha for any (k_s, k_f).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "basis/bake_description.h"
#include "basis/resident_frame.h"

namespace firelook::basis {

struct FrameFactors {
    int frame = 0;
    int pixels = 0;
    int columns = 0;
    int rank = 0;
    // U, pixel-major (the rank values of one pixel are contiguous), IEEE half.
    std::vector<uint16_t> u_half;
    // S V^T, column-major: the rank coefficients of basis column j are contiguous.
    std::vector<float> svt;
    // O_b(s, p) = integral of rho along ray s of pixel p: one image per footprint sample s.
    std::vector<float> depth_b;
    // O_a(s, T_c, p) = integral of rho f(T - T_c): per footprint sample, one image per alpha threshold.
    std::vector<float> depth_a;
};

// Decoded U in float (half -> float once per frame), for the tools and the tests' reference kernels.
std::vector<float> decodeU(const FrameFactors& factors);

// A frame's sizes as the description gives them, with no values yet (what a reader fills in).
FrameFactors emptyFrameFactors(const BakeDescription& description, int frame, int rank);

// The float layout of FrameFactors from the resident form (U rounded to half), for the tools that
// re-encode a package's frames (firelook repack) and the tests.
FrameFactors expandFrame(const BakeDescription& description, const ResidentFrame& frame);

// decodeResidentFrame (frame_codec.h), then expandFrame.
FrameFactors decodeFrame(const BakeDescription& description, int frame, int rank, std::span<const std::byte> u,
                         std::span<const std::byte> svt, std::span<const std::byte> depths,
                         const std::string& source);

}  // namespace firelook::basis
