#include "world/lens_flare.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "basis/simd.h"

namespace firelook::world {
namespace {

// Every helper is inlined into both builds of flareKernel below. The full-resolution passes (bright
// pass, upsampling) and the per-pixel sample weights are written 8 lanes at a time with GCC vector
// extensions (the auto-vectoriser leaves loops with selects and divisions scalar); the bilinear
// taps use 4-float RGB0 vectors, one load per tap; the rest are plain loops over planar rows.
// Measured on the 2-core development machine: 512x512 in 1.7 ms (tests/world/bench_runtime).
using basis::simd::v4f;
using basis::simd::v8f;
using basis::simd::v8i;

FIRELOOK_ALWAYS_INLINE float finiteNonNegative(float v) {
    return v > 0.0f && v <= std::numeric_limits<float>::max() ? v : 0.0f;
}

FIRELOOK_ALWAYS_INLINE void load4(v4f& v, const float* p) { std::memcpy(&v, p, sizeof v); }
FIRELOOK_ALWAYS_INLINE void store4(float* p, const v4f& v) { std::memcpy(p, &v, sizeof v); }
FIRELOOK_ALWAYS_INLINE void load8(v8f& v, const float* p) { std::memcpy(&v, p, sizeof v); }
FIRELOOK_ALWAYS_INLINE void store8(float* p, const v8f& v) { std::memcpy(p, &v, sizeof v); }

// exp(x) for x <= 0 (clamped at -87, where exp is still a normal float), 8 lanes: Cephes expf
// range reduction and polynomial, about 1 float ulp.
FIRELOOK_ALWAYS_INLINE void expNonPositive8(v8f& y, const v8f& x_in) {
    const v8f lowest = v8f{} - 87.0f;
    const v8f x = x_in > lowest ? x_in : lowest;
    const v8i n = __builtin_convertvector(x * 1.44269504088896341f - 0.5f, v8i);
    const v8f fn = __builtin_convertvector(n, v8f);
    v8f r = x - fn * 0.693359375f;
    r = r - fn * -2.12194440e-4f;
    v8f p = r * 1.9875691500e-4f + 1.3981999507e-3f;
    p = p * r + 8.3334519073e-3f;
    p = p * r + 4.1665795894e-2f;
    p = p * r + 1.6666665459e-1f;
    p = p * r + 5.0000001201e-1f;
    y = (p * (r * r) + r + 1.0f) * __builtin_bit_cast(v8f, (n + 127) << 23);
}

constexpr v8f kLane = {0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f};

constexpr float kGhostTint[8][3] = {{1.0f, 0.75f, 0.45f}, {0.55f, 0.8f, 1.0f}, {1.0f, 0.55f, 0.35f},
                                    {0.6f, 1.0f, 0.7f},   {0.9f, 0.6f, 1.0f},  {1.0f, 0.9f, 0.6f},
                                    {0.5f, 0.7f, 1.0f},   {1.0f, 0.7f, 0.7f}};
constexpr float kHaloTint[3] = {0.8f, 0.85f, 1.0f};
constexpr int kMaxGhosts = 8;

// The half-resolution working images (see lens_flare.h): w2 x h2 pixels, low-res pixel (P, Q)
// covering full-resolution pixels 2P..2P+1 x 2Q..2Q+1, its centre at (2P + 1, 2Q + 1) in
// full-resolution pixel units. The sizes here are what lensFlareScratchFloats() adds up.
struct Layout {
    int w2, h2;
    size_t n2;      // w2 * h2
    size_t pw;      // w2 + 2: a padded row
    float* bright;  // 3 planes of n2: the bright pass, box-averaged
    float* flare;   // 3 planes of n2: the flare before the gain and the upsampling
    float* vfwd;    // 3 planes of n2: the vertical streak's forward pass
    float* rgb0;    // (w2 + 2) x (h2 + 2) x 4: the bright pass as RGB0, one zero pixel around
    float* ghost;   // kMaxGhosts x (w2 + 2) x 4: per ghost, its source row (RGB0, padded, tinted)
    float* acc;     // w2 x 4: one low-res row of ghosts + halo
    float* up;      // (w2 + 2) x 4: one row being upsampled, edges repeated
    float* gx;      // w2 + 8: per-pixel sample x (padded low-res units)
    float* gy;      // w2 + 8: per-pixel sample y
    float* gw;      // w2 + 8: per-pixel sample weight
    float* dist;    // w2 + 8: |p - c| along one low-res row
    float* line;    // 3 x w2: the vertical streak's backward pass
};

FIRELOOK_ALWAYS_INLINE Layout layout(int width, int height, float* scratch) {
    Layout l;
    l.w2 = (width + 1) / 2;
    l.h2 = (height + 1) / 2;
    l.n2 = static_cast<size_t>(l.w2) * l.h2;
    l.pw = static_cast<size_t>(l.w2) + 2;
    l.bright = scratch;
    l.flare = l.bright + 3 * l.n2;
    l.vfwd = l.flare + 3 * l.n2;
    l.rgb0 = l.vfwd + 3 * l.n2;
    l.ghost = l.rgb0 + 4 * l.pw * (static_cast<size_t>(l.h2) + 2);
    l.acc = l.ghost + kMaxGhosts * 4 * l.pw;
    l.up = l.acc + 4 * static_cast<size_t>(l.w2);
    l.gx = l.up + 4 * l.pw;
    l.gy = l.gx + l.w2 + 8;
    l.gw = l.gy + l.w2 + 8;
    l.dist = l.gw + l.w2 + 8;
    l.line = l.dist + l.w2 + 8;
    return l;
}

// Bright pass of 8 full-resolution RGBA pixels (32 floats) into planar r, g, b, each times 1/4
// (the 2x2 box average); any |= the bits of every k.
FIRELOOK_ALWAYS_INLINE void brightOf8(const float* rgba, float threshold, v8f& r, v8f& g, v8f& b, v8i& any) {
    v8f p01, p23, p45, p67;
    load8(p01, rgba);
    load8(p23, rgba + 8);
    load8(p45, rgba + 16);
    load8(p67, rgba + 24);
    const v8f rg03 = __builtin_shufflevector(p01, p23, 0, 4, 8, 12, 1, 5, 9, 13);   // r0..r3 g0..g3
    const v8f b03 = __builtin_shufflevector(p01, p23, 2, 6, 10, 14, 3, 7, 11, 15);  // b0..b3 a0..a3
    const v8f rg47 = __builtin_shufflevector(p45, p67, 0, 4, 8, 12, 1, 5, 9, 13);
    const v8f b47 = __builtin_shufflevector(p45, p67, 2, 6, 10, 14, 3, 7, 11, 15);
    r = __builtin_shufflevector(rg03, rg47, 0, 1, 2, 3, 8, 9, 10, 11);
    g = __builtin_shufflevector(rg03, rg47, 4, 5, 6, 7, 12, 13, 14, 15);
    b = __builtin_shufflevector(b03, b47, 0, 1, 2, 3, 8, 9, 10, 11);
    const v8f zero = {};
    const v8f largest = zero + std::numeric_limits<float>::max();
    r = (r > zero) & (r <= largest) ? r : zero;  // NaN, inf and negatives -> 0
    g = (g > zero) & (g <= largest) ? g : zero;
    b = (b > zero) & (b <= largest) ? b : zero;
    const v8f lum = 0.2126f * r + 0.7152f * g + 0.0722f * b;
    const v8f tiny = zero + std::numeric_limits<float>::min();
    const v8f share = 0.25f * (lum - threshold) / (lum > tiny ? lum : tiny);
    const v8f k = lum > threshold ? share : zero;  // lum > threshold >= 0
    any |= __builtin_bit_cast(v8i, k);
    r *= k;
    g *= k;
    b *= k;
}

// 1. Bright pass at full resolution, 2x2 box-averaged into the low-res planes, 16 full-resolution
// pixels (8 low-res) at a time. Returns whether any light passed the threshold.
FIRELOOK_ALWAYS_INLINE bool brightPass(const float* rgba, int width, int height, float threshold, const Layout& l) {
    std::fill(l.bright, l.bright + 3 * l.n2, 0.0f);
    v8i any = {};
    uint32_t any_scalar = 0;
    const int blocks = width / 16;
    for (int y = 0; y < height; ++y) {
        const float* in = rgba + static_cast<size_t>(y) * width * 4;
        float* r2 = l.bright + static_cast<size_t>(y / 2) * l.w2;
        float* g2 = r2 + l.n2;
        float* b2 = g2 + l.n2;
        for (int i = 0; i < blocks; ++i) {
            v8f ra, ga, ba, rb, gb, bb;
            brightOf8(in + 64 * i, threshold, ra, ga, ba, any);
            brightOf8(in + 64 * i + 32, threshold, rb, gb, bb, any);
            v8f acc;
            load8(acc, r2 + 8 * i);
            acc += __builtin_shufflevector(ra, rb, 0, 2, 4, 6, 8, 10, 12, 14) +
                   __builtin_shufflevector(ra, rb, 1, 3, 5, 7, 9, 11, 13, 15);
            store8(r2 + 8 * i, acc);
            load8(acc, g2 + 8 * i);
            acc += __builtin_shufflevector(ga, gb, 0, 2, 4, 6, 8, 10, 12, 14) +
                   __builtin_shufflevector(ga, gb, 1, 3, 5, 7, 9, 11, 13, 15);
            store8(g2 + 8 * i, acc);
            load8(acc, b2 + 8 * i);
            acc += __builtin_shufflevector(ba, bb, 0, 2, 4, 6, 8, 10, 12, 14) +
                   __builtin_shufflevector(ba, bb, 1, 3, 5, 7, 9, 11, 13, 15);
            store8(b2 + 8 * i, acc);
        }
        for (int x = 16 * blocks; x < width; ++x) {  // the rest of the row, one pixel at a time
            const float r = finiteNonNegative(in[4 * x + 0]);
            const float g = finiteNonNegative(in[4 * x + 1]);
            const float b = finiteNonNegative(in[4 * x + 2]);
            const float lum = 0.2126f * r + 0.7152f * g + 0.0722f * b;
            const float k = lum > threshold ? 0.25f * (lum - threshold) / lum : 0.0f;
            any_scalar |= std::bit_cast<uint32_t>(k);
            r2[x / 2] += r * k;
            g2[x / 2] += g * k;
            b2[x / 2] += b * k;
        }
    }
    for (int i = 0; i < 8; ++i) any_scalar |= static_cast<uint32_t>(any[i]);
    return any_scalar != 0;
}

// The bright planes as RGB0 pixels with a zero border, for the bilinear taps.
FIRELOOK_ALWAYS_INLINE void packRgb0(const Layout& l) {
    std::fill(l.rgb0, l.rgb0 + 4 * l.pw, 0.0f);
    std::fill(l.rgb0 + 4 * l.pw * (static_cast<size_t>(l.h2) + 1), l.rgb0 + 4 * l.pw * (static_cast<size_t>(l.h2) + 2),
              0.0f);
    for (int q = 0; q < l.h2; ++q) {
        float* out = l.rgb0 + 4 * l.pw * (static_cast<size_t>(q) + 1);
        const float* r = l.bright + static_cast<size_t>(q) * l.w2;
        const float* g = r + l.n2;
        const float* b = g + l.n2;
        std::fill(out, out + 4, 0.0f);
        std::fill(out + 4 * (l.pw - 1), out + 4 * l.pw, 0.0f);
        for (int p = 0; p < l.w2; ++p) {
            out[4 * (p + 1) + 0] = r[p];
            out[4 * (p + 1) + 1] = g[p];
            out[4 * (p + 1) + 2] = b[p];
            out[4 * (p + 1) + 3] = 0.0f;
        }
    }
}

// 2. Streaks into l.flare (overwritten): the two-sided exponential blur of the bright image along
// rows (and columns), times `gain`: a forward pass f, a backward pass k, out = norm (f + k - v).
FIRELOOK_ALWAYS_INLINE void streaks(const Layout& l, int directions, float a, float gain) {
    const float norm = gain * (1.0f - a) / (1.0f + a);
    // Rows: four rows x three channels at a time, so that twelve recursions overlap.
    constexpr int kRows = 4;
    for (int q0 = 0; q0 < l.h2; q0 += kRows) {
        const int chains = 3 * std::min(kRows, l.h2 - q0);
        const float* v[kRows * 3];
        float* out[kRows * 3];
        for (int i = 0; i < chains; ++i) {
            v[i] = l.bright + (i % 3) * l.n2 + static_cast<size_t>(q0 + i / 3) * l.w2;
            out[i] = l.flare + (i % 3) * l.n2 + static_cast<size_t>(q0 + i / 3) * l.w2;
        }
        float f[kRows * 3] = {};
        for (int p = 0; p < l.w2; ++p)
            for (int i = 0; i < chains; ++i) out[i][p] = f[i] = v[i][p] + a * f[i];
        float k[kRows * 3] = {};
        for (int p = l.w2 - 1; p >= 0; --p)
            for (int i = 0; i < chains; ++i) {
                k[i] = v[i][p] + a * k[i];
                out[i][p] = norm * (out[i][p] + k[i] - v[i][p]);
            }
    }
    if (directions < 2) return;
    // Columns, all x of a row at once: forward pass into vfwd, backward pass in l.line.
    for (int c = 0; c < 3; ++c) {
        const float* v = l.bright + c * l.n2;
        float* fwd = l.vfwd + c * l.n2;
        std::copy(v, v + l.w2, fwd);
        for (int q = 1; q < l.h2; ++q) {
            const float* vq = v + static_cast<size_t>(q) * l.w2;
            float* f = fwd + static_cast<size_t>(q) * l.w2;
            const float* prev = f - l.w2;
            for (int p = 0; p < l.w2; ++p) f[p] = vq[p] + a * prev[p];
        }
        float* k = l.line;
        std::fill(k, k + l.w2, 0.0f);
        for (int q = l.h2 - 1; q >= 0; --q) {
            const float* vq = v + static_cast<size_t>(q) * l.w2;
            const float* f = fwd + static_cast<size_t>(q) * l.w2;
            float* out = l.flare + c * l.n2 + static_cast<size_t>(q) * l.w2;
            for (int p = 0; p < l.w2; ++p) {
                k[p] = vq[p] + a * k[p];
                out[p] += norm * (f[p] + k[p] - vq[p]);
            }
        }
    }
}

struct Geometry {
    float cx, cy;  // image centre, full-resolution pixel units
    float radius;  // |c|
    float halo_r, halo_w;
};

// acc[p] += gw[p] * (bilinear of the padded RGB0 row `src` at padded x gx[p]) for p in [p0, p1).
// gx in (0, w2 + 1): both taps inside the padded row.
FIRELOOK_ALWAYS_INLINE void addRowTaps(const Layout& l, const float* src, int p0, int p1) {
    for (int p = p0; p < p1; ++p) {
        const float x = l.gx[p];
        const int ix = static_cast<int>(x);
        const float t = x - static_cast<float>(ix);
        v4f a, b, s;
        load4(a, src + 4 * ix);
        load4(b, src + 4 * ix + 4);
        load4(s, l.acc + 4 * p);
        s += (l.gw[p] * (1.0f - t)) * a + (l.gw[p] * t) * b;
        store4(l.acc + 4 * p, s);
    }
}

// acc[p] += tint gw[p] (bilinear of the padded RGB0 image at padded (gx[p], gy[p])), p in [0, w2).
FIRELOOK_ALWAYS_INLINE void addImageTaps(const Layout& l, const v4f& tint) {
    for (int p = 0; p < l.w2; ++p) {
        const float x = l.gx[p], y = l.gy[p];
        const int ix = static_cast<int>(x), iy = static_cast<int>(y);
        const float tx = x - static_cast<float>(ix), ty = y - static_cast<float>(iy);
        const float* src = l.rgb0 + 4 * (static_cast<size_t>(iy) * l.pw + ix);
        v4f a, b, c, d, s;
        load4(a, src);
        load4(b, src + 4);
        load4(c, src + 4 * l.pw);
        load4(d, src + 4 * l.pw + 4);
        load4(s, l.acc + 4 * p);
        const float w = l.gw[p];
        const float w_top = w * (1.0f - ty), w_bottom = w * ty;
        s += tint * ((w_top * (1.0f - tx)) * a + (w_top * tx) * b + (w_bottom * (1.0f - tx)) * c + (w_bottom * tx) * d);
        store4(l.acc + 4 * p, s);
    }
}

// 3. Ghosts and halo of one low-res row q, added into l.flare.
FIRELOOK_ALWAYS_INLINE void ghostsAndHalo(const Layout& l, const Geometry& geo, const LensFlareSettings& s, int q) {
    const float py = 2.0f * static_cast<float>(q) + 1.0f;
    const float dy = py - geo.cy;
    const float inv_radius = 1.0f / geo.radius;
    for (int p = 0; p < l.w2 + 8; ++p) {  // the 8 of slack too: the loops below read whole vectors
        const float dx = 2.0f * static_cast<float>(p) + 1.0f - geo.cx;
        l.dist[p] = std::sqrt(dx * dx + dy * dy);
    }
    std::fill(l.acc, l.acc + 4 * static_cast<size_t>(l.w2), 0.0f);
    const float w2f = static_cast<float>(l.w2), h2f = static_cast<float>(l.h2);
    for (int i = 0; i < s.ghost_count; ++i) {
        // Ghost i samples b at c + scale (p - c); in padded low-res units: g = (c + scale (p - c)) / 2 + 1/2.
        const float scale = s.ghost_spacing * static_cast<float>(i + 1) * ((i % 2 == 0) ? -1.0f : 1.0f);
        const float abs_scale = std::fabs(scale);
        const float gy = 0.5f * (geo.cy + scale * dy) + 0.5f;
        if (!(gy > 0.0f && gy < h2f + 1.0f)) continue;  // the source row is outside the image
        const int iy = static_cast<int>(gy);
        const float ty = gy - static_cast<float>(iy);
        // The source row, interpolated between two padded rows and tinted.
        float* src = l.ghost + static_cast<size_t>(i) * 4 * l.pw;
        {
            const v4f tint = {kGhostTint[i][0], kGhostTint[i][1], kGhostTint[i][2], 0.0f};
            const v4f w_top = (1.0f - ty) * tint, w_bottom = ty * tint;
            const float* top = l.rgb0 + 4 * l.pw * static_cast<size_t>(iy);
            const float* bottom = top + 4 * l.pw;
            for (size_t x = 0; x < l.pw; ++x) {
                v4f a, b;
                load4(a, top + 4 * x);
                load4(b, bottom + 4 * x);
                store4(src + 4 * x, w_top * a + w_bottom * b);
            }
        }
        // Pixels whose sample lies inside the image: 0 < gx < w2 + 1, gx = x0 + step p.
        const float step = scale;  // (scale * 2) / 2
        const float x0 = 0.5f * (geo.cx + scale * (1.0f - geo.cx)) + 0.5f;
        int p0 = 0, p1 = l.w2;
        if (step != 0.0f) {
            const float pa = (0.0f - x0) / step, pb = (w2f + 1.0f - x0) / step;
            const float lo = std::min(pa, pb), hi = std::max(pa, pb);
            p0 = static_cast<int>(std::clamp(std::floor(lo), 0.0f, w2f));
            p1 = static_cast<int>(std::clamp(std::ceil(hi) + 1.0f, 0.0f, w2f));
        } else if (!(x0 > 0.0f && x0 < w2f + 1.0f)) {
            continue;
        }
        const v8f zero = {};
        for (int p = p0; p < p1; p += 8) {  // 8 at a time; the arrays have 8 floats of slack
            const v8f pv = static_cast<float>(p) + kLane;
            const v8f x = x0 + step * pv;
            const v8i inside = (x > 0.0f) & (x < w2f + 1.0f) & (pv < static_cast<float>(p1));
            v8f d;
            load8(d, l.dist + p);
            const v8f qd = abs_scale * inv_radius * d;  // |q - c| / |c|
            const v8f fade = qd < 1.0f ? (1.0f - qd) * (1.0f - qd) : zero;
            store8(l.gx + p, inside ? x : zero);
            store8(l.gw + p, inside ? fade : zero);
        }
        addRowTaps(l, src, p0, p1);
    }
    if (s.halo_intensity > 0.0f) {
        // Halo: samples b at q = p + R (c - p) / |c - p|, weight exp(-u^2), u = (|p - c| - R) / width;
        // skipped (weight 0) where exp(-u^2) <= 1e-4 or |p - c| <= 1e-3, as in the definition.
        const float inv_w = 1.0f / geo.halo_w;
        const v8f zero = {};
        for (int p = 0; p < l.w2; p += 8) {  // 8 at a time; the arrays have 8 floats of slack
            const v8f pv = static_cast<float>(p) + kLane;
            const v8f dx = 2.0f * pv + (1.0f - geo.cx);
            v8f d;
            load8(d, l.dist + p);
            const v8f u = (d - geo.halo_r) * inv_w;
            const v8f u2 = u * u;
            v8f ring;
            expNonPositive8(ring, -(u2 < 87.0f ? u2 : zero + 87.0f));
            const v8i on = (d > 1e-3f) & (ring > 1e-4f) & (pv < w2f);
            const v8f k = geo.halo_r / (on ? d : zero + 1.0f);
            const v8f x = 0.5f * (geo.cx + dx - k * dx) + 0.5f;
            const v8f y = 0.5f * (py - k * dy) + 0.5f;
            const v8i inside = on & (x > 0.0f) & (x < w2f + 1.0f) & (y > 0.0f) & (y < h2f + 1.0f);
            store8(l.gx + p, inside ? x : zero);
            store8(l.gy + p, inside ? y : zero);
            store8(l.gw + p, inside ? s.halo_intensity * ring : zero);
        }
        addImageTaps(l, v4f{kHaloTint[0], kHaloTint[1], kHaloTint[2], 0.0f});
    }
    float* fr = l.flare + static_cast<size_t>(q) * l.w2;
    float* fg = fr + l.n2;
    float* fb = fg + l.n2;
    for (int p = 0; p < l.w2; ++p) {
        fr[p] += l.acc[4 * p + 0];
        fg[p] += l.acc[4 * p + 1];
        fb[p] += l.acc[4 * p + 2];
    }
}

// 4. Bilinear 2x upsampling of l.flare (edges clamped) times `gain` into the RGBA output, alpha 0.
// Output pixels 2P and 2P + 1 of a row are 0.25 V[P-1] + 0.75 V[P] and 0.75 V[P] + 0.25 V[P+1],
// V the row of RGB0 low-res values: two 8-float loads from V, one 8-float store.
FIRELOOK_ALWAYS_INLINE void upsample(const Layout& l, int width, int height, float gain, float* flare_out) {
    float* v = l.up;  // pw RGB0 entries: v[0] = V[0], v[1 + P] = V[P], v[w2 + 1] = V[w2 - 1]
    const v8f w_left = {0.25f, 0.25f, 0.25f, 0.25f, 0.75f, 0.75f, 0.75f, 0.75f};
    const v8f w_right = {0.75f, 0.75f, 0.75f, 0.75f, 0.25f, 0.25f, 0.25f, 0.25f};
    const v8f zero = {};
    const v8f largest = zero + std::numeric_limits<float>::max();
    for (int y = 0; y < height; ++y) {
        // Low-res row coordinate of this row's centre: (y + 0.5) / 2 - 0.5 = y / 2 - 0.25.
        const int q = y / 2;
        const int q0 = y % 2 ? q : std::max(q - 1, 0);
        const int q1 = y % 2 ? std::min(q + 1, l.h2 - 1) : q;
        const float w0 = gain * (y % 2 ? 0.75f : 0.25f), w1 = gain - w0;
        const float* r0 = l.flare + static_cast<size_t>(q0) * l.w2;
        const float* r1 = l.flare + static_cast<size_t>(q1) * l.w2;
        for (int p = 0; p < l.w2; ++p) {
            v[4 * (p + 1) + 0] = w0 * r0[p] + w1 * r1[p];
            v[4 * (p + 1) + 1] = w0 * r0[p + l.n2] + w1 * r1[p + l.n2];
            v[4 * (p + 1) + 2] = w0 * r0[p + 2 * l.n2] + w1 * r1[p + 2 * l.n2];
            v[4 * (p + 1) + 3] = 0.0f;
        }
        std::copy(v + 4, v + 8, v);
        std::copy(v + 4 * l.w2, v + 4 * l.w2 + 4, v + 4 * (l.w2 + 1));
        float* out = flare_out + static_cast<size_t>(y) * width * 4;
        const int pairs = width / 2;
        for (int p = 0; p < pairs; ++p) {
            v8f left, right;
            load8(left, v + 4 * p);       // V[P-1], V[P]
            load8(right, v + 4 * p + 4);  // V[P], V[P+1]
            v8f o = w_left * left + w_right * right;
            o = (o > zero) & (o <= largest) ? o : zero;  // NaN, inf, negatives -> 0; lane 3, 7 stay 0
            store8(out + 8 * p, o);
        }
        if (width % 2) {
            v4f a, b;
            load4(a, v + 4 * pairs);
            load4(b, v + 4 * pairs + 4);
            v4f o = 0.25f * a + 0.75f * b;
            const v4f z4 = {};
            const v4f big4 = z4 + std::numeric_limits<float>::max();
            o = (o > z4) & (o <= big4) ? o : z4;
            store4(out + 8 * pairs, o);
        }
    }
}

// The whole flare for normalised settings. Two builds, picked once at load time by the CPU (as in
// basis/coefficients.cpp): AVX2 + FMA where available, the baseline elsewhere.
FIRELOOK_KERNEL_CLONES
void flareKernel(const float* rgba_in, int width, int height, const LensFlareSettings& s, float* scratch,
                 float* flare_out) {
    const Layout l = layout(width, height, scratch);
    if (s.intensity <= 0.0f || !brightPass(rgba_in, width, height, s.threshold, l)) {
        std::fill(flare_out, flare_out + static_cast<size_t>(width) * height * 4, 0.0f);
        return;
    }
    if (s.streaks > 0 && s.streak_intensity > 0.0f && s.streak_length > 0.0f) {
        // Decay length streak_length * width full-resolution pixels = half that in low-res pixels.
        const float a = std::exp(-1.0f / std::max(0.5f * s.streak_length * static_cast<float>(width), 1e-3f));
        streaks(l, s.streaks, a, s.streak_intensity);
    } else {
        std::fill(l.flare, l.flare + 3 * l.n2, 0.0f);
    }
    if (s.ghost_count > 0 || s.halo_intensity > 0.0f) {
        packRgb0(l);
        Geometry geo;
        geo.cx = 0.5f * static_cast<float>(width);
        geo.cy = 0.5f * static_cast<float>(height);
        geo.radius = std::sqrt(geo.cx * geo.cx + geo.cy * geo.cy);
        geo.halo_r = s.halo_radius * geo.radius;
        geo.halo_w = s.halo_width * geo.radius;
        for (int q = 0; q < l.h2; ++q) ghostsAndHalo(l, geo, s, q);
    }
    upsample(l, width, height, s.intensity, flare_out);
}

}  // namespace

void renderLensFlare(const float* rgba_in, int width, int height, const LensFlareSettings& s_in, float* scratch,
                     float* flare_out) {
    if (width <= 0 || height <= 0) return;
    LensFlareSettings s = s_in;
    s.threshold = std::isfinite(s.threshold) ? std::max(s.threshold, 0.0f) : 0.0f;
    s.intensity = finiteNonNegative(s.intensity);
    s.ghost_count = std::clamp(s.ghost_count, 0, kMaxGhosts);
    s.ghost_spacing = std::isfinite(s.ghost_spacing) ? std::clamp(s.ghost_spacing, -8.0f, 8.0f) : 0.0f;
    s.halo_radius = finiteNonNegative(s.halo_radius);
    s.halo_width = std::max(finiteNonNegative(s.halo_width), 1e-4f);
    s.halo_intensity = finiteNonNegative(s.halo_intensity);
    s.streak_length = finiteNonNegative(s.streak_length);
    s.streak_intensity = finiteNonNegative(s.streak_intensity);
    s.streaks = std::clamp(s.streaks, 0, 2);
    flareKernel(rgba_in, width, height, s, scratch, flare_out);
}

}  // namespace firelook::world
