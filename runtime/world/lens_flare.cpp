#include "world/lens_flare.h"

#include <algorithm>
#include <cmath>

namespace firelook::runtime {
namespace {

float finiteNonNegative(float v) { return v > 0.0f && std::isfinite(v) ? v : 0.0f; }

struct Image3 {
    const float* data;
    int w, h;
    // Bilinear at pixel-centre coordinates (x, y) in pixel units (pixel i's centre at i + 0.5), zero outside.
    void sample(float x, float y, float out[3]) const {
        out[0] = out[1] = out[2] = 0.0f;
        const float fx = x - 0.5f, fy = y - 0.5f;
        if (!(fx > -1.0f && fy > -1.0f && fx < static_cast<float>(w) && fy < static_cast<float>(h))) return;
        const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
        const float tx = fx - x0, ty = fy - y0;
        for (int j = 0; j < 2; ++j) {
            const int yy = y0 + j;
            if (yy < 0 || yy >= h) continue;
            const float wy = j ? ty : 1.0f - ty;
            for (int i = 0; i < 2; ++i) {
                const int xx = x0 + i;
                if (xx < 0 || xx >= w) continue;
                const float wgt = wy * (i ? tx : 1.0f - tx);
                const float* p = data + (static_cast<size_t>(yy) * w + xx) * 3;
                out[0] += wgt * p[0];
                out[1] += wgt * p[1];
                out[2] += wgt * p[2];
            }
        }
    }
};

// Two-sided exponential blur of n values spaced `stride` floats apart (3 channels interleaved), in place
// through `tmp` (n * 3 floats).
void expBlurLine(float* line, int n, size_t stride, float a, float* tmp) {
    const float norm = (1.0f - a) / (1.0f + a);
    float f[3] = {0, 0, 0};
    for (int x = 0; x < n; ++x) {
        const float* v = line + x * stride;
        for (int c = 0; c < 3; ++c) {
            f[c] = v[c] + a * f[c];
            tmp[x * 3 + c] = f[c];
        }
    }
    float bk[3] = {0, 0, 0};
    for (int x = n - 1; x >= 0; --x) {
        float* v = line + x * stride;
        for (int c = 0; c < 3; ++c) {
            const float original = v[c];
            bk[c] = original + a * bk[c];
            v[c] = norm * (tmp[x * 3 + c] + bk[c] - original);
        }
    }
}

constexpr float kGhostTint[8][3] = {{1.0f, 0.75f, 0.45f}, {0.55f, 0.8f, 1.0f}, {1.0f, 0.55f, 0.35f},
                                    {0.6f, 1.0f, 0.7f},   {0.9f, 0.6f, 1.0f},  {1.0f, 0.9f, 0.6f},
                                    {0.5f, 0.7f, 1.0f},   {1.0f, 0.7f, 0.7f}};
constexpr float kHaloTint[3] = {0.8f, 0.85f, 1.0f};

}  // namespace

void renderLensFlare(const float* rgba_in, int width, int height, const LensFlareSettings& s_in, float* scratch,
                     float* flare_out) {
    if (width <= 0 || height <= 0) return;
    LensFlareSettings s = s_in;
    s.threshold = std::isfinite(s.threshold) ? std::max(s.threshold, 0.0f) : 0.0f;
    s.intensity = finiteNonNegative(s.intensity);
    s.ghost_count = std::clamp(s.ghost_count, 0, 8);
    s.ghost_spacing = std::isfinite(s.ghost_spacing) ? std::clamp(s.ghost_spacing, -8.0f, 8.0f) : 0.0f;
    s.halo_radius = finiteNonNegative(s.halo_radius);
    s.halo_width = std::max(finiteNonNegative(s.halo_width), 1e-4f);
    s.halo_intensity = finiteNonNegative(s.halo_intensity);
    s.streak_length = finiteNonNegative(s.streak_length);
    s.streak_intensity = finiteNonNegative(s.streak_intensity);
    s.streaks = std::clamp(s.streaks, 0, 2);

    const size_t pixels = static_cast<size_t>(width) * height;
    float* bright = scratch;             // pixels x 3
    float* streak = scratch + pixels * 3;  // pixels x 3 (the first row/column also serves as line scratch)
    for (size_t p = 0; p < pixels; ++p) {
        const float r = finiteNonNegative(rgba_in[p * 4 + 0]);
        const float g = finiteNonNegative(rgba_in[p * 4 + 1]);
        const float b = finiteNonNegative(rgba_in[p * 4 + 2]);
        const float lum = 0.2126f * r + 0.7152f * g + 0.0722f * b;
        const float k = lum > s.threshold && lum > 0.0f ? (lum - s.threshold) / lum : 0.0f;
        bright[p * 3 + 0] = r * k;
        bright[p * 3 + 1] = g * k;
        bright[p * 3 + 2] = b * k;
    }

    // Streaks into `streak`.
    const bool any_streak = s.streaks > 0 && s.streak_intensity > 0.0f && s.streak_length > 0.0f;
    if (any_streak) {
        std::copy(bright, bright + pixels * 3, streak);
        // Line scratch: the flare output itself (not yet written), width or height x 3 floats fit in it.
        float* line_tmp = flare_out;
        const float ax = std::exp(-1.0f / std::max(s.streak_length * width, 1e-3f));
        for (int y = 0; y < height; ++y) expBlurLine(streak + static_cast<size_t>(y) * width * 3, width, 3, ax, line_tmp);
        if (s.streaks == 2 && width >= 2) {
            // A second copy blurred along columns, summed in: re-derive from bright per column.
            for (int x = 0; x < width; ++x) {
                // Column of `bright` blurred into line_tmp2 = flare_out + height*3 (fits: 4 * pixels >= 6 * height).
                float* col = flare_out + static_cast<size_t>(height) * 3;
                for (int y = 0; y < height; ++y)
                    for (int c = 0; c < 3; ++c) col[y * 3 + c] = bright[(static_cast<size_t>(y) * width + x) * 3 + c];
                expBlurLine(col, height, 3, ax, line_tmp);
                for (int y = 0; y < height; ++y)
                    for (int c = 0; c < 3; ++c) streak[(static_cast<size_t>(y) * width + x) * 3 + c] += col[y * 3 + c];
            }
        }
    }

    const Image3 img{bright, width, height};
    const float cx = 0.5f * width, cy = 0.5f * height;
    const float radius = std::sqrt(cx * cx + cy * cy);
    const float halo_r = s.halo_radius * radius;
    const float halo_w = s.halo_width * radius;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float px = x + 0.5f, py = y + 0.5f;
            const float dx = px - cx, dy = py - cy;
            float sum[3] = {0, 0, 0};
            float v[3];
            for (int i = 0; i < s.ghost_count; ++i) {
                const float scale = s.ghost_spacing * (i + 1) * ((i % 2 == 0) ? -1.0f : 1.0f);
                const float qx = cx + scale * dx, qy = cy + scale * dy;
                const float qd = std::sqrt((qx - cx) * (qx - cx) + (qy - cy) * (qy - cy)) / radius;
                if (qd >= 1.0f) continue;
                const float fade = (1.0f - qd) * (1.0f - qd);
                img.sample(qx, qy, v);
                for (int c = 0; c < 3; ++c) sum[c] += fade * kGhostTint[i][c] * v[c];
            }
            if (s.halo_intensity > 0.0f) {
                const float d = std::sqrt(dx * dx + dy * dy);
                if (d > 1e-3f) {
                    const float u = (d - halo_r) / halo_w;
                    const float ring = std::exp(-u * u);
                    if (ring > 1e-4f) {
                        img.sample(px - halo_r * dx / d, py - halo_r * dy / d, v);
                        for (int c = 0; c < 3; ++c) sum[c] += s.halo_intensity * ring * kHaloTint[c] * v[c];
                    }
                }
            }
            float* out = flare_out + (static_cast<size_t>(y) * width + x) * 4;
            const size_t p = static_cast<size_t>(y) * width + x;
            for (int c = 0; c < 3; ++c) {
                const float st = any_streak ? s.streak_intensity * streak[p * 3 + c] : 0.0f;
                out[c] = finiteNonNegative(s.intensity * (sum[c] + st));
            }
            out[3] = 0.0f;
        }
    }
}

}  // namespace firelook::runtime
