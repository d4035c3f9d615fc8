// The user-facing look: the few parameters an artist edits (docs/model.md)
// and the look file that stores them (docs/model.md, "The look file").
//
// A Look is what the user wrote, in the data's temperature units; a LookModel
// (look_model.h) is the same look resolved against a package's temperature
// bins and scene lights, ready to evaluate.
#pragma once

#include <filesystem>
#include <glm/vec3.hpp>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "common/error.h"
#include "look/look_model.h"

namespace firelook {

// Any problem with a look; the message names the file (or look) and the key. Code ErrorCode::Look, or
// ErrorCode::IoError for a look file that cannot be read (loadLook).
class LookError : public Error {
  public:
    explicit LookError(const std::string& message) : Error(ErrorCode::Look, message) {}
    LookError(ErrorCode code, const std::string& message) : Error(code, message) {}
};

// {"bins": [[r,g,b], ...]}: one emissivity per temperature bin.
struct EmissionBins {
    std::vector<Rgb> emissivity;
};

// {"stops": [[T, r,g,b], ...]}: linear between stops (temperatures in the data's
// units, non-decreasing), clamped outside; evaluated at the bin centres.
struct EmissionStop {
    double temperature = 0.0;
    Rgb emissivity{0.0f};
};
struct EmissionStops {
    std::vector<EmissionStop> stops;
};

// {"preset": NAME, "scale": S}: a named ramp over [T_lo, T_hi] (emission_presets.h).
struct EmissionPreset {
    std::string name;
    double scale = 1.0;
};

using EmissionSpec = std::variant<EmissionBins, EmissionStops, EmissionPreset>;

struct Look {
    double temperature_threshold = 0.0;  // T_c, in the data's temperature units
    double smoke_extinction = 1.0;       // k_s, per unit density per world unit
    double flame_extinction = 1.0;       // k_f
    double albedo = 0.8;                 // fixed when a package is baked
    EmissionSpec emission = EmissionPreset{"fire", 1.0};
    std::vector<Rgb> light_irradiance;  // one per directional light of the scene
    // Where this look came from, for error messages; not part of the file.
    std::string source_name;

    ExtinctionParams extinction() const {
        return {temperature_threshold, smoke_extinction, flame_extinction};
    }
};

// A fire look for data like the bundled Blender explosion: temperatures 0..3 in
// units of 1000 K above ambient, ignition around 1.5, one directional light.
Look defaultLook();

// Checks every value's range (finite; extinctions, emissivity, scale and
// irradiance >= 0; albedo in [0, 1]; stops sorted; preset known).
void validateLook(const Look& look);

// Reads a look file's text. `source_name` (usually the path) prefixes every
// error. Every key shown in docs/model.md, "The look file", is required except the preset's
// "scale" (default 1); unknown keys are ignored.
Look parseLook(std::string_view json, const std::string& source_name);
// parseLook of a file; a file that cannot be opened or read throws a LookError coded ErrorCode::IoError.
Look loadLook(const std::filesystem::path& path);

// Writes the look file; parseLook(lookToJson(l)) gives l back exactly.
std::string lookToJson(const Look& look);
// Atomic: writes a temporary file beside `path`, then renames it over `path`.
void saveLook(const std::filesystem::path& path, const Look& look);

// The emissivity e_i at each bin centre. Throws if "bins" has the wrong count.
std::vector<Rgb> resolveBinEmissivity(const Look& look, const TemperatureBins& bins);

// Everything a renderer needs: extinction, albedo, emission fitted with
// fitEmissionCoefficients() at `rbf_width` (units of dT), and lights pairing
// look.light_irradiance[l] with light_directions[l] (normalised here; the
// counts must match).
LookModel makeLookModel(const Look& look, const TemperatureBins& bins, double rbf_width,
                        std::span<const glm::dvec3> light_directions);

}  // namespace firelook
