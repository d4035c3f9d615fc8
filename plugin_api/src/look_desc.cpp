#include "look_desc.h"

#include <cstring>
#include <stdexcept>

#include "common/error.h"
#include <vector>

namespace firelook::plugin {
namespace {

// Count x 3 floats as colours; a null array with a count above 0 is the caller's mistake.
std::vector<Rgb> coloursOf(const float* values, uint32_t count, const char* what) {
    if (count > 0 && !values) throw Error(ErrorCode::InvalidArgument, std::string("desc->") + what + " is null");
    std::vector<Rgb> colours;
    for (uint32_t i = 0; i < count; ++i) colours.emplace_back(values[3 * i], values[3 * i + 1], values[3 * i + 2]);
    return colours;
}

}  // namespace

Look lookFromDesc(const fl_look_desc& desc, const std::string& source_name) {
    Look look;
    look.source_name = source_name;
    look.temperature_threshold = desc.temperature_threshold;
    look.smoke_extinction = desc.smoke_extinction;
    look.flame_extinction = desc.flame_extinction;
    look.albedo = desc.albedo;
    switch (desc.emission_form) {
        case FL_EMISSION_PRESET: {
            const size_t length = strnlen(desc.preset, sizeof desc.preset);
            if (length == sizeof desc.preset) throw Error(ErrorCode::InvalidArgument, "desc->preset is not NUL-terminated");
            look.emission = EmissionPreset{std::string(desc.preset, length), desc.preset_scale};
            break;
        }
        case FL_EMISSION_STOPS: {
            if (desc.stop_count > 0 && !desc.stops) throw Error(ErrorCode::InvalidArgument, "desc->stops is null");
            EmissionStops stops;
            for (uint32_t i = 0; i < desc.stop_count; ++i) {
                const double* s = desc.stops + 4 * i;
                stops.stops.push_back({s[0], Rgb(static_cast<float>(s[1]), static_cast<float>(s[2]),
                                                 static_cast<float>(s[3]))});
            }
            look.emission = std::move(stops);
            break;
        }
        case FL_EMISSION_BINS:
            look.emission = EmissionBins{coloursOf(desc.bins, desc.bin_count, "bins")};
            break;
        default:
            throw Error(ErrorCode::InvalidArgument, "desc->emission_form " + std::to_string(desc.emission_form) +
                                        " is not FL_EMISSION_PRESET, _STOPS or _BINS");
    }
    look.light_irradiance = coloursOf(desc.lights, desc.light_count, "lights");
    validateLook(look);  // LookError naming source_name and the key
    return look;
}

fl_look_desc descOf(const Look& look) {
    fl_look_desc desc{};
    desc.temperature_threshold = look.temperature_threshold;
    desc.smoke_extinction = look.smoke_extinction;
    desc.flame_extinction = look.flame_extinction;
    desc.albedo = look.albedo;
    if (const auto* preset = std::get_if<EmissionPreset>(&look.emission)) {
        desc.emission_form = FL_EMISSION_PRESET;
        if (preset->name.size() >= sizeof desc.preset)
            throw Error(ErrorCode::InvalidArgument, "preset name \"" + preset->name + "\" does not fit fl_look_desc.preset");
        std::memcpy(desc.preset, preset->name.c_str(), preset->name.size() + 1);
        desc.preset_scale = preset->scale;
    } else if (const auto* stops = std::get_if<EmissionStops>(&look.emission)) {
        desc.emission_form = FL_EMISSION_STOPS;
        desc.stop_count = static_cast<uint32_t>(stops->stops.size());
    } else {
        desc.emission_form = FL_EMISSION_BINS;
        desc.bin_count = static_cast<uint32_t>(std::get<EmissionBins>(look.emission).emissivity.size());
    }
    desc.light_count = static_cast<uint32_t>(look.light_irradiance.size());
    return desc;
}

void writeLookArrays(const Look& look, std::span<double> stops, std::span<float> bins, std::span<float> lights) {
    if (const auto* s = std::get_if<EmissionStops>(&look.emission); s && !stops.empty())
        for (size_t i = 0; i < s->stops.size(); ++i) {
            stops[4 * i] = s->stops[i].temperature;
            for (int c = 0; c < 3; ++c) stops[4 * i + 1 + c] = s->stops[i].emissivity[c];
        }
    if (const auto* b = std::get_if<EmissionBins>(&look.emission); b && !bins.empty())
        for (size_t i = 0; i < b->emissivity.size(); ++i)
            for (int c = 0; c < 3; ++c) bins[3 * i + c] = b->emissivity[i][c];
    if (!lights.empty())
        for (size_t i = 0; i < look.light_irradiance.size(); ++i)
            for (int c = 0; c < 3; ++c) lights[3 * i + c] = look.light_irradiance[i][c];
}

}  // namespace firelook::plugin
