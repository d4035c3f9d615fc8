// The lattice of optical depths toward each light (baker/bake/light_depth_field.h): where a light
// runs along an axis of the grid, one sweep per column of lattice points gives what a march from
// every point gives, up to the order of the float sums.
#include "bake/light_depth_field.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "bake/index_ray.h"
#include "bake/trace_tables.h"
#include "bake_test_support.h"
#include "reference/frame_medium.h"
#include "vdb/vdb_sequence.h"

namespace firelook::bake {
namespace {

using namespace test;

// Every lattice point in a cell with density (the points samples read), its depths toward each
// light against its own march to the influence box's end, on frame 12 of the bundled sample with
// lattice points 2 voxels apart: down the grid's z axis (the default light of a z-up scene), along
// +x and -y (six-way lights), and obliquely (marched from every point as before: the same code,
// checked for completeness). Points whose least extinct grid point is past a negligible
// transmittance are left out: a march from every point stops adding there, the sweep does not.
TEST(LightDepthField, AxisLightsSweepWhatAMarchFromEveryPointGives) {
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(FIRELOOK_SAMPLE_DIR);
    const render::Medium medium = reference::mediumFromFrame(sequence.load(12));
    BasisModel model = basisModel(16, 0.8, {{0.9, 1.5, 2.1}, {2.0, 8.0}, {1.0, 4.0}});
    model.bins = {0.0, 3.0, 16};
    model.light_directions = {{0.0, 0.0, -1.0}, {1.0, 0.0, 0.0}, {0.0, -1.0, 0.0}, {0.3, -0.5, -0.8}};
    const TraceTables tb(model);
    const ScatterCells cells = buildScatterCells(medium, tb, 2);
    constexpr int kSpacing = 2;
    constexpr double kStepVoxels = 0.25;
    const LightDepthField field = buildLightDepths(medium, model, tb, cells, kSpacing, kStepVoxels);
    const IndexBox box = influenceBox(medium);
    const double step = kStepVoxels * kSpacing * medium.minVoxelEdge();
    const std::size_t points = static_cast<std::size_t>(field.count.x) * field.count.y * field.count.z;
    for (int l = 0; l < tb.lights; ++l) {
        const glm::dvec3 toward_light = -glm::normalize(model.light_directions[l]);
        double worst = 0.0;
        int compared = 0;
        for (int z = 0; z < field.count.z; ++z)
            for (int y = 0; y < field.count.y; ++y)
                for (int x = 0; x < field.count.x; ++x) {
                    const glm::dvec3 p = field.origin + glm::dvec3(x, y, z) * double(kSpacing);
                    if (cells.slotAt(p) < 0) continue;  // the points samples read: in cells with density
                    const IndexRay ray =
                        toIndexSpace(medium, glm::dvec3(medium.indexToWorld() * glm::dvec4(p, 1.0)), toward_light);
                    float smoke[kMaxAxisSamples] = {}, flame[kMaxAxisSamples] = {};
                    float s[kMaxAxisSamples], f[kMaxAxisSamples];
                    double t0, t1;
                    if (clipToBox(ray, box, t0, t1))
                        march(medium, ray, 0.0, t1, step, [&](const glm::dvec3&, float dt, float rho, float t) {
                            if (rho <= 0.0f) return true;
                            tb.split(rho, t, s, f);
                            tb.advanceDepths(s, f, dt, smoke, flame);
                            return true;
                        });
                    if (smoke[0] + flame[0] <= 0.0f || tb.minDepthOfLeastExtinction(smoke, flame) >= kNegligibleDepth)
                        continue;
                    const std::size_t point = x + static_cast<std::size_t>(field.count.x) *
                                                      (y + static_cast<std::size_t>(field.count.y) * z);
                    const float* got = field.depths.data() + (l * points + point) * 2 * tb.n_tc;
                    for (int a = 0; a < tb.n_tc; ++a) {
                        worst = std::max(worst, std::fabs(double(got[a]) - smoke[a]) / std::max(1e-3, double(smoke[a])));
                        worst = std::max(worst,
                                         std::fabs(double(got[tb.n_tc + a]) - flame[a]) / std::max(1e-3, double(flame[a])));
                    }
                    ++compared;
                }
        std::printf("[measured] light %d: %d lattice points with light, worst relative difference %.2e\n", l, compared,
                    worst);
        EXPECT_GT(compared, 1000);
        // Float sums of up to a few hundred steps in another order (measured: at most 1.1e-6).
        EXPECT_LT(worst, 1e-4) << "light " << l;
    }
}

}  // namespace
}  // namespace firelook::bake
