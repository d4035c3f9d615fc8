// Pinhole cameras and the default framing of a volume.
#pragma once

#include <array>
#include <cmath>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "render/ray.h"

namespace firelook::render {

// Plain numbers that describe a camera completely, for a package to record and rebuild it from.
struct CameraParameters {
    // Column-major 4x4 (glm and glTF order): world = world_from_camera * camera. glTF's convention:
    // the camera sits at the local origin, looks down local -Z, +Y is up and +X right.
    std::array<double, 16> world_from_camera{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    double yfov_radians = 0.6981317007977318;  // 40 degrees
    int width = 256;
    int height = 256;
};

enum class UpAxis { Y, Z };

// A pinhole camera. Pixel (0, 0) is the top-left one; a pixel's value is the mean over its square
// footprint on the image plane.
class Camera {
  public:
    // Throws RenderError unless the size is positive, 0 < yfov < pi, and the transform is finite,
    // affine and invertible.
    explicit Camera(const CameraParameters& parameters);

    // Looks from position at target; up need only not be parallel to the view direction.
    static Camera lookAt(const glm::dvec3& position, const glm::dvec3& target, const glm::dvec3& up,
                         double yfov_radians, int width, int height);
    static Camera fromWorldFromCamera(const glm::dmat4& world_from_camera, double yfov_radians, int width,
                                      int height);

    // The ray through point (u, v) in [0,1)^2 of pixel (px, py)'s footprint, u to the right, v down.
    Ray generateRay(int px, int py, double u, double v) const {
        const double x = ((px + u) * inverse_width_ * 2.0 - 1.0) * tan_half_fov_x_;
        const double y = (1.0 - (py + v) * inverse_height_ * 2.0) * tan_half_fov_y_;
        const glm::dvec3 d = x * right_ + y * up_ + forward_;
        return Ray{position_, d / std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z)};
    }

    const CameraParameters& parameters() const { return parameters_; }
    // parameters().world_from_camera as a matrix (world = it * camera).
    glm::dmat4 worldFromCamera() const;
    int width() const { return parameters_.width; }
    int height() const { return parameters_.height; }
    // The height of a pixel's footprint per unit distance along the view (at the image's centre).
    double pixelAngle() const { return 2.0 * tan_half_fov_y_ / parameters_.height; }
    const glm::dvec3& position() const { return position_; }

  private:
    CameraParameters parameters_;
    glm::dvec3 position_{0.0};
    glm::dvec3 right_{1.0, 0.0, 0.0}, up_{0.0, 1.0, 0.0},
        forward_{0.0, 0.0, -1.0};  // world images of +X, +Y, -Z
    double tan_half_fov_x_ = 1.0, tan_half_fov_y_ = 1.0;
    double inverse_width_ = 1.0, inverse_height_ = 1.0;
};

// docs/cli.md: a camera that looks horizontally at the centre of the world box
// [world_min, world_max] from far enough that the whole box is inside the image, with a margin.
// Y up: it stands on the +Z side looking down -Z (+X right). Z up (Blender): it stands on the -Y
// side looking down +Y (+X right), Blender's front view. Throws RenderError for an empty or
// non-finite box.
Camera defaultCamera(const glm::dvec3& world_min, const glm::dvec3& world_max, UpAxis up, int width,
                     int height, double yfov_radians = CameraParameters{}.yfov_radians);

}  // namespace firelook::render
