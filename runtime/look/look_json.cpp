// The look file (docs/model.md, "The look file"): reading, writing, loading and saving.
#include <charconv>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <system_error>

#include "common/atomic_file.h"
#include "look/detail/look_error.h"
#include "look/look.h"

namespace firelook {
namespace {

using detail::indexedKey;
using detail::throwLookError;
using Json = nlohmann::json;

constexpr std::string_view kFormatTag = "firelook-look";
constexpr int kVersion = 1;  // bump when a reader of this version would misread a file

const char* typeName(const Json& value) { return value.type_name(); }

const Json& requireKey(const Json& object, const char* key, const std::string& source,
                       const std::string& path) {
    const auto it = object.find(key);
    if (it == object.end()) throwLookError(source, path, "is missing");
    return *it;
}

double readNumber(const Json& value, const std::string& source, const std::string& key) {
    if (!value.is_number())
        throwLookError(source, key, std::string("must be a number, got ") + typeName(value));
    return value.get<double>();
}

// An array of exactly `count` numbers, such as [r, g, b] or [T, r, g, b].
std::vector<double> readNumberArray(const Json& value, size_t count, const std::string& source,
                                    const std::string& key, const char* shape) {
    if (!value.is_array() || value.size() != count)
        throwLookError(source, key, std::string("must be an array ") + shape);
    std::vector<double> numbers;
    for (const Json& element : value) {
        if (!element.is_number())
            throwLookError(source, key,
                           std::string("must be an array ") + shape + " of numbers, got a " +
                               typeName(element) + " inside");
        numbers.push_back(element.get<double>());
    }
    return numbers;
}

Rgb toRgb(const std::vector<double>& numbers, size_t first) {
    return Rgb(static_cast<float>(numbers[first]), static_cast<float>(numbers[first + 1]),
               static_cast<float>(numbers[first + 2]));
}

const Json& requireArray(const Json& object, const char* key, const std::string& source,
                         const std::string& path) {
    const Json& value = requireKey(object, key, source, path);
    if (!value.is_array())
        throwLookError(source, path, std::string("must be an array, got ") + typeName(value));
    return value;
}

EmissionSpec readEmission(const Json& emission, const std::string& source) {
    if (!emission.is_object())
        throwLookError(source, "emission", std::string("must be an object, got ") + typeName(emission));
    const int forms = static_cast<int>(emission.contains("bins")) +
                      static_cast<int>(emission.contains("stops")) +
                      static_cast<int>(emission.contains("preset"));
    if (forms != 1)
        throwLookError(source, "emission", "must have exactly one of \"bins\", \"stops\" or \"preset\"");

    if (emission.contains("bins")) {
        EmissionBins bins;
        const Json& list = requireArray(emission, "bins", source, "emission.bins");
        for (size_t i = 0; i < list.size(); ++i)
            bins.emissivity.push_back(
                toRgb(readNumberArray(list[i], 3, source, indexedKey("emission.bins", i), "[r, g, b]"), 0));
        return bins;
    }
    if (emission.contains("stops")) {
        EmissionStops stops;
        const Json& list = requireArray(emission, "stops", source, "emission.stops");
        for (size_t i = 0; i < list.size(); ++i) {
            const std::vector<double> numbers =
                readNumberArray(list[i], 4, source, indexedKey("emission.stops", i), "[T, r, g, b]");
            stops.stops.push_back({numbers[0], toRgb(numbers, 1)});
        }
        return stops;
    }
    EmissionPreset preset;
    const Json& name = emission.at("preset");
    if (!name.is_string())
        throwLookError(source, "emission.preset", std::string("must be a string, got ") + typeName(name));
    preset.name = name.get<std::string>();
    if (emission.contains("scale")) preset.scale = readNumber(emission.at("scale"), source, "emission.scale");
    return preset;
}

// Shortest text that reads back to the same value (std::to_chars); a float
// colour is written as a float so 0.1f appears as 0.1, not 0.10000000149011612.
template <typename Number>
std::string formatNumber(Number value) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
    return std::string(buffer, result.ptr);
}

std::string formatRgb(const Rgb& c) {
    return formatNumber(c.r) + ", " + formatNumber(c.g) + ", " + formatNumber(c.b);
}

// One entry per line, e.g. "[\n    [1, 0.5, 0],\n    [2, 1, 0]\n  ]".
template <typename Item, typename Format>
std::string formatList(const std::vector<Item>& items, Format format) {
    if (items.empty()) return "[]";
    std::string text = "[";
    for (size_t i = 0; i < items.size(); ++i)
        text += std::string(i == 0 ? "\n" : ",\n") + "    [" + format(items[i]) + "]";
    return text + "\n  ]";
}

}  // namespace

Look parseLook(std::string_view text, const std::string& source_name) {
    Json root;
    try {
        root = Json::parse(text.begin(), text.end());
    } catch (const Json::exception& error) {  // syntax errors, and numbers too large for a double
        throwLookError(source_name, "", std::string("not valid JSON: ") + error.what());
    }
    if (!root.is_object()) throwLookError(source_name, "", "a look file must be a JSON object");

    const Json& format = requireKey(root, "format", source_name, "format");
    if (!format.is_string() || format.get<std::string>() != kFormatTag)
        throwLookError(source_name, "format",
                       "must be \"firelook-look\", got " + format.dump() + " (is this a look file?)");
    const Json& version = requireKey(root, "version", source_name, "version");
    if (!version.is_number_integer() || version.get<long long>() < 1)
        throwLookError(source_name, "version", "must be a positive integer, got " + version.dump());
    if (version.get<long long>() > kVersion)
        throwLookError(source_name, "version",
                       "is " + version.dump() + ", written by a newer FireLook; this build reads version " +
                           std::to_string(kVersion));

    Look look;
    look.source_name = source_name;
    const auto number = [&](const char* key) {
        return readNumber(requireKey(root, key, source_name, key), source_name, key);
    };
    look.temperature_threshold = number("temperature_threshold");
    look.smoke_extinction = number("smoke_extinction");
    look.flame_extinction = number("flame_extinction");
    look.albedo = number("albedo");
    look.emission = readEmission(requireKey(root, "emission", source_name, "emission"), source_name);
    const Json& lights = requireArray(root, "light_irradiance", source_name, "light_irradiance");
    for (size_t i = 0; i < lights.size(); ++i)
        look.light_irradiance.push_back(toRgb(
            readNumberArray(lights[i], 3, source_name, indexedKey("light_irradiance", i), "[r, g, b]"), 0));

    validateLook(look);
    return look;
}

Look loadLook(const std::filesystem::path& path) {
    std::ifstream file(path, std::ios::binary);
    // Coded as I/O, not as a bad look, so the C API can tell a missing file from bad JSON.
    if (!file) throw LookError(ErrorCode::IoError, path.string() + ": cannot open the look file (missing or unreadable)");
    std::ostringstream contents;
    contents << file.rdbuf();
    if (file.bad()) throw LookError(ErrorCode::IoError, path.string() + ": error while reading the look file");
    return parseLook(contents.str(), path.string());
}

std::string lookToJson(const Look& look) {
    validateLook(look);
    std::string emission;
    if (const auto* bins = std::get_if<EmissionBins>(&look.emission)) {
        emission = "{\"bins\": " + formatList(bins->emissivity, formatRgb) + "}";
    } else if (const auto* stops = std::get_if<EmissionStops>(&look.emission)) {
        const auto format_stop = [](const EmissionStop& s) {
            return formatNumber(s.temperature) + ", " + formatRgb(s.emissivity);
        };
        emission = "{\"stops\": " + formatList(stops->stops, format_stop) + "}";
    } else {
        const auto& preset = std::get<EmissionPreset>(look.emission);
        emission =
            "{\"preset\": " + Json(preset.name).dump() + ", \"scale\": " + formatNumber(preset.scale) + "}";
    }
    return std::string("{\n") +                                      //
           "  \"format\": \"" + std::string(kFormatTag) + "\",\n" +  //
           "  \"version\": " + std::to_string(kVersion) + ",\n" +    //
           "  \"temperature_threshold\": " + formatNumber(look.temperature_threshold) + ",\n" +
           "  \"smoke_extinction\": " + formatNumber(look.smoke_extinction) + ",\n" +
           "  \"flame_extinction\": " + formatNumber(look.flame_extinction) + ",\n" +
           "  \"albedo\": " + formatNumber(look.albedo) + ",\n" +  //
           "  \"emission\": " + emission + ",\n" +                 //
           "  \"light_irradiance\": " + formatList(look.light_irradiance, formatRgb) + "\n}\n";
}

void saveLook(const std::filesystem::path& path, const Look& look) {
    try {
        writeFileAtomically(path, lookToJson(look));
    } catch (const Error& error) {
        if (error.code() == ErrorCode::Look) throw;  // the look itself (validateLook), already named
        // The message already names the file: "<path>: cannot ...".
        std::string problem = error.what();
        if (problem.starts_with(path.string() + ": ")) problem.erase(0, path.string().size() + 2);
        throwLookError(path.string(), "", "cannot write the look file: " + problem);
    }
}

}  // namespace firelook
