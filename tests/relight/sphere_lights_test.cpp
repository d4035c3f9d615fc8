// The geodesic sphere of `firelook bake --lights sphere:N` and its weights (runtime/basis/sphere_lights.h,
// runtime/basis/relight.h): the sphere's shape, the interpolation's guarantees (non-negative, summing to
// 1, exact at a baked direction, reproducing the direction itself, continuous), several lights at once,
// the package description's record, and the refusals.
#include "basis/sphere_lights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <vector>

#include "../support/error_code.h"
#include "basis/bake_description.h"
#include "basis/relight.h"
#include "basis/six_way_lights.h"

namespace {

using namespace firelook;
constexpr double kNotANumber = std::numeric_limits<double>::quiet_NaN();

glm::dvec3 randomUnit(std::mt19937_64& random) {
    std::normal_distribution<double> n;
    return glm::normalize(glm::dvec3(n(random), n(random), n(random)));
}

// A camera turned away from every world axis, so no coordinate is trivially 0.
glm::dmat4 tiltedCamera() {
    glm::dmat4 m = glm::rotate(glm::dmat4(1.0), 0.7, glm::normalize(glm::dvec3(1.0, 2.0, 0.5)));
    return glm::translate(m, glm::dvec3(3.0, -1.0, 8.0));
}

std::vector<double> sphereWeightsOf(const basis::GeodesicSphere& s, const std::vector<glm::dvec3>& travel,
                                    const glm::dvec3& d) {
    return basis::sphereWeights(travel, s.triangles, d);
}

class SphereLights : public ::testing::TestWithParam<int> {};

TEST_P(SphereLights, AClosedGeodesicSphere) {
    const int n = GetParam();
    const basis::GeodesicSphere s = basis::geodesicSphere(n);
    ASSERT_EQ(s.axes.size(), static_cast<size_t>(n));
    ASSERT_EQ(s.triangles.size(), static_cast<size_t>(2 * n - 4));  // Euler: V - E + F = 2, 3F = 2E
    for (const glm::dvec3& a : s.axes) EXPECT_NEAR(glm::length(a), 1.0, 1e-15);
    // "top" first, as the six-way top light's axis: a sun overhead is a baked light.
    EXPECT_NEAR(glm::length(s.axes[0] - basis::sixWayCameraAxis(1)), 0.0, 1e-15);
    // Each edge borders two triangles, once each way round (closed and consistently oriented), and
    // every triangle faces outwards.
    std::map<std::pair<int, int>, int> edges;
    for (const auto& t : s.triangles) {
        EXPECT_GT(glm::dot(s.axes[t[0]], glm::cross(s.axes[t[1]], s.axes[t[2]])), 0.0);
        for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
    }
    for (const auto& [edge, count] : edges) {
        EXPECT_EQ(count, 1);
        EXPECT_EQ(edges.count({edge.second, edge.first}), 1u);
    }
    // Neighbours are evenly spaced: the icosahedron's edges span 63.4 degrees; the subdivided
    // sphere's 31.7 to 36.0 (its midpoints are pushed out onto the sphere).
    double shortest = 180.0, longest = 0.0;
    for (const auto& [edge, count] : edges) {
        const double angle =
            std::acos(glm::dot(s.axes[edge.first], s.axes[edge.second])) * 180.0 / std::numbers::pi;
        shortest = std::min(shortest, angle), longest = std::max(longest, angle);
    }
    EXPECT_GT(shortest, n == 12 ? 63.0 : 31.0);
    EXPECT_LT(longest, n == 12 ? 63.5 : 36.5);
}

TEST_P(SphereLights, WeightsAreBarycentricExactAtBakedDirectionsAndContinuous) {
    const int n = GetParam();
    const basis::GeodesicSphere s = basis::geodesicSphere(n);
    const std::vector<glm::dvec3> travel = basis::sphereTravelDirections(tiltedCamera(), n);
    std::mt19937_64 random(5);
    for (int k = 0; k < 2000; ++k) {
        const glm::dvec3 d = randomUnit(random);
        const std::vector<double> w = sphereWeightsOf(s, travel, 2.5 * d);  // any length
        double sum = 0.0;
        int used = 0;
        glm::dvec3 combined(0.0);
        for (int i = 0; i < n; ++i) {
            EXPECT_GE(w[i], 0.0);
            sum += w[i];
            used += w[i] > 0.0;
            combined += w[i] * travel[i];
        }
        EXPECT_NEAR(sum, 1.0, 1e-12);  // normalised in double
        EXPECT_LE(used, 3);            // the corners of one triangle
        // Barycentric coordinates reproduce the direction: the weighted travel directions point
        // along d (a chord point inside the sphere, so only the direction is compared).
        EXPECT_NEAR(glm::length(glm::cross(glm::normalize(combined), d)), 0.0, 1e-12);
    }
    for (int i = 0; i < n; ++i) {
        const std::vector<double> w = sphereWeightsOf(s, travel, 3.5 * travel[i]);
        // At a vertex the other coefficients are 0 up to the rounding of the triangle solve.
        for (int j = 0; j < n; ++j) ASSERT_NEAR(w[j], i == j ? 1.0 : 0.0, 1e-12) << i << " " << j;
    }
    // Continuity, across edges and vertices too: a weight moves by at most a few times the angle
    // turned (a coefficient's gradient is 1 / the triangle's height, 1.0 rad for 12 lights and 0.48
    // for 42, so about 2 per radian; 10 leaves room for the normalisation).
    for (int k = 0; k < 300; ++k) {
        const glm::dvec3 d =
            k < n ? glm::normalize(travel[k] + 1e-6 * randomUnit(random)) : randomUnit(random);
        const glm::dvec3 side = glm::normalize(glm::cross(d, randomUnit(random)));
        for (double angle : {1e-3, 1e-5}) {
            const std::vector<double> a = sphereWeightsOf(s, travel, d),
                                      b = sphereWeightsOf(s, travel,
                                                          std::cos(angle) * d + std::sin(angle) * side);
            double most = 0.0;
            for (int i = 0; i < n; ++i) most = std::max(most, std::abs(a[i] - b[i]));
            EXPECT_LE(most, 10.0 * angle) << k;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Counts, SphereLights, ::testing::Values(12, 42));

TEST(SphereLightsRefusals, BadCountsDirectionsAndTriangles) {
    EXPECT_ERROR_CODE(ErrorCode::InvalidArgument, basis::geodesicSphere(6));
    EXPECT_ERROR_CODE(ErrorCode::InvalidArgument, basis::geodesicSphere(0));
    basis::GeodesicSphere s = basis::geodesicSphere(12);
    for (const glm::dvec3& bad :
         {glm::dvec3(0.0), glm::dvec3(kNotANumber, 0, 1), glm::dvec3(1e300, 1e300, 0)})
        EXPECT_ERROR_CODE(ErrorCode::InvalidArgument, basis::sphereWeights(s.axes, s.triangles, bad));
    // A hole in the cover: the direction through the missing triangle's centre has no triangle.
    const std::array<int, 3> gone = s.triangles.back();
    const glm::dvec3 centre = s.axes[gone[0]] + s.axes[gone[1]] + s.axes[gone[2]];
    s.triangles.pop_back();
    EXPECT_ERROR_CODE(ErrorCode::InvalidArgument, basis::sphereWeights(s.axes, s.triangles, centre));
    s.triangles.push_back({0, 1, 12});  // no light 12
    EXPECT_ERROR_CODE(ErrorCode::InvalidArgument, basis::sphereWeights(s.axes, s.triangles, centre));
}

// A description with one scene light, then the 42 sphere lights of the tilted camera.
basis::BakeDescription sphereDescription() {
    basis::BakeDescription d;
    d.light_directions = {{0.3, -1.0, 0.2}};
    const std::vector<glm::dvec3> travel = basis::sphereTravelDirections(tiltedCamera(), 42);
    d.light_directions.insert(d.light_directions.end(), travel.begin(), travel.end());
    d.sphere_first_light = 1;
    d.sphere_light_count = 42;
    d.sphere_triangles = basis::geodesicSphere(42).triangles;
    return d;
}

TEST(SphereRelight, SeveralLightsAreTheSumOfEach) {
    const basis::BakeDescription d = sphereDescription();
    EXPECT_EQ(d.relightFirstLight(), 1);
    EXPECT_EQ(d.relightLightCount(), 42);
    const basis::RunTimeLight a{{0.2, -0.9, 0.4}, Rgb(1.0f, 0.5f, 0.25f)},
        b{{-1.0, 0.1, 0.3}, Rgb(0.0f, 2.0f, 1.0f)};
    const std::vector<basis::RunTimeLight> both = {a, b};
    const std::vector<Rgb> sum = basis::relightIrradiance(d, both, "pkg");
    const std::vector<Rgb> only_a = basis::relightIrradiance(d, std::span(&a, 1), "pkg");
    const std::vector<Rgb> only_b = basis::relightIrradiance(d, std::span(&b, 1), "pkg");
    ASSERT_EQ(sum.size(), 42u);
    for (size_t i = 0; i < sum.size(); ++i)
        for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(sum[i][c], only_a[i][c] + only_b[i][c]) << i;
    // The weights are the sphere's, of the package's own directions.
    const std::vector<double> w = basis::packageRelightWeights(d, a.direction, "pkg");
    const std::vector<glm::dvec3> travel(d.light_directions.begin() + 1, d.light_directions.end());
    EXPECT_EQ(w, basis::sphereWeights(travel, d.sphere_triangles, a.direction));
    for (size_t i = 0; i < sum.size(); ++i) EXPECT_FLOAT_EQ(only_a[i][0], static_cast<float>(w[i]));
    // No light: those lights dark; the scene's light keeps its entry.
    std::vector<Rgb> irradiance(43, Rgb(7.0f));
    basis::applyRunTimeLights(d, {}, "pkg", irradiance);
    EXPECT_EQ(irradiance[0], Rgb(7.0f));
    for (size_t i = 1; i < irradiance.size(); ++i) EXPECT_EQ(irradiance[i], Rgb(0.0f));
    // A bad light anywhere in the list refuses the whole list.
    const std::vector<basis::RunTimeLight> bad = {a, {{0.0, 0.0, 0.0}, Rgb(1.0f)}};
    EXPECT_ERROR_CODE(ErrorCode::InvalidArgument, basis::relightIrradiance(d, bad, "pkg"));
    // Each irradiance is finite, their sum is not: refused rather than an infinite light (NaN where
    // a column is 0).
    const basis::RunTimeLight huge{d.light_directions[1], Rgb(3e38f)};  // a baked direction: weight 1
    const std::vector<basis::RunTimeLight> overflow = {huge, huge};
    EXPECT_ERROR_CODE(ErrorCode::InvalidArgument, basis::relightIrradiance(d, overflow, "pkg"));
    basis::BakeDescription plain;
    plain.light_directions = {{0.0, -1.0, 0.0}};
    EXPECT_ERROR_CODE(ErrorCode::InvalidArgument, basis::relightIrradiance(plain, both, "pkg"));
}

// The description records the sphere (first, count, triangles) and reads it back; what does not
// describe a closed sphere of the package's lights is refused as corrupt.
TEST(SphereRelight, DescriptionRecordsTheSphere) {
    basis::BakeDescription d = sphereDescription();
    d.bins = {0.0, 3.0, 4};
    d.axes = {{1.0}, {4.0}, {1.5}};
    d.alpha_thresholds = {1.0};
    d.width = d.height = 4;
    const std::string json = basis::bakeDescriptionToJson(d);
    const basis::BakeDescription r = basis::parseBakeDescription(json, "pkg");
    EXPECT_EQ(r.sphere_first_light, 1);
    EXPECT_EQ(r.sphere_light_count, 42);
    EXPECT_EQ(r.sphere_triangles, d.sphere_triangles);
    EXPECT_EQ(r.six_way_first_light, -1);
    const auto corrupt = [&](const basis::BakeDescription& x) {
        EXPECT_ERROR_CODE(ErrorCode::Corrupt,
                          basis::parseBakeDescription(basis::bakeDescriptionToJson(x), "pkg"));
    };
    basis::BakeDescription x = d;
    x.sphere_triangles.pop_back();
    corrupt(x);
    x = d;
    x.sphere_triangles[3][1] = 42;
    corrupt(x);
    x = d;
    x.sphere_first_light = 2;  // past the last light
    corrupt(x);
    x = d;
    x.six_way_first_light = 1;  // both kinds
    corrupt(x);
}

}  // namespace
