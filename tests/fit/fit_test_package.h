// A small package for the fit tests, baked once per test process: frames 6-7 of the bundled sample
// at 32x32, 8 bins, a 3 x 2 x 2 grid over (T_c, k_s, k_f) kept whole (no axis collapses), few photons
// and a coarse light-depth grid (about 0.4 s of one core for both frames).
#pragma once

#include <filesystem>
#include <random>

#include "../support/temp_dir.h"
#include "bake/bake_pipeline.h"
#include "look/look.h"

namespace firelook::fit::test {

inline const std::filesystem::path& fitTestPackage() {
    static const firelook::testing::TempDir dir;
    static const std::filesystem::path path = [] {
        bake::BakeConfig c;
        c.frames = "6-7";
        c.scene.width = 32;
        c.scene.height = 32;
        c.scene.up = render::UpAxis::Z;
        c.bins = 8;
        c.t_lo = 0.0;
        c.t_hi = 3.0;
        c.axes = {{1.0, 1.5, 2.0}, {2.0, 8.0}, {0.5, 3.0}};
        c.collapse_unused_axes = false;
        c.alpha_threshold_samples = 5;
        c.trace.photons_primary = 4000;
        c.trace.photons_per_order = 2000;
        c.trace.photon_noise_target = 0.0;  // as many photons as given: the suite stays fast
        c.trace.max_orders = 3;
        c.trace.cell_voxels = 8;
        // The light's depths at 32^3 points instead of 128^3: the bake's dominant cost at this size
        // (2.6 of its 3.1 s per frame), and any light field serves a fit of the package's own images.
        c.trace.light_points_per_axis = 32;
        const std::filesystem::path out = dir / "fit.firelook";
        bake::bakePackage(FIRELOOK_SAMPLE_DIR, out, c, "test");
        return out;
    }();
    return path;
}

// A look drawn inside the test package's axes: T_c, k_s, k_f uniform in their ranges, an emission
// ramp rising with temperature (random colour per bin), a random light.
inline Look randomLook(std::mt19937& rng, int bins) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Look look;
    look.temperature_threshold = 1.0 + u(rng);
    look.smoke_extinction = 2.0 + 6.0 * u(rng);
    look.flame_extinction = 0.5 + 2.5 * u(rng);
    look.albedo = 0.7;  // the bake's default
    EmissionBins e;
    for (int i = 0; i < bins; ++i) {
        const float ramp = static_cast<float>(i * i) / static_cast<float>(bins);
        e.emissivity.push_back(Rgb(ramp * (1.0 + u(rng)), ramp * 0.5 * u(rng), ramp * 0.2 * u(rng)));
    }
    look.emission = e;
    look.light_irradiance = {Rgb(static_cast<float>(0.5 + u(rng)), static_cast<float>(0.5 + u(rng)),
                                 static_cast<float>(0.5 + u(rng)))};
    look.source_name = "random look";
    return look;
}

}  // namespace firelook::fit::test
