#include "gpu_layers.h"

#include <algorithm>
#include <glm/gtc/packing.hpp>

namespace firelook::plugin {

size_t uLayerElements(int rank, size_t pixels) { return (static_cast<size_t>(rank) + 3) / 4 * pixels * 4; }

size_t depthLayerFloats(const basis::BakeDescription& d) {
    return static_cast<size_t>(d.pixelCount()) * static_cast<size_t>(d.footprint_samples) *
           (1 + d.alpha_thresholds.size());
}

void writeULayers(const basis::ResidentFrame& f, uint16_t* out) {
    const size_t pixels = static_cast<size_t>(f.pixels), rank = static_cast<size_t>(f.rank);
    std::fill(out, out + uLayerElements(f.rank, pixels), uint16_t{0});
    // U = W u_scale rounded to half, as basis::expandFrame.
    for (size_t p = 0; p < pixels; ++p) {
        const int16_t* w = f.w.data() + p * static_cast<size_t>(f.rank_stride);
        for (size_t k = 0; k < rank; ++k)
            out[((k / 4) * pixels + p) * 4 + k % 4] = glm::packHalf1x16(w[k] * f.u_scale[k]);
    }
}

void writeDepthLayers(const basis::BakeDescription& d, const basis::ResidentFrame& f, float* out) {
    const size_t pixels = static_cast<size_t>(f.pixels), thresholds = d.alpha_thresholds.size();
    const size_t samples = static_cast<size_t>(d.footprint_samples), stride = static_cast<size_t>(f.depth_stride);
    const std::vector<float>& table = f.depth_table->depth;
    const int last = static_cast<int>(table.size()) - 1;
    const auto depth = [&](int q) { return table[static_cast<size_t>(std::clamp(q, 0, last))]; };
    // Layer by layer, each written front to back in one stream: writing pixel-major across all
    // S (1 + T) layers strides over hundreds of them per pixel and took five times as long
    // (tests/plugin_api/bench_frame_layers).
    std::vector<const int16_t*> rays(pixels);
    for (size_t s = 0; s < samples; ++s) {
        size_t next_detailed = 0;
        for (size_t p = 0; p < pixels; ++p) {
            const bool detailed = next_detailed < f.detailed_pixels.size() &&
                                  static_cast<size_t>(f.detailed_pixels[next_detailed]) == p;
            // A pixel that kept only its mean ray gives it to every sample.
            rays[p] = detailed ? f.detailed_depth.data() + (next_detailed++ * samples + s) * stride
                               : f.mean_depth.data() + p * stride;
        }
        float* o_b = out + s * pixels;
        for (size_t p = 0; p < pixels; ++p) o_b[p] = depth(rays[p][0]);
        for (size_t j = 0; j < thresholds; ++j) {  // O_a = O_b - 2 S_j
            float* o_a = out + (samples + s * thresholds + j) * pixels;
            for (size_t p = 0; p < pixels; ++p) o_a[p] = o_b[p] - 2.0f * depth(int(rays[p][0]) - int(rays[p][1 + j]));
        }
    }
}

}  // namespace firelook::plugin
