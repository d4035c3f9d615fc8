#include "look_edit.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "fl_check.h"

namespace firelook::viewer {
namespace {

using Json = nlohmann::ordered_json;

Json rgbJson(const Rgb3& c) { return Json::array({c[0], c[1], c[2]}); }

Rgb3 rgbFrom(const Json& j) {
    return {j.at(0).get<float>(), j.at(1).get<float>(), j.at(2).get<float>()};
}

// Releases an fl_look at scope exit.
struct LookHolder {
    fl_look look{};
    ~LookHolder() {
        if (look.id) fl_look_release(look);
    }
};

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
    static const std::vector<std::string> names = {"fire", "blackbody"};
    return names;
}

std::string lookEditToJson(const LookEdit& look) {
    Json j;
    j["format"] = "firelook-look";
    j["version"] = 1;
    j["temperature_threshold"] = look.temperature_threshold;
    j["smoke_extinction"] = look.smoke_extinction;
    j["flame_extinction"] = look.flame_extinction;
    j["albedo"] = look.albedo;
    Json emission = Json::object();
    switch (look.mode) {
        case EmissionMode::Preset:
            emission["preset"] = look.preset;
            emission["scale"] = look.preset_scale;
            break;
        case EmissionMode::Stops: {
            Json stops = Json::array();
            for (const EmissionStop& s : look.stops)
                stops.push_back(Json::array({s.temperature, s.emissivity[0], s.emissivity[1], s.emissivity[2]}));
            emission["stops"] = stops;
            break;
        }
        case EmissionMode::Bins: {
            Json bins = Json::array();
            for (const Rgb3& b : look.bins) bins.push_back(rgbJson(b));
            emission["bins"] = bins;
            break;
        }
    }
    j["emission"] = emission;
    Json lights = Json::array();
    for (const Rgb3& l : look.lights) lights.push_back(rgbJson(l));
    j["light_irradiance"] = lights;
    return j.dump(2);
}

fl_look makeFlLook(const LookEdit& look, const std::string& source) {
    const std::string json = lookEditToJson(look);
    fl_look handle{};
    check(fl_look_from_json(json.c_str(), json.size(), source.c_str(), &handle), "fl_look_from_json");
    return handle;
}

std::string canonicalLookJson(const LookEdit& look) {
    LookHolder holder;
    holder.look = makeFlLook(look, "look");
    return lookToJsonText(holder.look);
}

LookEdit parseLookEdit(const std::string& json, const std::string& source) {
    LookHolder holder;
    check(fl_look_from_json(json.c_str(), json.size(), source.c_str(), &holder.look), "fl_look_from_json");
    // The library's own JSON has every key in one canonical form, so reading it cannot miss a case.
    const Json j = Json::parse(lookToJsonText(holder.look));
    LookEdit look;
    look.temperature_threshold = j.at("temperature_threshold").get<double>();
    look.smoke_extinction = j.at("smoke_extinction").get<double>();
    look.flame_extinction = j.at("flame_extinction").get<double>();
    look.albedo = j.at("albedo").get<double>();
    const Json& e = j.at("emission");
    if (e.contains("preset")) {
        look.mode = EmissionMode::Preset;
        look.preset = e.at("preset").get<std::string>();
        look.preset_scale = e.value("scale", 1.0);
    } else if (e.contains("stops")) {
        look.mode = EmissionMode::Stops;
        for (const Json& s : e.at("stops"))
            look.stops.push_back({s.at(0).get<double>(), {s.at(1).get<float>(), s.at(2).get<float>(), s.at(3).get<float>()}});
    } else {
        look.mode = EmissionMode::Bins;
        for (const Json& b : e.at("bins")) look.bins.push_back(rgbFrom(b));
    }
    for (const Json& l : j.at("light_irradiance")) look.lights.push_back(rgbFrom(l));
    return look;
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
