// The fire as a light source for the scene (issue 16, item 4): per frame, a few point lights that
// stand for the light the fire emits after its own absorption, for any look.
//
// What a bake stores per frame (FireLightTable, the optional FLIT section, docs/package-format.md)
// is linear in the look's emission: for each of `clusters` groups of emitting voxels chosen from the
// data, each grid point g of the extinction axes and each temperature bin i, the escaping radiant
// intensity P = integral over the cluster of rho phi_i(T) tau_g dV (tau_g: the voxel's escape
// transmittance at g, averaged over directions) and its first and second moments about the
// cluster's reference point. A look then costs what the coefficients cost: the weighted sum over
// the bracketing grid points (parameter_grid.h) and bins with the look's c_i (look_model.h).
//
// Units: world space; intensity in the model's radiance times world area (radiance x length^2,
// i.e. radiant intensity, "W/sr" when radiance is W m^-2 sr^-1): a light of intensity I at distance d
// gives the fluence rate (the integral of radiance over all directions) I / d^2, which is also the
// irradiance on a surface facing it. The light radiates isotropically.
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

// Optional, per frame: packages without it load and simply have no fire lights.
inline constexpr uint32_t kSectionFireLights = package::makeFourCC('F', 'L', 'I', 'T');
inline constexpr int kFireLightsVersion = 1;
// Moments stored per (cluster, grid point, bin): P, P dx, P dy, P dz, P |d|^2 with d = x - reference.
inline constexpr int kFireLightMoments = 5;

struct FireLightTable {
    int clusters = 0;  // a power of two; clusters 2m and 2m+1 are the halves of one cluster of clusters / 2
    int points = 0;    // grid points of the extinction axes
    int bins = 0;
    // The transmittance that decided what escapes is exp(-extinction_scale * optical depth):
    // 1 - albedo counts absorption only (scattered light taken to leave where it was emitted).
    float extinction_scale = 1.0f;
    std::vector<glm::dvec3> reference;  // per cluster, world space: its voxels' mean position
    std::vector<float> moments;         // [cluster][point][bin][kFireLightMoments]

    float* at(int cluster, int point, int bin) {
        return moments.data() + ((static_cast<size_t>(cluster) * points + point) * bins + bin) * kFireLightMoments;
    }
    const float* at(int cluster, int point, int bin) const {
        return const_cast<FireLightTable*>(this)->at(cluster, point, bin);
    }
};

// An all-zero table of that shape (an empty frame's).
FireLightTable emptyFireLightTable(int clusters, int points, int bins, float extinction_scale,
                                   const glm::dvec3& reference);

// The FLIT payload: u32 version, u32 clusters, u32 points, u32 bins, f32 extinction_scale, u32 0,
// f64 reference[clusters][3], f32 moments[clusters][points][bins][5]; little-endian.
std::vector<std::byte> encodeFireLights(const FireLightTable& table);
// Throws a Corrupt Error starting with `where` (the file and frame) for a payload of the wrong
// size or version, a shape other than (points, bins), or a value that is not finite, or a power
// or second moment below 0.
FireLightTable decodeFireLights(std::span<const std::byte> bytes, int points, int bins, const std::string& where);

struct FireLight {
    glm::dvec3 position{0.0};  // world space: the power-weighted centroid of what the light stands for
    Rgb intensity{0.0f};       // radiant intensity, see above
    // World units: the RMS distance of that power from `position`. Treat the light as a sphere of
    // this radius (its fluence law I / d^2 holds beyond it); 0 for a single voxel or no power.
    double radius = 0.0;
};

// The `count` lights of a look: count is a power of two up to table.clusters, each light the merge
// of table.clusters / count neighbouring clusters. weights: the look's grid weights
// (interpolationWeights of its extinction); rbf: its c_i, one per bin (>= 0). Positions are those
// of the mean channel's power; a light with no power sits at its clusters' reference points' mean.
// Never NaN: every output is finite for finite, non-negative input. Allocation-free.
void evaluateFireLights(const FireLightTable& table, const GridWeights& weights, std::span<const Rgb> rbf,
                        int count, FireLight* out);

// True for 1, 2, 4, ... up to clusters.
bool validFireLightCount(const FireLightTable& table, int count);

}  // namespace firelook::basis
