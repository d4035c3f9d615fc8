#include "bake/photon_pass.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <glm/mat3x3.hpp>
#include <numbers>

#include "bake/index_ray.h"

namespace firelook::bake {
namespace {

// Photons of one pass are split into this many chunks with their own accumulation buffers, summed
// in a fixed order, so the result does not depend on the number of threads. Chunks run two at a
// time: memory holds the result and two buffers whatever the machine.
constexpr int kPhotonChunks = 4;
constexpr int kChunksAtOnce = 2;

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
    std::vector<float> weight(static_cast<std::size_t>(G) * C);
    std::vector<float> tau(G), tau_next(G), sigma_t(G), ltau(G), cell_sum(G);
    float smoke[kMaxAxisSamples], flame[kMaxAxisSamples], d_smoke[kMaxAxisSamples], d_flame[kMaxAxisSamples],
        lsm[kMaxAxisSamples], lfl[kMaxAxisSamples];
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
        std::fill(tau.begin(), tau.end(), 1.0f);
        // sigma_s * tau is summed per grid point while the track stays in one cell and deposited
        // (times the photon's weights) when it leaves: G*C work per cell crossed, not per step.
        int current_slot = -1;
        std::fill(cell_sum.begin(), cell_sum.end(), 0.0f);
        const auto deposit = [&] {
            if (current_slot < 0) return;
            if (!buffer.seen[current_slot]) {
                buffer.seen[current_slot] = 1;
                buffer.touched.push_back(current_slot);
            }
            float* out = field.data() + static_cast<std::size_t>(current_slot) * G * C;
            for (int g = 0; g < G; ++g) {
                const float sum = cell_sum[g];
                if (sum == 0.0f) continue;
                const float* __restrict w =
                    kind == SourceKind::Emission ? weight.data() : weight.data() + g * C;
                float* __restrict to = out + static_cast<std::size_t>(g) * C;
#pragma omp simd
                for (int col = col_first; col < col_last; ++col) to[col] += sum * w[col];
                cell_sum[g] = 0.0f;
            }
        };
        march(ctx.medium, ray, 0.0, t1, ctx.track_step, [&](const glm::dvec3& p, float dt, float rho, float t) {
            if (!(rho > 0.0f)) return true;  // no extinction, no scattering: tau stays
            tb.split(rho, t, smoke, flame);
            tb.advanceDepths(smoke, flame, dt, d_smoke, d_flame);
            tb.transmittance(d_smoke, d_flame, tau_next.data());
            const int slot = ctx.cells.slotAt(p);
            if (slot != current_slot) {
                deposit();
                current_slot = slot;
            }
            if (slot >= 0) {
                tb.extinction(smoke, flame, sigma_t.data());
                const float* __restrict s_t = sigma_t.data();
                const float* __restrict t_start = tau.data();
                const float* __restrict t_end = tau_next.data();
                float* __restrict sum = cell_sum.data();
#pragma omp simd
                for (int g = 0; g < G; ++g)
                    sum[g] += tb.albedo * s_t[g] * stepPathLength(t_start[g], t_end[g], s_t[g], dt);
            }
            tau.swap(tau_next);
            return tb.maxTransmittance(d_smoke, d_flame) > kNegligibleTransmittance;
        });
        deposit();
    }
}

}  // namespace

std::size_t photonPassBytes(std::size_t field_size, std::size_t slots) {
    return (1 + kChunksAtOnce) * field_size * sizeof(float) + kChunksAtOnce * slots * (sizeof(int) + 1);
}

std::vector<float> photonPass(const TransportContext& ctx, SourceKind kind, const PhotonStartSampler& sampler,
                              const std::vector<float>* previous, int photons, std::uint64_t seed,
                              PhotonPassBuffers& buffers) {
    // One shift per pass, from a stream no photon uses (photon indices are below 2^31).
    render::Pcg32 pass_rng = render::Pcg32::forSample(seed, static_cast<uint64_t>(kind), uint64_t(1) << 40);
    PhotonSequence sequence;
    sequence.shift_u = pass_rng.uniform();
    sequence.shift_v = pass_rng.uniform();
    buffers.chunks.resize(kChunksAtOnce);
    const std::size_t row = static_cast<std::size_t>(ctx.tables.points) * ctx.tables.columns;
    std::vector<float> total(ctx.field_size, 0.0f);
    for (int first = 0; first < kPhotonChunks; first += kChunksAtOnce) {
        tbb::parallel_for(0, kChunksAtOnce, [&](int b) {
            traceChunk(ctx, kind, sampler, sequence, previous, photons, seed, first + b, buffers.chunks[b]);
        });
        // Chunks add in a fixed order (0 + x is x exactly, so the total is the same as summing
        // whole buffers), and each buffer is left zero for the next pass.
        for (PhotonPassBuffers::Chunk& chunk : buffers.chunks) {
            for (int slot : chunk.touched) {
                float* from = chunk.field.data() + static_cast<std::size_t>(slot) * row;
                float* to = total.data() + static_cast<std::size_t>(slot) * row;
                for (std::size_t i = 0; i < row; ++i) {
                    to[i] += from[i];
                    from[i] = 0.0f;
                }
                chunk.seen[slot] = 0;
            }
            chunk.touched.clear();
        }
    }
    ctx.cells.normalise(total, ctx.tables.points, ctx.tables.columns);
    return total;
}

}  // namespace firelook::bake
