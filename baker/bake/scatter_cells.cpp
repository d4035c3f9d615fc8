#include "bake/scatter_cells.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <glm/mat3x3.hpp>

#include "bake/index_ray.h"

namespace firelook::bake {
namespace {
// Gauss-Legendre nodes and weights on [0, 1]: 4 points are exact for polynomials of degree 7 per
// axis, 3 points for degree 5, 2 points for degree 3.
constexpr double kGaussNode4[4] = {0.5 - 0.5 * 0.8611363115940526, 0.5 - 0.5 * 0.3399810435848563,
                                   0.5 + 0.5 * 0.3399810435848563, 0.5 + 0.5 * 0.8611363115940526};
constexpr double kGaussWeight4[4] = {0.5 * 0.3478548451374538, 0.5 * 0.6521451548625461,
                                     0.5 * 0.6521451548625461, 0.5 * 0.3478548451374538};
constexpr double kGaussNode2[2] = {0.5 - 0.5 / 1.7320508075688772, 0.5 + 0.5 / 1.7320508075688772};
constexpr double kGaussWeight2[2] = {0.5, 0.5};
constexpr double kGaussNode3[3] = {0.5 - 0.5 * 0.7745966692414834, 0.5, 0.5 + 0.5 * 0.7745966692414834};
constexpr double kGaussWeight3[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};

// A cube takes 2 Gauss points along an axis where its temperatures change by at most this many dT
// along that axis (the split's sigmoid scale: s(u) = 1 / (1 + e^u), u = (T - T_c) / dT) and lie on
// one side of each clamp. Along any axis of the cube the integrand is rho(x) s(u(x)) with rho and u
// linear, so its fourth derivative is rho s'''' du^4 + 4 rho' s''' du^3 (|s'''|, |s''''| <= 1/8),
// and the 2-point rule's error is that over 4320 per axis: with du <= 0.85 at most 8.6e-5 rho_max
// per axis, 2.6e-4 over the three, where rho falls from rho_max to 0 across the cube (and the same
// share in the sigmoid's tails, whose derivatives scale with s): a bias some thirty times below the
// photon noise a cell holds (0.5-1%). The product rule's error is the sum of each axis's rule's
// error on the lines along it (weighted by the other axes' rules), so each axis takes the rule its
// own du asks for: du along x is the largest change over the cube's four x edges (u is trilinear,
// so its slope along x is bilinear in y and z, largest at an edge). Measured against 64 points in
// every cube (tests/bake/scatter_cells_test.cpp): at most 1.3e-5 of a cell's mass on a real frame,
// whose cubes take 11.2 points on average (15.5 with 0.5 here and 1.5 below, at 1.4e-6).
constexpr float kSmoothTemperatureSpan = 0.85f;

// Where an axis's temperatures change by at most this many dT (and lie on one side of each clamp),
// 3 points along it. The 3-point rule's error per axis is the integrand's sixth derivative over
// 2016000, here rho s^(6) du^6 + 6 rho' s^(5) du^5 with |s^(5)| <= 1/4 and |s^(6)| <= 0.41: at du =
// 2.4 at most 9.8e-5 rho_max per axis, as the 2-point rule's above. On frame 12 of the bundled
// sample upsampled 4x at 128x128 the cells and the photon sources took 1.7 s against 2.1 s with
// 0.5 and 1.5.
constexpr float kVariedTemperatureSpan = 2.4f;

// Gauss-Legendre points along each axis (x, y, z) a cube takes (2, 3 or 4) by its temperatures.
glm::ivec3 cubeRule(const glm::vec2 (&corner)[8], const TraceTables& tb) {
    float lo = corner[0].y, hi = corner[0].y;
    for (int n = 1; n < 8; ++n) {
        lo = std::min(lo, corner[n].y);
        hi = std::max(hi, corner[n].y);
    }
    // The split clamps T to [t_lo, t_hi]: a cube across either end has a kink inside.
    const bool one_side = hi <= tb.t_lo || lo >= tb.t_hi || (lo >= tb.t_lo && hi <= tb.t_hi);
    if (!one_side) return glm::ivec3(4);
    glm::ivec3 rule;
    for (int axis = 0; axis < 3; ++axis) {
        const int bit = 1 << axis;  // corners are x fastest: corner n + bit is n's neighbour along axis
        float change = 0.0f;
        for (int n = 0; n < 8; ++n)
            if (!(n & bit)) change = std::max(change, std::fabs(corner[n + bit].y - corner[n].y));
        const float span = change * 2.0f * tb.inv_2dt;  // in dT
        rule[axis] = span <= kSmoothTemperatureSpan ? 2 : span <= kVariedTemperatureSpan ? 3 : 4;
    }
    return rule;
}

struct GaussRule {
    const double* node;
    const double* weight;
};
GaussRule gaussRule(int points) {
    return points == 2   ? GaussRule{kGaussNode2, kGaussWeight2}
           : points == 3 ? GaussRule{kGaussNode3, kGaussWeight3}
                         : GaussRule{kGaussNode4, kGaussWeight4};
}
}  // namespace

int ScatterCells::slotAt(const glm::dvec3& index_point) const {
    const glm::dvec3 u = (index_point - origin) / static_cast<double>(edge);
    const glm::ivec3 c(glm::floor(u));
    if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= count.x || c.y >= count.y || c.z >= count.z) return -1;
    return slot[cellIndex(c)];
}

int ScatterCells::corners(const glm::dvec3& index_point, int* slots_out, float* weights_out) const {
    const glm::dvec3 u = (index_point - origin) / static_cast<double>(edge) - 0.5;
    const glm::dvec3 base = glm::floor(u);
    const glm::dvec3 f = u - base;
    int n = 0;
    float total = 0.0f;
    for (int c = 0; c < 8; ++c) {
        glm::ivec3 cell(base);
        cell.x += c & 1;
        cell.y += (c >> 1) & 1;
        cell.z += (c >> 2) & 1;
        cell = glm::clamp(cell, glm::ivec3(0), count - 1);
        const float w = static_cast<float>(((c & 1) ? f.x : 1.0 - f.x) * (((c >> 1) & 1) ? f.y : 1.0 - f.y) *
                                           (((c >> 2) & 1) ? f.z : 1.0 - f.z));
        const int s = slot[cellIndex(cell)];
        if (s < 0 || w <= 0.0f) continue;
        slots_out[n] = s;
        weights_out[n] = w;
        total += w;
        ++n;
    }
    // A point with density lies in a cell with density, whose centre has weight >= 1/8 here.
    for (int c = 0; c < n; ++c) weights_out[c] /= total;
    return n;
}

int scatterCellEdge(const render::Medium& medium, int min_voxels, int max_per_axis) {
    const int per_axis = std::max(max_per_axis, 1);
    const int by_extent = (longestInfluenceAxis(medium) + per_axis - 1) / per_axis;
    return std::max({min_voxels, by_extent, 1});
}

glm::ivec3 scatterCellCounts(const render::Medium& medium, int edge) {
    return glm::max((influencePoints(medium) + edge - 1) / edge, glm::ivec3(1));
}

std::size_t scatterCellCount(const render::Medium& medium, int edge) {
    const glm::ivec3 count = scatterCellCounts(medium, edge);
    return static_cast<std::size_t>(count.x) * count.y * count.z;
}

std::size_t scatterSlotUpperBound(const render::Medium& medium, int edge) {
    // Bricks and cells both start at the influence box's low corner.
    const glm::ivec3 count = scatterCellCounts(medium, edge);
    std::vector<char> touched(scatterCellCount(medium, edge), 0);
    const glm::ivec3 bricks = medium.brickCounts();
    const int size = render::Medium::kBrickSize;
    std::size_t n = 0;
    for (int z = 0; z < bricks.z; ++z)
        for (int y = 0; y < bricks.y; ++y)
            for (int x = 0; x < bricks.x; ++x) {
                if (!(medium.brick({x, y, z}).max_density > 0.0f)) continue;
                const glm::ivec3 lo = glm::ivec3(x, y, z) * size / edge;
                const glm::ivec3 hi = glm::min((glm::ivec3(x, y, z) * size + size - 1) / edge, count - 1);
                for (int cz = lo.z; cz <= hi.z; ++cz)
                    for (int cy = lo.y; cy <= hi.y; ++cy)
                        for (int cx = lo.x; cx <= hi.x; ++cx) {
                            char& t = touched[cx + static_cast<std::size_t>(count.x) *
                                                       (cy + static_cast<std::size_t>(count.y) * cz)];
                            n += t == 0;
                            t = 1;
                        }
            }
    return n;
}

ScatterCells buildScatterCells(const render::Medium& medium, const TraceTables& tb, int edge,
                               const std::function<bool(double)>& progress) {
    ScatterCells cells;
    cells.edge = std::max(edge, 1);
    cells.origin = influenceBox(medium).lo;
    cells.count = scatterCellCounts(medium, cells.edge);
    const std::size_t n_cells = static_cast<std::size_t>(cells.count.x) * cells.count.y * cells.count.z;
    // Per cell, the integrals of the smoke and flame parts of the density per sampled T_c: sigma_s
    // of every grid point is a linear combination of them, so 2 n_tc sums give all G masses.
    // Each unit cube is integrated with 4 Gauss points along each axis (2 or 3 along an axis where
    // its temperature changes little: cubeRule), not at its centre alone: the parts are
    // rho (1 -+ f(T - T_c)) / 2, a product of the trilinear density and a sigmoid of the trilinear
    // temperature, and where density and temperature change together across a voxel (every flame
    // front, and the fringe where both fall to the background) the centre misjudges them and moves
    // mass between cells (64% in the worst cell of tests/bake/scatter_cells_test.cpp's front; 2 x 2
    // x 2 points: 10%). Lbar = deposit / M then came out wrong cell by cell: the scattered light of
    // sunlit smoke was 2% low on the explosion's frame 20 (tests/bake/scatter_order_report; issue
    // 27), with any cell size.
    const int parts = 2 * tb.n_tc;
    std::vector<double> part_sums(n_cells * parts, 0.0);
    // One task per layer of cells: the cubes of a layer only touch that layer's cells. A layer of a
    // large frame takes up to a few tenths of a second, so a stop is seen within that.
    std::atomic<int> layers_done{0};
    std::atomic<bool> stop{false};
    std::atomic<std::size_t> cubes{0}, smooth_cubes{0}, varied_cubes{0}, points{0};
    tbb::parallel_for(0, cells.count.z, [&](int cz) {
        if (stop.load(std::memory_order_relaxed)) return;
        float smoke[kMaxAxisSamples], flame[kMaxAxisSamples];
        std::size_t slab_cubes = 0, slab_smooth = 0, slab_varied = 0, slab_points = 0;
        forEachCubeInSlab(medium, cz * cells.edge, (cz + 1) * cells.edge,
                          [&](const glm::ivec3& q, const glm::vec2(&corner)[8], float, float) {
                              const glm::ivec3 c = (q - glm::ivec3(cells.origin)) / cells.edge;
                              if (c.x >= cells.count.x || c.y >= cells.count.y) return;
                              double* sums = part_sums.data() + cells.cellIndex(c) * parts;
                              const glm::ivec3 n = cubeRule(corner, tb);
                              ++slab_cubes;
                              slab_smooth += n == glm::ivec3(2);
                              slab_varied += std::max({n.x, n.y, n.z}) == 3;
                              slab_points += static_cast<std::size_t>(n.x) * n.y * n.z;
                              const GaussRule rx = gaussRule(n.x), ry = gaussRule(n.y), rz = gaussRule(n.z);
                              // Trilinear between the corners (as sampleIndex), z first, then y, then x.
                              for (int l = 0; l < n.z; ++l) {
                                  const float fz = static_cast<float>(rz.node[l]);
                                  glm::vec2 in_z[4];
                                  for (int e = 0; e < 4; ++e)
                                      in_z[e] = corner[e] + (corner[e + 4] - corner[e]) * fz;
                                  for (int j = 0; j < n.y; ++j) {
                                      const float fy = static_cast<float>(ry.node[j]);
                                      const glm::vec2 y0 = in_z[0] + (in_z[2] - in_z[0]) * fy;
                                      const glm::vec2 y1 = in_z[1] + (in_z[3] - in_z[1]) * fy;
                                      for (int i = 0; i < n.x; ++i) {
                                          const glm::vec2 v = y0 + (y1 - y0) * static_cast<float>(rx.node[i]);
                                          if (!(v.x > 0.0f)) continue;
                                          const double w = rx.weight[i] * ry.weight[j] * rz.weight[l];
                                          tb.split(v.x, v.y, smoke, flame);
                                          for (int a = 0; a < tb.n_tc; ++a) {
                                              sums[a] += w * smoke[a];
                                              sums[tb.n_tc + a] += w * flame[a];
                                          }
                                      }
                                  }
                              }
                          });
        cubes += slab_cubes;
        smooth_cubes += slab_smooth;
        varied_cubes += slab_varied;
        points += slab_points;
        const double done = double(++layers_done) / cells.count.z;
        if (progress && !progress(done)) stop.store(true);
    });
    if (stop.load()) return cells;
    cells.cubes = cubes.load();
    cells.smooth_cubes = smooth_cubes.load();
    cells.varied_cubes = varied_cubes.load();
    cells.gauss_points = points.load();
    cells.slot.assign(n_cells, -1);
    for (std::size_t c = 0; c < n_cells; ++c) {
        bool any = false;
        for (int a = 0; a < parts && !any; ++a) any = part_sums[c * parts + a] > 0.0;
        if (any) cells.slot[c] = cells.slots++;
    }
    // The cube's world volume is the voxel's.
    const double voxel_volume = std::fabs(glm::determinant(glm::dmat3(medium.indexToWorld())));
    cells.mass.assign(static_cast<std::size_t>(cells.slots) * tb.points, 0.0f);
    for (std::size_t c = 0; c < n_cells; ++c) {
        const int s = cells.slot[c];
        if (s < 0) continue;
        const double* sums = part_sums.data() + c * parts;
        int g = 0;
        for (int a = 0; a < tb.n_tc; ++a)
            for (int ks = 0; ks < tb.n_ks; ++ks)
                for (int kf = 0; kf < tb.n_kf; ++kf)
                    cells.mass[static_cast<std::size_t>(s) * tb.points + g++] = static_cast<float>(
                        tb.albedo * (tb.ks[ks] * sums[a] + tb.kf[kf] * sums[tb.n_tc + a]) * voxel_volume);
    }
    return cells;
}

}  // namespace firelook::bake
