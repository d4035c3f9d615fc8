#include "render/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <numbers>
#include <tuple>

#include "render/render_error.h"

namespace firelook::render {
namespace {

constexpr double kTolerance = 1e-12;  // double rounding of a few operations on unit vectors

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tolerance = kTolerance) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(Camera, LookAtCentreRayPointsAtTheTarget) {
    const glm::dvec3 position(1.0, 2.0, 3.0), target(-2.0, 0.5, 7.0);
    const Camera camera = Camera::lookAt(position, target, {0.0, 1.0, 0.0}, 0.8, 4, 2);
    // The image centre is the shared corner of the four middle pixels.
    const Ray ray = camera.generateRay(2, 1, 0.0, 0.0);
    expectNear(ray.origin, position);
    expectNear(ray.direction, glm::normalize(target - position));
}

TEST(Camera, FollowsTheGltfConvention) {
    // Identity: looks down -Z with +Y up; the top-left corner of the image is up and to the left.
    const double yfov = std::numbers::pi / 2.0;  // tan(yfov / 2) = 1
    const Camera camera = Camera::fromWorldFromCamera(glm::dmat4(1.0), yfov, 200, 100);
    expectNear(camera.generateRay(100, 50, 0.0, 0.0).direction, {0.0, 0.0, -1.0});
    expectNear(camera.generateRay(0, 0, 0.0, 0.0).direction, glm::normalize(glm::dvec3(-2.0, 1.0, -1.0)));
    // Bottom-right corner of the last pixel's footprint (u = v = 1 is its far edge).
    expectNear(camera.generateRay(199, 99, 1.0, 1.0).direction, glm::normalize(glm::dvec3(2.0, -1.0, -1.0)));
    // Turned 90 degrees about +Y and moved: looks down world -X.
    const glm::dmat4 turned = glm::translate(glm::dmat4(1.0), glm::dvec3(5.0, 0.0, 0.0)) *
                              glm::rotate(glm::dmat4(1.0), std::numbers::pi / 2.0, glm::dvec3(0.0, 1.0, 0.0));
    const Camera side = Camera::fromWorldFromCamera(turned, yfov, 2, 2);
    expectNear(side.position(), {5.0, 0.0, 0.0});
    expectNear(side.generateRay(1, 1, 0.0, 0.0).direction, {-1.0, 0.0, 0.0});
}

TEST(Camera, ParametersRebuildTheSameCamera) {
    const Camera camera = Camera::lookAt({1.0, -4.0, 2.0}, {0.0, 0.0, 0.5}, {0.0, 0.0, 1.0}, 0.5, 64, 48);
    const Camera rebuilt(camera.parameters());
    for (const auto& [px, py, u, v] :
         {std::tuple{0, 0, 0.1, 0.9}, std::tuple{63, 47, 0.5, 0.5}, std::tuple{10, 30, 0.7, 0.2}}) {
        const Ray a = camera.generateRay(px, py, u, v), b = rebuilt.generateRay(px, py, u, v);
        EXPECT_EQ(a.origin, b.origin);
        EXPECT_EQ(a.direction, b.direction);
    }
}

TEST(Camera, RejectsInvalidInput) {
    EXPECT_THROW(Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 0.5, 0, 10), RenderError);
    EXPECT_THROW(Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 0.0, 10, 10), RenderError);
    EXPECT_THROW(Camera::lookAt({0, 0, 0}, {0, 0, 0}, {0, 1, 0}, 0.5, 10, 10), RenderError);
    EXPECT_THROW(Camera::lookAt({0, 0, 0}, {0, 1, 0}, {0, 1, 0}, 0.5, 10, 10), RenderError);
    EXPECT_THROW(Camera::fromWorldFromCamera(glm::dmat4(0.0), 0.5, 10, 10), RenderError);
    EXPECT_THROW(defaultCamera({1, 1, 1}, {0, 0, 0}, UpAxis::Y, 10, 10), RenderError);
}

// Largest |NDC| coordinate of the box's corners seen by the camera (1 = on the image edge), and
// whether every corner lies in front of it.
double largestNdc(const Camera& camera, const glm::dvec3& lo, const glm::dvec3& hi, bool& in_front) {
    const CameraParameters& p = camera.parameters();
    const glm::dvec3 right(p.world_from_camera[0], p.world_from_camera[1], p.world_from_camera[2]);
    const glm::dvec3 up(p.world_from_camera[4], p.world_from_camera[5], p.world_from_camera[6]);
    const glm::dvec3 back(p.world_from_camera[8], p.world_from_camera[9], p.world_from_camera[10]);
    const double tan_y = std::tan(0.5 * p.yfov_radians), tan_x = tan_y * p.width / p.height;
    double largest = 0.0;
    in_front = true;
    for (int n = 0; n < 8; ++n) {
        const glm::dvec3 corner((n & 1) ? hi.x : lo.x, (n & 2) ? hi.y : lo.y, (n & 4) ? hi.z : lo.z);
        const glm::dvec3 d = corner - camera.position();
        const double depth = -glm::dot(d, back);
        in_front = in_front && depth > 0.0;
        largest = std::max({largest, std::abs(glm::dot(d, right) / depth / tan_x),
                            std::abs(glm::dot(d, up) / depth / tan_y)});
    }
    return largest;
}

TEST(Camera, DefaultCameraFramesTheBoundsHorizontally) {
    const glm::dvec3 lo(-1.0, 0.0, -3.0), hi(2.0, 5.0, 1.0);
    const glm::dvec3 centre = 0.5 * (lo + hi);
    bool in_front = false;

    const Camera y_up = defaultCamera(lo, hi, UpAxis::Y, 160, 90);
    EXPECT_NEAR(y_up.position().x, centre.x, kTolerance);
    EXPECT_NEAR(y_up.position().y, centre.y, kTolerance);
    EXPECT_GT(y_up.position().z, hi.z);
    expectNear(y_up.generateRay(80, 45, 0.0, 0.0).direction, {0.0, 0.0, -1.0});
    const double y_ndc = largestNdc(y_up, lo, hi, in_front);
    EXPECT_TRUE(in_front);
    // Every corner inside the image, the tightest one at the 5% margin.
    EXPECT_NEAR(y_ndc, 0.95, 1e-9);

    const Camera z_up = defaultCamera(lo, hi, UpAxis::Z, 90, 160);
    EXPECT_NEAR(z_up.position().x, centre.x, kTolerance);
    EXPECT_NEAR(z_up.position().z, centre.z, kTolerance);
    EXPECT_LT(z_up.position().y, lo.y);
    expectNear(z_up.generateRay(45, 80, 0.0, 0.0).direction, {0.0, 1.0, 0.0});
    EXPECT_GT(z_up.generateRay(45, 0, 0.5, 0.5).direction.z, 0.0);  // the top row looks up: +Z is up
    EXPECT_NEAR(largestNdc(z_up, lo, hi, in_front), 0.95, 1e-9);
    EXPECT_TRUE(in_front);

    // A single point still gives a usable camera outside it.
    const Camera point = defaultCamera(centre, centre, UpAxis::Y, 8, 8);
    EXPECT_GT(glm::length(point.position() - centre), 0.0);
}

}  // namespace
}  // namespace firelook::render
