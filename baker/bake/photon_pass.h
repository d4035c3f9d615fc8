// One scattering order of the basis tracer: photons start at points drawn from one kind of source,
// fly straight in a uniform direction, and deposit into each cell they cross the integral of
// sigma_s * tau over their track inside it (exact per step: albedo * (tau_start - tau_end), which
// summed over the cell's steps is albedo * (tau at entry - tau at exit)), for every grid point at once.
// Divided by the cell's sigma_s mass (ScatterCells), that is the sigma_s-weighted mean radiance Lbar the
// order's source produces.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "bake/light_depth_field.h"
#include "bake/photon_start_sampler.h"
#include "bake/scatter_cells.h"
#include "bake/trace_tables.h"
#include "render/medium.h"

namespace firelook::bake {

struct TransportContext {
    const render::Medium& medium;
    const TraceTables& tables;
    const ScatterCells& cells;
    const LightDepthField& light_depths;
    double track_step;       // world units
    std::size_t field_size;  // slots * points * columns
    const std::atomic<bool>& stop;  // set to abandon the pass (its result is then meaningless)
};

enum class SourceKind { Emission, LightScatter, Scattered };

// What photonPass accumulates into, kept between passes: one buffer per chunk of photons that run
// at once, each zero outside the slots its photons reached. A pass reads and clears only those
// slots, so few photons over many fine cells cost by the cells they reached and one write of the
// result.
struct PhotonPassBuffers {
    struct Chunk {
        std::vector<float> field;  // field_size floats, zero outside seen slots (layout: photon_pass.cpp)
        std::vector<std::uint8_t> seen;  // per slot: deposited into
    };
    std::vector<Chunk> chunks;  // allocated by the first pass
    // A field the caller no longer needs (an order before the previous one), which the next pass
    // overwrites and returns instead of allocating one: a fresh field of the bundled sample's frame 12
    // (97 MB) cost 40-50 ms of page faults a pass, a dozen passes a chain.
    std::vector<float> spare;
};

// Lbar per slot, grid point and column produced by `photons` photons from one kind of source.
// `previous` (for Scattered) is the Lbar of the previous order. The result does not depend on the
// number of threads.
std::vector<float> photonPass(const TransportContext& ctx, SourceKind kind, const PhotonStartSampler& sampler,
                              const std::vector<float>* previous, int photons, std::uint64_t seed,
                              PhotonPassBuffers& buffers);

// Bytes photonPass holds at its peak besides its inputs: its result and the accumulation buffers.
std::size_t photonPassBytes(std::size_t field_size, std::size_t slots);

}  // namespace firelook::bake
