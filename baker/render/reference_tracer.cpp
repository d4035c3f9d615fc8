#include "render/reference_tracer.h"

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "render/render_error.h"
#include "render/volume_scene.h"
#include "render/volume_walk.h"

namespace firelook::render {
namespace {

constexpr int kTileSize = 16;
// Passes grow 1, 2, 4, ... up to this many samples per pixel, so a viewer sees a first image at
// once and later passes keep the per-pass overhead small.
constexpr int kLargestPass = 16;

// Per-pixel sums of the samples and of their squares, RGBA, and how many samples they hold.
struct PixelAccumulator {
    double sum[4] = {0, 0, 0, 0};
    double sum_of_squares[4] = {0, 0, 0, 0};
    int samples = 0;
};

float toFiniteFloat(double x) {
    constexpr double kLargest = std::numeric_limits<float>::max();
    return static_cast<float>(std::clamp(x, -kLargest, kLargest));
}

void checkSettings(const ReferenceSettings& settings) {
    if (settings.samples_per_pixel < 1)
        throw RenderError("reference: samples per pixel must be at least 1, got " +
                          std::to_string(settings.samples_per_pixel));
    if (settings.roulette_depth < 0) throw RenderError("reference: the roulette depth must not be negative");
    if (settings.threads < 0) throw RenderError("reference: the thread count must not be negative");
    if (settings.max_scattering_order < 0)
        throw RenderError("reference: the maximum scattering order must not be negative");
}

}  // namespace

ReferenceResult renderReference(const Medium& medium, const LookModel& look, const Camera& camera,
                                const ReferenceSettings& settings,
                                const std::function<bool(double progress)>& keep_going) {
    const auto start = std::chrono::steady_clock::now();
    checkSettings(settings);
    const VolumeScene scene(medium, look);
    WalkSettings walk;
    walk.roulette_depth = settings.roulette_depth;
    walk.max_scattering_order = settings.max_scattering_order;

    const int width = camera.width(), height = camera.height();
    std::vector<PixelAccumulator> pixels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    std::atomic<std::uint64_t> sanitized{0}, truncated{0};
    std::atomic<bool> stopped{false};
    const auto stopRequested = [&] {
        if (stopped.load(std::memory_order_relaxed)) return true;
        if (!settings.stop_requested || !settings.stop_requested()) return false;
        stopped.store(true, std::memory_order_relaxed);
        return true;
    };
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);

    ReferenceResult result;
    int done = 0;
    for (int pass = 1; done < settings.samples_per_pixel; pass = std::min(2 * pass, kLargestPass)) {
        const int first = done, last = std::min(settings.samples_per_pixel, done + pass);
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range2d<int>(0, height, kTileSize, 0, width, kTileSize),
                              [&](const tbb::blocked_range2d<int>& tile) {
                                  std::uint64_t tile_sanitized = 0, tile_truncated = 0;
                                  for (int py = tile.rows().begin(); py < tile.rows().end(); ++py)
                                      for (int px = tile.cols().begin(); px < tile.cols().end(); ++px) {
                                          if (stopRequested()) {
                                              sanitized += tile_sanitized;
                                              truncated += tile_truncated;
                                              return;
                                          }
                                          const std::size_t index = static_cast<std::size_t>(py) * width + px;
                                          PixelAccumulator& acc = pixels[index];
                                          for (int s = first; s < last; ++s) {
                                              Pcg32 rng = Pcg32::forSample(settings.seed, index,
                                                                           static_cast<std::uint64_t>(s));
                                              const double u = rng.uniform(), v = rng.uniform();
                                              const PathEstimate e = estimateCameraPath(
                                                  scene, camera.generateRay(px, py, u, v), rng, walk);
                                              double sample[4] = {e.radiance.r, e.radiance.g, e.radiance.b,
                                                                  1.0 - e.transmittance};
                                              if (!(std::isfinite(sample[0]) && std::isfinite(sample[1]) &&
                                                    std::isfinite(sample[2]) && std::isfinite(sample[3]))) {
                                                  sample[0] = sample[1] = sample[2] = sample[3] = 0.0;
                                                  ++tile_sanitized;
                                              }
                                              if (e.truncated) ++tile_truncated;
                                              for (int ch = 0; ch < 4; ++ch) {
                                                  acc.sum[ch] += sample[ch];
                                                  acc.sum_of_squares[ch] += sample[ch] * sample[ch];
                                              }
                                          }
                                          acc.samples = last;
                                      }
                                  sanitized += tile_sanitized;
                                  truncated += tile_truncated;
                              });
        });
        if (stopped.load()) {
            result.cancelled = true;
            break;
        }
        done = last;
        if (keep_going && done < settings.samples_per_pixel &&
            !keep_going(static_cast<double>(done) / settings.samples_per_pixel)) {
            result.cancelled = true;
            break;
        }
    }

    // Stopped within a pass, some pixels hold one pass more than `done`.
    result.image = {width, height, std::vector<float>(pixels.size() * 4)};
    result.variance_of_mean = {width, height, std::vector<float>(pixels.size() * 4, 0.0f)};
    double variance_sum = 0.0, mean_squared_sum = 0.0;
    for (std::size_t i = 0; i < pixels.size(); ++i)
        for (int ch = 0; ch < 4; ++ch) {
            const double n = pixels[i].samples;
            const double mean = n > 0 ? pixels[i].sum[ch] / n : 0.0;
            result.image.rgba[4 * i + ch] = toFiniteFloat(mean);
            if (n < 2) continue;
            // Unbiased sample variance divided by n: the variance of the mean.
            const double variance =
                std::max(0.0, (pixels[i].sum_of_squares[ch] - pixels[i].sum[ch] * mean) / (n - 1.0)) / n;
            result.variance_of_mean.rgba[4 * i + ch] = toFiniteFloat(variance);
            if (ch < 3) {
                variance_sum += variance;
                mean_squared_sum += mean * mean;
            }
        }
    if (done < 2)
        result.estimated_relative_rmse = std::numeric_limits<double>::infinity();
    else if (mean_squared_sum > 0.0)
        result.estimated_relative_rmse = std::sqrt(variance_sum / mean_squared_sum);
    else
        result.estimated_relative_rmse = variance_sum > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
    result.sanitized_samples = sanitized;
    result.truncated_paths = truncated;
    result.samples_per_pixel_done = done;
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace firelook::render
