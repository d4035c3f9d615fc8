#include "basis/frame_factors.h"

#include <algorithm>
#include <glm/gtc/packing.hpp>
#include <memory_resource>

#include "basis/frame_codec.h"

namespace firelook::basis {

std::vector<float> decodeU(const FrameFactors& factors) {
    std::vector<float> u(factors.u_half.size());
    for (size_t i = 0; i < u.size(); ++i) u[i] = glm::unpackHalf1x16(factors.u_half[i]);
    return u;
}

FrameFactors emptyFrameFactors(const BakeDescription& description, int frame, int rank) {
    FrameFactors f;
    f.frame = frame;
    f.pixels = description.pixelCount();
    f.columns = description.columnCount();
    f.rank = rank;
    return f;
}

FrameFactors expandFrame(const BakeDescription& description, const ResidentFrame& r) {
    FrameFactors f = emptyFrameFactors(description, r.frame, r.rank);
    const size_t pixels = static_cast<size_t>(f.pixels);
    f.u_half.resize(pixels * r.rank);
    for (size_t p = 0; p < pixels; ++p)
        for (int k = 0; k < r.rank; ++k)
            f.u_half[p * r.rank + k] = glm::packHalf1x16(r.w[p * r.rank_stride + k] * r.u_scale[k]);
    f.svt.assign(r.svt.begin(), r.svt.end());
    const size_t thresholds = description.alpha_thresholds.size();
    const int samples = description.footprint_samples;
    f.depth_b.resize(pixels * samples);
    f.depth_a.resize(pixels * samples * thresholds);
    const std::vector<float>& table = r.depth_table->depth;
    const int last = static_cast<int>(table.size()) - 1;
    auto depth = [&](int q) { return table[static_cast<size_t>(std::clamp(q, 0, last))]; };
    size_t next_detailed = 0;
    for (size_t p = 0; p < pixels; ++p) {
        const bool detailed =
            next_detailed < r.detailed_pixels.size() && static_cast<size_t>(r.detailed_pixels[next_detailed]) == p;
        for (int s = 0; s < samples; ++s) {
            const int16_t* v = detailed ? r.detailed_depth.data() + (next_detailed * samples + s) * r.depth_stride
                                        : r.mean_depth.data() + p * r.depth_stride;
            const float o_b = depth(v[0]);
            f.depth_b[static_cast<size_t>(s) * pixels + p] = o_b;
            // O_a = 2 F - O_b = O_b - 2 S.
            for (size_t j = 0; j < thresholds; ++j)
                f.depth_a[(static_cast<size_t>(s) * thresholds + j) * pixels + p] =
                    o_b - 2.0f * depth(int(v[0]) - int(v[1 + j]));
        }
        if (detailed) ++next_detailed;
    }
    return f;
}

FrameFactors decodeFrame(const BakeDescription& description, int frame, int rank, std::span<const std::byte> u,
                         std::span<const std::byte> svt, std::span<const std::byte> depths,
                         const std::string& source) {
    return expandFrame(description,
                       decodeResidentFrame(description, frame, rank, u, svt, depths, source,
                                           std::pmr::get_default_resource(), nullptr));
}

}  // namespace firelook::basis
