// The camera a package was baked with, as its META records it ("camera": docs/package-format.md):
// read once when the package is opened, for hosts that place the effect in their own scene.
#pragma once

#include <array>
#include <optional>
#include <string>

namespace firelook::world {

struct PackageCamera {
    // Column-major 4x4 (glTF order): world = world_from_camera * camera; the camera looks down its
    // local -Z with +Y up (baker/render/camera.h).
    std::array<double, 16> world_from_camera{};
    double yfov_radians = 0.0;  // vertical field of view
    int width = 0, height = 0;  // the image size it was baked at
};

// The camera in `metadata_json` (the package's META text); nullopt when it records none. Throws
// firelook::Error(Corrupt), naming `name`, for a camera that is malformed: not 16 finite numbers,
// a field of view outside (0, pi), or a size that is not positive.
std::optional<PackageCamera> readPackageCamera(const std::string& metadata_json, const std::string& name);

}  // namespace firelook::world
