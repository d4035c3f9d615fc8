// The compressed basis of one frame (docs/model.md):
//   B ~= U (S V^T)   with B = pixels x columns, U = pixels x rank,
// plus the per-pixel optical depths that give exact alpha for any (k_s, k_f).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

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

// Decoded U in float, for CPU reconstruction (half -> float once per frame).
std::vector<float> decodeU(const FrameFactors& factors);

}  // namespace firelook::basis
