// The look as the viewer edits it: the fields of a firelook-look document (docs/model.md, "The look file") in
// plain editable form. The C API has no look accessors, only JSON in and out, so the viewer keeps
// this struct and turns it into JSON (then an fl_look) whenever it changes.
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

// The emission presets the look format knows (runtime/look/emission_presets.cpp). The C API does
// not list them, so they are named here; fl_look_from_json still validates the choice.
const std::vector<std::string>& presetNames();

// JSON text of a look document. Numbers are written with full precision, so the look round-trips
// exactly (a float emissivity survives double formatting and parsing unchanged).
std::string lookEditToJson(const LookEdit& look);

// Validates `json` with the library (fl_look_from_json; errors name `source`), then reads the
// library's canonical JSON of it into a LookEdit. Throws ViewerError.
LookEdit parseLookEdit(const std::string& json, const std::string& source);

// An fl_look for `look` (caller releases). Throws ViewerError with the library's message.
fl_look makeFlLook(const LookEdit& look, const std::string& source);

// fl_look_to_json's text of an fl_look. Throws ViewerError.
std::string lookToJsonText(fl_look look);

// The canonical look-file text the CLI reads and writes (fl_look_to_json of the look).
std::string canonicalLookJson(const LookEdit& look);

// Colour + intensity view of an emissivity: intensity = the largest channel, colour = e / intensity.
struct ColourIntensity {
    Rgb3 colour{1.0f, 1.0f, 1.0f};
    float intensity = 0.0f;
};
ColourIntensity splitEmissivity(const Rgb3& e);
Rgb3 joinEmissivity(const ColourIntensity& c);

}  // namespace firelook::viewer
