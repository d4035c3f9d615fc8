// The fixed-step march every pass of the basis tracer uses (baker/bake/index_ray.h): its first step
// is the ray's phase times the step, and it leaves out the steps whose midpoints lie in bricks of
// zero density, which every visitor ignores (rho = 0), and no other step.
#include "bake/index_ray.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <vector>

#include "render/random.h"

namespace firelook::bake {
namespace {

// 32^3 voxels of 0.1 world units, density only in two small blocks (one brick across and a lone
// voxel), so that most of any ray's steps cross empty bricks.
render::Medium blocksMedium() {
    const glm::ivec3 dims(32);
    std::vector<float> density(32 * 32 * 32, 0.0f), temperature(density.size(), 0.5f);
    const auto at = [&](int i, int j, int k) { return static_cast<std::size_t>(i + 32 * (j + 32 * k)); };
    for (int k = 10; k < 15; ++k)
        for (int j = 9; j < 14; ++j)
            for (int i = 12; i < 16; ++i) density[at(i, j, k)] = 1.0f + 0.1f * static_cast<float>(i - j);
    density[at(25, 5, 20)] = 2.0f;
    const glm::dmat4 index_to_world = glm::scale(glm::dmat4(1.0), glm::dvec3(0.1));
    return render::Medium(glm::ivec3(0), dims, density, temperature, index_to_world, 0.5f);
}

struct Step {
    double mid;
    float dt, rho;
};

// The march without the skipping: every step, midpoints at t_start + (phase - 1/2) step + k step.
std::vector<Step> everyStep(const render::Medium& medium, const IndexRay& ray, double t0, double t1,
                            double step, double phase) {
    std::vector<Step> steps;
    double dt = std::min(phase * step, t1 - t0);
    for (double t = t0; t < t1; t += dt, dt = std::min(step, t1 - t)) {
        const double mid = t + 0.5 * dt;
        steps.push_back(
            {mid, static_cast<float>(dt), medium.sampleIndex(ray.origin + mid * ray.direction).density});
    }
    return steps;
}

TEST(IndexRayMarch, VisitsEveryStepWithDensityAtItsPhaseAndSkipsOnlyEmptyOnes) {
    const render::Medium medium = blocksMedium();
    const IndexBox box = influenceBox(medium);
    render::Pcg32 rng(7);
    std::size_t visited_total = 0, steps_total = 0, rays_with_density = 0;
    for (int r = 0; r < 400; ++r) {
        // Directions of every kind: along an axis (the case the phases are for), and random.
        glm::dvec3 direction(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
        if (r % 4 == 0) direction = glm::dvec3(0.0, 0.0, r % 8 == 0 ? 1.0 : -1.0);
        direction = glm::normalize(direction);
        // Aimed at a point near the block, from outside the box.
        const glm::dvec3 target(12.0 + 6.0 * rng.uniform(), 9.0 + 6.0 * rng.uniform(),
                                9.0 + 7.0 * rng.uniform());
        const IndexRay ray{target - 60.0 * direction, direction};
        double t0, t1;
        if (!clipToBox(ray, box, t0, t1)) continue;
        const double step = 0.25 + 0.5 * rng.uniform();
        const double phase = 1.0 - rng.uniform();
        std::vector<Step> visited;
        march(medium, ray, t0, t1, step, phase, [&](const glm::dvec3& p, float dt, float rho, float) {
            EXPECT_NEAR(glm::length(p - ray.origin), glm::dot(p - ray.origin, ray.direction), 1e-9);
            visited.push_back({glm::dot(p - ray.origin, ray.direction), dt, rho});
            return true;
        });
        const std::vector<Step> every = everyStep(medium, ray, t0, t1, step, phase);
        ASSERT_FALSE(every.empty());
        EXPECT_NEAR(every.front().dt, std::min(phase * step, t1 - t0), 1e-6)
            << "the first step is the phase's";
        // Every step with density is visited, at the same midpoint and length (to the rounding of
        // where a skip lands), and every step left out has none.
        std::size_t v = 0;
        for (const Step& s : every) {
            const bool matched = v < visited.size() && std::abs(visited[v].mid - s.mid) < 1e-9;
            if (matched) {
                EXPECT_NEAR(visited[v].dt, s.dt, 1e-6);
                EXPECT_EQ(visited[v].rho, s.rho);
                ++v;
            } else {
                EXPECT_EQ(s.rho, 0.0f)
                    << "ray " << r << ": a step with density at t " << s.mid << " was left out";
            }
        }
        EXPECT_EQ(v, visited.size()) << "ray " << r << ": visited a step the full march does not take";
        bool any = false;
        for (const Step& s : every) any = any || s.rho > 0.0f;
        rays_with_density += any;
        visited_total += visited.size();
        steps_total += every.size();
    }
    std::printf("[measured] %zu rays with density; %zu of %zu steps visited\n", rays_with_density,
                visited_total, steps_total);
    EXPECT_GT(rays_with_density, 100u);
    // Most steps cross empty bricks: the skipping must take most of them away (the block is 5
    // voxels across in a 34-voxel box; the bricks round it up to at most 12).
    EXPECT_LT(visited_total * 2, steps_total);
}

TEST(IndexRayMarch, ARayThatMissesEveryBrickWithDensityVisitsNothing) {
    const render::Medium medium = blocksMedium();
    const IndexBox box = influenceBox(medium);
    const IndexRay ray{glm::dvec3(-5.0, 2.0, 30.0), glm::normalize(glm::dvec3(1.0, 0.1, 0.0))};
    double t0, t1;
    ASSERT_TRUE(clipToBox(ray, box, t0, t1));
    int visits = 0;
    march(medium, ray, t0, t1, 0.25, 0.5, [&](const glm::dvec3&, float, float, float) {
        ++visits;
        return true;
    });
    EXPECT_EQ(visits, 0);
}

}  // namespace
}  // namespace firelook::bake
