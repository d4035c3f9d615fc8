#include "bake/fire_light_tracer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "bake/index_ray.h"
#include "bake/trace_tables.h"

namespace firelook::bake {
namespace {

// A spherical Fibonacci set: n directions of (nearly) equal solid angle.
std::vector<glm::dvec3> fibonacciDirections(int n) {
    std::vector<glm::dvec3> d(static_cast<size_t>(n));
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / n, r = std::sqrt(std::max(0.0, 1.0 - z * z));
        d[i] = {r * std::cos(golden * i), r * std::sin(golden * i), z};
    }
    return d;
}

// A block of s^3 voxels with density.
struct Block {
    glm::ivec3 first{0}, last{0};  // stored-voxel coordinates, relative to the origin, last exclusive
    glm::dvec3 centre{0.0};        // world
    double weight = 0.0;           // clustering weight
};

// Recursive split of blocks[begin, end) into 2^levels leaves, leaf order = tree order.
void splitBlocks(std::vector<Block>& blocks, std::vector<int>& order, int begin, int end, int levels,
                 std::vector<std::pair<int, int>>& leaves) {
    if (levels == 0) {
        leaves.emplace_back(begin, end);
        return;
    }
    if (end - begin >= 2) {
        double total = 0.0;
        glm::dvec3 mean(0.0), square(0.0);
        for (int i = begin; i < end; ++i) {
            const Block& b = blocks[order[i]];
            const double w = b.weight > 0.0 ? b.weight : 1e-300;
            total += w;
            mean += w * b.centre;
            square += w * b.centre * b.centre;
        }
        mean /= total;
        const glm::dvec3 variance = square / total - mean * mean;
        const int axis = variance.x >= variance.y ? (variance.x >= variance.z ? 0 : 2) : (variance.y >= variance.z ? 1 : 2);
        std::stable_sort(order.begin() + begin, order.begin() + end,
                         [&](int a, int b) { return blocks[a].centre[axis] < blocks[b].centre[axis]; });
        // The weighted median, keeping at least one block on each side.
        double sum = 0.0;
        int mid = begin + 1;
        for (int i = begin; i < end - 1; ++i) {
            const Block& b = blocks[order[i]];
            sum += b.weight > 0.0 ? b.weight : 1e-300;
            mid = i + 1;
            if (sum >= 0.5 * total) break;
        }
        splitBlocks(blocks, order, begin, mid, levels - 1, leaves);
        splitBlocks(blocks, order, mid, end, levels - 1, leaves);
    } else {
        splitBlocks(blocks, order, begin, end, levels - 1, leaves);
        splitBlocks(blocks, order, end, end, levels - 1, leaves);
    }
}

glm::dvec3 toWorld(const render::Medium& medium, const glm::dvec3& index_point) {
    return glm::dvec3(medium.indexToWorld() * glm::dvec4(index_point, 1.0));
}

}  // namespace

basis::FireLightTable traceFireLights(const render::Medium& medium, const BasisModel& model,
                                      const FireLightSettings& settings) {
    const TraceTables tb(model);
    const float scale = static_cast<float>(1.0 - model.albedo);
    int levels = 0;
    while ((1 << levels) < std::max(settings.clusters, 1)) ++levels;
    const int clusters = 1 << levels;
    const render::WorldBox bounds = medium.worldBounds();
    basis::FireLightTable table =
        basis::emptyFireLightTable(clusters, tb.points, tb.bins, scale, 0.5 * (bounds.min + bounds.max));
    if (medium.empty()) return table;

    const glm::ivec3 dims = medium.dims();
    const int s = std::max(1, (std::max({dims.x, dims.y, dims.z}) + settings.max_blocks_per_axis - 1) /
                                  std::max(settings.max_blocks_per_axis, 1));
    const glm::ivec3 counts = (dims + s - 1) / s;
    std::vector<Block> blocks;
    for (int z = 0; z < counts.z; ++z)
        for (int y = 0; y < counts.y; ++y)
            for (int x = 0; x < counts.x; ++x) {
                Block b;
                b.first = glm::ivec3(x, y, z) * s;
                b.last = glm::min(b.first + s, dims);
                bool any = false;
                for (int k = b.first.z; k < b.last.z && !any; ++k)
                    for (int j = b.first.y; j < b.last.y && !any; ++j)
                        for (int i = b.first.x; i < b.last.x && !any; ++i)
                            any = medium.voxel({i, j, k}).density > 0.0f;
                if (!any) continue;
                b.centre = toWorld(medium, glm::dvec3(medium.origin()) + 0.5 * glm::dvec3(b.first + b.last - 1));
                blocks.push_back(b);
            }
    if (blocks.empty()) return table;

    // Escape transmittance per block and grid point: the mean over the directions of
    // exp(-scale (k_s D_smoke + k_f D_flame)), the depths marched once per direction for every T_c.
    const std::vector<glm::dvec3> directions = fibonacciDirections(std::max(settings.directions, 1));
    const IndexBox box = influenceBox(medium);
    const double step = medium.minVoxelEdge();
    std::vector<float> escape(blocks.size() * tb.points, 0.0f);
    tbb::parallel_for(size_t{0}, blocks.size(), [&](size_t n) {
        float smoke[kMaxAxisSamples], flame[kMaxAxisSamples], ds[kMaxAxisSamples], df[kMaxAxisSamples];
        std::vector<float> tau(tb.points);
        float* out = escape.data() + n * tb.points;
        for (const glm::dvec3& d : directions) {
            std::fill(smoke, smoke + tb.n_tc, 0.0f);
            std::fill(flame, flame + tb.n_tc, 0.0f);
            const IndexRay ray = toIndexSpace(medium, blocks[n].centre, d);
            double t0, t1;
            if (clipToBox(ray, box, t0, t1))
                march(medium, ray, std::max(t0, 0.0), t1, step, [&](const glm::dvec3&, float dt, float rho, float t) {
                    if (rho <= 0.0f) return true;
                    tb.split(rho, t, ds, df);
                    tb.advanceDepths(ds, df, dt * scale, smoke, flame);
                    return tb.minDepthOfLeastExtinction(smoke, flame) < kNegligibleDepth;
                });
            tb.transmittance(smoke, flame, tau.data());
            for (int g = 0; g < tb.points; ++g) out[g] += tau[g] / static_cast<float>(directions.size());
        }
    });

    // Clustering weights: the emission of a hotter-is-brighter look (bin i weighs i + 1) that escapes
    // at the middle grid point.
    const int middle = tb.points / 2;
    for (size_t n = 0; n < blocks.size(); ++n) {
        Block& b = blocks[n];
        for (int k = b.first.z; k < b.last.z; ++k)
            for (int j = b.first.y; j < b.last.y; ++j)
                for (int i = b.first.x; i < b.last.x; ++i) {
                    const render::MediumSample v = medium.voxel({i, j, k});
                    if (v.density <= 0.0f) continue;
                    int lo, hi;
                    tb.binWindow(v.temperature, lo, hi);
                    for (int bin = lo; bin < hi; ++bin) b.weight += v.density * tb.rbf(bin, v.temperature) * (bin + 1);
                }
        b.weight *= escape[n * tb.points + middle];
    }
    std::vector<int> order(blocks.size());
    std::iota(order.begin(), order.end(), 0);
    std::vector<std::pair<int, int>> leaves;
    splitBlocks(blocks, order, 0, static_cast<int>(blocks.size()), levels, leaves);

    const glm::dmat3 linear(medium.indexToWorld());
    const double voxel_volume = std::abs(glm::determinant(linear));
    std::vector<double> sums(static_cast<size_t>(tb.points) * tb.bins * basis::kFireLightMoments);
    for (int c = 0; c < clusters; ++c) {
        const auto [begin, end] = leaves[c];
        if (begin == end) {
            table.reference[c] = c > 0 ? table.reference[c - 1] : blocks[order[0]].centre;
            continue;
        }
        glm::dvec3 reference(0.0);
        for (int i = begin; i < end; ++i) reference += blocks[order[i]].centre;
        reference /= static_cast<double>(end - begin);
        table.reference[c] = reference;
        std::fill(sums.begin(), sums.end(), 0.0);
        for (int i = begin; i < end; ++i) {
            const Block& b = blocks[order[i]];
            const float* esc = escape.data() + static_cast<size_t>(order[i]) * tb.points;
            for (int k = b.first.z; k < b.last.z; ++k)
                for (int j = b.first.y; j < b.last.y; ++j)
                    for (int x = b.first.x; x < b.last.x; ++x) {
                        const render::MediumSample v = medium.voxel({x, j, k});
                        if (v.density <= 0.0f) continue;
                        const glm::dvec3 d = toWorld(medium, glm::dvec3(medium.origin() + glm::ivec3(x, j, k))) - reference;
                        const double d2 = glm::dot(d, d);
                        int lo, hi;
                        tb.binWindow(v.temperature, lo, hi);
                        for (int bin = lo; bin < hi; ++bin) {
                            const double e = v.density * tb.rbf(bin, v.temperature) * voxel_volume;
                            for (int g = 0; g < tb.points; ++g) {
                                const double p = e * esc[g];
                                double* m = sums.data() + (static_cast<size_t>(g) * tb.bins + bin) * basis::kFireLightMoments;
                                m[0] += p;
                                m[1] += p * d.x;
                                m[2] += p * d.y;
                                m[3] += p * d.z;
                                m[4] += p * d2;
                            }
                        }
                    }
        }
        std::transform(sums.begin(), sums.end(), table.at(c, 0, 0), [](double v) { return static_cast<float>(v); });
    }
    return table;
}

}  // namespace firelook::bake
