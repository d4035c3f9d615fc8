// The look as the viewer edits it: an fl_look_desc (firelook.h) in editable C++ form. Looks come in
// and go out through the C API only (fl_look_create / fl_look_get_desc, fl_look_from_json,
// fl_look_load_file, fl_look_to_json), so the viewer holds no copy of the look file's schema.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "firelook/firelook.h"

namespace firelook::viewer {

using Rgb3 = std::array<float, 3>;

enum class EmissionMode { Preset, Stops, Bins };

struct EmissionStop {
    double temperature = 0.0;
    Rgb3 emissivity{0.0f, 0.0f, 0.0f};
    bool operator==(const EmissionStop&) const = default;
};

struct LookEdit {
    double temperature_threshold = 0.0;
    double smoke_extinction = 1.0;
    double flame_extinction = 1.0;
    double albedo = 0.8;  // fixed by the package; shown, not edited
    EmissionMode mode = EmissionMode::Preset;
    std::string preset = "fire";
    double preset_scale = 1.0;
    std::vector<EmissionStop> stops;
    std::vector<Rgb3> bins;
    std::vector<Rgb3> lights;  // irradiance per light

    bool operator==(const LookEdit&) const = default;
};

// The emission presets the library knows (fl_emission_preset_count / fl_emission_preset_name).
const std::vector<std::string>& presetNames();

// The values of an fl_look (fl_look_get_desc). Throws ViewerError.
LookEdit lookEditOf(fl_look look);

// Validates `json` with the library (fl_look_from_json; errors name `source`) and reads its values.
// Throws ViewerError.
LookEdit parseLookEdit(const std::string& json, const std::string& source);

// A look file read by the library (fl_look_load_file; errors name the path). Throws ViewerError.
LookEdit loadLookEdit(const std::string& path);

// An fl_look for `look` (fl_look_create; caller releases). Throws ViewerError with the library's
// message, which names `source` and the key.
fl_look makeFlLook(const LookEdit& look, const std::string& source);

// fl_look_to_json's text of an fl_look. Throws ViewerError.
std::string lookToJsonText(fl_look look);

// The look-file text the CLI reads and writes (fl_look_to_json of the look). Throws ViewerError.
std::string canonicalLookJson(const LookEdit& look);

// Colour + intensity view of an emissivity: intensity = the largest channel, colour = e / intensity.
struct ColourIntensity {
    Rgb3 colour{1.0f, 1.0f, 1.0f};
    float intensity = 0.0f;
};
ColourIntensity splitEmissivity(const Rgb3& e);
Rgb3 joinEmissivity(const ColourIntensity& c);

}  // namespace firelook::viewer
