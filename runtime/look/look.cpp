#include "look/look.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "look/detail/look_error.h"
#include "look/emission_fit.h"
#include "look/emission_presets.h"

namespace firelook {
namespace {

using detail::indexedKey;
using detail::throwLookError;

void checkNonNegative(const Look& look, std::string_view key, double value) {
    if (!std::isfinite(value)) throwLookError(look.source_name, key, "must be a finite number");
    if (value < 0.0) throwLookError(look.source_name, key, "must be >= 0, got " + std::to_string(value));
}

void checkColor(const Look& look, const std::string& key, const Rgb& color) {
    for (int channel = 0; channel < 3; ++channel) {
        if (!std::isfinite(color[channel]))
            throwLookError(look.source_name, key,
                           "colour components must be finite (and fit a 32-bit float)");
        if (color[channel] < 0.0f)
            throwLookError(look.source_name, key,
                           "colour components must be >= 0, got " + std::to_string(color[channel]));
    }
}

std::string presetList() {
    std::string list;
    for (const std::string& name : presetNames()) list += (list.empty() ? "" : ", ") + name;
    return list;
}

void checkBins(const Look& look, const TemperatureBins& bins) {
    if (bins.count < 1 || !std::isfinite(bins.t_lo) || !std::isfinite(bins.t_hi) ||
        !(bins.t_hi > bins.t_lo) || !(bins.width() > 0.0))
        throwLookError(look.source_name, "",
                       "cannot resolve against " + std::to_string(bins.count) + " temperature bins over [" +
                           std::to_string(bins.t_lo) + ", " + std::to_string(bins.t_hi) +
                           "]: need at least one bin and a finite, non-empty range");
}

Rgb evaluateStops(const std::vector<EmissionStop>& stops, double t) {
    if (t <= stops.front().temperature) return stops.front().emissivity;
    if (t >= stops.back().temperature) return stops.back().emissivity;
    // First stop hotter than t; the one before it is at or below t, so the
    // segment has positive length even where two stops share a temperature.
    const auto next =
        std::upper_bound(stops.begin(), stops.end(), t,
                         [](double value, const EmissionStop& s) { return value < s.temperature; });
    const auto previous = next - 1;
    const double f = (t - previous->temperature) / (next->temperature - previous->temperature);
    return previous->emissivity + static_cast<float>(f) * (next->emissivity - previous->emissivity);
}

}  // namespace

Look defaultLook() {
    Look look;
    look.temperature_threshold = 1.4;  // just below ignition (~1.5) so the flame front reads as flame
    look.smoke_extinction = 6.0;       // dense smoke: opaque over a few tenths of a world unit
    look.flame_extinction = 1.5;       // flames are thinner, so the glowing core shows through
    look.albedo = 0.7;                 // grey, not white, smoke
    look.emission = EmissionStops{{
        {1.4, Rgb(0.0f, 0.0f, 0.0f)},    // smoke does not glow
        {1.8, Rgb(1.5f, 0.35f, 0.04f)},  // deep orange-red at the flame front
        {2.3, Rgb(5.0f, 2.2f, 0.35f)},   // orange
        {3.0, Rgb(10.0f, 7.0f, 3.0f)},   // yellow-white core
    }};
    look.light_irradiance = {Rgb(2.5f, 2.4f, 2.25f)};  // warm daylight, bright enough to show the smoke
    look.source_name = "default look";
    return look;
}

void validateLook(const Look& look) {
    if (!std::isfinite(look.temperature_threshold))
        throwLookError(look.source_name, "temperature_threshold", "must be a finite number");
    checkNonNegative(look, "smoke_extinction", look.smoke_extinction);
    checkNonNegative(look, "flame_extinction", look.flame_extinction);
    if (!(look.albedo >= 0.0 && look.albedo <= 1.0))
        throwLookError(look.source_name, "albedo",
                       "must be within [0, 1], got " + std::to_string(look.albedo));

    if (const auto* bins = std::get_if<EmissionBins>(&look.emission)) {
        if (bins->emissivity.empty()) throwLookError(look.source_name, "emission.bins", "must not be empty");
        for (size_t i = 0; i < bins->emissivity.size(); ++i)
            checkColor(look, indexedKey("emission.bins", i), bins->emissivity[i]);
    } else if (const auto* stops = std::get_if<EmissionStops>(&look.emission)) {
        if (stops->stops.empty()) throwLookError(look.source_name, "emission.stops", "must not be empty");
        for (size_t i = 0; i < stops->stops.size(); ++i) {
            const std::string key = indexedKey("emission.stops", i);
            const double t = stops->stops[i].temperature;
            if (!std::isfinite(t)) throwLookError(look.source_name, key, "temperature must be finite");
            if (i > 0 && t < stops->stops[i - 1].temperature)
                throwLookError(look.source_name, key,
                               "temperatures must not decrease from one stop to the next");
            checkColor(look, key, stops->stops[i].emissivity);
        }
    } else {
        const auto& preset = std::get<EmissionPreset>(look.emission);
        if (!findEmissionPreset(preset.name))
            throwLookError(look.source_name, "emission.preset",
                           "unknown preset \"" + preset.name + "\"; known presets: " + presetList());
        checkNonNegative(look, "emission.scale", preset.scale);
    }

    for (size_t i = 0; i < look.light_irradiance.size(); ++i)
        checkColor(look, indexedKey("light_irradiance", i), look.light_irradiance[i]);
}

std::vector<Rgb> resolveBinEmissivity(const Look& look, const TemperatureBins& bins) {
    validateLook(look);
    checkBins(look, bins);
    const int n = bins.count;
    std::vector<Rgb> emissivity(n);
    if (const auto* given = std::get_if<EmissionBins>(&look.emission)) {
        if (static_cast<int>(given->emissivity.size()) != n)
            throwLookError(look.source_name, "emission.bins",
                           "has " + std::to_string(given->emissivity.size()) + " entries, but there are " +
                               std::to_string(n) + " temperature bins (one entry per bin is required)");
        emissivity = given->emissivity;
    } else if (const auto* stops = std::get_if<EmissionStops>(&look.emission)) {
        for (int i = 0; i < n; ++i) emissivity[i] = evaluateStops(stops->stops, bins.center(i));
    } else {
        const auto& preset = std::get<EmissionPreset>(look.emission);
        const EmissionPresetDefinition* definition = findEmissionPreset(preset.name);
        for (int i = 0; i < n; ++i)
            emissivity[i] = definition->evaluate((i + 0.5) / n) * static_cast<float>(preset.scale);
    }
    return emissivity;
}

LookModel makeLookModel(const Look& look, const TemperatureBins& bins, double rbf_width,
                        std::span<const glm::dvec3> light_directions) {
    const std::vector<Rgb> emissivity = resolveBinEmissivity(look, bins);
    if (!std::isfinite(rbf_width) || !(rbf_width > 0.0))
        throwLookError(look.source_name, "",
                       "RBF width must be positive and finite, got " + std::to_string(rbf_width));
    if (look.light_irradiance.size() != light_directions.size())
        throwLookError(look.source_name, "light_irradiance",
                       "has " + std::to_string(look.light_irradiance.size()) +
                           " entries, but the scene has " + std::to_string(light_directions.size()) +
                           " directional light(s)");

    LookModel model;
    model.bins = bins;
    model.extinction = look.extinction();
    model.albedo = look.albedo;
    model.emission.basis = EmissionBasis{bins, rbf_width};
    model.emission.coefficients = fitEmissionCoefficients(model.emission.basis, emissivity);
    for (size_t l = 0; l < light_directions.size(); ++l) {
        const glm::dvec3& d = light_directions[l];
        const double length = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        if (!std::isfinite(length) || !(length > 0.0))
            throwLookError(look.source_name, "",
                           "direction of light " + std::to_string(l) + " is zero or not finite");
        model.lights.push_back({d / length, look.light_irradiance[l]});
    }
    return model;
}

}  // namespace firelook
