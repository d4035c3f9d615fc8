// A screen-space lens flare driven by the bright flame of an instance's image.
// Deterministic (no randomness; the same image and settings give the same
// bytes on one build), allocation-free given the scratch buffer.
//
// Definition, with the image centre c = (W/2, H/2) in pixel units and every
// sample bilinear with zero outside the image:
//  1. Bright pass: b(p) = rgb(p) * max(0, L(p) - threshold) / L(p), with
//     L = 0.2126 r + 0.7152 g + 0.0722 b (Rec. 709 luminance of the
//     premultiplied radiance). Only light above the threshold feeds the flare.
//  2. Ghosts: ghost i samples b at c + s_i (p - c) with
//     s_i = ghost_spacing * (i + 1) * (-1)^(i+1): -s, +2s, -3s, ... so the
//     copies are scaled and, for odd i, flipped through the centre; each is
//     tinted by a fixed colour and faded towards the image border by
//     (1 - |q - c| / |c|)^2 at its sample point q.
//  3. Halo: samples b at q = p + R (c - p) / |c - p| (R = halo_radius * |c|),
//     weighted by exp(-((|p - c| - R) / (halo_width * |c|))^2): a ring of
//     radius R showing the bright light opposite to each point.
//  4. Streaks: a directional blur of b along the rows (and the columns when
//     streaks = 2) with the normalised two-sided exponential kernel
//     (1 - a)/(1 + a) * a^|j|, a = exp(-1 / (streak_length * W)), computed
//     with one forward and one backward recursive pass (O(1) per pixel).
//  flare = intensity * (sum_i tint_i ghost_i + halo_intensity * halo +
//                       streak_intensity * streaks).
// Computed at half resolution (what makes it cheap): the bright pass b is box-averaged over 2x2
// pixels, the ghosts, halo and streaks above are evaluated at the centres of those blocks (same
// centre, scales, fades, radii and decay length in full-resolution units, so every parameter
// keeps its meaning), and the result is upsampled bilinearly (edges clamped). Energy and
// placement stay (tests/world/lens_flare_test.cpp compares each part with the definition evaluated
// at full resolution: energy within 5%, centroids within half a pixel for soft sources). What is
// lost is detail finer than 2 pixels: a single bright pixel acts as if at its block's centre (up
// to half a pixel away), its streak is about 3 pixels thick instead of 1, and its halo - which
// shows the light near the image centre enlarged - can land a few pixels off.
// The flare is returned as a separate RGBA image with alpha 0: it is light
// added on top of everything (final = rgb + (1 - alpha) background + flare),
// not part of the fire's coverage, so the fire image stays what
// `firelook render` produces.
#pragma once

#include <cstddef>

namespace firelook::world {

struct LensFlareSettings {
    float threshold = 1.0f;       // luminance (linear radiance) above which light feeds the flare
    float intensity = 0.15f;      // overall gain
    int ghost_count = 4;          // 0..8
    float ghost_spacing = 0.45f;  // |s_i| = ghost_spacing * (i + 1)
    float halo_radius = 0.6f;     // fraction of |c| (half the image diagonal)
    float halo_width = 0.08f;     // fraction of |c|
    float halo_intensity = 0.5f;
    float streak_length = 0.06f;  // decay length, fraction of the image width
    float streak_intensity = 0.6f;
    int streaks = 1;              // 0 none, 1 horizontal, 2 horizontal + vertical
};

// Floats of scratch renderLensFlare needs for a width x height image.
// (The half-resolution working images of lens_flare.cpp's Layout: three sets of RGB planes, the
// bright pass as padded RGB0, and a few low-res rows.)
inline size_t lensFlareScratchFloats(int width, int height) {
    const size_t w = static_cast<size_t>(width > 0 ? width : 0);
    const size_t w2 = (w + 1) / 2, h2 = (static_cast<size_t>(height > 0 ? height : 0) + 1) / 2;
    const size_t padded_row = w2 + 2;
    return 9 * w2 * h2 + 4 * padded_row * (h2 + 2) + 36 * padded_row + 11 * w2 + 32;
}

// rgba_in: width x height premultiplied RGBA; flare_out: the same size, RGBA
// with A = 0; scratch: lensFlareScratchFloats() floats. Non-finite or negative
// input radiance is treated as 0, so the output is always finite and >= 0.
// Settings out of range are clamped (negative gains to 0, counts into range).
void renderLensFlare(const float* rgba_in, int width, int height, const LensFlareSettings& settings, float* scratch,
                     float* flare_out);

}  // namespace firelook::world
