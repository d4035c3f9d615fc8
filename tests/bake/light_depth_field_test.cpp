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
    const LightDepthField field = buildLightDepths(medium, model, tb, cells, kSpacing,
                                                   std::vector<double>(tb.lights, kStepVoxels * kSpacing));
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

// The single-scatter source rho * tau_light at every lattice point with density, per light and grid
// point, from two fields' depths: the relative Frobenius norm of their difference, the points
// weighted by density, as chooseLightSteps measures it on its sparse points.
double sourceDifference(const render::Medium& medium, const TraceTables& tb, const LightDepthField& a,
                        const LightDepthField& b, int light) {
    const std::size_t points = static_cast<std::size_t>(a.count.x) * a.count.y * a.count.z;
    std::vector<float> ta(tb.points), tbuf(tb.points);
    double diff2 = 0.0, value2 = 0.0;
    for (int z = 0; z < a.count.z; ++z)
        for (int y = 0; y < a.count.y; ++y)
            for (int x = 0; x < a.count.x; ++x) {
                const glm::dvec3 p = a.origin + glm::dvec3(x, y, z) * double(a.spacing);
                const double rho = medium.sampleIndex(p).density;
                if (!(rho > 0.0)) continue;
                const std::size_t point = x + static_cast<std::size_t>(a.count.x) * (y + static_cast<std::size_t>(a.count.y) * z);
                const float* da = a.depths.data() + (light * points + point) * 2 * tb.n_tc;
                const float* db = b.depths.data() + (light * points + point) * 2 * tb.n_tc;
                tb.transmittance(da, da + tb.n_tc, ta.data());
                tb.transmittance(db, db + tb.n_tc, tbuf.data());
                for (int g = 0; g < tb.points; ++g) {
                    diff2 += rho * rho * (double(ta[g]) - tbuf[g]) * (double(ta[g]) - tbuf[g]);
                    value2 += rho * rho * double(tbuf[g]) * tbuf[g];
                }
            }
    return std::sqrt(diff2 / value2);
}

// Each light's depths take the coarsest step whose change of the lit source, on one point of every
// 4^3 block of the lattice, is within the allowance (light_depth_field.h). Over every lattice point
// with density the step taken changes the source by at most twice the allowance, and a step the
// check refused changes it by more than the allowance: the check sees what the whole lattice does.
// A uniform box lit from above is the hard case: marches of whole steps from lattice points of one
// parity meet its faces at one phase, and a check on every 4th point (all of one parity) passed a
// step of 2 voxels that left the image 7% dark (BasisTracer.ThickHighAlbedoSmokeKeepsItsEnergy).
// Frame 12 of the bundled sample, lit obliquely, is the real case.
TEST(LightDepthField, StepIsChosenByWhatItChangesOfTheLitSource) {
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(FIRELOOK_SAMPLE_DIR);
    BasisModel model = basisModel(4, 0.8, {{0.9, 1.5, 2.1}, {2.0, 16.0}, {1.0, 4.0}});
    model.light_directions = {{0.0, 0.0, -1.0}, {0.35, 0.45, -0.82}};
    const TraceTables tb(model);
    const std::vector<int> scales = {2, 4, 8, 16};
    const double kAllowance = TraceSettings{}.step_radiance_target, kMeanAllowance = 5e-4, kStepVoxels = 0.25;
    const std::atomic<bool> stop{false};
    struct Case {
        const char* name;
        render::Medium medium;
        int spacing;
    };
    const Case cases[] = {{"uniform 32^3 box", unitBox(0.5f, 0.1f, 32), 1},
                          {"frame 12", reference::mediumFromFrame(sequence.load(12)), 2}};
    for (const Case& c : cases) {
        const ScatterCells cells = buildScatterCells(c.medium, tb, 2);
        const std::vector<LightStep> steps = chooseLightSteps(c.medium, model, tb, cells, c.spacing, kStepVoxels, scales,
                                                              kAllowance, kMeanAllowance, stop);
        ASSERT_EQ(steps.size(), 2u);
        const double finest = kStepVoxels * c.spacing;
        const LightDepthField fine = buildLightDepths(c.medium, model, tb, cells, c.spacing, {finest, finest});
        for (int l = 0; l < tb.lights; ++l) {
            const LightStep& taken = steps[l];
            ASSERT_EQ(taken.candidates.size(), scales.size()) << c.name;
            EXPECT_EQ(taken.step_voxels, finest * taken.step_scale);
            const auto whole = [&](double step_voxels) {
                std::vector<double> per_light(tb.lights, finest);
                per_light[l] = step_voxels;
                return sourceDifference(c.medium, tb, buildLightDepths(c.medium, model, tb, cells, c.spacing, per_light),
                                        fine, l);
            };
            const double taken_error = whole(taken.step_voxels);
            std::printf("[measured] %s, light %d: step %g voxel (x%d), checked %.2e, whole lattice %.2e\n", c.name, l,
                        taken.step_voxels, taken.step_scale, taken.source_error, taken_error);
            EXPECT_LE(taken.source_error, kAllowance);
            // The sparse points against every point: a few times the allowance would be a blind spot.
            EXPECT_LE(taken_error, 2.0 * kAllowance) << c.name << ", light " << l;
            // The next coarser step, refused, does change the source by more than the allowance.
            if (taken.step_scale < scales.back()) {
                const auto next = static_cast<std::size_t>(std::log2(taken.step_scale));  // scales[next]: twice it
                const LightStepCandidate& refused = taken.candidates[next];
                const double refused_error = whole(finest * refused.step_scale);
                std::printf("[measured] %s, light %d: refused x%d, checked %.2e (mean %.2e), whole lattice %.2e\n",
                            c.name, l, refused.step_scale, refused.source_error, refused.mean_change, refused_error);
                if (refused.source_error > kAllowance) {
                    EXPECT_GT(refused_error, 0.5 * kAllowance) << c.name;
                }
            }
        }
    }
}

}  // namespace
}  // namespace firelook::bake
