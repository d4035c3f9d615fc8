// The reference: an unbiased volumetric path tracer of exactly the look model (docs/model.md and
// docs/testing.md), against which every faster image is measured.
#pragma once

#include <climits>
#include <cstdint>
#include <functional>

#include "look/look_model.h"
#include "render/camera.h"
#include "render/medium.h"
#include "render/render_image.h"

namespace firelook::render {

struct ReferenceSettings {
    int samples_per_pixel = 64;
    std::uint64_t seed = 1;
    int roulette_depth = 8;  // scattering events before Russian roulette
    int threads = 0;         // 0: all available
    // For tests and diagnostics: paths end after this many scattering events (0: emission seen
    // directly only, 1: single scattering). The default keeps every order.
    int max_scattering_order = INT_MAX;
    // Polled from the worker threads before every pixel of every pass (so within a millisecond or so
    // at any image size and sample count): returning true stops the render as soon as the pixels
    // being traced are done, and renderReference returns what it has with cancelled set. Must be
    // thread-safe and cheap (an atomic load). Empty: never stops early.
    std::function<bool()> stop_requested;
};

struct ReferenceResult {
    RenderImage image;
    // Per pixel and channel (RGBA, same layout as image): the estimated variance of the pixel's
    // mean, from the spread of its samples. 0 where fewer than two samples were taken.
    RenderImage variance_of_mean;
    // sqrt(sum of RGB variances of the means / sum of squared RGB means): the expected relative
    // RMSE of image against the exact answer. Infinity with fewer than two samples per pixel.
    double estimated_relative_rmse = 0.0;
    // Samples with a non-finite value, dropped (counted as radiance 0, transmittance 1).
    std::uint64_t sanitized_samples = 0;
    // Walks cut after an enormous number of scattering events (see PathEstimate::truncated).
    std::uint64_t truncated_paths = 0;
    // Samples every pixel received: less than asked when cancelled. A render stopped within a pass
    // (stop_requested) leaves some pixels with one pass more; each pixel's mean and variance use its
    // own count, this is the smallest.
    int samples_per_pixel_done = 0;
    bool cancelled = false;
    double seconds = 0.0;
};

// Renders premultiplied RGBA (alpha = 1 - transmittance of the camera ray) in passes of increasing
// sample counts. After every pass keep_going (if given) is called on the calling thread with the
// fraction of samples done; returning false stops the render, which then returns what it has
// (settings.stop_requested stops it within a pass).
// The image depends only on the inputs and settings.seed, never on threads or pass boundaries.
// Throws RenderError for invalid settings or look (see LookEvaluator, VolumeScene).
ReferenceResult renderReference(const Medium& medium, const LookModel& look, const Camera& camera,
                                const ReferenceSettings& settings,
                                const std::function<bool(double progress)>& keep_going = {});

}  // namespace firelook::render
