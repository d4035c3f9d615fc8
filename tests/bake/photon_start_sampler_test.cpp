// Where photons start (baker/bake/photon_start_sampler.h): stratified draws give every cube its share
// of photons to within one, which is what takes the Poisson noise out of each cell's photon count
// (baker/bake/photon_pass.cpp).
#include "bake/photon_start_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <tuple>
#include <vector>

#include "bake_test_support.h"

namespace firelook::bake {
namespace {

// A 16^3 box of uniform density, whose fringe cubes (half a voxel outside the box, where the
// trilinear density falls to 0) weigh less, so the cdf is not flat; weights rho^2. Draw
// u = (n + 0.5) / N. Each cube must get N times its
// probability to within one photon, and the pdf the sampler reports must be that probability.
TEST(PhotonStartSampler, StratifiedDrawsGiveEveryCubeItsShare) {
    const render::Medium medium = unitBox(0.5f, 0.1f, 16);
    const PhotonStartSampler sampler(medium, [](float rho, float) { return double(rho) * rho; });
    ASSERT_FALSE(sampler.empty());
    const int photons = 200000;
    render::Pcg32 rng = render::Pcg32::forSample(1, 0, 0);
    std::map<std::tuple<int, int, int>, int> count;
    std::map<std::tuple<int, int, int>, double> probability;
    for (int n = 0; n < photons; ++n) {
        const PhotonStartSampler::Start s = sampler.sample((n + 0.5) / photons, rng);
        const glm::ivec3 q(glm::floor(s.point));
        const auto key = std::make_tuple(q.x, q.y, q.z);
        ++count[key];
        probability[key] = s.pdf;  // per unit index volume = per cube
    }
    double total_probability = 0.0;
    int worst = 0;
    for (const auto& [key, n] : count) {
        total_probability += probability[key];
        worst = std::max(worst, static_cast<int>(std::ceil(std::abs(n - photons * probability[key]))));
    }
    // Every cube with a share of a photon or more was reached: the probabilities of the cubes
    // reached sum to 1 but for the box's outermost corner cubes, whose share is below 1 / N.
    EXPECT_NEAR(total_probability, 1.0, 1e-4);
    // Independent draws would miss by sqrt(N p) ~ 7 photons in a cube of this box (~5000 cubes).
    EXPECT_LE(worst, 1);
    // The memory plan counts what the sampler keeps (its cube weights, brick list and cdf).
    EXPECT_GT(sampler.bytes(), 0u);
    EXPECT_LE(sampler.bytes(), PhotonStartSampler::bytesFor(medium));
}

// The cube centres the samplers weigh are the medium's own values there (what sampleIndex gives),
// for every cube of every brick that holds density, bricks z slowest and cubes x fastest.
TEST(CubeCentres, HoldTheMediumAtEveryCubeCentreOfItsDenseBricks) {
    // Values that differ from voxel to voxel, a few empty ones, and an origin off zero.
    const glm::ivec3 dims(9, 7, 6);
    std::vector<float> rho, t;
    for (int n = 0; n < dims.x * dims.y * dims.z; ++n) {
        rho.push_back(n % 5 == 0 ? 0.0f : 0.1f + 0.01f * static_cast<float>((n * 37) % 23));
        t.push_back(0.5f + 0.02f * static_cast<float>((n * 11) % 17));
    }
    glm::dmat4 index_to_world(0.1);
    index_to_world[3][3] = 1.0;
    const render::Medium medium(glm::ivec3(2, -3, 1), dims, rho, t, index_to_world, 0.25f);
    const CubeCentres centres(medium);
    ASSERT_FALSE(centres.bricks.empty());
    ASSERT_EQ(centres.values.size(), centres.bricks.size() * CubeCentres::kCubes);
    std::size_t dense = 0;
    const glm::ivec3 counts = medium.brickCounts();
    for (int z = 0; z < counts.z; ++z)
        for (int y = 0; y < counts.y; ++y)
            for (int x = 0; x < counts.x; ++x) dense += medium.brick({x, y, z}).max_density > 0.0f;
    EXPECT_EQ(centres.bricks.size(), dense);
    const int size = render::Medium::kBrickSize;
    for (std::size_t b = 0; b < centres.bricks.size(); ++b) {
        if (b > 0) {
            const glm::ivec3 p = centres.bricks[b - 1], q = centres.bricks[b];
            EXPECT_LT(std::make_tuple(p.z, p.y, p.x), std::make_tuple(q.z, q.y, q.x));
        }
        for (int n = 0; n < CubeCentres::kCubes; ++n) {
            const glm::ivec3 cube(n % size, (n / size) % size, n / (size * size));
            const glm::dvec3 centre = glm::dvec3(medium.origin() - 1 + centres.bricks[b] * size + cube) + 0.5;
            const render::MediumSample s = medium.sampleIndex(centre);
            const glm::vec2 v = centres.values[b * CubeCentres::kCubes + n];
            ASSERT_EQ(v.x, s.density) << "brick " << b << " cube " << n;
            ASSERT_EQ(v.y, s.temperature) << "brick " << b << " cube " << n;
        }
    }
}

}  // namespace
}  // namespace firelook::bake
