// The fire's light as engines take it (issue 29, item 2): per frame, an irradiance volume around the
// effect, a grid of probes each holding the radiance arriving from the fire as real spherical
// harmonics up to order 2 (9 coefficients), for any look.
//
// What a bake stores per frame (FireProbeTable, the optional FPRB section, docs/package-format.md)
// is linear in the look's emission: per probe, grid point g of the extinction axes and temperature
// bin i, the SH projection of the radiance the fire's bin-i emission sends to the probe through the
// extinction of g, factored over the grid points as sum_r factors[g][r] sh[probe][r][i] (a truncated
// eigen-decomposition: the extinction changes the probes smoothly, so a few terms carry them; one
// term per grid point would be 96 on the bundled sample). A look's probes cost what its coefficients
// cost: the grid weights (parameter_grid.h) applied to the factors, then the weighted sum over the
// terms and bins with the look's c_i (look_model.h), as the image and the fire lights (fire_lights.h).
//
// SH: the real basis in the usual order (Y00; Y1-1, Y10, Y11; Y2-2, Y2-1, Y20, Y21, Y22) of world
// directions pointing from the probe towards where the light comes from. Units: radiance (the
// model's, docs/model.md). From a probe's coefficients L_lm: fluence rate (radiance integrated over
// all directions) sqrt(4 pi) L00; irradiance on a surface facing n, irradianceFromSh below: the SH rule
// sum_l A_l sum_m L_lm Y_lm(n), A = (pi, 2 pi / 3, pi / 4) (Ramamoorthi and Hanrahan), clamped at 0,
// blended with a directional split where the light comes from one side.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <string>
#include <vector>

#include "basis/parameter_grid.h"
#include "look/look_model.h"
#include "package/format.h"

namespace firelook::basis {

// Optional, per frame: packages without it load and simply have no fire probes.
inline constexpr uint32_t kSectionFireProbes = package::makeFourCC('F', 'P', 'R', 'B');
inline constexpr int kFireProbesVersion = 1;
inline constexpr int kFireProbeCoefficients = 9;
// The most terms a table's factorisation over the grid points may have.
inline constexpr int kMaxFireProbeRank = 64;

// Where the probes are and how values between them are interpolated.
struct FireProbeGrid {
    glm::ivec3 counts{0};     // probes per axis, each >= 2
    glm::dvec3 origin{0.0};   // world position of probe (0, 0, 0)
    glm::dvec3 spacing{0.0};  // world distance between neighbouring probes along x, y, z (> 0)
    // Between probes the values are weighted by s(x) = |x - falloff_centre|^2 + falloff_radius^2
    // before the trilinear blend and divided by s at the point: the fire's light falls off about as
    // 1 / s, so what is blended varies slowly (and beyond the grid the nearest face's values fall off
    // as the inverse square). falloff_radius 0: plain trilinear, clamped at the grid's faces.
    glm::dvec3 falloff_centre{0.0};
    double falloff_radius = 0.0;

    int probes() const { return counts.x * counts.y * counts.z; }
    // Probe (i, j, k) is number i + counts.x (j + counts.y k), at origin + spacing * (i, j, k).
    glm::dvec3 position(int i, int j, int k) const { return origin + spacing * glm::dvec3(i, j, k); }
};

struct FireProbeTable {
    FireProbeGrid grid;
    int points = 0;  // grid points of the extinction axes
    int bins = 0;
    int rank = 0;  // terms of the factorisation over the grid points, 1 to min(points, kMaxFireProbeRank)
    // The transmittance the radiance was marched with is exp(-extinction_scale * optical depth):
    // 1 - albedo counts absorption only (scattered light taken to go on as if unscattered).
    float extinction_scale = 1.0f;
    std::vector<float> factors;  // [point][rank]
    std::vector<float> sh;       // [probe][rank][bin][kFireProbeCoefficients]

    float* at(int probe, int term, int bin) {
        return sh.data() + ((static_cast<size_t>(probe) * rank + term) * bins + bin) * kFireProbeCoefficients;
    }
    const float* at(int probe, int term, int bin) const {
        return const_cast<FireProbeTable*>(this)->at(probe, term, bin);
    }
};

// The FPRB payload, little-endian: u32 version, u32 counts[3], u32 points, u32 bins, u32 9,
// u32 rank, f32 extinction_scale, u32 0, f64 origin[3], f64 spacing[3], f64 falloff_centre[3],
// f64 falloff_radius, f32 factors[points][rank], f32 sh[probes][rank][bins][9].
std::vector<std::byte> encodeFireProbes(const FireProbeTable& table);
// Throws a Corrupt Error starting with `where` (the file and frame) for a payload of the wrong size
// or version, a shape other than (points, bins), a rank outside 1..min(points, 64), fewer than 2 or more
// than 64 probes an axis, a spacing that is not positive, or a value that is not finite.
FireProbeTable decodeFireProbes(std::span<const std::byte> bytes, int points, int bins,
                                const std::string& where);

// A look's probes: out[probe * 9 + k] = sum over the grid weights w_g, terms r and bins i of
// w_g factors[g][r] c_i sh[probe][r][i][k] (RGB). weights: the look's grid weights (interpolationWeights of
// its extinction); rbf: its c_i, one per bin. Finite for finite input; allocation-free; out holds
// table.grid.probes() * 9 values.
void evaluateFireProbes(const FireProbeTable& table, const GridWeights& weights, std::span<const Rgb> rbf,
                        Rgb* out);

// The SH coefficients at a world point, blended from a look's probes (`values`, as evaluateFireProbes
// writes them) by the grid's rule above; zeros for a point that is not finite. out: 9 values.
void sampleFireProbes(const FireProbeGrid& grid, std::span<const Rgb> values, const glm::dvec3& point,
                      Rgb* out);
// From 9 coefficients: the fluence rate, and the irradiance on a surface facing `normal` (a unit
// vector); both >= 0 and finite for finite input.
//
// The irradiance is order-2 SH's where the light comes from all around, and a directional split's
// where it comes from one side, blended by how one-sided it is (per channel). Order 2 alone makes a
// small source's irradiance 6.25% high facing it (the cosine lobe's bands beyond 2 are cut) and up to
// 15% off towards its horizon, and a fire seen from the ground or the probes beside it is such a
// source. The split takes out the light from d = L1 / |L1| of the intensity I whose projection has
// that L1, I max(0, n . d), and adds the rest (L - I Y(d)) by the SH rule: exact for light from one
// direction. For a uniform cone of half-angle a, q = |L1| / (sqrt(3) L00) = (1 + cos a) / 2 (1 for
// one direction, 0.5 for a hemisphere), and the weight w = clamp(4 q - 3, 0, 1)^1.5 of the split,
// fitted to cones facing the surface (the split alone is 6% low for a hemisphere, where order 2 is
// exact), leaves the irradiance facing a cone within 0.5% up to a = 30 degrees, where order 2 alone
// is 4-6% high, and within order 2's own 1% beyond; off-axis within 4.3% up to 80 degrees, where order
// 2 alone is up to 15% off (tests/bake/fire_probes_test.cpp, IrradianceOfAConeOfLight).
Rgb fluenceFromSh(const Rgb* sh);
Rgb irradianceFromSh(const Rgb* sh, const glm::dvec3& normal);
// The weight of the directional split above for a channel's L00 and |L1|: 0 to 1.
double directionalShare(double l00, double l1_length);
// The 9 basis functions at a unit direction.
void shBasis(const glm::dvec3& direction, double* y);

}  // namespace firelook::basis
