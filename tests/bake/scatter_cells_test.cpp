// The scattered-light cells (baker/bake/scatter_cells.h): each cell's sigma_s mass must be the
// integral of the same sigma_s the photon tracks and camera rays see, Lbar = deposit / mass.
#include "bake/scatter_cells.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <vector>

#include "bake/trace_tables.h"
#include "bake_test_support.h"
#include "reference/frame_medium.h"
#include "vdb/vdb_sequence.h"

namespace firelook::bake {
namespace {

using namespace test;

// A flame front: density and temperature rise together along x across 12 voxels, the temperature
// crossing T_c in the middle, so sigma_t = kappa(T) rho is a product of two ramps through a sigmoid.
render::Medium flameFront() {
    const glm::ivec3 dims(12, 4, 4);
    std::vector<float> density, temperature;
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) {
                density.push_back(0.05f + 0.08f * static_cast<float>(x));
                temperature.push_back(0.1f + 0.075f * static_cast<float>(x));
            }
    return render::Medium({0, 0, 0}, dims, density, temperature, glm::scale(glm::dmat4(1.0), glm::dvec3(0.1)), 0.0f);
}

// The mass of every cell against a 24^3-point midpoint quadrature of sigma_s over each of its unit
// cubes (its own error falls as 1/n^2: 0.17% at 12^3 in the worst cell, so ~0.04% here). The worst
// cell is the last cube of the front, where density and temperature both fall to the background (0)
// across one voxel and the temperature crosses T_c on the way: a sigmoid sharper than the voxel,
// which no low-order rule integrates well. Measured: the old single sample at the cube centre 64%
// there, 2 x 2 x 2 Gauss points 10%, 4 x 4 x 4 (what buildScatterCells uses) 0.56%. (The sum over
// all cells is right with any of them here: the centre sample moves mass between cells, which moves
// Lbar up in one and down in the other, and the camera weighs the cells differently.) Tolerance 1%:
// twice the measured.
TEST(ScatterCells, MassIsTheIntegralOfSigmaS) {
    const render::Medium medium = flameFront();
    // 8 bins over [0, 1]: dT = 0.125, so the sigmoid turns over about 2 voxels of the front.
    BasisModel model = basisModel(8, 0.8, {{0.5}, {2.0, 40.0}, {2.0, 40.0}});
    const TraceTables tb(model);
    const ScatterCells cells = buildScatterCells(medium, tb, 2);
    ASSERT_GT(cells.slots, 0);
    const double voxel_volume = 1e-3;
    const int n = 24;
    std::vector<double> exact(static_cast<size_t>(cells.slots) * tb.points, 0.0);
    float smoke[kMaxAxisSamples], flame[kMaxAxisSamples], sigma_t[kMaxAxisSamples * kMaxAxisSamples];
    const glm::ivec3 lo = glm::ivec3(cells.origin);
    for (int z = lo.z; z < lo.z + cells.count.z * cells.edge; ++z)
        for (int y = lo.y; y < lo.y + cells.count.y * cells.edge; ++y)
            for (int x = lo.x; x < lo.x + cells.count.x * cells.edge; ++x) {
                const int slot = cells.slotAt(glm::dvec3(x, y, z) + 0.5);
                if (slot < 0) continue;
                for (int k = 0; k < n * n * n; ++k) {
                    const glm::dvec3 p = glm::dvec3(x, y, z) +
                                         (glm::dvec3(k % n, (k / n) % n, k / (n * n)) + 0.5) / static_cast<double>(n);
                    const render::MediumSample s = medium.sampleIndex(p);
                    if (!(s.density > 0.0f)) continue;
                    tb.split(s.density, s.temperature, smoke, flame);
                    tb.extinction(smoke, flame, sigma_t);
                    for (int g = 0; g < tb.points; ++g)
                        exact[static_cast<size_t>(slot) * tb.points + g] +=
                            tb.albedo * sigma_t[g] * voxel_volume / (n * n * n);
                }
            }
    double worst = 0.0;
    for (size_t i = 0; i < exact.size(); ++i) {
        ASSERT_GT(exact[i], 0.0);
        worst = std::max(worst, std::abs(cells.mass[i] / exact[i] - 1.0));
    }
    std::printf("[measured] worst relative error of a cell's sigma_s mass: %.2e\n", worst);
    EXPECT_LT(worst, 1e-2);
}

// The masses of a region of a real frame (the bundled sample's frame 12, 24^3 voxels around its
// centre) and of the same region upsampled 3x per axis (trilinearly here: a smooth field, as
// tests/tools/upsample_frame.cpp makes with a quadratic filter), against every cube integrated with
// 4 x 4 x 4 Gauss points here. Each axis of a cube takes 2 points where its temperatures change by
// at most 0.85 dT along it, 3 up to 2.4 dT, whose errors the derivations in scatter_cells.cpp bound
// by about 3e-4 of a cube's integral; a cell's mass (many cubes, most of them inside the smoke)
// must stay within 1e-4 of it. The upsampled region must take the cheap rule for most cubes, or the
// fast path would go untested.
render::Medium sampleRegion(int factor) {
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(FIRELOOK_SAMPLE_DIR);
    const render::Medium frame = reference::mediumFromFrame(sequence.load(12));
    const int edge = 24;
    const glm::ivec3 lo = frame.origin() + frame.dims() / 2 - edge / 2;
    const glm::ivec3 dims(edge * factor);
    std::vector<float> density, temperature;
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) {
                const render::MediumSample s =
                    frame.sampleIndex(glm::dvec3(lo) + glm::dvec3(x, y, z) / static_cast<double>(factor));
                density.push_back(s.density);
                temperature.push_back(s.temperature);
            }
    return render::Medium({0, 0, 0}, dims, density, temperature,
                          glm::scale(glm::dmat4(1.0), glm::dvec3(0.1 / factor)),
                          frame.backgroundTemperature());
}

TEST(ScatterCells, SmoothCubesTakeFewerPointsAtTheSameMass) {
    BasisModel model =
        basisModel(16, 0.8, {{0.9, 1.2, 1.5, 1.8, 2.1, 2.4}, {1.0, 2.0, 4.0, 8.0}, {1.0, 2.0}});
    model.bins = {0.0, 3.0, 16};  // the sample's temperatures: dT = 0.1875
    const TraceTables tb(model);
    constexpr double kGauss[4][2] = {{0.5 - 0.5 * 0.8611363115940526, 0.5 * 0.3478548451374538},
                                     {0.5 - 0.5 * 0.3399810435848563, 0.5 * 0.6521451548625461},
                                     {0.5 + 0.5 * 0.3399810435848563, 0.5 * 0.6521451548625461},
                                     {0.5 + 0.5 * 0.8611363115940526, 0.5 * 0.3478548451374538}};
    for (int factor : {1, 3}) {
        const render::Medium medium = sampleRegion(factor);
        const int edge = 2 * factor;
        const ScatterCells cells = buildScatterCells(medium, tb, edge);
        ASSERT_GT(cells.slots, 0);
        const double voxel_volume = std::pow(0.1 / factor, 3);
        std::vector<double> exact(static_cast<size_t>(cells.slots) * tb.points, 0.0);
        float smoke[kMaxAxisSamples], flame[kMaxAxisSamples], sigma_t[kMaxAxisSamples * kMaxAxisSamples];
        const glm::ivec3 lo = glm::ivec3(cells.origin);
        for (int z = lo.z; z < lo.z + cells.count.z * edge; ++z)
            for (int y = lo.y; y < lo.y + cells.count.y * edge; ++y)
                for (int x = lo.x; x < lo.x + cells.count.x * edge; ++x) {
                    const int slot = cells.slotAt(glm::dvec3(x, y, z) + 0.5);
                    if (slot < 0) continue;
                    for (int k = 0; k < 64; ++k) {
                        const int i = k % 4, j = (k / 4) % 4, l = k / 16;
                        const render::MediumSample s = medium.sampleIndex(
                            glm::dvec3(x, y, z) + glm::dvec3(kGauss[i][0], kGauss[j][0], kGauss[l][0]));
                        if (!(s.density > 0.0f)) continue;
                        tb.split(s.density, s.temperature, smoke, flame);
                        tb.extinction(smoke, flame, sigma_t);
                        for (int g = 0; g < tb.points; ++g)
                            exact[static_cast<size_t>(slot) * tb.points + g] += kGauss[i][1] * kGauss[j][1] *
                                                                                kGauss[l][1] * tb.albedo *
                                                                                sigma_t[g] * voxel_volume;
                    }
                }
        double worst = 0.0;
        for (size_t m = 0; m < exact.size(); ++m) {
            ASSERT_GT(exact[m], 0.0);
            worst = std::max(worst, std::abs(cells.mass[m] / exact[m] - 1.0));
        }
        const double smooth_share = double(cells.smooth_cubes) / double(cells.cubes);
        const double varied_share = double(cells.varied_cubes) / double(cells.cubes);
        const double points_per_cube = double(cells.gauss_points) / double(cells.cubes);
        std::printf(
            "[measured] %dx: %zu cubes, %.1f%% with 2 x 2 x 2 points, %.1f%% with 3 along some axis; %.1f "
            "points a cube; worst relative mass change %.2e\n",
            factor, cells.cubes, 100.0 * smooth_share, 100.0 * varied_share, points_per_cube, worst);
        EXPECT_LT(worst, 1e-4);
        if (factor == 3) {
            EXPECT_GT(smooth_share, 0.5);
        } else {
            EXPECT_GT(varied_share, 0.05) << "the real frame's cubes must test the 3-point rule";
        }
    }
}

}  // namespace
}  // namespace firelook::bake
