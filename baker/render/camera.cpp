#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <numbers>
#include <string>

#include "render/render_error.h"

namespace firelook::render {
namespace {

// Fraction of the image left free around the framed box.
constexpr double kFramingMargin = 0.05;

bool allFinite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

glm::dmat4 toMatrix(const std::array<double, 16>& m) { return glm::make_mat4(m.data()); }

std::array<double, 16> toArray(const glm::dmat4& m) {
    std::array<double, 16> a{};
    const double* p = glm::value_ptr(m);
    std::copy(p, p + 16, a.begin());
    return a;
}

}  // namespace

Camera::Camera(const CameraParameters& parameters) : parameters_(parameters) {
    if (parameters.width < 1 || parameters.height < 1)
        throw RenderError("camera: image size " + std::to_string(parameters.width) + "x" +
                          std::to_string(parameters.height) + " is not positive");
    if (!(parameters.yfov_radians > 0.0 && parameters.yfov_radians < std::numbers::pi))
        throw RenderError("camera: vertical field of view must be in (0, pi) radians");
    const glm::dmat4 m = toMatrix(parameters.world_from_camera);
    for (double x : parameters.world_from_camera)
        if (!std::isfinite(x)) throw RenderError("camera: world_from_camera is not finite");
    const double det = glm::determinant(glm::dmat3(m));
    if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0 || !(std::abs(det) > 0.0))
        throw RenderError("camera: world_from_camera is not an invertible affine transform");
    position_ = glm::dvec3(m[3]);
    right_ = glm::dvec3(m[0]);
    up_ = glm::dvec3(m[1]);
    forward_ = -glm::dvec3(m[2]);
    tan_half_fov_y_ = std::tan(0.5 * parameters.yfov_radians);
    tan_half_fov_x_ = tan_half_fov_y_ * parameters.width / parameters.height;
    inverse_width_ = 1.0 / parameters.width;
    inverse_height_ = 1.0 / parameters.height;
}

glm::dmat4 Camera::worldFromCamera() const { return toMatrix(parameters_.world_from_camera); }

Camera Camera::fromWorldFromCamera(const glm::dmat4& world_from_camera, double yfov_radians, int width,
                                   int height) {
    return Camera(CameraParameters{toArray(world_from_camera), yfov_radians, width, height});
}

Camera Camera::lookAt(const glm::dvec3& position, const glm::dvec3& target, const glm::dvec3& up,
                      double yfov_radians, int width, int height) {
    if (!allFinite(position) || !allFinite(target) || !allFinite(up))
        throw RenderError("camera: position, target and up must be finite");
    const glm::dvec3 view = target - position;
    const glm::dvec3 side = glm::cross(view, up);
    if (!(glm::length(view) > 0.0) || !(glm::length(side) > 1e-12 * glm::length(view) * glm::length(up)))
        throw RenderError("camera: target equals position or up is parallel to the view direction");
    const glm::dvec3 back = -glm::normalize(view);  // camera +Z
    const glm::dvec3 right = glm::normalize(side);
    const glm::dvec3 true_up = glm::cross(back, right);
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(right, 0.0);
    m[1] = glm::dvec4(true_up, 0.0);
    m[2] = glm::dvec4(back, 0.0);
    m[3] = glm::dvec4(position, 1.0);
    return fromWorldFromCamera(m, yfov_radians, width, height);
}

Camera defaultCamera(const glm::dvec3& world_min, const glm::dvec3& world_max, UpAxis up, int width,
                     int height, double yfov_radians) {
    if (!allFinite(world_min) || !allFinite(world_max) || world_min.x > world_max.x ||
        world_min.y > world_max.y || world_min.z > world_max.z)
        throw RenderError("default camera: the bounds are empty or not finite");
    if (width < 1 || height < 1 || !(yfov_radians > 0.0 && yfov_radians < std::numbers::pi))
        throw RenderError("default camera: needs a positive image size and a field of view in (0, pi)");
    const glm::dvec3 centre = 0.5 * (world_min + world_max);
    const glm::dvec3 half = 0.5 * (world_max - world_min);
    // Camera axes in world space: right, up, and back (towards the camera).
    const glm::dvec3 right(1.0, 0.0, 0.0);
    const glm::dvec3 upward = up == UpAxis::Y ? glm::dvec3(0.0, 1.0, 0.0) : glm::dvec3(0.0, 0.0, 1.0);
    const glm::dvec3 back = up == UpAxis::Y ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(0.0, -1.0, 0.0);
    // A corner at (x, y, z) in camera axes (z towards the camera) seen from distance d projects
    // inside the image iff |x| <= (d - z) tan_x and |y| <= (d - z) tan_y.
    const double tan_y = std::tan(0.5 * yfov_radians) * (1.0 - kFramingMargin);
    const double tan_x = tan_y * width / height;
    const double extent_right = std::abs(glm::dot(half, right));
    const double extent_up = std::abs(glm::dot(half, upward));
    const double extent_back = std::abs(glm::dot(half, back));
    double distance = extent_back + std::max(extent_right / tan_x, extent_up / tan_y);
    // A box of zero size still needs the camera somewhere else than inside it.
    if (!(distance > extent_back)) distance = extent_back + std::max(1.0, glm::length(half));
    const glm::dvec3 position = centre + distance * back;
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(right, 0.0);
    m[1] = glm::dvec4(upward, 0.0);
    m[2] = glm::dvec4(back, 0.0);
    m[3] = glm::dvec4(position, 1.0);
    return Camera::fromWorldFromCamera(m, yfov_radians, width, height);
}

}  // namespace firelook::render
