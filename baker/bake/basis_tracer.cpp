#include "bake/basis_tracer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/mat3x3.hpp>
#include <numbers>
#include <stdexcept>

#include "render/random.h"

namespace firelook::bake {
namespace {

constexpr float kInv4Pi = static_cast<float>(0.25 / std::numbers::pi);
// Photons of one order are split into this many chunks with their own
// accumulation buffers, summed in a fixed order: the result does not depend on
// the number of threads (same seed, same bytes).
constexpr int kPhotonChunks = 4;
// Below this transmittance at the thinnest grid point a path adds nothing visible.
constexpr float kNegligibleTransmittance = 1e-5f;
// phi(u) = exp(-(u/w)^2) < 1e-7 beyond |u| > 4 w: bins further away are skipped.
constexpr double kRbfSupport = 4.0;

// Flattened model: the per-sample arithmetic every march shares.
struct Tables {
    int n_tc = 0, n_ks = 0, n_kf = 0, points = 0, bins = 0, lights = 0, columns = 0, n_alpha = 0;
    std::vector<float> tc, ks, kf, alpha_tc, bin_centre;
    float t_lo = 0, t_hi = 0, inv_2dt = 0, inv_rbf_width = 0, rbf_reach = 0, albedo = 0;

    explicit Tables(const BasisModel& m) {
        n_tc = static_cast<int>(m.axes.temperature_threshold.size());
        n_ks = static_cast<int>(m.axes.smoke_extinction.size());
        n_kf = static_cast<int>(m.axes.flame_extinction.size());
        points = n_tc * n_ks * n_kf;
        bins = m.bins.count;
        lights = static_cast<int>(m.light_directions.size());
        columns = bins + lights;
        n_alpha = static_cast<int>(m.alpha_thresholds.size());
        for (double v : m.axes.temperature_threshold) tc.push_back(static_cast<float>(v));
        for (double v : m.axes.smoke_extinction) ks.push_back(static_cast<float>(v));
        for (double v : m.axes.flame_extinction) kf.push_back(static_cast<float>(v));
        for (double v : m.alpha_thresholds) alpha_tc.push_back(static_cast<float>(v));
        for (int i = 0; i < bins; ++i) bin_centre.push_back(static_cast<float>(m.bins.center(i)));
        t_lo = static_cast<float>(m.bins.t_lo);
        t_hi = static_cast<float>(m.bins.t_hi);
        inv_2dt = static_cast<float>(1.0 / (2.0 * m.bins.width()));
        inv_rbf_width = static_cast<float>(1.0 / (m.rbf_width * m.bins.width()));
        rbf_reach = static_cast<float>(kRbfSupport * m.rbf_width * m.bins.width());
        albedo = static_cast<float>(m.albedo);
    }

    float clampT(float t) const { return t >= t_lo ? (t <= t_hi ? t : t_hi) : t_lo; }

    // rho (1 -+ f(T - T_c)) / 2 for every sampled T_c: extinction is k_s*smoke + k_f*flame.
    void split(float rho, float t, float* smoke, float* flame) const {
        const float tcl = clampT(t);
        for (int i = 0; i < n_tc; ++i) {
            const float f = std::tanh((tcl - tc[i]) * inv_2dt);
            smoke[i] = 0.5f * rho * (1.0f - f);
            flame[i] = 0.5f * rho * (1.0f + f);
        }
    }

    // tau_g = exp(-k_s D_s(T_c) - k_f D_f(T_c)) for every grid point g, factorised
    // so that only n_tc * (n_ks + n_kf) exponentials are evaluated.
    void transmittance(const float* d_smoke, const float* d_flame, float* tau) const {
        float es[64], ef[64];
        int g = 0;
        for (int a = 0; a < n_tc; ++a) {
            for (int s = 0; s < n_ks; ++s) es[s] = std::exp(-ks[s] * d_smoke[a]);
            for (int f = 0; f < n_kf; ++f) ef[f] = std::exp(-kf[f] * d_flame[a]);
            for (int s = 0; s < n_ks; ++s)
                for (int f = 0; f < n_kf; ++f) tau[g++] = es[s] * ef[f];
        }
    }

    // One midpoint step of the smoke/flame depths: `half` gets the depths at the step's
    // midpoint (where the step's sample is weighted), `depth` the depths at its end.
    void advanceDepths(const float* smoke, const float* flame, float dt, float* depth_smoke, float* depth_flame,
                       float* half_smoke, float* half_flame) const {
        for (int a = 0; a < n_tc; ++a) {
            half_smoke[a] = depth_smoke[a] + 0.5f * smoke[a] * dt;
            half_flame[a] = depth_flame[a] + 0.5f * flame[a] * dt;
            depth_smoke[a] += smoke[a] * dt;
            depth_flame[a] += flame[a] * dt;
        }
    }

    // Largest transmittance over the grid (smallest k_s and k_f, every T_c).
    float maxTransmittance(const float* d_smoke, const float* d_flame) const {
        float best = 0.0f;
        for (int a = 0; a < n_tc; ++a)
            best = std::max(best, std::exp(-ks[0] * d_smoke[a] - kf[0] * d_flame[a]));
        return best;
    }

    void scattering(const float* smoke, const float* flame, float* sigma_s) const {
        int g = 0;
        for (int a = 0; a < n_tc; ++a)
            for (int s = 0; s < n_ks; ++s)
                for (int f = 0; f < n_kf; ++f) sigma_s[g++] = albedo * (ks[s] * smoke[a] + kf[f] * flame[a]);
    }

    // Bins whose RBF is non-negligible at temperature t: [first, last).
    void binWindow(float t, int& first, int& last) const {
        const float tcl = clampT(t);
        first = bins;
        last = 0;
        for (int i = 0; i < bins; ++i) {
            if (std::fabs(tcl - bin_centre[i]) <= rbf_reach) {
                first = std::min(first, i);
                last = i + 1;
            }
        }
        if (last <= first) first = last = 0;
    }

    float rbf(int i, float t) const {
        const float u = (clampT(t) - bin_centre[i]) * inv_rbf_width;
        return std::exp(-u * u);
    }
};

// A world ray expressed in the medium's index space, parameterised by world distance.
struct IndexRay {
    glm::dvec3 origin;
    glm::dvec3 direction;  // index-space displacement per world unit
};

IndexRay toIndexSpace(const render::Medium& medium, const glm::dvec3& origin, const glm::dvec3& direction) {
    const glm::dmat4& w2i = medium.worldToIndex();
    return {glm::dvec3(w2i * glm::dvec4(origin, 1.0)), glm::dmat3(w2i) * direction};
}

// The index box where interpolated values can be non-zero: [origin - 1, origin + dims].
struct IndexBox {
    glm::dvec3 lo, hi;
};

IndexBox influenceBox(const render::Medium& medium) {
    return {glm::dvec3(medium.origin()) - 1.0, glm::dvec3(medium.origin() + medium.dims())};
}

bool clipToBox(const IndexRay& ray, const IndexBox& box, double& t0, double& t1) {
    return render::intersectBox(ray.origin, ray.direction, box.lo, box.hi, t0, t1);
}

// Coarse cells over the influence box holding Lbar for every grid point and column.
// Only cells near density get storage ("slots"); elsewhere sigma_s = 0 and Lbar is never used.
struct CellGrid {
    glm::dvec3 origin;  // index point of the corner of cell (0,0,0)
    int edge = 4;
    glm::ivec3 count{0};
    std::vector<int> slot;
    int slots = 0;

    int cellIndex(const glm::ivec3& c) const { return c.x + count.x * (c.y + count.y * c.z); }

    int slotAt(const glm::dvec3& index_point) const {
        const glm::dvec3 u = (index_point - origin) / static_cast<double>(edge);
        const glm::ivec3 c(glm::floor(u));
        if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= count.x || c.y >= count.y || c.z >= count.z) return -1;
        return slot[cellIndex(c)];
    }

    // Trilinear interpolation between cell centres, clamped at the grid's faces.
    int corners(const glm::dvec3& index_point, int* slots_out, float* weights_out) const {
        const glm::dvec3 u = (index_point - origin) / static_cast<double>(edge) - 0.5;
        const glm::dvec3 base = glm::floor(u);
        const glm::dvec3 f = u - base;
        int n = 0;
        for (int c = 0; c < 8; ++c) {
            glm::ivec3 cell(base);
            cell.x += c & 1;
            cell.y += (c >> 1) & 1;
            cell.z += (c >> 2) & 1;
            cell = glm::clamp(cell, glm::ivec3(0), count - 1);
            const float w =
                static_cast<float>(((c & 1) ? f.x : 1.0 - f.x) * (((c >> 1) & 1) ? f.y : 1.0 - f.y) *
                                   (((c >> 2) & 1) ? f.z : 1.0 - f.z));
            const int s = slot[cellIndex(cell)];
            if (s < 0 || w <= 0.0f) continue;
            slots_out[n] = s;
            weights_out[n] = w;
            ++n;
        }
        return n;
    }
};

struct Voxel {
    glm::ivec3 index;
    float density;
    float temperature;
};

std::vector<Voxel> occupiedVoxels(const render::Medium& medium) {
    std::vector<Voxel> out;
    const glm::ivec3 o = medium.origin(), d = medium.dims();
    for (int k = 0; k < d.z; ++k)
        for (int j = 0; j < d.y; ++j)
            for (int i = 0; i < d.x; ++i) {
                const glm::ivec3 idx = o + glm::ivec3(i, j, k);
                const render::MediumSample s = medium.sampleIndex(glm::dvec3(idx));
                if (s.density > 0.0f) out.push_back({idx, s.density, s.temperature});
            }
    return out;
}

CellGrid buildCellGrid(const render::Medium& medium, const std::vector<Voxel>& voxels, int edge) {
    CellGrid grid;
    grid.edge = std::max(edge, 1);
    grid.origin = influenceBox(medium).lo;
    const glm::ivec3 points = medium.dims() + 2;
    grid.count = (points + grid.edge - 1) / grid.edge;
    grid.count = glm::max(grid.count, glm::ivec3(1));
    std::vector<char> occupied(static_cast<size_t>(grid.count.x) * grid.count.y * grid.count.z, 0);
    for (const Voxel& v : voxels) {
        // A voxel influences index points within one voxel of it; mark those cells.
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p = glm::dvec3(v.index) +
                                 glm::dvec3(c & 1 ? 1 : -1, (c >> 1) & 1 ? 1 : -1, (c >> 2) & 1 ? 1 : -1);
            const glm::ivec3 cell = glm::clamp(glm::ivec3(glm::floor((p - grid.origin) / double(grid.edge))),
                                               glm::ivec3(0), grid.count - 1);
            occupied[grid.cellIndex(cell)] = 1;
        }
    }
    // Dilate by one cell so interpolation next to the density reads stored values.
    grid.slot.assign(occupied.size(), -1);
    for (int z = 0; z < grid.count.z; ++z)
        for (int y = 0; y < grid.count.y; ++y)
            for (int x = 0; x < grid.count.x; ++x) {
                bool near = false;
                for (int dz = -1; dz <= 1 && !near; ++dz)
                    for (int dy = -1; dy <= 1 && !near; ++dy)
                        for (int dx = -1; dx <= 1 && !near; ++dx) {
                            const glm::ivec3 c(x + dx, y + dy, z + dz);
                            if (glm::any(glm::lessThan(c, glm::ivec3(0))) ||
                                glm::any(glm::greaterThanEqual(c, grid.count)))
                                continue;
                            near = occupied[grid.cellIndex(c)] != 0;
                        }
                if (near) grid.slot[grid.cellIndex({x, y, z})] = grid.slots++;
            }
    return grid;
}

// Photon start points: a voxel drawn from a discrete distribution, then an offset from the
// trilinear hat around it (u1 - u2 per axis, in (-1, 1)). The start density is then the
// trilinear interpolation of the voxel probabilities, so it covers exactly the region where
// interpolated density (and so any source) can be non-zero, the outer half-voxel shells included.
struct VoxelSampler {
    std::vector<double> cdf;  // normalised, cdf.back() == 1
    std::vector<double> probability;
    glm::ivec3 origin{0}, dims{0};
    std::vector<double> dense_probability;  // per voxel of the medium's box, 0 where unoccupied

    VoxelSampler(const std::vector<double>& weights, const std::vector<Voxel>& voxels, const render::Medium& medium)
        : VoxelSampler(weights) {
        origin = medium.origin();
        dims = medium.dims();
        dense_probability.assign(static_cast<size_t>(dims.x) * dims.y * dims.z, 0.0);
        for (size_t n = 0; n < voxels.size(); ++n) {
            const glm::ivec3 r = voxels[n].index - origin;
            dense_probability[r.x + static_cast<size_t>(dims.x) * (r.y + static_cast<size_t>(dims.y) * r.z)] =
                probability[n];
        }
    }

    glm::dvec3 startPoint(size_t voxel_index, const std::vector<Voxel>& voxels, render::Pcg32& rng) const {
        glm::dvec3 offset;
        for (int a = 0; a < 3; ++a) offset[a] = rng.uniform() - rng.uniform();
        return glm::dvec3(voxels[voxel_index].index) + offset;
    }

    // Probability density of startPoint() at an index point, per unit index volume.
    double densityAt(const glm::dvec3& index_point) const {
        const glm::dvec3 relative = index_point - glm::dvec3(origin);
        const glm::dvec3 base = glm::floor(relative);
        const glm::dvec3 f = relative - base;
        double sum = 0.0;
        for (int c = 0; c < 8; ++c) {
            const glm::ivec3 v = glm::ivec3(base) + glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
            if (glm::any(glm::lessThan(v, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(v, dims))) continue;
            const double w = ((c & 1) ? f.x : 1.0 - f.x) * (((c >> 1) & 1) ? f.y : 1.0 - f.y) *
                             (((c >> 2) & 1) ? f.z : 1.0 - f.z);
            sum += w * dense_probability[v.x + static_cast<size_t>(dims.x) * (v.y + static_cast<size_t>(dims.y) * v.z)];
        }
        return sum;
    }

private:
    explicit VoxelSampler(const std::vector<double>& weights) {
        double total = 0.0;
        for (double w : weights) total += w;
        cdf.resize(weights.size());
        probability.resize(weights.size());
        double running = 0.0;
        for (size_t i = 0; i < weights.size(); ++i) {
            probability[i] = total > 0.0 ? weights[i] / total : 0.0;
            running += probability[i];
            cdf[i] = running;
        }
        if (!cdf.empty()) cdf.back() = 1.0;
    }

public:
    bool empty() const { return cdf.empty(); }
    size_t sample(double u) const {
        const auto it = std::upper_bound(cdf.begin(), cdf.end(), u);
        size_t i = static_cast<size_t>(it - cdf.begin());
        if (i >= cdf.size()) i = cdf.size() - 1;
        while (probability[i] == 0.0 && i > 0) --i;  // never land on a zero-probability voxel
        return i;
    }
};

// Optical depths toward each light (smoke and flame parts per T_c) at every index point of the
// influence box near density, so the single-scatter source needs no shadow ray per sample.
struct LightDepthField {
    glm::dvec3 origin;  // index point of element (0,0,0)
    glm::ivec3 count{0};
    int n_tc = 0;
    std::vector<float> depths;  // [light][point][2 * n_tc]: smoke then flame

    void sample(int light, const glm::dvec3& index_point, float* smoke, float* flame) const {
        const glm::dvec3 u = glm::clamp(index_point - origin, glm::dvec3(0.0), glm::dvec3(count - 1));
        const glm::ivec3 base = glm::min(glm::ivec3(glm::floor(u)), glm::max(count - 2, glm::ivec3(0)));
        const glm::dvec3 f = u - glm::dvec3(base);
        for (int a = 0; a < 2 * n_tc; ++a) (a < n_tc ? smoke[a] : flame[a - n_tc]) = 0.0f;
        for (int c = 0; c < 8; ++c) {
            glm::ivec3 p = base + glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
            p = glm::min(p, count - 1);
            const float w =
                static_cast<float>(((c & 1) ? f.x : 1.0 - f.x) * (((c >> 1) & 1) ? f.y : 1.0 - f.y) *
                                   (((c >> 2) & 1) ? f.z : 1.0 - f.z));
            if (w <= 0.0f) continue;
            const float* d =
                depths.data() + (static_cast<size_t>(light) * count.x * count.y * count.z + p.x +
                                 static_cast<size_t>(count.x) * (p.y + static_cast<size_t>(count.y) * p.z)) *
                                    2 * n_tc;
            for (int a = 0; a < n_tc; ++a) {
                smoke[a] += w * d[a];
                flame[a] += w * d[n_tc + a];
            }
        }
    }
};

// Marches the medium from an index-space point along a world direction to the box exit,
// calling visit(index_point_mid, step_length, rho, t) at each step's midpoint.
template <typename Visit>
void march(const render::Medium& medium, const IndexBox& box, const IndexRay& ray, double t_start,
           double t_end, double step, Visit&& visit) {
    for (double t = t_start; t < t_end; t += step) {
        const double dt = std::min(step, t_end - t);
        const glm::dvec3 p = ray.origin + (t + 0.5 * dt) * ray.direction;
        const render::MediumSample s = medium.sampleIndex(p);
        if (!visit(p, static_cast<float>(dt), s.density, s.temperature)) return;
    }
    (void)box;
}

LightDepthField buildLightDepths(const render::Medium& medium, const BasisModel& model, const Tables& tables,
                                 const CellGrid& cells, double step) {
    LightDepthField field;
    field.origin = influenceBox(medium).lo;
    field.count = medium.dims() + 2;
    field.n_tc = tables.n_tc;
    const size_t points = static_cast<size_t>(field.count.x) * field.count.y * field.count.z;
    field.depths.assign(points * tables.lights * 2 * tables.n_tc, 0.0f);
    const IndexBox box = influenceBox(medium);
    for (int l = 0; l < tables.lights; ++l) {
        const glm::dvec3 toward_light = -glm::normalize(model.light_directions[l]);
        tbb::parallel_for(0, field.count.z, [&](int z) {
            std::vector<float> smoke(tables.n_tc), flame(tables.n_tc);
            for (int y = 0; y < field.count.y; ++y)
                for (int x = 0; x < field.count.x; ++x) {
                    const glm::dvec3 p = field.origin + glm::dvec3(x, y, z);
                    if (cells.slotAt(p) < 0) continue;  // no density nearby: never sampled
                    const IndexRay ray = toIndexSpace(
                        medium, glm::dvec3(medium.indexToWorld() * glm::dvec4(p, 1.0)), toward_light);
                    double t0, t1;
                    float* out = field.depths.data() + (l * points + x +
                                                        static_cast<size_t>(field.count.x) *
                                                            (y + static_cast<size_t>(field.count.y) * z)) *
                                                           2 * tables.n_tc;
                    if (!clipToBox(ray, box, t0, t1)) continue;
                    std::fill(smoke.begin(), smoke.end(), 0.0f);
                    std::fill(flame.begin(), flame.end(), 0.0f);
                    march(medium, box, ray, 0.0, t1, step,
                          [&](const glm::dvec3&, float dt, float rho, float t) {
                              if (rho <= 0.0f) return true;
                              float s[64], f[64];
                              tables.split(rho, t, s, f);
                              for (int a = 0; a < tables.n_tc; ++a) {
                                  smoke[a] += s[a] * dt;
                                  flame[a] += f[a] * dt;
                              }
                              return true;
                          });
                    std::copy(smoke.begin(), smoke.end(), out);
                    std::copy(flame.begin(), flame.end(), out + tables.n_tc);
                }
        });
    }
    return field;
}

glm::dvec3 uniformDirection(render::Pcg32& rng) {
    const double z = 1.0 - 2.0 * rng.uniform();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = 2.0 * std::numbers::pi * rng.uniform();
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// Everything a photon pass needs.
struct TransportContext {
    const render::Medium& medium;
    const BasisModel& model;
    const Tables& tables;
    const CellGrid& cells;
    const LightDepthField& light_depths;
    IndexBox box;
    double step;
    size_t field_size;  // slots * points * columns
};

enum class SourceKind { Emission, LightScatter, Scattered };

// One pass of photons from one kind of source, returning the Lbar it produces.
// `previous` (for Scattered) is the Lbar of the previous order.
std::vector<float> photonPass(const TransportContext& ctx, SourceKind kind, const VoxelSampler& sampler,
                              const std::vector<Voxel>& voxels, const std::vector<float>* previous,
                              int photons, uint64_t seed) {
    const Tables& tb = ctx.tables;
    const int G = tb.points, C = tb.columns;
    std::vector<std::vector<float>> chunk_fields(kPhotonChunks);
    const double voxel_volume = std::fabs(glm::determinant(glm::dmat3(ctx.medium.indexToWorld())));
    const double cell_volume = voxel_volume * std::pow(double(ctx.cells.edge), 3);
    tbb::parallel_for(0, kPhotonChunks, [&](int chunk) {
        std::vector<float>& field = chunk_fields[chunk];
        field.assign(ctx.field_size, 0.0f);
        std::vector<float> weight(static_cast<size_t>(G) * C);
        std::vector<float> tau(G), sigma_s(G), ltau(G), cell_length(G);
        float smoke[64], flame[64], d_smoke[64], d_flame[64], half_s[64], half_f[64], lsm[64], lfl[64];
        int interp_slots[8];
        float interp_w[8];
        const int first = static_cast<int>(static_cast<int64_t>(photons) * chunk / kPhotonChunks);
        const int last = static_cast<int>(static_cast<int64_t>(photons) * (chunk + 1) / kPhotonChunks);
        for (int n = first; n < last; ++n) {
            render::Pcg32 rng =
                render::Pcg32::forSample(seed, static_cast<uint64_t>(kind), static_cast<uint64_t>(n));
            const size_t v = sampler.sample(rng.uniform());
            const glm::dvec3 start = sampler.startPoint(v, voxels, rng);
            const render::MediumSample at = ctx.medium.sampleIndex(start);
            // Track-length estimator of the cell-averaged Lbar: (Q/p) * tau * length / (N * V_cell).
            const double pdf = sampler.densityAt(start) / voxel_volume;
            if (!(pdf > 0.0)) continue;
            const float scale = static_cast<float>(1.0 / (pdf * photons * cell_volume));
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
                tb.scattering(smoke, flame, sigma_s.data());
                if (kind == SourceKind::LightScatter) {
                    for (int l = 0; l < tb.lights; ++l) {
                        ctx.light_depths.sample(l, start, lsm, lfl);
                        tb.transmittance(lsm, lfl, ltau.data());
                        for (int g = 0; g < G; ++g) {
                            const float w = sigma_s[g] * ltau[g] * kInv4Pi * scale;
                            weight[g * C + tb.bins + l] = w;
                            any = any || w > 0.0f;
                        }
                    }
                } else {
                    const int n_corner = ctx.cells.corners(start, interp_slots, interp_w);
                    for (int c = 0; c < n_corner; ++c) {
                        const float* src = previous->data() + static_cast<size_t>(interp_slots[c]) * G * C;
                        for (int g = 0; g < G; ++g) {
                            const float k = interp_w[c] * sigma_s[g] * scale;
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

            const glm::dvec3 direction = uniformDirection(rng);
            const IndexRay ray{start, glm::dmat3(ctx.medium.worldToIndex()) * direction};
            double t0, t1;
            if (!clipToBox(ray, ctx.box, t0, t1)) continue;
            std::fill(d_smoke, d_smoke + tb.n_tc, 0.0f);
            std::fill(d_flame, d_flame + tb.n_tc, 0.0f);
            // Transmittance-weighted length is summed per grid point while the track stays in
            // one cell and deposited (times the photon's weights) when it leaves: G*C work per
            // cell crossed instead of per step.
            int current_slot = -1;
            std::fill(cell_length.begin(), cell_length.end(), 0.0f);
            std::fill(tau.begin(), tau.end(), 1.0f);
            bool depth_changed = false;
            const auto deposit = [&] {
                if (current_slot < 0) return;
                float* out = field.data() + static_cast<size_t>(current_slot) * G * C;
                for (int g = 0; g < G; ++g) {
                    const float length = cell_length[g];
                    if (length == 0.0f) continue;
                    const float* w = kind == SourceKind::Emission ? weight.data() : weight.data() + g * C;
                    for (int col = col_first; col < col_last; ++col) out[g * C + col] += length * w[col];
                    cell_length[g] = 0.0f;
                }
            };
            march(ctx.medium, ctx.box, ray, 0.0, t1, ctx.step,
                  [&](const glm::dvec3& p, float dt, float rho, float t) {
                      if (rho > 0.0f) {
                          tb.split(rho, t, smoke, flame);
                          tb.advanceDepths(smoke, flame, dt, d_smoke, d_flame, half_s, half_f);
                          tb.transmittance(half_s, half_f, tau.data());
                          depth_changed = true;
                      } else if (depth_changed) {  // empty space: tau stays what it was at the last density
                          tb.transmittance(d_smoke, d_flame, tau.data());
                          depth_changed = false;
                      }
                      const int slot = ctx.cells.slotAt(p);
                      if (slot != current_slot) {
                          deposit();
                          current_slot = slot;
                      }
                      if (slot >= 0)
                          for (int g = 0; g < G; ++g) cell_length[g] += tau[g] * dt;
                      return !depth_changed ||
                             tb.maxTransmittance(d_smoke, d_flame) > kNegligibleTransmittance;
                  });
            deposit();
        }
    });
    std::vector<float> total = std::move(chunk_fields[0]);
    for (int c = 1; c < kPhotonChunks; ++c)
        for (size_t i = 0; i < total.size(); ++i) total[i] += chunk_fields[c][i];
    return total;
}

double fieldEnergy(const std::vector<float>& field) {
    double sum = 0.0;
    for (float v : field) sum += v;
    return sum;
}

}  // namespace

FrameBasis traceFrameBasis(const render::Medium& medium, const render::Camera& camera,
                           const BasisModel& model, const TraceSettings& settings,
                           const std::function<bool(double)>& progress) {
    basis::validateAxes(model.axes);
    if (model.axes.temperature_threshold.size() > 64 || model.axes.smoke_extinction.size() > 64 ||
        model.axes.flame_extinction.size() > 64 || model.alpha_thresholds.size() > 64 ||
        model.alpha_thresholds.empty())
        throw std::invalid_argument("at most 64 samples per parameter axis and 1..64 alpha thresholds");
    const auto report = [&](double f) {
        if (progress && !progress(f)) throw std::runtime_error("cancelled");
    };
    const Tables tb(model);
    const int G = tb.points, C = tb.columns;
    FrameBasis out;
    out.width = camera.width();
    out.height = camera.height();
    out.columns = G * C;
    const size_t pixels = static_cast<size_t>(out.width) * out.height;
    out.matrix.assign(pixels * out.columns, 0.0f);
    const int per_axis = std::max(settings.footprint_samples_per_axis, 1);
    out.footprint_samples = per_axis * per_axis;
    out.depth_density.assign(pixels * out.footprint_samples, 0.0f);
    out.depth_sigmoid.assign(pixels * out.footprint_samples * tb.n_alpha, 0.0f);
    if (medium.empty()) return out;

    const double step = settings.step_voxels * medium.minVoxelEdge();
    const std::vector<Voxel> voxels = occupiedVoxels(medium);
    if (voxels.empty()) return out;
    const CellGrid cells = buildCellGrid(medium, voxels, settings.cell_voxels);
    const LightDepthField light_depths = buildLightDepths(medium, model, tb, cells, step);
    report(0.05);

    // Scattering orders: Lbar_sum = sum over orders of the mean radiance each produces.
    // Tracks only feed cell averages over cell_voxels^3 voxels: a one-voxel step is accurate enough.
    const double track_step = std::max(settings.step_voxels, 1.0) * medium.minVoxelEdge();
    // Tracks run to the end of the cell grid, not just of the influence box: the outer cells
    // reach past it, and a cell's mean radiance is its track length over its whole volume.
    const IndexBox cell_box{cells.origin, cells.origin + glm::dvec3(cells.count * cells.edge)};
    const TransportContext ctx{medium,       model,
                               tb,           cells,
                               light_depths, cell_box,
                               track_step,   static_cast<size_t>(cells.slots) * G * C};
    std::vector<float> lbar_sum(ctx.field_size, 0.0f);
    if (model.albedo > 0.0) {
        // Emission photons are drawn half by density and half equally per bin, so
        // rare hot bins get as many photons as common cool ones.
        std::vector<double> bin_mass(tb.bins, 0.0);
        double density_mass = 0.0;
        for (const Voxel& v : voxels) {
            density_mass += v.density;
            for (int i = 0; i < tb.bins; ++i) bin_mass[i] += v.density * tb.rbf(i, v.temperature);
        }
        int active_bins = 0;
        for (double m : bin_mass) active_bins += m > 0.0;
        std::vector<double> emission_weight(voxels.size()), density_weight(voxels.size());
        for (size_t n = 0; n < voxels.size(); ++n) {
            double per_bin = 0.0;
            for (int i = 0; i < tb.bins; ++i)
                if (bin_mass[i] > 0.0) per_bin += tb.rbf(i, voxels[n].temperature) / bin_mass[i];
            emission_weight[n] =
                voxels[n].density * (0.5 / density_mass + 0.5 * per_bin / std::max(active_bins, 1));
            density_weight[n] = voxels[n].density;
        }
        const VoxelSampler emission_sampler(emission_weight, voxels, medium), density_sampler(density_weight, voxels, medium);

        std::vector<float> order = photonPass(ctx, SourceKind::Emission, emission_sampler, voxels, nullptr,
                                              settings.photons_primary, settings.seed);
        if (tb.lights > 0) {
            const std::vector<float> light =
                photonPass(ctx, SourceKind::LightScatter, density_sampler, voxels, nullptr,
                           settings.photons_primary, settings.seed + 1);
            for (size_t i = 0; i < order.size(); ++i) order[i] += light[i];
        }
        for (size_t i = 0; i < order.size(); ++i) lbar_sum[i] += order[i];
        double total = fieldEnergy(lbar_sum);
        out.scattering_orders = 1;
        out.last_order_fraction = 1.0;
        report(0.25);
        for (int k = 2; k <= settings.max_orders && total > 0.0; ++k) {
            order = photonPass(ctx, SourceKind::Scattered, density_sampler, voxels, &order,
                               settings.photons_per_order, settings.seed + 16 * k);
            const double added = fieldEnergy(order);
            for (size_t i = 0; i < order.size(); ++i) lbar_sum[i] += order[i];
            total += added;
            out.scattering_orders = k;
            out.last_order_fraction = total > 0.0 ? added / total : 0.0;
            report(0.25 + 0.35 * k / settings.max_orders);
            if (out.last_order_fraction < settings.order_tolerance) break;
        }
    }
    report(0.6);

    // Camera rays: exact march of the fine medium.
    const IndexBox box = influenceBox(medium);
    const int rows_per_band = 8;
    for (int band = 0; band < out.height; band += rows_per_band) {
        const int band_end = std::min(out.height, band + rows_per_band);
        tbb::parallel_for(tbb::blocked_range<int>(band, band_end), [&](const tbb::blocked_range<int>& rows) {
            std::vector<float> tau(G), sigma_s(G), ltau(G);
            std::vector<int> entry_of_slot(cells.slots, -1);
            std::vector<int> touched;
            std::vector<float> kernel;  // [entry][G]
            std::vector<double> depth_sigmoid(tb.n_alpha);
            float smoke[64], flame[64], d_smoke[64], d_flame[64], half_s[64], half_f[64], lsm[64], lfl[64];
            int corner_slots[8];
            float corner_w[8];
            for (int py = rows.begin(); py != rows.end(); ++py) {
                for (int px = 0; px < out.width; ++px) {
                    const size_t pixel = static_cast<size_t>(py) * out.width + px;
                    float* row = out.matrix.data() + pixel * out.columns;
                    touched.clear();
                    kernel.clear();
                    const float sample_weight = 1.0f / static_cast<float>(out.footprint_samples);
                    for (int sample = 0; sample < out.footprint_samples; ++sample) {
                        const render::Ray world_ray =
                            camera.generateRay(px, py, (sample % per_axis + 0.5) / per_axis,
                                               (sample / per_axis + 0.5) / per_axis);
                        const IndexRay ray = toIndexSpace(medium, world_ray.origin, world_ray.direction);
                        double t0, t1;
                        if (!clipToBox(ray, box, t0, t1)) continue;
                        std::fill(d_smoke, d_smoke + tb.n_tc, 0.0f);
                        std::fill(d_flame, d_flame + tb.n_tc, 0.0f);
                        double depth_density = 0.0;
                        std::fill(depth_sigmoid.begin(), depth_sigmoid.end(), 0.0);
                        march(medium, box, ray, t0, t1, step,
                              [&](const glm::dvec3& p, float step_length, float rho, float t) {
                                  if (rho <= 0.0f) return true;
                                  depth_density += double(rho) * step_length;
                                  const float tcl = tb.clampT(t);
                                  for (int a = 0; a < tb.n_alpha; ++a)
                                      depth_sigmoid[a] += double(rho) *
                                                          std::tanh((tcl - tb.alpha_tc[a]) * tb.inv_2dt) *
                                                          step_length;
                                  tb.split(rho, t, smoke, flame);
                                  tb.advanceDepths(smoke, flame, step_length, d_smoke, d_flame, half_s, half_f);
                                  if (tb.maxTransmittance(half_s, half_f) <= kNegligibleTransmittance)
                                      return true;
                                  tb.transmittance(half_s, half_f, tau.data());
                                  tb.scattering(smoke, flame, sigma_s.data());
                                  // The pixel is the mean of its footprint rays: each adds 1/samples of its
                                  // integral.
                                  const float dt = step_length * sample_weight;
                                  // Direct emission.
                                  int bin_first, bin_last;
                                  tb.binWindow(t, bin_first, bin_last);
                                  for (int i = bin_first; i < bin_last; ++i) {
                                      const float j = rho * tb.rbf(i, t) * dt;
                                      for (int g = 0; g < G; ++g) row[g * C + i] += tau[g] * j;
                                  }
                                  // Single scattering of each directional light.
                                  for (int l = 0; l < tb.lights; ++l) {
                                      light_depths.sample(l, p, lsm, lfl);
                                      tb.transmittance(lsm, lfl, ltau.data());
                                      for (int g = 0; g < G; ++g)
                                          row[g * C + tb.bins + l] +=
                                              tau[g] * sigma_s[g] * ltau[g] * kInv4Pi * dt;
                                  }
                                  // Scattered light: gather the weights of Lbar's cells, contract once per
                                  // pixel.
                                  if (model.albedo > 0.0) {
                                      const int n = cells.corners(p, corner_slots, corner_w);
                                      for (int c = 0; c < n; ++c) {
                                          int& entry = entry_of_slot[corner_slots[c]];
                                          if (entry < 0) {
                                              entry = static_cast<int>(touched.size());
                                              touched.push_back(corner_slots[c]);
                                              kernel.resize(kernel.size() + G, 0.0f);
                                          }
                                          float* k = kernel.data() + static_cast<size_t>(entry) * G;
                                          for (int g = 0; g < G; ++g)
                                              k[g] += corner_w[c] * tau[g] * sigma_s[g] * dt;
                                      }
                                  }
                                  return true;
                              });
                        float* density_out =
                            out.depth_density.data() + static_cast<size_t>(sample) * pixels + pixel;
                        float* sigmoid_out = out.depth_sigmoid.data() +
                                             static_cast<size_t>(sample) * tb.n_alpha * pixels + pixel;
                        *density_out = static_cast<float>(depth_density);
                        for (int a = 0; a < tb.n_alpha; ++a)
                            sigmoid_out[a * pixels] = static_cast<float>(depth_sigmoid[a]);
                    }
                    for (size_t e = 0; e < touched.size(); ++e) {
                        const float* k = kernel.data() + e * G;
                        const float* lbar = lbar_sum.data() + static_cast<size_t>(touched[e]) * G * C;
                        for (int g = 0; g < G; ++g) {
                            if (k[g] == 0.0f) continue;
                            for (int c = 0; c < C; ++c) row[g * C + c] += k[g] * lbar[g * C + c];
                        }
                        entry_of_slot[touched[e]] = -1;
                    }
                }
            }
        });
        report(0.6 + 0.4 * band_end / out.height);
    }
    return out;
}

}  // namespace firelook::bake
