// The bake half of the fire's point lights (runtime/basis/fire_lights.h): which voxels make up each
// light, and per grid point and bin how much of their emission escapes the volume.
#pragma once

#include "bake/basis_tracer.h"
#include "basis/fire_lights.h"
#include "render/medium.h"

namespace firelook::bake {

struct FireLightSettings {
    // Leaf clusters (a power of two): any power of two up to it can be asked for at run time.
    int clusters = 8;
    // Directions the escape transmittance is averaged over (a spherical Fibonacci set, equal weights).
    int directions = 32;
    // Voxels are grouped into blocks of s^3 that share one escape estimate, s chosen so that no axis
    // has more than this many blocks: the cost is bounded whatever the resolution.
    int max_blocks_per_axis = 48;
};

// Every voxel with density contributes rho phi_i(T) dV (the voxel's share of the integral of the
// trilinear interpolant) times the escape transmittance at its block's centre, the mean over the
// directions of exp(-(1 - albedo) * optical depth to the edge of the volume): scattered light is
// taken to leave from where it was emitted (tests and scripts/bench/fire_lights.sh measure it
// against the full model). Clusters are the leaves of a recursive split of the blocks at the
// weighted median of their widest axis, weighted by a hotter-is-brighter emission (bin i weighs
// i + 1), so leaves 2m and 2m+1 are the halves of one cluster of the coarser level. Deterministic
// (same bytes for the same inputs, any thread count). An empty medium gives an all-zero table.
basis::FireLightTable traceFireLights(const render::Medium& medium, const BasisModel& model,
                                      const FireLightSettings& settings = {});

}  // namespace firelook::bake
