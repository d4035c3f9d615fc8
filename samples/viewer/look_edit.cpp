#include "look_edit.h"

#include <algorithm>

#include "fl_check.h"

namespace firelook::viewer {
namespace {

// Releases an fl_look at scope exit.
struct LookHolder {
    fl_look look{};
    ~LookHolder() {
        if (look.id) fl_look_release(look);
    }
};

Rgb3 rgbAt(const float* values, size_t i) { return {values[3 * i], values[3 * i + 1], values[3 * i + 2]}; }

}  // namespace

std::string lookToJsonText(fl_look look) {
    size_t size = 0;
    check(fl_look_to_json(look, nullptr, 0, &size), "fl_look_to_json");
    std::string text(size, '\0');
    check(fl_look_to_json(look, text.data(), text.size(), &size), "fl_look_to_json");
    text.resize(size > 0 ? size - 1 : 0);  // drop the NUL
    return text;
}

const std::vector<std::string>& presetNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> list;
        uint32_t count = 0;
        check(fl_emission_preset_count(&count), "fl_emission_preset_count");
        for (uint32_t i = 0; i < count; ++i) {
            size_t size = 0;
            check(fl_emission_preset_name(i, nullptr, 0, &size), "fl_emission_preset_name");
            std::string name(size, '\0');
            check(fl_emission_preset_name(i, name.data(), name.size(), &size), "fl_emission_preset_name");
            name.resize(size > 0 ? size - 1 : 0);
            list.push_back(name);
        }
        return list;
    }();
    return names;
}

fl_look makeFlLook(const LookEdit& look, const std::string& source) {
    fl_look_desc desc = fl_look_desc_defaults();
    desc.temperature_threshold = look.temperature_threshold;
    desc.smoke_extinction = look.smoke_extinction;
    desc.flame_extinction = look.flame_extinction;
    desc.albedo = look.albedo;
    std::vector<double> stops;
    std::vector<float> bins, lights;
    switch (look.mode) {
        case EmissionMode::Preset:
            desc.emission_form = FL_EMISSION_PRESET;
            // A name too long for the field stays unterminated: the library refuses it.
            std::copy_n(look.preset.begin(), std::min(look.preset.size(), sizeof desc.preset), desc.preset);
            desc.preset_scale = look.preset_scale;
            break;
        case EmissionMode::Stops:
            desc.emission_form = FL_EMISSION_STOPS;
            for (const EmissionStop& s : look.stops)
                stops.insert(stops.end(), {s.temperature, s.emissivity[0], s.emissivity[1], s.emissivity[2]});
            desc.stops = stops.data();
            desc.stop_count = static_cast<uint32_t>(look.stops.size());
            break;
        case EmissionMode::Bins:
            desc.emission_form = FL_EMISSION_BINS;
            for (const Rgb3& b : look.bins) bins.insert(bins.end(), b.begin(), b.end());
            desc.bins = bins.data();
            desc.bin_count = static_cast<uint32_t>(look.bins.size());
            break;
    }
    for (const Rgb3& l : look.lights) lights.insert(lights.end(), l.begin(), l.end());
    desc.lights = lights.data();
    desc.light_count = static_cast<uint32_t>(look.lights.size());
    fl_look handle{};
    check(fl_look_create(&desc, source.c_str(), &handle), "fl_look_create");
    return handle;
}

LookEdit lookEditOf(fl_look handle) {
    fl_look_desc desc = fl_look_desc_defaults();
    check(fl_look_get_desc(handle, &desc, nullptr, 0, nullptr, 0, nullptr, 0), "fl_look_get_desc");
    std::vector<double> stops(4 * size_t{desc.stop_count});
    std::vector<float> bins(3 * size_t{desc.bin_count}), lights(3 * size_t{desc.light_count});
    check(fl_look_get_desc(handle, &desc, stops.data(), desc.stop_count, bins.data(), desc.bin_count, lights.data(),
                           desc.light_count),
          "fl_look_get_desc");
    LookEdit look;
    look.temperature_threshold = desc.temperature_threshold;
    look.smoke_extinction = desc.smoke_extinction;
    look.flame_extinction = desc.flame_extinction;
    look.albedo = desc.albedo;
    if (desc.emission_form == FL_EMISSION_PRESET) {
        look.mode = EmissionMode::Preset;
        look.preset = desc.preset;  // NUL-terminated by the library
        look.preset_scale = desc.preset_scale;
    } else if (desc.emission_form == FL_EMISSION_STOPS) {
        look.mode = EmissionMode::Stops;
        for (size_t i = 0; i < desc.stop_count; ++i)
            look.stops.push_back({stops[4 * i],
                                  {static_cast<float>(stops[4 * i + 1]), static_cast<float>(stops[4 * i + 2]),
                                   static_cast<float>(stops[4 * i + 3])}});
    } else {
        look.mode = EmissionMode::Bins;
        for (size_t i = 0; i < desc.bin_count; ++i) look.bins.push_back(rgbAt(bins.data(), i));
    }
    for (size_t i = 0; i < desc.light_count; ++i) look.lights.push_back(rgbAt(lights.data(), i));
    return look;
}

std::string canonicalLookJson(const LookEdit& look) {
    LookHolder holder;
    holder.look = makeFlLook(look, "look");
    return lookToJsonText(holder.look);
}

LookEdit parseLookEdit(const std::string& json, const std::string& source) {
    LookHolder holder;
    check(fl_look_from_json(json.c_str(), json.size(), source.c_str(), &holder.look), "fl_look_from_json");
    return lookEditOf(holder.look);
}

LookEdit loadLookEdit(const std::string& path) {
    LookHolder holder;
    check(fl_look_load_file(path.c_str(), &holder.look), "fl_look_load_file");
    return lookEditOf(holder.look);
}

ColourIntensity splitEmissivity(const Rgb3& e) {
    const float m = std::max({e[0], e[1], e[2]});
    if (!(m > 0.0f)) return {{1.0f, 1.0f, 1.0f}, 0.0f};
    return {{e[0] / m, e[1] / m, e[2] / m}, m};
}

Rgb3 joinEmissivity(const ColourIntensity& c) {
    return {c.colour[0] * c.intensity, c.colour[1] * c.intensity, c.colour[2] * c.intensity};
}

}  // namespace firelook::viewer
