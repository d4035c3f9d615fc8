// The compressed basis of one frame (DESIGN.md section 2):
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
    // O_b(p) = integral of rho along the pixel's ray.
    std::vector<float> depth_density;
    // O_a(p, T_c) = integral of rho f(T - T_c), one image per alpha threshold sample.
    std::vector<float> depth_sigmoid;
};

// Decoded U in float, for CPU reconstruction (half -> float once per frame).
std::vector<float> decodeU(const FrameFactors& factors);

}  // namespace firelook::basis
