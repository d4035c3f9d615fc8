// alpha_footprint_report: how many camera rays per pixel the bake must store so
// that alpha = mean over the footprint of 1 - exp(-tau) is within 0.01 of the
// pixel's true mean transmittance. For one frame of a sequence and the most
// opaque corners of a baked range, prints the largest per-pixel difference
// between n x n cell-centred rays (n = 1..6, 8) and a 16 x 16 quadrature.
// Built, not a ctest test: the lead quotes its figures when choosing the default.
//   alpha_footprint_report SEQUENCE FRAME WxH [k_s_max k_f_max]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bake/scene_setup.h"
#include "render/ray.h"
#include "reference/frame_medium.h"

using namespace firelook;

namespace {

// Optical depth of each of a pixel's n x n cell-centred rays, midpoint rule at 0.25 voxel
// (the same rule for every n, so the differences are the footprint quadrature's alone).
std::vector<double> rayDepths(const render::Medium& medium, const LookModel& model, const render::Camera& camera,
                              int px, int py, int n) {
    const render::WorldBox box = medium.worldBounds();
    const double step = 0.25 * medium.minVoxelEdge();
    std::vector<double> depths;
    for (int s = 0; s < n * n; ++s) {
        const render::Ray ray = camera.generateRay(px, py, (s % n + 0.5) / n, (s / n + 0.5) / n);
        double t0 = 0.0, t1 = 0.0;
        if (!render::intersectBox(ray.origin, ray.direction, box.min, box.max, t0, t1)) t1 = t0;
        double tau = 0.0;
        for (double t = t0; t < t1; t += step) {
            const double dt = std::min(step, t1 - t);
            const render::MediumSample m = medium.sampleWorld(ray.origin + (t + 0.5 * dt) * ray.direction);
            tau += model.sigmaT(m.density, m.temperature) * dt;
        }
        depths.push_back(tau);
    }
    return depths;
}

double meanAlpha(const std::vector<double>& depths) {
    double sum = 0.0;
    for (double tau : depths) sum += 1.0 - std::exp(-tau);
    return sum / static_cast<double>(depths.size());
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: %s SEQUENCE FRAME WxH [k_s_max k_f_max]\n", argv[0]);
        return 2;
    }
    const int frame = std::atoi(argv[2]);
    const double k_s = argc > 4 ? std::atof(argv[4]) : 16.0;
    const double k_f = argc > 5 ? std::atof(argv[5]) : 4.0;
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(argv[1]);
    bake::SceneOptions options;
    options.up = render::UpAxis::Z;
    std::tie(options.width, options.height) = bake::parseSize(argv[3]);
    const bake::SceneSetup scene = bake::resolveScene(sequence, options);
    const render::Medium medium = reference::mediumFromFrame(sequence.load(frame));
    const auto [t_lo, t_hi] = bake::sequenceTemperatureRange(sequence);

    const int counts[] = {1, 2, 3, 4, 5, 6, 8};
    for (const double t_c : {1.0, 2.0}) {
        LookModel model;
        model.bins = TemperatureBins{t_lo, t_hi, 16};
        model.extinction = ExtinctionParams{t_c, k_s, k_f};
        double worst[7] = {};
        for (int py = 0; py < scene.camera.height(); ++py)
            for (int px = 0; px < scene.camera.width(); ++px) {
                // Screen with 4 x 4 rays: where their alphas agree within 0.002 the pixel is
                // uniform and no footprint rule can be off by 0.01 (saves the 16 x 16 cost).
                const std::vector<double> screen = rayDepths(medium, model, scene.camera, px, py, 4);
                double lo = 1.0, hi = 0.0;
                for (double tau : screen) lo = std::min(lo, 1.0 - std::exp(-tau)), hi = std::max(hi, 1.0 - std::exp(-tau));
                if (hi - lo < 0.002) continue;
                const double truth = meanAlpha(rayDepths(medium, model, scene.camera, px, py, 16));
                for (int i = 0; i < 7; ++i)
                    worst[i] = std::max(worst[i],
                                        std::fabs(meanAlpha(rayDepths(medium, model, scene.camera, px, py, counts[i])) - truth));
            }
        std::printf("frame %d %dx%d T_c %.2f k_s %.2f k_f %.2f: max |alpha(n x n) - alpha(16 x 16)|:", frame,
                    scene.camera.width(), scene.camera.height(), t_c, k_s, k_f);
        for (int i = 0; i < 7; ++i) std::printf("  n=%d %.4f", counts[i], worst[i]);
        std::printf("\n");
    }
    return 0;
}
