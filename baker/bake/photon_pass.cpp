#include "bake/photon_pass.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <glm/mat3x3.hpp>
#include <numbers>

#include "bake/index_ray.h"

namespace firelook::bake {
namespace {

// Photons of one pass are split into this many chunks with their own accumulation buffers, run at
// once and summed in a fixed order, so the result does not depend on the number of threads: memory
// holds the result and two buffers whatever the machine. Two, not more in two waves: every buffer
// is read, added and cleared whole at the end of a pass, and with four the passes over those fields
// (with the normalise) were a sixth of the photon passes' samples on frame 12 upsampled 4x (fields
// of 260 MB; 9% with two and the one pass below).
constexpr int kPhotonChunks = 2;

// The unit sphere's area-preserving map from [0, 1)^2.
glm::dvec3 uniformDirection(double u, double v) {
    const double z = 1.0 - 2.0 * u;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = 2.0 * std::numbers::pi * v;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// Photon n of a pass of N starts from u = (n + xi) / N in the start sampler's cdf (stratified: every
// brick and cube gets its share of photons to within one, not a Poisson number) and flies along
// point n of the R2 lattice (additive recurrence on the plastic number), shifted by one random
// offset per pass (Cranley-Patterson) so that each direction is uniform on its own. Both keep every
// photon's start and direction distributed as before, so the estimator stays exact; what changes is
// the photon noise of each cell's Lbar. In dense smoke a photon deposits most of its light within a
// cell or two of its start, so the random number of photons starting near a cell was most of that
// noise. Measured on dense smoke (frame 20 of samples/data/smoke at albedo 0.95, 128x128, one look,
// two seeds): seed-to-seed relative RMSE of the image 1.26% with independent draws, 0.95% with
// these (as much as 1.75 times the photons would give, at no cost); image means within 0.1%.
// On tests/bake's thick box (BasisTracer.ThickHighAlbedoSmokeKeepsItsEnergy, seeds 1-6) the
// spread of the image's sum fell from 1.7% to 0.3% (0.5% with stratified starts alone).
struct PhotonSequence {
    double shift_u = 0.0, shift_v = 0.0;
    static constexpr double kAlpha1 = 0.7548776662466927;  // 1 / plastic number
    static constexpr double kAlpha2 = 0.5698402909980532;  // 1 / plastic number^2

    static double fraction(double x) { return x - std::floor(x); }
    glm::dvec3 direction(int n) const {
        return uniformDirection(fraction(shift_u + kAlpha1 * n), fraction(shift_v + kAlpha2 * n));
    }
};

// Whether a pass's chunk fields are [slot][column][point] (the kinds whose photons carry a few
// columns) rather than [slot][point][column] (traceChunk's deposit).
bool depositsByColumn(SourceKind kind) { return kind != SourceKind::Scattered; }

void traceChunk(const TransportContext& ctx, SourceKind kind, const PhotonStartSampler& sampler,
                const PhotonSequence& sequence, const std::vector<float>* previous, int photons,
                std::uint64_t seed, int chunk, PhotonPassBuffers::Chunk& buffer) {
    const TraceTables& tb = ctx.tables;
    const int G = tb.points, C = tb.columns;
    if (buffer.field.empty()) {
        buffer.field.assign(ctx.field_size, 0.0f);
        buffer.seen.assign(static_cast<std::size_t>(ctx.cells.slots), 0);
    }
    std::vector<float>& field = buffer.field;
    // A photon's weight per grid point and column, and a light-scatter photon's as [column][point]
    // (what its deposit loops over).
    std::vector<float> weight(static_cast<std::size_t>(G) * C),
        weight_by_column(static_cast<std::size_t>(G) * C);
    std::vector<float> tau(G), tau_next(G), sigma_t(G), ltau(G), cell_sum(G), cell_depth(G);
    float smoke[kMaxAxisSamples], flame[kMaxAxisSamples], d_smoke[kMaxAxisSamples], d_flame[kMaxAxisSamples],
        lsm[kMaxAxisSamples], lfl[kMaxAxisSamples], entry_smoke[kMaxAxisSamples],
        entry_flame[kMaxAxisSamples], cell_smoke[kMaxAxisSamples], cell_flame[kMaxAxisSamples];
    int interp_slots[8];
    float interp_w[8];
    // The cells span the influence box in whole cells; tracks run to their end, where the outer
    // cells stop.
    const IndexBox cell_box{ctx.cells.origin, ctx.cells.origin + glm::dvec3(ctx.cells.count * ctx.cells.edge)};
    // pdf per unit index volume -> per unit world volume.
    const double voxel_volume = std::fabs(glm::determinant(glm::dmat3(ctx.medium.indexToWorld())));
    const int first = static_cast<int>(static_cast<int64_t>(photons) * chunk / kPhotonChunks);
    const int last = static_cast<int>(static_cast<int64_t>(photons) * (chunk + 1) / kPhotonChunks);
    for (int n = first; n < last; ++n) {
        if ((n & 255) == 0 && ctx.stop.load(std::memory_order_relaxed)) return;
        render::Pcg32 rng = render::Pcg32::forSample(seed, static_cast<uint64_t>(kind), static_cast<uint64_t>(n));
        const PhotonStartSampler::Start start = sampler.sample((n + rng.uniform()) / photons, rng);
        const render::MediumSample at = ctx.medium.sampleIndex(start.point);
        const double pdf = start.pdf / voxel_volume;
        if (!(pdf > 0.0) || !(at.density > 0.0f)) continue;
        // Track-length estimator of integral_cell sigma_s Lbar dV: (Q / p) integral sigma_s tau ds / N.
        const float scale = static_cast<float>(1.0 / (pdf * photons));
        int bin_first = 0, bin_last = 0;
        bool any = false;
        std::fill(weight.begin(), weight.end(), 0.0f);
        if (kind == SourceKind::Emission) {
            tb.binWindow(at.temperature, bin_first, bin_last);
            for (int i = bin_first; i < bin_last; ++i) {
                const float w = at.density * tb.rbf(i, at.temperature) * scale;
                weight[i] = w;  // independent of the grid point: stored once in row 0
                any = any || w > 0.0f;
            }
        } else {
            tb.split(at.density, at.temperature, smoke, flame);
            tb.extinction(smoke, flame, sigma_t.data());
            if (kind == SourceKind::LightScatter) {
                for (int l = 0; l < tb.lights; ++l) {
                    ctx.light_depths.sample(l, start.point, lsm, lfl);
                    tb.transmittance(lsm, lfl, ltau.data());
                    for (int g = 0; g < G; ++g) {
                        const float w = tb.albedo * sigma_t[g] * ltau[g] * kInv4Pi * scale;
                        weight[g * C + tb.bins + l] = w;
                        any = any || w > 0.0f;
                    }
                }
            } else {
                const int n_corner = ctx.cells.corners(start.point, interp_slots, interp_w);
                for (int c = 0; c < n_corner; ++c) {
                    const float* src = previous->data() + static_cast<std::size_t>(interp_slots[c]) * G * C;
                    for (int g = 0; g < G; ++g) {
                        const float k = interp_w[c] * tb.albedo * sigma_t[g] * scale;
                        for (int col = 0; col < C; ++col) weight[g * C + col] += k * src[g * C + col];
                    }
                }
                for (float w : weight) any = any || w > 0.0f;
            }
        }
        if (!any) continue;
        if (kind == SourceKind::LightScatter)
            for (int g = 0; g < G; ++g)
                for (int col = tb.bins; col < C; ++col) weight_by_column[col * G + g] = weight[g * C + col];

        // Columns this photon carries: a window of bins, or the light columns, or all.
        int col_first = 0, col_last = C;
        if (kind == SourceKind::Emission) {
            col_first = bin_first;
            col_last = bin_last;
        } else if (kind == SourceKind::LightScatter) {
            col_first = tb.bins;
        }

        const glm::dvec3 direction = sequence.direction(n);
        const IndexRay ray{start.point, glm::dmat3(ctx.medium.worldToIndex()) * direction};
        double t0, t1;
        if (!clipToBox(ray, cell_box, t0, t1)) continue;
        std::fill(d_smoke, d_smoke + tb.n_tc, 0.0f);
        std::fill(d_flame, d_flame + tb.n_tc, 0.0f);
        std::fill(entry_smoke, entry_smoke + tb.n_tc, 0.0f);
        std::fill(entry_flame, entry_flame + tb.n_tc, 0.0f);
        std::fill(tau.begin(), tau.end(), 1.0f);
        // What a track scatters in a cell is albedo * sum over its steps there of (tau_start -
        // tau_end) (stepRemoved: each step integrated exactly), and that sum telescopes to
        // albedo * (tau at entry - tau at exit). So the steps only add up optical depths, and the
        // transmittance of every grid point is taken once a cell, where the track leaves it: the
        // same estimator, its rounding aside, for a third of the work a step. Where the cell's
        // optical depth x is below 1e-3 the difference would cancel; stepRemoved takes its series
        // there, as it does for a step.
        int current_slot = -1;
        const auto leaveCell = [&] {
            tb.transmittance(d_smoke, d_flame, tau_next.data());
            if (current_slot >= 0) {
                buffer.seen[current_slot] = 1;
                for (int a = 0; a < tb.n_tc; ++a) {
                    cell_smoke[a] = d_smoke[a] - entry_smoke[a];
                    cell_flame[a] = d_flame[a] - entry_flame[a];
                }
                tb.extinction(cell_smoke, cell_flame, cell_depth.data());  // the cell's optical depth x
                {
                    const float* __restrict x = cell_depth.data();
                    const float* __restrict t_entry = tau.data();
                    const float* __restrict t_exit = tau_next.data();
                    float* __restrict removed = cell_sum.data();
#pragma omp simd
                    for (int g = 0; g < G; ++g)  // x as the extinction over a unit length
                        removed[g] = tb.albedo * stepRemoved(t_entry[g], t_exit[g], x[g], 1.0f);
                }
                // Emission and light-scatter photons carry a few bins or one column: their chunk's
                // field is [slot][column][point] (photonPass turns it back), so that every column is
                // one loop over the grid points, where [point][column] made 96 loops of 1-6. The
                // further orders' photons carry every column, and keep [point][column].
                float* out = field.data() + static_cast<std::size_t>(current_slot) * G * C;
                const float* __restrict sum = cell_sum.data();
                if (!depositsByColumn(kind)) {
                    for (int g = 0; g < G; ++g) {
                        const float* __restrict w = weight.data() + static_cast<std::size_t>(g) * C;
                        float* __restrict to = out + static_cast<std::size_t>(g) * C;
                        const float sum_g = sum[g];
#pragma omp simd
                        for (int col = 0; col < C; ++col) to[col] += sum_g * w[col];
                    }
                } else {
                    for (int col = col_first; col < col_last; ++col) {
                        float* __restrict to = out + static_cast<std::size_t>(col) * G;
                        if (kind == SourceKind::Emission) {
                            const float w = weight[col];
#pragma omp simd
                            for (int g = 0; g < G; ++g) to[g] += sum[g] * w;
                        } else {
                            const float* __restrict w =
                                weight_by_column.data() + static_cast<std::size_t>(col) * G;
#pragma omp simd
                            for (int g = 0; g < G; ++g) to[g] += sum[g] * w[g];
                        }
                    }
                }
            }
            tau.swap(tau_next);
            std::copy(d_smoke, d_smoke + tb.n_tc, entry_smoke);
            std::copy(d_flame, d_flame + tb.n_tc, entry_flame);
        };
        march(ctx.medium, ray, 0.0, t1, ctx.track_step,
              [&](const glm::dvec3& p, float dt, float rho, float t) {
                  if (!(rho > 0.0f)) return true;  // no extinction, no scattering: tau stays
                  const int slot = ctx.cells.slotAt(p);
                  if (slot != current_slot) {
                      leaveCell();
                      current_slot = slot;
                  }
                  tb.split(rho, t, smoke, flame);
                  tb.advanceDepths(smoke, flame, dt, d_smoke, d_flame);
                  return tb.minDepthOfLeastExtinction(d_smoke, d_flame) < kNegligibleDepth;
              });
        leaveCell();
    }
}

}  // namespace

std::size_t photonPassBytes(std::size_t field_size, std::size_t slots) {
    return (1 + kPhotonChunks) * field_size * sizeof(float) + kPhotonChunks * slots;
}

std::vector<float> photonPass(const TransportContext& ctx, SourceKind kind, const PhotonStartSampler& sampler,
                              const std::vector<float>* previous, int photons, std::uint64_t seed,
                              PhotonPassBuffers& buffers) {
    // One shift per pass, from a stream no photon uses (photon indices are below 2^31).
    render::Pcg32 pass_rng = render::Pcg32::forSample(seed, static_cast<uint64_t>(kind), uint64_t(1) << 40);
    PhotonSequence sequence;
    sequence.shift_u = pass_rng.uniform();
    sequence.shift_v = pass_rng.uniform();
    buffers.chunks.resize(kPhotonChunks);
    tbb::parallel_for(0, kPhotonChunks, [&](int chunk) {
        traceChunk(ctx, kind, sampler, sequence, previous, photons, seed, chunk, buffers.chunks[chunk]);
    });
    // One pass over the slots writes every slot of the result: the chunks' sum (in chunk order)
    // times the cell's inverse mass (Lbar = deposit / M), turned to [point][column] where the chunks
    // hold [column][point]; the chunks' slots are cleared for the next pass. Each slot is written
    // once, so slots run on both cores in any split (the same bytes). The result reuses the spare
    // field as it is: nothing in it survives.
    const int G = ctx.tables.points, C = ctx.tables.columns;
    const std::size_t row = static_cast<std::size_t>(G) * C;
    std::vector<float> total = std::move(buffers.spare);
    buffers.spare = {};
    if (total.size() != ctx.field_size) total.assign(ctx.field_size, 0.0f);
    const bool by_column = depositsByColumn(kind);
    tbb::parallel_for(tbb::blocked_range<int>(0, ctx.cells.slots, 64),
                      [&](const tbb::blocked_range<int>& slots) {
                          std::vector<float> inv_mass(static_cast<std::size_t>(G));
                          for (int slot = slots.begin(); slot != slots.end(); ++slot) {
                              float* to = total.data() + static_cast<std::size_t>(slot) * row;
                              std::fill(to, to + row, 0.0f);
                              bool any = false;
                              for (PhotonPassBuffers::Chunk& chunk : buffers.chunks) {
                                  if (!chunk.seen[slot]) continue;
                                  any = true;
                                  float* from = chunk.field.data() + static_cast<std::size_t>(slot) * row;
                                  if (by_column) {
                                      for (int g = 0; g < G; ++g)
                                          for (int col = 0; col < C; ++col)
                                              to[g * C + col] += from[col * G + g];
                                  } else {
                                      for (std::size_t j = 0; j < row; ++j) to[j] += from[j];
                                  }
                                  std::fill(from, from + row, 0.0f);
                                  chunk.seen[slot] = 0;
                              }
                              if (!any) continue;
                              ctx.cells.inverseMasses(slot, G, inv_mass.data());
                              for (int g = 0; g < G; ++g) {
                                  float* __restrict v = to + static_cast<std::size_t>(g) * C;
                                  for (int col = 0; col < C; ++col) v[col] *= inv_mass[g];
                              }
                          }
                      });
    return total;
}

}  // namespace firelook::bake
