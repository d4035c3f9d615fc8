#include "render/majorant_grid.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "look/look_model.h"
#include "render/medium.h"

namespace firelook::render {
namespace {

// A sparse random medium (many empty bricks) under a rotated, anisotropically scaled transform.
Medium sparseMedium() {
    const glm::ivec3 dims(30, 20, 26);
    std::mt19937 gen(11);
    std::uniform_real_distribution<float> value(0.0f, 1.0f);
    std::vector<float> density, temperature;
    for (int k = 0; k < dims.z; ++k)
        for (int j = 0; j < dims.y; ++j)
            for (int i = 0; i < dims.x; ++i) {
                const bool inside = (i - 15) * (i - 15) + (j - 10) * (j - 10) + (k - 13) * (k - 13) < 64;
                density.push_back(inside ? 2.0f * value(gen) : 0.0f);
                temperature.push_back(value(gen));
            }
    const glm::dmat4 index_to_world =
        glm::translate(glm::dmat4(1.0), glm::dvec3(-1.0, 0.5, 2.0)) *
        glm::rotate(glm::dmat4(1.0), 1.1, glm::normalize(glm::dvec3(0.3, 1.0, 0.2))) *
        glm::scale(glm::dmat4(1.0), glm::dvec3(0.1, 0.07, 0.13));
    return Medium(glm::ivec3(2, -3, 1), dims, density, temperature, index_to_world, 0.0f);
}

Ray randomRayThrough(const Medium& medium, std::mt19937& gen) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const WorldBox box = medium.worldBounds();
    const glm::dvec3 target = box.min + glm::dvec3(u(gen), u(gen), u(gen)) * (box.max - box.min);
    const glm::dvec3 d = glm::normalize(glm::dvec3(u(gen) - 0.5, u(gen) - 0.5, u(gen) - 0.5));
    return Ray{target - 10.0 * d, d};
}

double brickMajorantAt(const MajorantGrid& grid, const glm::dvec3& world) {
    const Medium& m = grid.medium();
    const glm::dvec3 index(m.worldToIndex() * glm::dvec4(world, 1.0));
    const glm::ivec3 b = glm::ivec3(glm::floor((index - m.brickGridOrigin()) / double(Medium::kBrickSize)));
    if (glm::any(glm::lessThan(b, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(b, grid.brickCounts())))
        return 0.0;
    return grid.majorant(b);
}

// The tentative collisions of the tracker along a random ray through the grid's medium, drawn at
// unit-mean exponential optical steps, at most `limit` of them.
std::vector<TentativeCollision> tentativeCollisions(
    const MajorantGrid& grid, std::mt19937& gen,
    std::size_t limit = std::numeric_limits<std::size_t>::max()) {
    std::exponential_distribution<double> exp1(1.0);
    MajorantTracker tracker(grid, randomRayThrough(grid.medium(), gen));
    std::vector<TentativeCollision> collisions;
    TentativeCollision c;
    while (collisions.size() < limit && tracker.advance(exp1(gen), c)) collisions.push_back(c);
    return collisions;
}

// k_s > k_f and a threshold inside the data: kappa varies strongly across bricks (and with T).
const TemperatureBins kEightBins{0.0, 1.0, 8};
const ExtinctionParams kVaryingExtinction{0.4, 9.0, 0.5};

TEST(MajorantGrid, BoundsExtinctionAtEveryTentativeCollision) {
    const Medium medium = sparseMedium();
    const MajorantGrid grid(medium, kVaryingExtinction, kEightBins, 0.0);
    std::mt19937 gen(3);
    int collisions = 0;
    for (int r = 0; r < 300; ++r)
        for (const TentativeCollision& c : tentativeCollisions(grid, gen)) {
            const MediumSample s = medium.sampleIndex(c.index_point);
            ASSERT_LE(s.density * extinctionPerDensity(s.temperature, kVaryingExtinction, kEightBins), c.majorant);
            ++collisions;
        }
    EXPECT_GT(collisions, 1000);  // the test exercised the tracker
}

TEST(MajorantGrid, TrackerIntegratesTheMajorantAlongTheRay) {
    // Stepping in small optical increments until the ray leaves must consume the majorant's integral
    // along the ray, computed here by brute-force quadrature in world space. General affine transform:
    // distances must come out in world units.
    const Medium medium = sparseMedium();
    const MajorantGrid grid(medium, ExtinctionParams{0.5, 3.0, 1.0}, TemperatureBins{0.0, 1.0, 8}, 0.0);
    std::mt19937 gen(5);
    constexpr double kStep = 1e-3;  // optical increment per advance()
    for (int r = 0; r < 40; ++r) {
        const Ray ray = randomRayThrough(medium, gen);
        MajorantTracker tracker(grid, ray);
        TentativeCollision c;
        long steps = 0;
        double last = 0.0;
        while (tracker.advance(kStep, c)) {
            ASSERT_GE(c.distance, last);
            last = c.distance;
            ++steps;
        }
        double integral = 0.0;
        constexpr double kDs = 1e-4;  // world units; the ray crosses ~3 units of grid
        for (double s = 0.5 * kDs; s < 20.0; s += kDs)
            integral += brickMajorantAt(grid, ray.origin + s * ray.direction) * kDs;
        // The count truncates by < 1 step; the quadrature misplaces each brick boundary by < kDs, where
        // majorants (< ~20 / world unit) jump: ~10 boundaries * 20 * 1e-4 = 0.02 at most.
        EXPECT_NEAR(steps * kStep, integral, kStep + 0.02) << "ray " << r;
    }
}

TEST(MajorantGrid, EmptyBricksAreSkippedAndTheFloorAppliesWhereDensityIs) {
    const Medium medium = sparseMedium();
    const MajorantGrid grid(medium, ExtinctionParams{0.5, 0.0, 0.0}, TemperatureBins{0.0, 1.0, 8}, 2.5);
    int empty = 0, floored = 0;
    const glm::ivec3 n = grid.brickCounts();
    for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
            for (int x = 0; x < n.x; ++x) {
                const double m = grid.majorant({x, y, z});
                if (medium.brick({x, y, z}).max_density > 0.0f) {
                    EXPECT_EQ(m, 2.5);
                    ++floored;
                } else {
                    EXPECT_EQ(m, 0.0);
                    ++empty;
                }
            }
    EXPECT_GT(empty, 0);
    EXPECT_GT(floored, 0);
    // A ray along the grid's corner edge in index z crosses only bricks (0, 0, z), which hold voxels
    // with i, j <= kBrickSize - 1 <= 7: all at least sqrt(73) > 8 from the ball of density at
    // (15, 10, 13).
    const glm::dvec3 corner(medium.indexToWorld() * glm::dvec4(glm::dvec3(medium.origin()), 1.0));
    const glm::dvec3 along = glm::normalize(glm::dvec3(medium.indexToWorld()[2]));
    MajorantTracker tracker(grid, Ray{corner - along, along});
    TentativeCollision c;
    EXPECT_FALSE(tracker.advance(1e-9, c));
}

// sparseMedium with spikes: every 37th voxel of the ball 1e4 times denser, so most bricks the ball
// touches have a majorant optical depth far above MajorantGrid::kDefaultRefineOpticalDepth and are refined.
Medium spikyMedium() {
    const Medium base = sparseMedium();
    const glm::ivec3 dims = base.dims();
    std::vector<float> density, temperature;
    int n = 0;
    for (int k = 0; k < dims.z; ++k)
        for (int j = 0; j < dims.y; ++j)
            for (int i = 0; i < dims.x; ++i, ++n) {
                const MediumSample v = base.voxel({i, j, k});
                density.push_back(v.density > 0.0f && n % 37 == 0 ? 2e4f * v.density : v.density);
                temperature.push_back(v.temperature);
            }
    return Medium(base.origin(), dims, density, temperature, base.indexToWorld(), 0.0f);
}

TEST(MajorantGrid, RefinedBricksBoundExtinctionAndInterpolateExactly) {
    const Medium medium = spikyMedium();
    const MajorantGrid grid(medium, kVaryingExtinction, kEightBins, 0.0);
    std::mt19937 gen(13);
    int collisions = 0, refined = 0;
    double largest = 0.0;
    for (int r = 0; r < 300; ++r) {
        double last = 0.0;
        for (const TentativeCollision& c : tentativeCollisions(grid, gen, 3000)) {
            ASSERT_GE(c.distance, last);
            last = c.distance;
            const double sigma =
                c.sample.density * extinctionPerDensity(c.sample.temperature, kVaryingExtinction, kEightBins);
            ASSERT_LE(sigma, c.majorant);
            // The tracker's values are the trilinear interpolant at the collision.
            const MediumSample s = medium.sampleIndex(c.index_point);
            ASSERT_NEAR(c.sample.density, s.density, 1e-4 * (1.0 + s.density));
            ASSERT_NEAR(c.sample.temperature, s.temperature, 1e-4);
            ++collisions;
            refined += c.majorant < grid.majorant(glm::ivec3(glm::floor(
                                        (c.index_point - medium.brickGridOrigin()) / double(Medium::kBrickSize)))) /
                                        1.01;
            largest = std::max(largest, c.majorant);
        }
    }
    EXPECT_GT(collisions, 10000);
    EXPECT_GT(refined, 1000) << "the test exercised the refinement";
    EXPECT_GT(largest, 1e4) << "and met the spikes";
}

TEST(MajorantGrid, RefiningEveryBrickOrNoneGivesTheExactTransmittance) {
    // Ratio tracking (no roulette) on the tracker alone: the mean of prod(1 - sigma / majorant) over
    // the tentative collisions is exp(-tau) for any valid majorant, refined or not. tau by midpoint
    // quadrature along the ray. kappa varies strongly with T here (k_s 9, k_f 0.5), so the refined
    // majorants bound kappa(T) through the temperature polynomial too.
    const Medium medium = sparseMedium();
    std::mt19937 gen(19);
    std::exponential_distribution<double> exp1(1.0);
    int refined_rays = 0;
    for (const double refine : {0.0, std::numeric_limits<double>::infinity()}) {
        const MajorantGrid grid(medium, kVaryingExtinction, kEightBins, 0.0, refine);
        for (int r = 0; r < 12; ++r) {
            const Ray ray = randomRayThrough(medium, gen);
            double tau = 0.0;
            constexpr double kDs = 2e-4;
            for (double s = 0.5 * kDs; s < 20.0; s += kDs) {
                const MediumSample m = medium.sampleWorld(ray.origin + s * ray.direction);
                tau += m.density * extinctionPerDensity(m.temperature, kVaryingExtinction, kEightBins) * kDs;
            }
            constexpr int kCount = 4000;
            double sum = 0.0, sum2 = 0.0;
            bool any_refined = false;
            for (int n = 0; n < kCount; ++n) {
                MajorantTracker tracker(grid, ray);
                TentativeCollision c;
                double weight = 1.0;
                while (tracker.advance(exp1(gen), c)) {
                    const double sigma =
                        c.sample.density * extinctionPerDensity(c.sample.temperature, kVaryingExtinction, kEightBins);
                    ASSERT_LE(sigma, c.majorant);
                    weight *= 1.0 - sigma / c.majorant;
                    any_refined = any_refined || c.majorant < 0.99 * brickMajorantAt(grid, tracker.worldPoint(c.distance));
                }
                sum += weight;
                sum2 += weight * weight;
            }
            refined_rays += any_refined;
            const double mean = sum / kCount;
            const double standard_error = std::sqrt(std::max(0.0, sum2 / kCount - mean * mean) / (kCount - 1));
            // 5 standard errors, and the quadrature's error (< 1e-4 of tau here).
            EXPECT_NEAR(mean, std::exp(-tau), 5.0 * standard_error + 1e-4 * tau * std::exp(-tau))
                << "ray " << r << " refine " << refine << " tau " << tau;
        }
    }
    EXPECT_GE(refined_rays, 4) << "refine 0 refined the rays that met density (5 of these 12 do)";
}

TEST(MajorantGrid, ReachesOpticalDepthOneInsideA1e30BoxInFewSteps) {
    // Density 1e30: optical depth 1 lies ~1.4e-15 voxel inside the face's ramp, below the rounding
    // of the distance (~4 from the ray's origin). The tracker must get there in a bounded number of
    // calls and report collisions at the face: the real optical depth (sum of sigma / majorant over
    // tentative collisions, whose mean is the optical depth) reaches 20 within a few hundred.
    const Medium box = Medium::homogeneousBox(glm::dvec3(2.0), glm::ivec3(8), 1e30f, 0.5f);
    const ExtinctionParams extinction{0.5, 2.0, 2.0};
    const TemperatureBins bins{0.0, 1.0, 4};
    const MajorantGrid grid(box, extinction, bins, 0.0);
    std::mt19937 gen(17);
    std::exponential_distribution<double> exp1(1.0);
    for (int r = 0; r < 100; ++r) {
        MajorantTracker tracker(grid, Ray{glm::dvec3(0.1, -0.2, 5.0), glm::dvec3(0.0, 0.0, -1.0)});
        TentativeCollision c;
        double depth = 0.0;
        int calls = 0;
        while (depth < 20.0) {
            ASSERT_TRUE(tracker.advance(exp1(gen), c));
            ASSERT_LT(++calls, 1000);
            const double sigma = c.sample.density * extinctionPerDensity(c.sample.temperature, extinction, bins);
            ASSERT_LE(sigma, c.majorant);
            depth += sigma / c.majorant;
        }
        // The face's ramp starts at z = 1 + 0.125 (half a voxel outside the box): distance 3.875.
        EXPECT_NEAR(c.distance, 3.875, 1e-12);
    }
}

TEST(MajorantGrid, RayMissingTheGridOrStartingInsideIt) {
    const Medium box = Medium::homogeneousBox(glm::dvec3(2.0), glm::ivec3(8), 1.0f, 0.5f);
    const MajorantGrid grid(box, ExtinctionParams{0.5, 2.0, 2.0}, TemperatureBins{0.0, 1.0, 4}, 0.0);
    TentativeCollision c;
    MajorantTracker miss(grid, Ray{glm::dvec3(0.0, 5.0, 0.0), glm::dvec3(1.0, 0.0, 0.0)});
    EXPECT_FALSE(miss.advance(1e-9, c));
    MajorantTracker away(grid, Ray{glm::dvec3(0.0, 0.0, 5.0), glm::dvec3(0.0, 0.0, 1.0)});
    EXPECT_FALSE(away.advance(1e-9, c));
    // From the centre the first collision at optical distance 1 lies 1 / sigma_bar away.
    MajorantTracker inside(grid, Ray{glm::dvec3(0.0), glm::dvec3(0.0, 0.0, 1.0)});
    ASSERT_TRUE(inside.advance(1.0, c));
    EXPECT_NEAR(c.distance, 1.0 / c.majorant, 1e-12);
    EXPECT_NEAR(c.majorant, 2.0, 2.0 * 2e-5);  // density 1 * kappa 2, inflated by the 1e-5 safety factor
}

}  // namespace
}  // namespace firelook::render
