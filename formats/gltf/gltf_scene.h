// Camera and directional lights from a glTF 2.0 scene (.gltf JSON or .glb binary).
//
// Only the default scene is read (the first scene when the file names no default; every node that is
// no other node's child when the file has no scenes at all). Its node hierarchy is walked depth
// first, in the order the file lists root nodes and children, and a node's world transform is the
// product of the local transforms (matrix, or translation * rotation * scale) from its root down.
//
// Camera: the first perspective camera met on that walk. A camera that no node of the default scene
// references has no placement and is ignored. glTF cameras look down their local -Z with +Y up and
// +X to the right; world_from_camera is the node's world transform as stored, so it carries any
// scale of the node or its ancestors.
//
// Lights: every directional light of KHR_lights_punctual on a node of the walk, once per node that
// references it. The direction is the node's world -Z axis, normalised: the way the light travels.
// Lights of other types (point, spot) are ignored and counted in ignored_lights.
//
// Errors (GltfError, naming the file): the file cannot be read or parsed (tinygltf's message is
// included); the scene has neither a perspective camera nor a directional light; its only cameras
// are orthographic (named, since silently replacing the camera a user chose would surprise); a node,
// camera or light index is out of range; the node graph has a cycle; a transform is degenerate.
#pragma once

#include <filesystem>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/error.h"

namespace firelook::gltf {

// Every glTF failure: a firelook::Error naming the file, code BadScene unless the site gives another.
class GltfError : public Error {
  public:
    explicit GltfError(const std::string& message) : Error(ErrorCode::BadScene, message) {}
    GltfError(ErrorCode code, const std::string& message) : Error(code, message) {}
};

struct PerspectiveCamera {
    std::string name;  // the camera's name, or its node's when the camera has none
    glm::dmat4 world_from_camera{1.0};
    double yfov_radians = 0.0;
    std::optional<double> aspect_ratio;  // width / height; absent: use the output's
    double znear = 0.0;
    std::optional<double> zfar;  // absent: infinite
};

struct DirectionalLight {
    std::string name;                      // the light's name, or its node's when the light has none
    glm::dvec3 direction{0.0, 0.0, -1.0};  // unit vector, the way the light travels
    glm::dvec3 color{1.0};                 // linear RGB
    double intensity = 1.0;                // lux, as KHR_lights_punctual defines it
};

struct Scene {
    std::optional<PerspectiveCamera> camera;
    std::vector<DirectionalLight> lights;
    int ignored_lights = 0;  // non-directional lights met on the walk
};

Scene loadScene(const std::filesystem::path& path);

}  // namespace firelook::gltf
