#include "basis/sphere_lights.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <utility>

#include "common/error.h"

namespace firelook::basis {
namespace {

// The icosahedron with a vertex at +Y: two rings of five at elevation +-atan(1/2), the upper ring's
// first vertex towards the camera (+Z), the lower ring turned by 36 degrees.
GeodesicSphere icosahedron() {
    GeodesicSphere s;
    const double elevation = std::atan(0.5), pi = std::numbers::pi;
    s.axes.push_back({0.0, 1.0, 0.0});
    for (int ring = 0; ring < 2; ++ring)
        for (int i = 0; i < 5; ++i) {
            const double azimuth = 2.0 * pi * (i + 0.5 * ring) / 5.0;
            const double y = ring == 0 ? std::sin(elevation) : -std::sin(elevation);
            s.axes.push_back(
                {std::cos(elevation) * std::sin(azimuth), y, std::cos(elevation) * std::cos(azimuth)});
        }
    s.axes.push_back({0.0, -1.0, 0.0});
    const auto upper = [](int i) { return 1 + (i % 5); };
    const auto lower = [](int i) { return 6 + (i % 5); };
    for (int i = 0; i < 5; ++i) {
        s.triangles.push_back({0, upper(i), upper(i + 1)});
        s.triangles.push_back({upper(i), lower(i), upper(i + 1)});
        s.triangles.push_back({lower(i), lower(i + 1), upper(i + 1)});
        s.triangles.push_back({11, lower(i + 1), lower(i)});
    }
    return s;
}

// Each triangle split in four at its edges' midpoints (pushed onto the sphere), the original
// vertices first, midpoints in the order the triangles first reach them.
GeodesicSphere subdivided(const GeodesicSphere& in) {
    GeodesicSphere s{in.axes, {}};
    std::map<std::pair<int, int>, int> midpoint;
    const auto middle = [&](int a, int b) {
        const std::pair<int, int> key(std::min(a, b), std::max(a, b));
        const auto found = midpoint.find(key);
        if (found != midpoint.end()) return found->second;
        s.axes.push_back(glm::normalize(in.axes[a] + in.axes[b]));
        return midpoint[key] = static_cast<int>(s.axes.size()) - 1;
    };
    for (const auto& [a, b, c] : in.triangles) {
        const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
        s.triangles.push_back({a, ab, ca});
        s.triangles.push_back({ab, b, bc});
        s.triangles.push_back({ca, bc, c});
        s.triangles.push_back({ab, bc, ca});
    }
    return s;
}

}  // namespace

GeodesicSphere geodesicSphere(int count) {
    if (count == 12) return icosahedron();
    if (count == 42) return subdivided(icosahedron());
    throw Error(ErrorCode::InvalidArgument,
                "a sphere of lights has 12 or 42 directions, not " + std::to_string(count));
}

std::vector<glm::dvec3> sphereTravelDirections(const glm::dmat4& world_from_camera, int count) {
    const glm::dvec3 x = glm::normalize(glm::dvec3(world_from_camera[0]));
    const glm::dvec3 y = glm::normalize(glm::dvec3(world_from_camera[1]));
    const glm::dvec3 z = glm::normalize(glm::dvec3(world_from_camera[2]));
    std::vector<glm::dvec3> out;
    for (const glm::dvec3& a : geodesicSphere(count).axes) out.push_back(-(a.x * x + a.y * y + a.z * z));
    return out;
}

std::vector<double> sphereWeights(std::span<const glm::dvec3> directions,
                                  std::span<const std::array<int, 3>> triangles,
                                  const glm::dvec3& direction) {
    const double length = glm::length(direction);
    if (!std::isfinite(length) || !(length > 0.0))
        throw Error(ErrorCode::InvalidArgument, "the light direction must be finite and non-zero");
    const glm::dvec3 d = direction / length;
    const int n = static_cast<int>(directions.size());
    // The triangle whose smallest coefficient is largest holds d (>= 0 there, up to rounding on an
    // edge); a triangle on the far side has all three negative.
    double best = -std::numeric_limits<double>::infinity();
    std::array<double, 3> coefficients{};
    const std::array<int, 3>* holder = nullptr;
    for (const std::array<int, 3>& t : triangles) {
        for (int v : t)
            if (v < 0 || v >= n)
                throw Error(ErrorCode::InvalidArgument, "a sphere triangle names light " + std::to_string(v) +
                                                            " of " + std::to_string(n));
        const glm::dvec3 &a = directions[t[0]], &b = directions[t[1]], &c = directions[t[2]];
        const double det = glm::dot(a, glm::cross(b, c));
        if (!(std::abs(det) > 0.0)) continue;  // a degenerate triangle holds nothing
        const std::array<double, 3> k = {glm::dot(d, glm::cross(b, c)) / det,
                                         glm::dot(d, glm::cross(c, a)) / det,
                                         glm::dot(d, glm::cross(a, b)) / det};
        const double smallest = std::min({k[0], k[1], k[2]});
        if (smallest > best) best = smallest, coefficients = k, holder = &t;
    }
    // 1e-9: rounding of a direction on an edge or at a vertex; a gap in the cover is far larger.
    if (holder == nullptr || best < -1e-9)
        throw Error(ErrorCode::InvalidArgument,
                    "the sphere lights' triangles hold no light travelling along (" + std::to_string(d.x) +
                        ", " + std::to_string(d.y) + ", " + std::to_string(d.z) + ")");
    double sum = 0.0;
    for (double& k : coefficients) sum += (k = std::max(k, 0.0));
    std::vector<double> w(static_cast<size_t>(n), 0.0);
    // On the triangle the coefficients sum to at least 1 (d is unit, their combination's chord point
    // is inside the sphere), so the division is safe.
    for (int i = 0; i < 3; ++i) w[static_cast<size_t>((*holder)[i])] += coefficients[i] / sum;
    return w;
}

}  // namespace firelook::basis
