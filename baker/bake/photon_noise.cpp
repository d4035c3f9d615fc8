#include "bake/photon_noise.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "bake/camera_march.h"

namespace firelook::bake {
namespace {

constexpr double kNegligibleColumn = 1e-6;

}  // namespace

double predictPhotonNoise(const PhotonNoiseInputs& in, const std::vector<float>& lbar,
                          const std::vector<float>& noise, double weight, const std::atomic<bool>& stop) {
    const TraceTables& tb = in.tables;
    const int G = tb.points, C = tb.columns;
    const std::size_t GC = static_cast<std::size_t>(G) * C;
    const int width = in.camera.width(), height = in.camera.height();
    const int stride = std::max(1, (std::max(width, height) + kPhotonNoisePixelsPerAxis - 1) / kPhotonNoisePixelsPerAxis);
    const int cols = (width + stride - 1) / stride, rows = (height + stride - 1) / stride;
    const float inv_weight = weight > 0.0 ? static_cast<float>(1.0 / weight) : 1.0f;
    // Per coarse row, then summed in row order: the same prediction with any number of threads.
    std::vector<double> value2(static_cast<std::size_t>(rows) * GC, 0.0), noise2(value2.size(), 0.0);
    tbb::parallel_for(0, rows, [&](int r) {
        CameraMarch ray_march(in.medium, tb, in.cells, in.light_depths, in.camera, in.min_step, in.footprint_step,
                              true);
        std::vector<float> direct(GC), scattered(GC), noisy(GC);
        double* v2 = value2.data() + static_cast<std::size_t>(r) * GC;
        double* n2 = noise2.data() + static_cast<std::size_t>(r) * GC;
        const int py = std::min(height - 1, r * stride + stride / 2);
        for (int c = 0; c < cols && !stop.load(std::memory_order_relaxed); ++c) {
            const int px = std::min(width - 1, c * stride + stride / 2);
            std::fill(direct.begin(), direct.end(), 0.0f);
            std::fill(scattered.begin(), scattered.end(), 0.0f);
            std::fill(noisy.begin(), noisy.end(), 0.0f);
            ray_march.beginPixel();
            // The pixel's centre ray, with the bake's step for one ray per pixel.
            if (!ray_march.marchPixelRay(px, py, 0.5, 0.5, 1, 1.0f, nullptr, nullptr, 1.0)) continue;
            ray_march.addDirect(direct.data());
            ray_march.contract(lbar, scattered.data());
            ray_march.contract(noise, noisy.data());
            for (std::size_t i = 0; i < GC; ++i) {
                const double v = direct[i] + inv_weight * scattered[i];
                const double n = inv_weight * noisy[i];
                v2[i] += v * v;
                n2[i] += n * n;
            }
        }
    });
    std::vector<double> v2(GC, 0.0), n2(GC, 0.0);
    for (int r = 0; r < rows; ++r)
        for (std::size_t i = 0; i < GC; ++i) {
            v2[i] += value2[static_cast<std::size_t>(r) * GC + i];
            n2[i] += noise2[static_cast<std::size_t>(r) * GC + i];
        }
    // A column is judged where its image holds light: at least kNegligibleColumn of the brightest
    // column's energy (a temperature bin that barely occurs has an image 1e-12 of the others', whose
    // noise estimate is itself noise and which no look in the baked range can lift into view).
    std::vector<double> column_energy(in.counted, 0.0);
    for (int c = 0; c < in.counted; ++c)
        for (int g = 0; g < G; ++g) column_energy[c] += v2[static_cast<std::size_t>(g) * C + c];
    const double brightest = column_energy.empty() ? 0.0 : *std::max_element(column_energy.begin(), column_energy.end());
    double worst = 0.0;
    for (int c = 0; c < in.counted; ++c) {
        if (!(column_energy[c] > kNegligibleColumn * brightest)) continue;
        double sum = 0.0;
        int points = 0;
        for (int g = 0; g < G; ++g) {
            const std::size_t i = static_cast<std::size_t>(g) * C + c;
            if (!(v2[i] > 0.0)) continue;
            sum += n2[i] / v2[i];
            ++points;
        }
        worst = std::max(worst, std::sqrt(sum / points));
    }
    return worst;
}

}  // namespace firelook::bake
