// reference_timing: renders a synthetic explosion-sized volume (80^3 voxels, sparse, hot core,
// smoke around it, one light) with the reference path tracer and prints the seconds it took.
// Usage: reference_timing [width height spp threads]   (defaults: 256 256 16 0)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <random>
#include <vector>

#include "look/look_model.h"
#include "render/camera.h"
#include "render/medium.h"
#include "render/reference_tracer.h"

namespace {

using namespace firelook;

// A lumpy ball of smoke 4 world units across (voxel 0.05) with a hot, thinner core.
render::Medium syntheticExplosion() {
    constexpr int kN = 80;
    std::mt19937 gen(1);
    std::uniform_real_distribution<double> phase(0.0, 6.28);
    const double a = phase(gen), b = phase(gen), c = phase(gen);
    std::vector<float> density, temperature;
    for (int k = 0; k < kN; ++k)
        for (int j = 0; j < kN; ++j)
            for (int i = 0; i < kN; ++i) {
                const glm::dvec3 p = (glm::dvec3(i, j, k) + 0.5) / double(kN) * 2.0 - 1.0;
                const double lumps =
                    0.15 * (std::sin(7 * p.x + a) * std::sin(6 * p.y + b) * std::sin(8 * p.z + c));
                const double r = glm::length(p) + lumps;
                density.push_back(r < 0.8 ? float(std::min(1.0, (0.8 - r) * 4.0)) : 0.0f);
                temperature.push_back(float(std::max(0.0, 2.0 * (1.0 - r / 0.6))));
            }
    glm::dmat4 index_to_world(1.0);
    for (int axis = 0; axis < 3; ++axis) index_to_world[axis][axis] = 0.05;
    index_to_world[3] = glm::dvec4(-2.0, -2.0, -2.0, 1.0);
    return render::Medium(glm::ivec3(0), glm::ivec3(kN), density, temperature, index_to_world, 0.0f);
}

// docs/model.md's example look: T_c 1.4, k_s 6, k_f 1.5, albedo 0.8, emission rising with T.
LookModel exampleLook() {
    LookModel look;
    look.bins = TemperatureBins{0.0, 2.0, 16};
    look.extinction = ExtinctionParams{1.4, 6.0, 1.5};
    look.albedo = 0.8;
    look.emission.basis.bins = look.bins;
    for (int i = 0; i < look.bins.count; ++i) {
        const float t = static_cast<float>(look.bins.center(i));
        look.emission.coefficients.push_back(t < 1.0f ? Rgb(4.0f, 1.0f, 0.2f) * t
                                                      : Rgb(4.0f, 1.0f, 0.2f) +
                                                            (t - 1.0f) * Rgb(8.0f, 5.0f, 1.8f));
    }
    look.lights.push_back(
        DirectionalLight{glm::normalize(glm::dvec3(0.3, -1.0, -0.4)), Rgb(1.0f, 0.95f, 0.9f)});
    return look;
}

}  // namespace

int main(int argc, char** argv) {
    const int width = argc > 1 ? std::atoi(argv[1]) : 256;
    const int height = argc > 2 ? std::atoi(argv[2]) : 256;
    render::ReferenceSettings settings;
    settings.samples_per_pixel = argc > 3 ? std::atoi(argv[3]) : 16;
    settings.threads = argc > 4 ? std::atoi(argv[4]) : 0;
    const render::Medium medium = syntheticExplosion();
    const render::WorldBox bounds = medium.worldBounds();
    const render::Camera camera =
        render::defaultCamera(bounds.min, bounds.max, render::UpAxis::Y, width, height);
    const render::ReferenceResult r = render::renderReference(medium, exampleLook(), camera, settings);
    double alpha = 0.0;
    for (std::size_t p = 3; p < r.image.rgba.size(); p += 4) alpha += r.image.rgba[p];
    std::printf(
        "%dx%d, %d spp, threads %d: %.3f s (%.0f ns per path), estimated relative RMSE %.4f, mean alpha "
        "%.3f, "
        "sanitized %llu, truncated %llu\n",
        width, height, settings.samples_per_pixel, settings.threads, r.seconds,
        1e9 * r.seconds / (double(width) * height * settings.samples_per_pixel), r.estimated_relative_rmse,
        alpha / (double(width) * height), static_cast<unsigned long long>(r.sanitized_samples),
        static_cast<unsigned long long>(r.truncated_paths));
    return 0;
}
