#include "bake/light_depth_field.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "bake/index_ray.h"
#include "render/random.h"

namespace firelook::bake {
void LightDepthField::sample(int light, const glm::dvec3& index_point, float* smoke, float* flame) const {
    const glm::dvec3 u =
        glm::clamp((index_point - origin) / static_cast<double>(spacing), glm::dvec3(0.0), glm::dvec3(count - 1));
    const glm::ivec3 base = glm::min(glm::ivec3(glm::floor(u)), glm::max(count - 2, glm::ivec3(0)));
    const glm::dvec3 f = u - glm::dvec3(base);
    for (int a = 0; a < n_tc; ++a) smoke[a] = flame[a] = 0.0f;
    const std::size_t points = static_cast<std::size_t>(count.x) * count.y * count.z;
    for (int c = 0; c < 8; ++c) {
        const glm::ivec3 p = glm::min(base + glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1), count - 1);
        const float w = static_cast<float>(((c & 1) ? f.x : 1.0 - f.x) * (((c >> 1) & 1) ? f.y : 1.0 - f.y) *
                                           (((c >> 2) & 1) ? f.z : 1.0 - f.z));
        if (w <= 0.0f) continue;
        const float* d = depths.data() + (static_cast<std::size_t>(light) * points + p.x +
                                          static_cast<std::size_t>(count.x) * (p.y + static_cast<std::size_t>(count.y) * p.z)) *
                                             2 * n_tc;
        for (int a = 0; a < n_tc; ++a) {
            smoke[a] += w * d[a];
            flame[a] += w * d[n_tc + a];
        }
    }
}

int lightLatticeSpacing(const render::Medium& medium, int max_per_axis) {
    const int per_axis = std::max(max_per_axis, 2);
    return std::max(1, (longestInfluenceAxis(medium) + per_axis - 1) / per_axis);
}

glm::ivec3 lightLatticeCount(const render::Medium& medium, int spacing) {
    // Points at origin + spacing * i up to (and including) the first at or beyond the box's end.
    return (medium.dims() + 1 + spacing - 1) / spacing + 1;
}

namespace {

// The axis of the index space (0-2) a light's direction runs along, or -1: the default light,
// straight down, and the six-way lights, in a grid without rotation. Where the march's step also
// divides the lattice spacing (the default step is a quarter of it), the march from each lattice
// point visits the same midpoints as the one from its neighbour toward the light, plus those between
// the two, so one sweep per column of lattice points gives every point's depths: frame 12 of the
// bundled sample at 128x128 with the six-way lights and the key light took 0.87 s for its light
// depths against 4.0 s.
int sweepAxis(const glm::dvec3& index_direction) {
    for (int a = 0; a < 3; ++a)
        if (index_direction[a] != 0.0 && index_direction[(a + 1) % 3] == 0.0 && index_direction[(a + 2) % 3] == 0.0)
            return a;
    return -1;
}

// A lattice point is read only by samples within one spacing of it, and samples only where there
// is density: points whose neighbourhood of cells has none are skipped.
bool nearDensity(const ScatterCells& cells, int spacing, const glm::dvec3& p) {
    const glm::ivec3 c(glm::floor((p - cells.origin) / static_cast<double>(cells.edge)));
    const int reach = (spacing + cells.edge - 1) / cells.edge;
    for (int dz = -reach; dz <= reach; ++dz)
        for (int dy = -reach; dy <= reach; ++dy)
            for (int dx = -reach; dx <= reach; ++dx) {
                const glm::ivec3 n = c + glm::ivec3(dx, dy, dz);
                if (glm::any(glm::lessThan(n, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(n, cells.count)))
                    continue;
                if (cells.slot[cells.cellIndex(n)] >= 0) return true;
            }
    return false;
}

// One march step's smoke and flame optical depths per T_c, added to a point's.
void addStep(const TraceTables& tb, float rho, float t, float dt, float* smoke, float* flame) {
    float s[kMaxAxisSamples], f[kMaxAxisSamples];
    tb.split(rho, t, s, f);
    tb.advanceDepths(s, f, dt, smoke, flame);
}

// Index point p's depths toward a light (toward_light: the unit world direction toward it) from a
// march to the influence box's end, stopped past a negligible transmittance; false where the ray
// leaves the box at once.
bool marchToLight(const render::Medium& medium, const TraceTables& tb, const IndexBox& box, const glm::dvec3& p,
                  const glm::dvec3& toward_light, double step, float* smoke, float* flame) {
    const IndexRay ray = toIndexSpace(medium, glm::dvec3(medium.indexToWorld() * glm::dvec4(p, 1.0)), toward_light);
    double t0, t1;
    if (!clipToBox(ray, box, t0, t1)) return false;
    std::fill(smoke, smoke + tb.n_tc, 0.0f);
    std::fill(flame, flame + tb.n_tc, 0.0f);
    march(medium, ray, 0.0, t1, step, [&](const glm::dvec3&, float dt, float rho, float t) {
        if (rho <= 0.0f) return true;
        addStep(tb, rho, t, dt, smoke, flame);
        return tb.minDepthOfLeastExtinction(smoke, flame) < kNegligibleDepth;
    });
    return true;
}

}  // namespace

LightDepthField buildLightDepths(const render::Medium& medium, const BasisModel& model, const TraceTables& tb,
                                 const ScatterCells& cells, int spacing, const std::vector<double>& step_voxels,
                                 const std::function<bool(double)>& progress) {
    LightDepthField field;
    field.origin = influenceBox(medium).lo;
    field.spacing = spacing;
    field.count = lightLatticeCount(medium, spacing);
    field.n_tc = tb.n_tc;
    const std::size_t points = static_cast<std::size_t>(field.count.x) * field.count.y * field.count.z;
    field.depths.assign(points * tb.lights * 2 * tb.n_tc, 0.0f);
    const IndexBox box = influenceBox(medium);
    // A stop is seen after each lattice layer (tenths of a second on a large frame).
    std::atomic<int> layers_done{0};
    std::atomic<bool> stop{false};
    // Each light's share of the progress, in its tasks (lattice layers or columns).
    const auto report = [&](int light, int tasks) {
        return !progress || progress((light + double(++layers_done) / tasks) / tb.lights);
    };
    const auto store = [&](int light, const glm::ivec3& q, const float* smoke, const float* flame) {
        const std::size_t point = static_cast<std::size_t>(q.x) +
                                  static_cast<std::size_t>(field.count.x) *
                                      (q.y + static_cast<std::size_t>(field.count.y) * q.z);
        float* out = field.depths.data() + (light * points + point) * 2 * tb.n_tc;
        std::copy(smoke, smoke + tb.n_tc, out);
        std::copy(flame, flame + tb.n_tc, out + tb.n_tc);
    };
    for (int l = 0; l < tb.lights && !stop.load(); ++l) {
        layers_done = 0;
        const double step = step_voxels.at(l) * medium.minVoxelEdge();
        const glm::dvec3 toward_light = -glm::normalize(model.light_directions[l]);
        const glm::dvec3 index_direction = toIndexSpace(medium, glm::dvec3(0.0), toward_light).direction;
        const int axis = sweepAxis(index_direction);
        // World length between neighbouring lattice points along that axis, and in steps.
        const double between = axis >= 0 ? spacing / std::fabs(index_direction[axis]) : 0.0;
        const double steps_between = between / step;
        if (axis >= 0 && std::fabs(steps_between - std::round(steps_between)) < 1e-9) {
            // One sweep per column of lattice points along the axis, from the end nearest the light:
            // each point's depths are its neighbour's (toward the light) plus the march between them.
            // The same midpoints as a march from every point; only the sums' order, and points past
            // a negligible transmittance (which that march stopped adding to), differ.
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            const int toward = index_direction[axis] > 0.0 ? 1 : -1;
            tbb::parallel_for(0, field.count[v], [&](int j) {
                if (stop.load(std::memory_order_relaxed)) return;
                float smoke[kMaxAxisSamples], flame[kMaxAxisSamples];
                const auto add = [&](const glm::dvec3&, float dt, float rho, float t) {
                    if (rho > 0.0f) addStep(tb, rho, t, dt, smoke, flame);
                    return true;
                };
                for (int i = 0; i < field.count[u]; ++i) {
                    std::fill(smoke, smoke + tb.n_tc, 0.0f);
                    std::fill(flame, flame + tb.n_tc, 0.0f);
                    glm::ivec3 q(0);
                    q[u] = i;
                    q[v] = j;
                    const int first = toward > 0 ? field.count[axis] - 1 : 0;
                    for (int k = first; k >= 0 && k < field.count[axis]; k -= toward) {
                        q[axis] = k;
                        const glm::dvec3 p = field.origin + glm::dvec3(q) * static_cast<double>(spacing);
                        const IndexRay ray{p, index_direction};
                        double t0, t1;
                        if (k == first) {  // the point nearest the light: a march of its own
                            if (clipToBox(ray, box, t0, t1)) march(medium, ray, 0.0, t1, step, add);
                        } else {
                            march(medium, ray, 0.0, between, step, add);
                        }
                        store(l, q, smoke, flame);
                    }
                }
                if (!report(l, field.count[v])) stop.store(true);
            });
            continue;
        }
        tbb::parallel_for(0, field.count.z, [&](int z) {
            if (stop.load(std::memory_order_relaxed)) return;
            float smoke[kMaxAxisSamples], flame[kMaxAxisSamples];
            for (int y = 0; y < field.count.y; ++y)
                for (int x = 0; x < field.count.x; ++x) {
                    const glm::dvec3 p = field.origin + glm::dvec3(x, y, z) * static_cast<double>(spacing);
                    if (nearDensity(cells, spacing, p) &&
                        marchToLight(medium, tb, box, p, toward_light, step, smoke, flame))
                        store(l, glm::ivec3(x, y, z), smoke, flame);
                }
            if (!report(l, field.count.z)) stop.store(true);
        });
    }
    return field;
}

std::vector<LightStep> chooseLightSteps(const render::Medium& medium, const BasisModel& model, const TraceTables& tb,
                                        const ScatterCells& cells, int spacing, double step_voxels,
                                        const std::vector<int>& step_scales, double error_allowance,
                                        double mean_change_allowance, const std::atomic<bool>& stop) {
    const int L = tb.lights, G = tb.points;
    const double finest_voxels = step_voxels * spacing;
    std::vector<LightStep> out(L);
    for (LightStep& light : out) light.step_voxels = finest_voxels;
    const std::size_t S = step_scales.size();
    if (S == 0 || L == 0) return out;
    const IndexBox box = influenceBox(medium);
    const glm::ivec3 count = lightLatticeCount(medium, spacing);
    const double step = finest_voxels * medium.minVoxelEdge();
    // Per layer of checked blocks, per light: each step's sum of squared differences and the finest
    // step's squared sources (diff2[l * S + s], value2[l]), and per grid point the finest step's
    // source sum and each coarser step's change of it (fine_sum[l * G + g], change[(l * S + s) * G + g]).
    struct Layer {
        std::vector<double> diff2, value2, fine_sum, change;
        std::vector<int> points;  // per light, the checked points
        Layer() = default;  // a layer the stop left unmeasured: adds nothing
        Layer(int L, std::size_t S, int G)
            : diff2(L * S), value2(L), fine_sum(static_cast<std::size_t>(L) * G), change(L * S * G), points(L) {}
        void add(const Layer& layer) {
            if (layer.value2.empty()) return;
            for (std::size_t k = 0; k < diff2.size(); ++k) diff2[k] += layer.diff2[k];
            for (std::size_t k = 0; k < value2.size(); ++k) value2[k] += layer.value2[k];
            for (std::size_t k = 0; k < fine_sum.size(); ++k) fine_sum[k] += layer.fine_sum[k];
            for (std::size_t k = 0; k < change.size(); ++k) change[k] += layer.change[k];
            for (std::size_t k = 0; k < points.size(); ++k) points[k] += layer.points[k];
        }
    };
    // One point of each stride^3 block of the lattice, at a fixed pseudo-random place in it: marches
    // of whole steps from lattice points meet the field's kinks at a phase that repeats with the
    // point's position modulo the step, so points of one parity (every 4th) see one phase only. On a
    // uniform 16^3 box lit from above, every 4th point saw 2e-7 at a step of 2 voxels that left the
    // image 7% dark (BasisTracer.ThickHighAlbedoSmokeKeepsItsEnergy).
    const int stride = kLightStepCheckStride;
    const glm::ivec3 blocks = (count + stride - 1) / stride;
    std::vector<Layer> layers(blocks.z);
    tbb::parallel_for(0, blocks.z, [&](int bz) {
        if (stop.load(std::memory_order_relaxed)) return;
        Layer& layer = layers[bz];
        layer = Layer(L, S, G);
        float smoke[kMaxAxisSamples], flame[kMaxAxisSamples];
        std::vector<float> fine(G), coarse(G);
        for (int by = 0; by < blocks.y; ++by)
            for (int bx = 0; bx < blocks.x; ++bx) {
                // "lightchk" in ASCII: the same points for any seed.
                render::Pcg32 rng = render::Pcg32::forSample(0x6c6967687463686bULL, bx + std::uint64_t(blocks.x) * by,
                                                             static_cast<std::uint64_t>(bz));
                const glm::ivec3 q = glm::ivec3(bx, by, bz) * stride +
                                     glm::ivec3(rng.nextUint32() % stride, rng.nextUint32() % stride,
                                                rng.nextUint32() % stride);
                if (glm::any(glm::greaterThanEqual(q, count))) continue;
                const glm::dvec3 p = box.lo + glm::dvec3(q) * static_cast<double>(spacing);
                // The source there is sigma_s tau_light: density times what the march gives.
                const double rho = medium.sampleIndex(p).density;
                if (!(rho > 0.0) || !nearDensity(cells, spacing, p)) continue;
                for (int l = 0; l < L; ++l) {
                    const glm::dvec3 toward_light = -glm::normalize(model.light_directions[l]);
                    if (!marchToLight(medium, tb, box, p, toward_light, step, smoke, flame)) continue;
                    ++layer.points[l];
                    tb.transmittance(smoke, flame, fine.data());
                    double* fine_sum = layer.fine_sum.data() + static_cast<std::size_t>(l) * G;
                    for (int g = 0; g < G; ++g) {
                        layer.value2[l] += rho * rho * fine[g] * fine[g];
                        fine_sum[g] += rho * fine[g];
                    }
                    for (std::size_t s = 0; s < S; ++s) {
                        marchToLight(medium, tb, box, p, toward_light, step * step_scales[s], smoke, flame);
                        tb.transmittance(smoke, flame, coarse.data());
                        double* change = layer.change.data() + (l * S + s) * G;
                        for (int g = 0; g < G; ++g) {
                            const double d = double(coarse[g]) - fine[g];
                            layer.diff2[l * S + s] += rho * rho * d * d;
                            change[g] += rho * d;
                        }
                    }
                }
            }
    });
    // The layers' sums in layer order.
    Layer total(L, S, G);
    for (const Layer& layer : layers) total.add(layer);
    for (int l = 0; l < L; ++l) {
        if (!(total.value2[l] > 0.0)) continue;  // nothing lit to measure: the finest step
        // Too few points to judge by: measured, and the finest step.
        const bool judged = total.points[l] >= kMinLightCheckPoints;
        double sum = 0.0;
        for (int g = 0; g < G; ++g) sum += std::fabs(total.fine_sum[static_cast<std::size_t>(l) * G + g]);
        for (std::size_t s = 0; s < S; ++s) {
            double moved = 0.0;
            for (int g = 0; g < G; ++g) moved += std::fabs(total.change[(l * S + s) * G + g]);
            const LightStepCandidate c{step_scales[s], std::sqrt(total.diff2[l * S + s] / total.value2[l]),
                                       sum > 0.0 ? moved / sum : 0.0};
            out[l].candidates.push_back(c);
            if (judged && c.source_error <= error_allowance && c.mean_change <= mean_change_allowance) {
                out[l].step_scale = c.step_scale;
                out[l].step_voxels = finest_voxels * c.step_scale;
                out[l].source_error = c.source_error;
            }
        }
    }
    return out;
}

}  // namespace firelook::bake
