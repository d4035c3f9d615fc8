// Where the frame codec puts each footprint ray (internal to runtime/basis): the lattice its
// encoder (frame_encoder.cpp) predicts the rays' depth codes on and its decoder
// (frame_decoder.cpp) undoes the prediction on.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "basis/bake_description.h"

namespace firelook::basis::codec {

// ---- ray lattice -----------------------------------------------------------------------------
// Footprint ray s of pixel p, for n x n cell-centred rays, sits at (px n + s % n, py n + s / n)
// of a lattice n times finer than the image, so neighbouring rays (of one pixel or of two) are
// neighbours there. A footprint that is not square keeps one image per ray, stacked.
struct RayLattice {
    int width = 0, height = 0;
    int n = 0;  // rays per axis; 0 = stacked images
    int image_width = 0, image_height = 0;

    static RayLattice of(const BakeDescription& d) {
        RayLattice l;
        l.image_width = d.width;
        l.image_height = d.height;
        const int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(d.footprint_samples))));
        if (n * n == d.footprint_samples) {
            l.n = n;
            l.width = d.width * n;
            l.height = d.height * n;
        } else {
            l.width = d.width;
            l.height = d.height * d.footprint_samples;
        }
        return l;
    }
    size_t size() const { return static_cast<size_t>(width) * height; }
    int samples() const { return n > 0 ? n * n : height / std::max(image_height, 1); }
    // A per-pixel value on every ray of the pixel.
    std::vector<uint8_t> spread(const std::vector<uint8_t>& per_pixel) const {
        std::vector<uint8_t> out(size());
        for (int s = 0; s < samples(); ++s)
            for (size_t p = 0; p < per_pixel.size(); ++p) out[at(s, p)] = per_pixel[p];
        return out;
    }
    // Lattice index of ray (sample s, pixel p).
    size_t at(int s, size_t p) const {
        if (n == 0) return static_cast<size_t>(s) * image_width * image_height + p;
        const size_t px = p % image_width, py = p / image_width;
        return (py * n + s / n) * width + px * n + s % n;
    }
};

}  // namespace firelook::basis::codec
