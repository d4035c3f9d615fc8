// What a baked package holds and how to read its factors: the numbers the
// runtime needs to turn a look into an image. Stored as the "bake" object of
// the package's META JSON (docs/package-format.md, "Baked basis layout").
#pragma once

#include <array>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "basis/parameter_grid.h"
#include "look/look_model.h"

namespace firelook::basis {

struct FrameRecord {
    int frame = 0;
    int rank = 0;
};

// What fixes the basis images: the bake traces them from this (baker/bake/basis_tracer.h), the
// runtime weights their columns by it. A BakeDescription is this plus how the package stores them.
struct BasisModel {
    TemperatureBins bins;
    double rbf_width = 0.9;          // Gaussian RBF width in units of dT
    // The emission rule the basis was traced with (look_model.h, EmissionBasis::clamp_to_centres).
    bool emission_clamp_to_centres = true;
    double albedo = 0.8;             // fixed at bake time
    ParameterAxes axes;              // sampled extinction parameters
    std::vector<double> alpha_thresholds;  // T_c samples of the per-pixel optical depth maps
    std::vector<glm::dvec3> light_directions;  // direction each light travels, world space
    // Index of the first of the six camera-relative lights of `bake --lights six-way`
    // (six_way_lights.h), which follow the scene's own lights; -1 when the bake has none.
    int six_way_first_light = -1;
    // The lights of `bake --lights sphere:N` (sphere_lights.h), after the scene's own: the first's
    // index (-1 without them; never together with six-way lights), their count N and their
    // geodesic triangles (indices 0..N-1 from sphere_first_light), which relight.h interpolates on.
    int sphere_first_light = -1;
    int sphere_light_count = 0;
    std::vector<std::array<int, 3>> sphere_triangles;

    // The lights a run-time light direction is made of (relight.h): the six-way or the sphere
    // lights, as [first, first + count); first is -1 (and count 0) without either.
    int relightFirstLight() const {
        return six_way_first_light >= 0 ? six_way_first_light : sphere_first_light;
    }
    int relightLightCount() const;

    int columnsPerPoint() const { return bins.count + static_cast<int>(light_directions.size()); }
    int columnCount() const { return axes.pointCount() * columnsPerPoint(); }
};

struct BakeDescription : BasisModel {
    // Optical depths are stored for this many rays per pixel (a square grid over
    // its footprint) so alpha = mean of 1 - exp(-tau) is exact for any (k_s, k_f).
    int footprint_samples = 1;
    int width = 0;
    int height = 0;
    std::vector<FrameRecord> frames;
    std::string default_look_json;   // a firelook-look document

    int pixelCount() const { return width * height; }  // parseBakeDescription bounds it by 2^28
    const FrameRecord* findFrame(int frame) const;
};

// JSON of the "bake" object; parse errors throw a Corrupt Error naming `source`.
std::string bakeDescriptionToJson(const BakeDescription& description);
BakeDescription parseBakeDescription(const std::string& json_text, const std::string& source);

}  // namespace firelook::basis
