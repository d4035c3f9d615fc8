// One frame as the runtime keeps it resident for reconstruction: the frame codec's quantised
// values themselves (docs/package-format.md, "Frame codec"), not an expansion of them. Decoding a
// frame into this form is the codec's prediction undone and nothing more, so it takes about as
// long as reading the frame's bytes (tests/world/bench_frame_decode), and the form is about a
// third of the float layout of FrameFactors (frame_factors.h), which the tools and the GPU upload
// (fl_package_get_frame_u / _depths) still use.
//
//   U:      W = U S on a grid, int16 per value, pixel-major with each pixel's row zero-padded to
//           `rank_stride` (a multiple of 8); U[p][k] = w[p * rank_stride + k] * u_scale[k].
//   S V^T:  float, as FrameFactors::svt (columns x rank, column-major).
//   Depths: codes on the companding grid (DepthTable turns a code into an optical depth). Every
//           pixel has its mean ray, 1 + thresholds int16 (zero-padded to `depth_stride`, a
//           multiple of 8): q(O_b), then
//           e_j = q(O_b) - q(S_j) per alpha threshold, with S_j = (O_b - O_a(T_c,j)) / 2 the smoke
//           part; so O_b = D[q], O_a(j) = D[q] - 2 D[q - e_j]. Pixels whose footprint rays differ
//           ("detailed", sorted) also keep every ray: footprint_samples rows of depth_stride each.
//           A pixel's alpha is that of its mean ray, or the mean of its rays' alphas if detailed.
//   Runs:   the pixels whose W row (u_runs) or mean-ray codes (depth_runs) are not all 0, as runs in
//           scan order: what the payload codes (version 3 on; every pixel before). Every other row
//           is 0, so such a pixel's radiance (or, unless detailed, its alpha) is 0 for any look and
//           reconstructImage does not read it: a frame costs what its fire covers.
//
// Memory comes from a std::pmr::memory_resource (the world routes it to the host's allocator).
#pragma once

#include <cstdint>
#include <memory>
#include <memory_resource>
#include <vector>

namespace firelook::basis {

// Optical depth of every code of one companding grid: D[q] = g^-1(q step), at most 2^15 + 1
// entries. Built once and shared by every frame stored on the same grid.
struct DepthTable {
    double step = 0.0, k_lo = 0.0, k_hi = 0.0;  // the grid (frame payloads carry these)
    std::vector<float> depth;                   // D[q], q in [0, levels]
    bool sameGrid(double s, double lo, double hi) const { return step == s && k_lo == lo && k_hi == hi; }
    size_t bytes() const { return depth.capacity() * sizeof(float); }
    static std::shared_ptr<const DepthTable> build(double step, double k_lo, double k_hi);
};

// Pixels [first, first + count) in scan order.
struct PixelRun {
    int32_t first = 0;
    int32_t count = 0;
};

struct ResidentFrame {
    explicit ResidentFrame(std::pmr::memory_resource* memory = std::pmr::get_default_resource())
        : w(memory), u_scale(memory), svt(memory), mean_depth(memory), detailed_pixels(memory),
          detailed_depth(memory), u_runs(memory), depth_runs(memory) {}

    int frame = 0;
    int pixels = 0;
    int columns = 0;
    int rank = 0;
    int rank_stride = 0;   // rank rounded up to a multiple of 8
    int depth_stride = 0;  // 1 + alpha thresholds, rounded up to a multiple of 8
    int samples = 1;       // footprint rays of a detailed pixel

    std::pmr::vector<int16_t> w;            // pixels x rank_stride
    std::pmr::vector<float> u_scale;        // rank_stride (0 beyond rank)
    std::pmr::vector<float> svt;            // columns x rank
    std::pmr::vector<int16_t> mean_depth;   // pixels x depth_stride
    std::pmr::vector<int32_t> detailed_pixels;  // increasing
    std::pmr::vector<int16_t> detailed_depth;   // detailed x samples x depth_stride
    std::pmr::vector<PixelRun> u_runs;          // increasing, disjoint, non-empty
    std::pmr::vector<PixelRun> depth_runs;
    std::shared_ptr<const DepthTable> depth_table;

    // Bytes held, by capacity (the depth table is shared and counted once by its owner).
    size_t bytes() const {
        return w.capacity() * sizeof(int16_t) + u_scale.capacity() * sizeof(float) + svt.capacity() * sizeof(float) +
               mean_depth.capacity() * sizeof(int16_t) + detailed_pixels.capacity() * sizeof(int32_t) +
               detailed_depth.capacity() * sizeof(int16_t) +
               (u_runs.capacity() + depth_runs.capacity()) * sizeof(PixelRun);
    }
};

}  // namespace firelook::basis
