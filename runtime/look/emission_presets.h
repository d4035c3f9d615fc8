// Named emissivity ramps for the look file's {"preset": NAME, "scale": S}.
//
// A preset is a colour over normalised temperature u in [0, 1] across the
// bins' [T_lo, T_hi], so the same name fits data in any temperature unit.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "look/look_model.h"

namespace firelook {

struct EmissionPresetDefinition {
    std::string_view name;
    std::string_view description;
    Rgb (*evaluate)(double u);  // u is clamped into [0, 1]; values >= 0, luminance ~1 at u = 1
};

std::span<const EmissionPresetDefinition> emissionPresets();

// nullptr if no preset has this name.
const EmissionPresetDefinition* findEmissionPreset(std::string_view name);

std::vector<std::string> presetNames();

}  // namespace firelook
