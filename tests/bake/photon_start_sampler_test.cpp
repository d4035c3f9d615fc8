// Where photons start (baker/bake/photon_start_sampler.h): stratified draws give every cube its share
// of photons to within one, which is what takes the Poisson noise out of each cell's photon count
// (baker/bake/photon_pass.cpp).
#include "bake/photon_start_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <tuple>

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

}  // namespace
}  // namespace firelook::bake
