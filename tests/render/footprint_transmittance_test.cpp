// FootprintTransmittance (the exact alpha `firelook bench` judges packages against) against the
// closed form of a homogeneous box, and its independence of the thread count.
//
// Tolerances:
// - With k_s = k_f the extinction does not depend on temperature, so only the march matters: the
//   midpoint rule is exact on constant density, and on the one-voxel trilinear ramps where the
//   rays enter and leave the box it integrates a linear function, also exactly; what is left is
//   float accumulation (~1e-6). 1e-4 on alpha.
// - With k_s != k_f the sigmoid is evaluated at the 128 temperature nodes and split linearly: T =
//   0.5 lies halfway between two nodes, where linear interpolation of f misses by at most
//   max|f''| h^2 / 8 (h = 1/127 of the range, dT = 1/4 of it): < 3e-5 of a * O_a, i.e. < 1e-5 in
//   alpha here. 1e-4 on alpha.
#include "render/footprint_transmittance.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <numbers>

#include "render/camera.h"
#include "render/medium.h"
#include "render_test_support.h"

namespace firelook::render {
namespace {

// Every ray of narrowCamera (render_test_support.h) crosses a 2-unit box at the origin through its z faces.
using test::narrowCamera;

// The exact alpha of a pixel of the unit box: mean over the n x n rays of 1 - exp(-kappa * 2 / |d_z|).
double boxAlpha(const Camera& camera, int px, int py, int n, double kappa) {
    double sum = 0.0;
    for (int s = 0; s < n * n; ++s) {
        const Ray ray = camera.generateRay(px, py, (s % n + 0.5) / n, (s / n + 0.5) / n);
        sum += 1.0 - std::exp(-kappa * 2.0 / std::abs(ray.direction.z));
    }
    return sum / (n * n);
}

const TemperatureBins kFourBins{0.0, 1.0, 4};

TEST(FootprintTransmittance, HomogeneousBoxMatchesClosedForm) {
    const Medium box = Medium::homogeneousBox(glm::dvec3(2.0), glm::ivec3(8), 1.0f, 0.5f);
    const Camera camera = narrowCamera(6);
    const FootprintTransmittance exact(box, camera, kFourBins, 3);
    EXPECT_EQ(exact.raysPerPixel(), 9);
    for (const ExtinctionParams e : {ExtinctionParams{0.5, 0.7, 0.7}, ExtinctionParams{0.3, 0.2, 2.5},
                                     ExtinctionParams{0.8, 3.0, 0.1}}) {
        const double kappa = extinctionPerDensity(0.5, e, kFourBins);
        const std::vector<float> alpha = exact.alpha(e);
        ASSERT_EQ(alpha.size(), 36u);
        for (int py = 0; py < 6; ++py)
            for (int px = 0; px < 6; ++px)
                EXPECT_NEAR(alpha[py * 6 + px], boxAlpha(camera, px, py, 3, kappa), 1e-4)
                    << "pixel " << px << "," << py << " k_s " << e.smoke_extinction << " k_f " << e.flame_extinction;
    }
}

TEST(FootprintTransmittance, EmptyMediumAndMissedRaysGiveZero) {
    const Camera camera = narrowCamera(4);
    EXPECT_EQ(FootprintTransmittance(Medium(), camera, kFourBins, 2).alpha({0.5, 4.0, 4.0}), std::vector<float>(16, 0.0f));
    // Looking away from the box: no ray meets it.
    const Medium box = Medium::homogeneousBox(glm::dvec3(2.0), glm::ivec3(8), 1.0f, 0.5f);
    const Camera away = Camera::lookAt({0.0, 0.0, 10.0}, {0.0, 0.0, 20.0}, {0.0, 1.0, 0.0}, 0.1, 4, 4);
    EXPECT_EQ(FootprintTransmittance(box, away, kFourBins, 2).alpha({0.5, 4.0, 4.0}), std::vector<float>(16, 0.0f));
}

TEST(FootprintTransmittance, SameResultForAnyThreadCount) {
    const Medium box = Medium::homogeneousBox(glm::dvec3(2.0), glm::ivec3(8), 1.0f, 0.5f);
    const Camera camera = Camera::lookAt({3.0, 2.0, 6.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 0.6, 12, 12);
    const ExtinctionParams e{0.4, 1.5, 3.0};
    std::vector<float> one, many;
    tbb::task_arena(1).execute([&] { one = FootprintTransmittance(box, camera, kFourBins, 2).alpha(e); });
    many = FootprintTransmittance(box, camera, kFourBins, 2).alpha(e);
    EXPECT_EQ(one, many);
    double total = 0.0;
    for (float a : one) {
        ASSERT_TRUE(a >= 0.0f && a <= 1.0f) << a;
        total += a;
    }
    EXPECT_GT(total, 1.0) << "the box is in view";
}

}  // namespace
}  // namespace firelook::render
