// Synthetic frames for the frame codec's tests (frame_codec_test.cpp, resident_frame_test.cpp):
// a small description and factors with smooth fields, sharp edges, empty regions, huge and
// non-finite depths.
#pragma once

#include <cmath>
#include <glm/gtc/packing.hpp>
#include <random>

#include "basis/bake_description.h"
#include "basis/frame_factors.h"

namespace firelook::basis {

inline BakeDescription codecDescription(int width, int height, int samples) {
    BakeDescription d;
    d.bins = {0.0, 3.0, 3};
    d.axes = {{1.0, 1.5, 2.0}, {2.0, 4.0, 16.0}, {0.5, 4.0}};
    d.alpha_thresholds = {1.0, 1.25, 1.5, 1.75, 2.0};
    d.footprint_samples = samples;
    d.light_directions = {{0.0, 0.0, -1.0}};
    d.width = width;
    d.height = height;
    return d;
}

// What a bake writes, and what it should not.
inline FrameFactors codecFactors(const BakeDescription& d, int rank, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    FrameFactors f;
    f.frame = 3;
    f.pixels = d.pixelCount();
    f.columns = d.columnCount();
    f.rank = rank;
    for (int p = 0; p < f.pixels; ++p)
        for (int k = 0; k < rank; ++k) {
            const float x = float(p % d.width) / d.width, y = float(p / d.width) / d.height;
            const float smooth = std::sin(6.0f * x * (k + 1)) * std::cos(5.0f * y) / std::sqrt(float(f.pixels));
            f.u_half.push_back(glm::packHalf1x16(x < 0.2f ? 0.0f : smooth + 0.002f * (unit(rng) - 0.5f)));
        }
    for (int j = 0; j < f.columns; ++j)
        for (int k = 0; k < rank; ++k) f.svt.push_back((unit(rng) - 0.5f) * 100.0f * std::ldexp(1.0f, -k));
    const size_t rays = static_cast<size_t>(f.pixels) * d.footprint_samples;
    for (size_t r = 0; r < rays; ++r) {
        const float v = unit(rng);
        f.depth_b.push_back(v < 0.2f ? 0.0f : v < 0.25f ? 1e6f : v < 0.26f ? NAN : 8.0f * v * v * v);
    }
    for (int s = 0; s < d.footprint_samples; ++s)
        for (size_t j = 0; j < d.alpha_thresholds.size(); ++j)
            for (int p = 0; p < f.pixels; ++p) {
                const float o_b = f.depth_b[static_cast<size_t>(s) * f.pixels + p];
                const float flame = (p % 3 == 0) ? 0.0f : o_b * (1.0f - 0.2f * float(j)) * unit(rng);
                f.depth_a.push_back(2.0f * flame - o_b);  // O_a = 2 F - O_b
            }
    return f;
}

}  // namespace firelook::basis
