// What `bake` and `reference` share so their images are directly comparable:
// the sequence, the camera, the lights and the temperature bins, all resolved
// the same way from the same options (docs/cli.md).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "look/look_model.h"
#include "render/camera.h"
#include "render/medium.h"
#include "vdb/vdb_sequence.h"

namespace firelook::bake {

// The sphere `--lights sphere` bakes (basis/sphere_lights.h): 42 lights, the fewest that relight
// within the README's bar ("Light from any direction").
inline constexpr int kDefaultSphereLights = 42;

struct SceneOptions {
    std::string scene_path;                       // glTF: first perspective camera + directional lights
    std::optional<std::array<double, 7>> camera;  // position xyz, target xyz, vertical fov in degrees
    render::UpAxis up = render::UpAxis::Y;
    int width = 256;
    int height = 256;
    // `--lights six-way`: six camera-relative lights after the scene's own (basis/six_way_lights.h).
    bool six_way_lights = false;
    // `--lights sphere:N`: N camera-relative lights on a geodesic sphere after the scene's own
    // (basis/sphere_lights.h); 0 without them. Not together with six_way_lights.
    int sphere_lights = 0;
};

struct SceneSetup {
    render::Camera camera;
    std::vector<glm::dvec3> light_directions;  // direction each light travels
    std::vector<Rgb> light_colors;             // from the scene (color * intensity), else defaults
    std::string camera_source;                 // "default", "--camera" or the glTF file
    int six_way_first_light = -1;              // index of the first six-way light, -1 without them
    int sphere_first_light = -1;               // index of the first sphere light, -1 without them
    std::vector<std::array<int, 3>> sphere_triangles;  // the sphere lights' geodesic triangles
};

// Without a scene, one default light shines from above and in front of the camera. With
// options.six_way_lights the six camera-relative lights follow, with options.sphere_lights the
// sphere's; both with zero colour.
SceneSetup resolveScene(const vdb::VdbSequence& sequence, const SceneOptions& options);

// [min, max] of the temperature over every frame of the sequence (loads each frame once).
// The range includes the temperature grids' background (ambient air: 0 for Blender's heat, 300 in
// Kelvin), so ambient air sits in bin 0.
std::pair<double, double> sequenceTemperatureRange(const vdb::VdbSequence& sequence);
// The same range gathered one frame at a time (a bake's one pass over the sequence).
struct TemperatureSpan {
    std::optional<double> lo, hi;  // none before the first frame
    void add(const vdb::VolumeFrame& frame);
    std::pair<double, double> range() const;
};

// Parses "A-B,C,..." into its ranges ([first, last], a single frame as [C, C]); empty gives none.
// An InvalidArgument Error naming the text when it is not such a list.
std::vector<std::pair<int, int>> parseFrameRanges(const std::string& selection);

// Parses "A-B,C,..." into the frames of the sequence it selects (all when empty).
std::vector<int> selectFrames(const vdb::VdbSequence& sequence, const std::string& range);

// Parses "WxH".
std::pair<int, int> parseSize(const std::string& text);

}  // namespace firelook::bake
