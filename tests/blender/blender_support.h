// What the Blender tests share: whether Blender can run here (they skip, saying why, where it
// cannot), and a tiny bake of the bundled sample whose camera and lights Cycles is handed.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "../support/command.h"
#include "../support/sample.h"
#include "../support/temp_dir.h"

namespace firelook::testing {

// Empty when `blender` runs here; else why not (the reason a test skips with).
inline std::string whyNoBlender() {
    const TempDir dir;
    const CommandResult r = runIn(dir, "blender -b --factory-startup --python-expr 'import bpy' 2>&1");
    if (r.exit_code == 0) return "";
    return "Blender is not installed or does not run (`blender -b` exited " + std::to_string(r.exit_code) +
           "; scripts/setup.sh installs it from Debian)";
}

// bake.json: the tiny bake's speed (few photons, no axes to speak of: export-cycles reads only the
// package's camera, lights, bins, albedo and provenance) with the default 16 bins, so the emission
// fit has as many RBFs as a real bake's.
inline constexpr const char* kCyclesBakeConfig = R"({
    "bins": 16,
    "axes": {"temperature_threshold": [1.0, 2.0], "smoke_extinction": 4, "flame_extinction": 1.5},
    "alpha_threshold_samples": 3,
    "trace": {"photons_primary": 2000, "photons_per_order": 1000, "photon_noise_target": 0, "max_orders": 3, "cell_voxels": 8}
})";

// The flags a bake and its references share (same camera, lights and bins).
inline const std::string kCyclesSceneFlags = "--size 64x64 --up z --config bake.json";

}  // namespace firelook::testing
