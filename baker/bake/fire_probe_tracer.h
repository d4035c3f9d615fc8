// The bake half of the fire's probe grid (runtime/basis/fire_probes.h): per probe, grid point and
// bin, the radiance the fire sends to the probe projected onto spherical harmonics.
#pragma once

#include "bake/basis_tracer.h"
#include "basis/fire_probes.h"
#include "render/medium.h"

namespace firelook::bake {

struct FireProbeSettings {
    // Probes per axis (>= 2). The tracer holds resolution^3 x points x bins x 9 floats while it
    // factors them (226 MiB at 16 with 96 grid points and 16 bins), outside the bake's memory
    // estimate: the bake allows up to kMaxFireProbeResolution (bake_config.h).
    int resolution = 4;
    double box_scale = 1.5;  // the grid spans the volume's world bounds scaled by this about their centre
    // Directions per probe: a spherical Fibonacci set over the cone that bounds the volume's bounding
    // sphere as seen from the probe (the whole sphere from inside it), each weighing its share of
    // the cone's solid angle.
    int directions = 1024;
    double step_voxels = 0.5;  // march step, in the medium's smallest voxel edge
    // Marches with the extinction scaled by 1 - albedo (absorption only: scattered light goes on as
    // if unscattered) when true, with the full extinction (the emission seen directly) when false.
    bool absorption_only = true;
    // Interpolation weighting (FireProbeGrid): on, about the emission's centroid and RMS radius.
    bool falloff = true;
    // The factorisation over the grid points keeps the fewest terms whose dropped part is within
    // this relative Frobenius norm of the whole table (at most basis::kMaxFireProbeRank terms); 0
    // keeps every term it may.
    double rank_error = 1e-3;
};

// Per probe the radiance is marched along each direction and projected onto the SH; the table of
// every (probe, bin, coefficient) by grid point is then factored through the eigenvectors of its
// Gram matrix over the grid points. Deterministic (same bytes for the same inputs, any thread
// count). An empty medium gives an all-zero table of rank 1 around the origin.
basis::FireProbeTable traceFireProbes(const render::Medium& medium, const BasisModel& model,
                                      const FireProbeSettings& settings = {});

}  // namespace firelook::bake
