// Bake settings for end-to-end bakes that take well under a second: a 2-point T_c axis, everything
// else collapsed, few photons. The command-line tests write it as bake.json next to the package.
// Shared by every test suite (included as "../support/tiny_bake_config.h").
#pragma once

namespace firelook::testing {

inline constexpr const char* kTinyBakeConfig = R"({
    "bins": 4, "t_lo": 0, "t_hi": 3,
    "axes": {"temperature_threshold": [1.0, 2.0], "smoke_extinction": 4, "flame_extinction": 1.5},
    "alpha_threshold_samples": 3,
    "trace": {"photons_primary": 2000, "photons_per_order": 1000, "photon_noise_target": 0, "max_orders": 3, "cell_voxels": 8}
})";

}  // namespace firelook::testing
