#include "look/emission_presets.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "look/blackbody.h"

namespace firelook {
namespace {

double clampUnit(double u) { return u > 0.0 ? std::min(u, 1.0) : 0.0; }  // NaN -> 0

// The colour-temperature range the blackbody preset spans: a dull red glow at
// the cold end to the yellow-white of a hot flame.
constexpr double kBlackbodyColdKelvin = 1000.0;
constexpr double kBlackbodyHotKelvin = 3500.0;

// Chromaticity from Planck's law; intensity follows the radiated power
// (Stefan-Boltzmann, T^4) relative to the cold end, so it is 0 at u = 0 and 1 at u = 1.
Rgb blackbody(double u) {
    const double kelvin = kBlackbodyColdKelvin + clampUnit(u) * (kBlackbodyHotKelvin - kBlackbodyColdKelvin);
    const double cold4 = std::pow(kBlackbodyColdKelvin, 4);
    const double intensity = (std::pow(kelvin, 4) - cold4) / (std::pow(kBlackbodyHotKelvin, 4) - cold4);
    return Rgb(blackbodyColor(kelvin) * intensity);
}

// An artist's ramp in linear sRGB: black -> dark red -> orange -> yellow-white.
Rgb fire(double u) {
    struct Stop {
        double u;
        Rgb color;
    };
    static constexpr std::array<Stop, 5> kStops{{
        {0.00, Rgb(0.00f, 0.00f, 0.00f)},
        {0.25, Rgb(0.12f, 0.01f, 0.00f)},
        {0.50, Rgb(0.45f, 0.10f, 0.01f)},
        {0.75, Rgb(0.90f, 0.45f, 0.08f)},
        {1.00, Rgb(1.20f, 1.00f, 0.70f)},
    }};
    u = clampUnit(u);
    for (size_t i = 1; i < kStops.size(); ++i) {
        if (u <= kStops[i].u) {
            const float t = static_cast<float>((u - kStops[i - 1].u) / (kStops[i].u - kStops[i - 1].u));
            return kStops[i - 1].color + t * (kStops[i].color - kStops[i - 1].color);
        }
    }
    return kStops.back().color;
}

constexpr std::array<EmissionPresetDefinition, 2> kPresets{{
    {"blackbody", "Planck colour from 1000 K to 3500 K, intensity rising as T^4", blackbody},
    {"fire", "artist ramp black -> red -> orange -> yellow-white", fire},
}};

}  // namespace

std::span<const EmissionPresetDefinition> emissionPresets() { return kPresets; }

const EmissionPresetDefinition* findEmissionPreset(std::string_view name) {
    for (const EmissionPresetDefinition& preset : kPresets)
        if (preset.name == name) return &preset;
    return nullptr;
}

std::vector<std::string> presetNames() {
    std::vector<std::string> names;
    for (const EmissionPresetDefinition& preset : kPresets) names.emplace_back(preset.name);
    return names;
}

}  // namespace firelook
