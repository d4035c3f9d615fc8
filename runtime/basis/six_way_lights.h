// The six camera-relative directional lights of `firelook bake --lights six-way` (docs/cli.md,
// "Six-way lights"): one light from each side of the image, for engines' six-way lightmaps
// (runtime/flipbook/flipbook_layout.h) and for relighting from a direction chosen at run time.
//
// Convention (the camera frame: +X right, +Y up, the camera looking down -Z, as glTF): the light
// "from +X" (right) sits on the image's right and travels towards -X; "top" sits above and travels
// down; "back" sits behind the volume, on the far side from the camera (camera -Z), and travels
// towards the camera (+Z); "left", "bottom" and "front" (on the camera's side) are their opposites.
// This is Unity's six-way naming (right = +X, top = +Y, back = -Z seen from the camera).
// The package lists them, in this order, after the scene's own lights; its default look gives
// them zero irradiance, so a default render is the scene's lights alone.
#pragma once

#include <array>
#include <string_view>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace firelook::basis {

inline constexpr int kSixWayLightCount = 6;
inline constexpr std::array<std::string_view, kSixWayLightCount> kSixWayLightNames = {"right", "top",    "back",
                                                                                     "left",  "bottom", "front"};

// The direction each six-way light travels, in world space, for a camera with this
// world_from_camera transform (its axes normalised; a scale in it does not matter).
std::array<glm::dvec3, kSixWayLightCount> sixWayTravelDirections(const glm::dmat4& world_from_camera);

// The same in the camera frame (+X right, +Y up, +Z towards the viewer): the light from side i
// travels along -sixWayCameraAxis(i), where the axis points from the volume towards the light.
glm::dvec3 sixWayCameraAxis(int light);

}  // namespace firelook::basis
