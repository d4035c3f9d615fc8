#include "bake/fire_probe_tracer.h"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "bake/index_ray.h"
#include "bake/trace_tables.h"

namespace firelook::bake {
namespace {

// The emission's centroid and RMS radius, weighted by a hotter-is-brighter look (bin i weighs
// i + 1, as the fire lights cluster): where the probes' values are taken to fall off from.
void emissionCentroid(const render::Medium& medium, const TraceTables& tb, glm::dvec3& centre,
                      double& radius) {
    double total = 0.0;
    glm::dvec3 first(0.0), second(0.0);
    const glm::ivec3 dims = medium.dims();
    for (int k = 0; k < dims.z; ++k)
        for (int j = 0; j < dims.y; ++j)
            for (int i = 0; i < dims.x; ++i) {
                const render::MediumSample v = medium.voxel({i, j, k});
                if (!(v.density > 0.0f)) continue;
                int lo, hi;
                tb.binWindow(v.temperature, lo, hi);
                double w = 0.0;
                for (int bin = lo; bin < hi; ++bin) w += v.density * tb.rbf(bin, v.temperature) * (bin + 1);
                if (!(w > 0.0)) continue;
                const glm::dvec3 x(medium.indexToWorld() *
                                   glm::dvec4(glm::dvec3(medium.origin() + glm::ivec3(i, j, k)), 1.0));
                total += w;
                first += w * x;
                second += w * x * x;
            }
    const render::WorldBox box = medium.worldBounds();
    if (!(total > 0.0)) {
        centre = 0.5 * (box.min + box.max);
        radius = 0.25 * glm::length(box.max - box.min);
        return;
    }
    centre = first / total;
    const glm::dvec3 variance = glm::max(second / total - centre * centre, glm::dvec3(0.0));
    // Never below a voxel: the weighting divides by s, which must stay away from 0.
    radius = std::max(std::sqrt(variance.x + variance.y + variance.z), medium.minVoxelEdge());
}

// Factors full[probe][point][bin][K] into table.factors [point][rank] and table.sh
// [probe][rank][bin][K]: the leading eigenvectors of the Gram matrix over the grid points, as many as
// keep the dropped eigenvalues' sum within rank_error^2 of their total.
void factorOverGridPoints(const std::vector<float>& full, double rank_error, basis::FireProbeTable& table) {
    constexpr int K = basis::kFireProbeCoefficients;
    const int P = table.points, rows_per_probe = table.bins * K, probes = table.grid.probes();
    const auto value = [&](int probe, int point, int row) {  // row = bin * K + k
        return full[(static_cast<size_t>(probe) * P + point) * rows_per_probe + row];
    };
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(P, P);
    std::vector<double> column(P);
    for (int probe = 0; probe < probes; ++probe)
        for (int row = 0; row < rows_per_probe; ++row) {
            for (int p = 0; p < P; ++p) column[p] = value(probe, p, row);
            for (int p = 0; p < P; ++p)
                for (int q = 0; q <= p; ++q) gram(p, q) += column[p] * column[q];
        }
    for (int p = 0; p < P; ++p)
        for (int q = 0; q < p; ++q) gram(q, p) = gram(p, q);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);  // eigenvalues ascending
    const Eigen::VectorXd& lambda = eigen.eigenvalues();
    const double total = std::max(lambda.sum(), 0.0);
    const int max_rank = std::min(P, basis::kMaxFireProbeRank);
    int rank = 1;
    double dropped = std::max(total - std::max(lambda(P - 1), 0.0), 0.0);
    while (rank < max_rank && dropped > rank_error * rank_error * total) {
        dropped -= std::max(lambda(P - 1 - rank), 0.0);
        ++rank;
    }
    table.rank = rank;
    table.factors.assign(static_cast<size_t>(P) * rank, 0.0f);
    table.sh.assign(static_cast<size_t>(probes) * rank * rows_per_probe, 0.0f);
    if (!(total > 0.0)) return;  // nothing emits: an all-zero table
    for (int p = 0; p < P; ++p)
        for (int r = 0; r < rank; ++r)
            table.factors[static_cast<size_t>(p) * rank + r] =
                static_cast<float>(eigen.eigenvectors()(p, P - 1 - r));
    // sh = full projected on the kept eigenvectors (as stored: the float factors).
    for (int probe = 0; probe < probes; ++probe)
        for (int r = 0; r < rank; ++r)
            for (int row = 0; row < rows_per_probe; ++row) {
                double sum = 0.0;
                for (int p = 0; p < P; ++p)
                    sum += value(probe, p, row) * table.factors[static_cast<size_t>(p) * rank + r];
                table.sh[(static_cast<size_t>(probe) * rank + r) * rows_per_probe + row] =
                    static_cast<float>(sum);
            }
}

}  // namespace

basis::FireProbeTable traceFireProbes(const render::Medium& medium, const BasisModel& model,
                                      const FireProbeSettings& settings) {
    constexpr int K = basis::kFireProbeCoefficients;
    const TraceTables tb(model);
    basis::FireProbeTable table;
    table.points = tb.points;
    table.bins = tb.bins;
    table.extinction_scale = settings.absorption_only ? static_cast<float>(1.0 - model.albedo) : 1.0f;
    const int n = std::max(settings.resolution, 2);
    table.grid.counts = glm::ivec3(n);
    // The table before the factorisation: [probe][point][bin][K], in float as the sections store
    // (FireProbeSettings says what it holds).
    std::vector<float> full(static_cast<size_t>(table.grid.probes()) * tb.points * tb.bins * K, 0.0f);
    if (medium.empty()) {
        factorOverGridPoints(full, settings.rank_error, table);
        table.grid.origin = glm::dvec3(-0.5);
        table.grid.spacing = glm::dvec3(1.0 / (n - 1));
        table.grid.falloff_centre = glm::dvec3(0.0);
        table.grid.falloff_radius = settings.falloff ? 1.0 : 0.0;
        return table;
    }
    const render::WorldBox bounds = medium.worldBounds();
    const glm::dvec3 centre = 0.5 * (bounds.min + bounds.max);
    // A flat volume still gets a grid with extent: at least a tenth of its largest side per axis.
    const glm::dvec3 size =
        glm::max(bounds.max - bounds.min, glm::dvec3(0.1 * glm::length(bounds.max - bounds.min)));
    const glm::dvec3 half = 0.5 * settings.box_scale * size;
    table.grid.origin = centre - half;
    table.grid.spacing = 2.0 * half / double(n - 1);
    emissionCentroid(medium, tb, table.grid.falloff_centre, table.grid.falloff_radius);
    if (!settings.falloff) table.grid.falloff_radius = 0.0;

    const double sphere_radius = 0.5 * glm::length(bounds.max - bounds.min);
    const IndexBox box = influenceBox(medium);
    const double step = medium.minVoxelEdge() * settings.step_voxels;
    const int directions = std::max(settings.directions, 1);
    const float scale = table.extinction_scale;
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    tbb::parallel_for(0, table.grid.probes(), [&](int probe) {
        const int ix = probe % n, iy = (probe / n) % n, iz = probe / (n * n);
        const glm::dvec3 x = table.grid.position(ix, iy, iz);
        // The cone bounding the volume's bounding sphere, and a frame around its axis.
        const glm::dvec3 axis = centre - x;
        const double distance = glm::length(axis);
        const double cos_max = distance > sphere_radius
                                   ? std::sqrt(1.0 - (sphere_radius / distance) * (sphere_radius / distance))
                                   : -1.0;
        const glm::dvec3 w = distance > sphere_radius ? axis / distance : glm::dvec3(0.0, 0.0, 1.0);
        const glm::dvec3 helper = std::abs(w.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
        const glm::dvec3 u = glm::normalize(glm::cross(helper, w)), v = glm::cross(w, u);
        const double weight = 2.0 * std::numbers::pi * (1.0 - cos_max) / directions;

        const int G = tb.points;
        float smoke[kMaxAxisSamples], flame[kMaxAxisSamples], d_smoke[kMaxAxisSamples],
            d_flame[kMaxAxisSamples];
        std::vector<float> tau(G), tau_next(G), sigma_t(G), path(G),
            radiance(static_cast<size_t>(tb.bins) * G);
        std::vector<double> sum(static_cast<size_t>(G) * tb.bins * K, 0.0);
        for (int s = 0; s < directions; ++s) {
            const double z = 1.0 - (s + 0.5) / directions * (1.0 - cos_max);
            const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const glm::dvec3 d =
                glm::normalize(r * std::cos(golden * s) * u + r * std::sin(golden * s) * v + z * w);
            const IndexRay ray = toIndexSpace(medium, x, d);
            double t0, t1;
            if (!clipToBox(ray, box, t0, t1)) continue;
            std::fill(d_smoke, d_smoke + tb.n_tc, 0.0f);
            std::fill(d_flame, d_flame + tb.n_tc, 0.0f);
            std::fill(tau.begin(), tau.end(), 1.0f);
            std::fill(radiance.begin(), radiance.end(), 0.0f);
            bool any = false;
            march(medium, ray, std::max(t0, 0.0), t1, step,
                  [&](const glm::dvec3&, float dt, float rho, float t) {
                      if (!(rho > 0.0f)) return true;
                      // The extinction scaled (split is linear in the density); the emission is not.
                      tb.split(rho * scale, t, smoke, flame);
                      tb.advanceDepths(smoke, flame, dt, d_smoke, d_flame);
                      tb.transmittance(d_smoke, d_flame, tau_next.data());
                      tb.extinction(smoke, flame, sigma_t.data());
                      for (int g = 0; g < G; ++g)
                          path[g] = stepPathLength(tau[g], tau_next[g], sigma_t[g], dt);
                      int lo, hi;
                      tb.binWindow(t, lo, hi);
                      for (int i = lo; i < hi; ++i) {
                          const float j = rho * tb.rbf(i, t);
                          float* out = radiance.data() + static_cast<size_t>(i) * G;
                          for (int g = 0; g < G; ++g) out[g] += path[g] * j;
                          any = true;
                      }
                      tau.swap(tau_next);
                      return tb.maxTransmittance(tau.data()) > kNegligibleTransmittance;
                  });
            if (!any) continue;
            double y[K];
            basis::shBasis(d, y);
            for (int i = 0; i < tb.bins; ++i)
                for (int g = 0; g < G; ++g) {
                    const double l = radiance[static_cast<size_t>(i) * G + g] * weight;
                    if (l == 0.0) continue;
                    double* out = sum.data() + (static_cast<size_t>(g) * tb.bins + i) * K;
                    for (int k = 0; k < K; ++k) out[k] += l * y[k];
                }
        }
        std::transform(sum.begin(), sum.end(), full.begin() + static_cast<ptrdiff_t>(probe) * G * tb.bins * K,
                       [](double value) { return static_cast<float>(value); });
    });
    factorOverGridPoints(full, settings.rank_error, table);
    return table;
}

}  // namespace firelook::bake
