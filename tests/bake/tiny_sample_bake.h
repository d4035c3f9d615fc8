// A bake of the bundled sample kept tiny (16x16, few photons, a 2x1x1 parameter grid, frame 1
// unless changed), shared by the bake pipeline, merge and resume tests.
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "bake/bake_config.h"

namespace firelook::bake::test {

inline BakeConfig tinyConfig(uint64_t seed = 1) {
    BakeConfig c;
    c.frames = "1";
    c.scene.width = 16;
    c.scene.height = 16;
    c.scene.up = render::UpAxis::Z;
    c.bins = 4;
    // Given explicitly, so the bake does not load all 12 frames to find the range.
    c.t_lo = 0.0;
    c.t_hi = 3.0;
    c.axes = {{1.0, 2.0}, {4.0}, {1.5}};
    c.alpha_threshold_samples = 3;
    c.trace.photons_primary = 2000;
    c.trace.photons_per_order = 1000;
    c.trace.photon_noise_target = 0.0;  // as many photons as given: the suite stays fast
    c.trace.max_orders = 3;
    c.trace.cell_voxels = 8;
    c.seed = seed;
    return c;
}

inline std::string fileBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace firelook::bake::test
