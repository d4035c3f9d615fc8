// Light from a direction chosen at run time (runtime/basis/relight.h, fl_instance_set_light_direction,
// `firelook render --light-dir`): the weights (non-negative, summing to 1, continuous, one light's
// at a baked direction), the world's image against the package relit by hand, the C API's refusals
// and struct rule, and the command line (render, and reference on the bundled sample). Packages are
// synthetic (tests/world/synthetic_package.h) with the six-way lights of a tilted camera after one
// scene light.
#include "basis/relight.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "../support/command.h"
#include "../support/error_code.h"
#include "../support/temp_dir.h"
#include "basis/basis_package.h"
#include "basis/look_renderer.h"
#include "basis/six_way_lights.h"
#include "basis/sphere_lights.h"
#include "firelook/firelook.h"
#include "image/image_io.h"
#include "look/look.h"
#include "render/render_image.h"
#include "synthetic_package.h"

namespace {

using namespace firelook;
using firelook::testing::TempDir;
constexpr int kSix = basis::kSixWayLightCount;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Six-way directions of a camera turned away from every world axis, so no weight is trivially 0.
std::array<glm::dvec3, kSix> tiltedSixWay() {
    glm::dmat4 m = glm::rotate(glm::dmat4(1.0), 0.7, glm::normalize(glm::dvec3(1.0, 2.0, 0.5)));
    m = glm::translate(m, glm::dvec3(3.0, -1.0, 8.0));
    return basis::sixWayTravelDirections(m);
}

std::array<double, kSix> weights(const glm::dvec3& d) { return basis::relightWeights(tiltedSixWay(), d); }

glm::dvec3 randomDirection(std::mt19937_64& random) {
    std::normal_distribution<double> n;
    return glm::normalize(glm::dvec3(n(random), n(random), n(random)));
}

TEST(RelightWeights, NonNegativeSumToOneAndOneLightAtABakedDirection) {
    std::mt19937_64 random(7);
    for (int k = 0; k < 1000; ++k) {
        const std::array<double, kSix> w = weights(randomDirection(random));
        double sum = 0.0;
        for (double x : w) {
            EXPECT_GE(x, 0.0);
            sum += x;
        }
        EXPECT_NEAR(sum, 1.0, 1e-12);  // normalised in double
    }
    const std::array<glm::dvec3, kSix> six = tiltedSixWay();
    for (int i = 0; i < kSix; ++i) {
        const std::array<double, kSix> w = weights(3.5 * six[i]);  // any length
        for (int j = 0; j < kSix; ++j)
            // The other directions are orthogonal or opposite: cosines of 0 up to double rounding,
            // squared (1e-32), or negative.
            EXPECT_NEAR(w[j], i == j ? 1.0 : 0.0, 1e-20) << i << " " << j;
    }
}

TEST(RelightWeights, ContinuousInTheDirection) {
    // Directions where a cosine crosses 0 (a light's weight turns on) and random ones: the weights
    // move by at most a few times the angle turned (the derivative of cos^2 / sum is bounded by 2 /
    // (1/3) at most; 10 leaves room), and by a tenth as much for a tenth of the angle.
    const std::array<glm::dvec3, kSix> six = tiltedSixWay();
    std::mt19937_64 random(11);
    std::vector<glm::dvec3> starts;
    for (int k = 0; k < 200; ++k) starts.push_back(randomDirection(random));
    for (int i = 0; i < kSix; ++i) starts.push_back(glm::normalize(six[(i + 1) % kSix] + six[(i + 2) % kSix]));
    for (const glm::dvec3& d : starts) {
        const glm::dvec3 side = glm::normalize(glm::cross(d, randomDirection(random)));
        const auto change = [&](double angle) {
            const std::array<double, kSix> a = weights(d), b = weights(std::cos(angle) * d + std::sin(angle) * side);
            double most = 0.0;
            for (int i = 0; i < kSix; ++i) most = std::max(most, std::abs(a[i] - b[i]));
            return most;
        };
        EXPECT_LE(change(1e-3), 10.0 * 1e-3);
        EXPECT_LE(change(1e-4), 10.0 * 1e-4);
    }
}

TEST(RelightWeights, RefusesZeroAndNonFiniteDirections) {
    for (const glm::dvec3& bad : {glm::dvec3(0.0), glm::dvec3(kNaN, 0, 1), glm::dvec3(0, kInf, 0),
                                  glm::dvec3(1e300, 1e300, 0)})  // the last one's length overflows
        EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, weights(bad));
    basis::RunTimeLight light;
    light.irradiance = Rgb(1.0f, -0.5f, 1.0f);
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, basis::checkedUnitDirection(light));
    light.irradiance = Rgb(1.0f, std::numeric_limits<float>::quiet_NaN(), 1.0f);
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, basis::checkedUnitDirection(light));
}

// Writes the synthetic frames of `shape` with description d (its lights set by the caller).
void writeSynthetic(const std::filesystem::path& file, basis::BakeDescription d,
                    const firelook::testing::SyntheticShape& shape) {
    package::ContainerWriter writer(file, package::WriterOptions{1});
    for (int frame : shape.frames) {
        basis::writeFrameFactors(writer, d, firelook::testing::syntheticFrame(d, frame, shape.rank, 3));
        d.frames.push_back({frame, shape.rank});
    }
    writer.addMetadata(basis::makeMetadata(d, R"({"provenance": {"tool": "relight_test"}})"));
    writer.commit();
}

// A synthetic package: one scene light, then (with six_way) the six-way lights of tiltedSixWay().
void writePackage(const std::filesystem::path& file, bool six_way) {
    firelook::testing::SyntheticShape shape;
    shape.lights = six_way ? 1 + kSix : 1;
    basis::BakeDescription d = firelook::testing::syntheticDescription(shape);
    if (six_way) {
        const std::array<glm::dvec3, kSix> six = tiltedSixWay();
        std::copy(six.begin(), six.end(), d.light_directions.begin() + 1);
        d.six_way_first_light = 1;
    }
    writeSynthetic(file, d, shape);
}

class RelightApi : public ::testing::Test {
  protected:
    void SetUp() override {
        fl_init_desc desc = fl_init_desc_defaults();
        ASSERT_EQ(fl_init(&desc), FL_OK) << fl_last_error();
        six_path_ = (dir_ / "six.firelook").string();
        plain_path_ = (dir_ / "plain.firelook").string();
        writePackage(six_path_, true);
        writePackage(plain_path_, false);
        ASSERT_EQ(fl_package_load(six_path_.c_str(), &six_), FL_OK) << fl_last_error();
        ASSERT_EQ(fl_package_load(plain_path_.c_str(), &plain_), FL_OK) << fl_last_error();
        ASSERT_EQ(fl_world_create(nullptr, &world_), FL_OK);
    }
    void TearDown() override { EXPECT_EQ(fl_shutdown(), FL_OK); }

    fl_instance instance(fl_package package) {
        fl_instance_desc d = fl_instance_desc_defaults();
        d.package = package;
        fl_instance i{};
        EXPECT_EQ(fl_instance_create(world_, &d, &i), FL_OK) << fl_last_error();
        fl_outputs_desc out = fl_outputs_desc_defaults();
        out.image = 1;
        EXPECT_EQ(fl_instance_set_outputs(world_, i, &out), FL_OK);
        return i;
    }
    std::vector<float> image(fl_instance i) {
        EXPECT_EQ(fl_world_update(world_, 0.0), FL_OK) << fl_last_error();
        std::vector<float> rgba(16 * 12 * 4);
        EXPECT_EQ(fl_instance_get_image(world_, i, rgba.data(), rgba.size()), FL_OK) << fl_last_error();
        return rgba;
    }
    // The package's first frame under its default look with the six-way lights' irradiance `six`,
    // rendered by the runtime directly (what the world must match).
    std::vector<float> expected(const std::array<Rgb, kSix>& six) {
        const basis::BasisReader p = basis::BasisReader::open(six_path_);
        const basis::BakeDescription& d = p.description();
        Look look = parseLook(d.default_look_json, "default");
        std::copy(six.begin(), six.end(), look.light_irradiance.begin() + 1);
        const basis::ResidentFrame frame = p.loadResidentFrame(d.frames[0].frame, std::pmr::get_default_resource());
        std::vector<float> rgba(static_cast<size_t>(d.pixelCount()) * 4);
        basis::renderLookImage(d, frame, look, rgba);
        return rgba;
    }
    static fl_light_direction_desc light(glm::dvec3 d, Rgb e) {
        fl_light_direction_desc x = fl_light_direction_desc_defaults();
        x.direction[0] = d.x, x.direction[1] = d.y, x.direction[2] = d.z;
        x.irradiance[0] = e.r, x.irradiance[1] = e.g, x.irradiance[2] = e.b;
        return x;
    }

    TempDir dir_;
    std::string six_path_, plain_path_;
    fl_package six_{}, plain_{};
    fl_world world_{};
};

float maxAbs(const std::vector<float>& v) {
    float m = 0.0f;
    for (float x : v) m = std::max(m, std::abs(x));
    return m;
}

TEST_F(RelightApi, ABakedDirectionGivesThatLightsImage) {
    const fl_instance i = instance(six_);
    const std::array<glm::dvec3, kSix> six = tiltedSixWay();
    const Rgb e(2.0f, 1.5f, 0.5f);
    for (int k = 0; k < kSix; ++k) {
        const fl_light_direction_desc desc = light(2.0 * six[k], e);
        ASSERT_EQ(fl_instance_set_light_direction(world_, i, &desc), FL_OK) << fl_last_error();
        std::array<Rgb, kSix> alone{};
        alone[k] = e;
        const std::vector<float> got = image(i), want = expected(alone);
        ASSERT_EQ(got.size(), want.size());
        // The other lights' weights are 0 or below 1e-30 (rounding of orthogonal directions) and the
        // rest is the same float arithmetic: equal to a millionth of the image's largest value.
        const float tolerance = 1e-6f * maxAbs(want);
        for (size_t p = 0; p < got.size(); ++p) ASSERT_NEAR(got[p], want[p], tolerance) << "light " << k << " value " << p;
    }
}

TEST_F(RelightApi, AnyDirectionIsTheWeightedSixWayLights) {
    const fl_instance i = instance(six_);
    const glm::dvec3 d(0.3, -0.8, 0.45);
    const Rgb e(1.0f, 0.9f, 0.7f);
    const fl_light_direction_desc desc = light(d, e);
    ASSERT_EQ(fl_instance_set_light_direction(world_, i, &desc), FL_OK) << fl_last_error();
    const std::array<double, kSix> w = weights(d);
    std::array<Rgb, kSix> six{};
    for (int k = 0; k < kSix; ++k) six[k] = static_cast<float>(w[k]) * e;
    const std::vector<float> got = image(i), want = expected(six);
    for (size_t p = 0; p < got.size(); ++p) ASSERT_NEAR(got[p], want[p], 1e-6f * maxAbs(want)) << p;
    // The look the instance shows reports the irradiance the light gave, and the light outlives a new look.
    fl_look shown{};
    ASSERT_EQ(fl_instance_get_look(world_, i, &shown), FL_OK);
    size_t size = 0;
    ASSERT_EQ(fl_look_to_json(shown, nullptr, 0, &size), FL_OK);
    std::string json(size, '\0');
    ASSERT_EQ(fl_look_to_json(shown, json.data(), size, &size), FL_OK);
    json.resize(size - 1);
    const Look look = parseLook(json, "shown");
    for (int k = 0; k < kSix; ++k)
        for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(look.light_irradiance[1 + k][c], six[k][c]);
    fl_look fresh{};
    ASSERT_EQ(fl_package_default_look(six_, &fresh), FL_OK);
    ASSERT_EQ(fl_instance_set_look(world_, i, fresh), FL_OK);
    const std::vector<float> again = image(i);
    EXPECT_EQ(again, got);
    // Null goes back to the look's own six-way irradiance (the synthetic default: (2, 1.9, 1.8) each).
    ASSERT_EQ(fl_instance_set_light_direction(world_, i, nullptr), FL_OK);
    std::array<Rgb, kSix> own;
    own.fill(Rgb(2.0f, 1.9f, 1.8f));
    const std::vector<float> back = image(i), own_image = expected(own);
    for (size_t p = 0; p < back.size(); ++p) ASSERT_NEAR(back[p], own_image[p], 1e-6f * maxAbs(own_image)) << p;
    EXPECT_NE(back, got);
    EXPECT_EQ(fl_look_release(shown), FL_OK);
    EXPECT_EQ(fl_look_release(fresh), FL_OK);
}

TEST_F(RelightApi, SixWayLightsQuery) {
    int32_t first = -7;
    EXPECT_EQ(fl_package_get_six_way_lights(six_, &first), FL_OK) << fl_last_error();
    EXPECT_EQ(first, 1);
    first = -7;
    EXPECT_EQ(fl_package_get_six_way_lights(plain_, &first), FL_ERROR_NOT_FOUND);
    EXPECT_EQ(first, -7);
    EXPECT_NE(std::string(fl_last_error()).find(plain_path_), std::string::npos) << fl_last_error();
    EXPECT_EQ(fl_package_get_six_way_lights(six_, nullptr), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_package_get_six_way_lights(fl_package{}, &first), FL_ERROR_INVALID_HANDLE);
}

TEST_F(RelightApi, RefusesAPackageWithoutSixWayLightsAndBadLights) {
    const fl_instance plain = instance(plain_);
    fl_light_direction_desc desc = light({0.0, -1.0, 0.0}, Rgb(1.0f));
    EXPECT_EQ(fl_instance_set_light_direction(world_, plain, &desc), FL_ERROR_NOT_FOUND);
    EXPECT_NE(std::string(fl_last_error()).find(plain_path_), std::string::npos) << fl_last_error();
    EXPECT_NE(std::string(fl_last_error()).find("six-way"), std::string::npos) << fl_last_error();

    const fl_instance i = instance(six_);
    const std::vector<float> before = image(i);
    for (const glm::dvec3& bad : {glm::dvec3(0.0), glm::dvec3(kNaN, 0, 1), glm::dvec3(0, -kInf, 0)}) {
        desc = light(bad, Rgb(1.0f));
        EXPECT_EQ(fl_instance_set_light_direction(world_, i, &desc), FL_ERROR_INVALID_ARGUMENT);
    }
    for (float bad : {-1.0f, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
        desc = light({0.0, -1.0, 0.0}, Rgb(1.0f, bad, 1.0f));
        EXPECT_EQ(fl_instance_set_light_direction(world_, i, &desc), FL_ERROR_INVALID_ARGUMENT);
    }
    EXPECT_EQ(image(i), before);  // nothing changed
    fl_instance stale = i;
    ASSERT_EQ(fl_instance_destroy(world_, i), FL_OK);
    desc = light({0.0, -1.0, 0.0}, Rgb(1.0f));
    EXPECT_EQ(fl_instance_set_light_direction(world_, stale, &desc), FL_ERROR_INVALID_HANDLE);
}

TEST_F(RelightApi, StructRule) {
    const fl_instance i = instance(six_);
    // First published size: through reserved2. Smaller (0 included) is refused.
    const uint32_t first = offsetof(fl_light_direction_desc, reserved2) + sizeof(int32_t);
    fl_light_direction_desc desc = light({0.0, -1.0, 0.0}, Rgb(1.0f));
    desc.struct_size = 0;
    EXPECT_EQ(fl_instance_set_light_direction(world_, i, &desc), FL_ERROR_STRUCT_SIZE);
    desc.struct_size = first - 1;
    EXPECT_EQ(fl_instance_set_light_direction(world_, i, &desc), FL_ERROR_STRUCT_SIZE);
    desc.struct_size = first;
    EXPECT_EQ(fl_instance_set_light_direction(world_, i, &desc), FL_OK) << fl_last_error();
    const std::vector<float> at_first = image(i);
    // A newer caller's larger struct: what it adds is not read.
    struct Larger {
        fl_light_direction_desc desc;
        double added[4];
    } larger;
    larger.desc = light({0.0, -1.0, 0.0}, Rgb(1.0f));
    larger.desc.struct_size = sizeof(Larger);
    std::fill(std::begin(larger.added), std::end(larger.added), kNaN);
    EXPECT_EQ(fl_instance_set_light_direction(world_, i, &larger.desc), FL_OK) << fl_last_error();
    EXPECT_EQ(image(i), at_first);
}

// A synthetic package with one scene light, then the 12 sphere lights of the tilted camera.
constexpr int kSphere = 12;
std::vector<glm::dvec3> tiltedSphere() {
    glm::dmat4 m = glm::rotate(glm::dmat4(1.0), 0.7, glm::normalize(glm::dvec3(1.0, 2.0, 0.5)));
    return basis::sphereTravelDirections(glm::translate(m, glm::dvec3(3.0, -1.0, 8.0)), kSphere);
}

void writeSpherePackage(const std::filesystem::path& file) {
    firelook::testing::SyntheticShape shape;
    shape.lights = 1 + kSphere;
    basis::BakeDescription d = firelook::testing::syntheticDescription(shape);
    const std::vector<glm::dvec3> sphere = tiltedSphere();
    std::copy(sphere.begin(), sphere.end(), d.light_directions.begin() + 1);
    d.sphere_first_light = 1;
    d.sphere_light_count = kSphere;
    d.sphere_triangles = basis::geodesicSphere(kSphere).triangles;
    writeSynthetic(file, d, shape);
}

class RelightSphereApi : public RelightApi {
  protected:
    void SetUp() override {
        RelightApi::SetUp();
        sphere_path_ = (dir_ / "sphere.firelook").string();
        writeSpherePackage(sphere_path_);
        ASSERT_EQ(fl_package_load(sphere_path_.c_str(), &sphere_), FL_OK) << fl_last_error();
    }
    // The sphere package's first frame under its default look with the sphere lights' irradiance.
    std::vector<float> expectedSphere(const std::vector<Rgb>& lights) {
        const basis::BasisReader p = basis::BasisReader::open(sphere_path_);
        const basis::BakeDescription& d = p.description();
        Look look = parseLook(d.default_look_json, "default");
        std::copy(lights.begin(), lights.end(), look.light_irradiance.begin() + 1);
        const basis::ResidentFrame frame =
            p.loadResidentFrame(d.frames[0].frame, std::pmr::get_default_resource());
        std::vector<float> rgba(static_cast<size_t>(d.pixelCount()) * 4);
        basis::renderLookImage(d, frame, look, rgba);
        return rgba;
    }
    static void expectNear(const std::vector<float>& got, const std::vector<float>& want) {
        ASSERT_EQ(got.size(), want.size());
        // The same float arithmetic up to the order of a few sums: a millionth of the largest value.
        for (size_t p = 0; p < got.size(); ++p) ASSERT_NEAR(got[p], want[p], 1e-6f * maxAbs(want)) << p;
    }
    std::string sphere_path_;
    fl_package sphere_{};
};

TEST_F(RelightSphereApi, RelightLightsQuery) {
    int32_t first = -7, count = -7;
    EXPECT_EQ(fl_package_get_relight_lights(sphere_, &first, &count), FL_OK) << fl_last_error();
    EXPECT_EQ(first, 1);
    EXPECT_EQ(count, kSphere);
    EXPECT_EQ(fl_package_get_relight_lights(six_, &first, &count), FL_OK) << fl_last_error();
    EXPECT_EQ(first, 1);
    EXPECT_EQ(count, kSix);
    first = count = -7;
    EXPECT_EQ(fl_package_get_relight_lights(plain_, &first, &count), FL_ERROR_NOT_FOUND);
    EXPECT_EQ(first, -7);
    EXPECT_NE(std::string(fl_last_error()).find(plain_path_), std::string::npos) << fl_last_error();
    EXPECT_EQ(fl_package_get_relight_lights(sphere_, nullptr, &count), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_package_get_relight_lights(sphere_, &first, nullptr), FL_ERROR_INVALID_ARGUMENT);
    // A sphere package has no six-way lights (the six-way export needs them).
    EXPECT_EQ(fl_package_get_six_way_lights(sphere_, &first), FL_ERROR_NOT_FOUND);
}

TEST_F(RelightSphereApi, BakedAndBetweenDirections) {
    const fl_instance i = instance(sphere_);
    const std::vector<glm::dvec3> sphere = tiltedSphere();
    const Rgb e(2.0f, 1.5f, 0.5f);
    for (int k = 0; k < kSphere; ++k) {
        const fl_light_direction_desc desc = light(2.0 * sphere[k], e);
        ASSERT_EQ(fl_instance_set_light_direction(world_, i, &desc), FL_OK) << fl_last_error();
        std::vector<Rgb> alone(kSphere, Rgb(0.0f));
        alone[k] = e;
        expectNear(image(i), expectedSphere(alone));
    }
    const glm::dvec3 d(0.3, -0.8, 0.45);
    const fl_light_direction_desc desc = light(d, e);
    ASSERT_EQ(fl_instance_set_light_direction(world_, i, &desc), FL_OK) << fl_last_error();
    const std::vector<double> w = basis::sphereWeights(sphere, basis::geodesicSphere(kSphere).triangles, d);
    std::vector<Rgb> lights(kSphere);
    int used = 0;
    for (int k = 0; k < kSphere; ++k) lights[k] = static_cast<float>(w[k]) * e, used += w[k] > 0.0;
    EXPECT_EQ(used, 3);  // inside a triangle
    expectNear(image(i), expectedSphere(lights));
}

TEST_F(RelightSphereApi, SeveralLightsAtOnce) {
    const fl_instance i = instance(sphere_);
    const std::vector<glm::dvec3> sphere = tiltedSphere();
    const std::array<fl_light_direction_desc, 2> two = {light({0.3, -0.8, 0.45}, Rgb(1.0f, 0.9f, 0.7f)),
                                                        light({-0.6, 0.2, -0.5}, Rgb(0.2f, 0.3f, 1.5f))};
    ASSERT_EQ(fl_instance_set_light_directions(world_, i, two.data(), 2), FL_OK) << fl_last_error();
    const std::vector<float> both = image(i);
    const auto triangles = basis::geodesicSphere(kSphere).triangles;
    std::vector<Rgb> lights(kSphere, Rgb(0.0f));
    for (const fl_light_direction_desc& l : two) {
        const std::vector<double> w =
            basis::sphereWeights(sphere, triangles, {l.direction[0], l.direction[1], l.direction[2]});
        for (int k = 0; k < kSphere; ++k)
            lights[k] += static_cast<float>(w[k]) * Rgb(l.irradiance[0], l.irradiance[1], l.irradiance[2]);
    }
    expectNear(both, expectedSphere(lights));
    // One light through the list form is the single form's image.
    ASSERT_EQ(fl_instance_set_light_directions(world_, i, two.data(), 1), FL_OK) << fl_last_error();
    const std::vector<float> first = image(i);
    ASSERT_EQ(fl_instance_set_light_direction(world_, i, &two[0]), FL_OK) << fl_last_error();
    EXPECT_EQ(image(i), first);
    // No lights: the sphere lights dark, the scene's light on.
    ASSERT_EQ(fl_instance_set_light_directions(world_, i, nullptr, 0), FL_OK) << fl_last_error();
    expectNear(image(i), expectedSphere(std::vector<Rgb>(kSphere, Rgb(0.0f))));
    // A bad light anywhere refuses the list and changes nothing.
    std::array<fl_light_direction_desc, 2> bad = two;
    bad[1].direction[1] = kNaN;
    const std::vector<float> before = image(i);
    EXPECT_EQ(fl_instance_set_light_directions(world_, i, bad.data(), 2), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_instance_set_light_directions(world_, i, nullptr, 2), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(image(i), before);
    // A package without six-way or sphere lights.
    const fl_instance plain = instance(plain_);
    EXPECT_EQ(fl_instance_set_light_directions(world_, plain, two.data(), 2), FL_ERROR_NOT_FOUND);
}

TEST_F(RelightSphereApi, ListStructRule) {
    const fl_instance i = instance(sphere_);
    // A newer caller's larger elements: stepped over by their size, what they add not read.
    struct Larger {
        fl_light_direction_desc desc;
        double added[3];
    };
    std::array<Larger, 2> larger{};
    const std::array<fl_light_direction_desc, 2> two = {light({0.3, -0.8, 0.45}, Rgb(1.0f)),
                                                        light({-0.6, 0.2, -0.5}, Rgb(0.5f))};
    for (int k = 0; k < 2; ++k) {
        larger[k].desc = two[k];
        larger[k].desc.struct_size = sizeof(Larger);
        std::fill(std::begin(larger[k].added), std::end(larger[k].added), kNaN);
    }
    ASSERT_EQ(fl_instance_set_light_directions(world_, i, two.data(), 2), FL_OK) << fl_last_error();
    const std::vector<float> want = image(i);
    ASSERT_EQ(fl_instance_set_light_directions(world_, i, &larger[0].desc, 2), FL_OK) << fl_last_error();
    EXPECT_EQ(image(i), want);
    // Elements of different sizes, or below the first published size, are refused.
    larger[1].desc.struct_size = sizeof(fl_light_direction_desc);
    EXPECT_EQ(fl_instance_set_light_directions(world_, i, &larger[0].desc, 2), FL_ERROR_STRUCT_SIZE);
    std::array<fl_light_direction_desc, 2> small = two;
    small[0].struct_size = small[1].struct_size = 8;
    EXPECT_EQ(fl_instance_set_light_directions(world_, i, small.data(), 2), FL_ERROR_STRUCT_SIZE);
}

// `firelook render --light-dir`: the same image as the look with that six-way light on; refusals
// in one line naming the problem.
TEST(RelightCli, RenderLightDirection) {
    const TempDir dir;
    writePackage(dir / "six.firelook", true);
    writePackage(dir / "plain.firelook", false);
    const basis::BasisReader p = basis::BasisReader::open(dir / "six.firelook");
    Look look = parseLook(p.description().default_look_json, "default");
    std::fill(look.light_irradiance.begin() + 1, look.light_irradiance.end(), Rgb(0.0f));
    look.light_irradiance[1 + 4] = Rgb(3.0f);  // bottom
    saveLook(dir / "bottom.json", look);
    const glm::dvec3 t = tiltedSixWay()[4];
    char dir_text[128];
    std::snprintf(dir_text, sizeof dir_text, "%.17g,%.17g,%.17g", t.x, t.y, t.z);
    const auto run = [&](const std::string& args) { return firelook::testing::runFirelook(dir, args); };
    auto r = run("render six.firelook --frame 1 --look bottom.json -o look.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run("render six.firelook --frame 1 --light-dir " + std::string(dir_text) + " --light-irradiance 3,3,3 -o dir.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const image::ImageRGBA a = image::readImage(dir / "look.exr"), b = image::readImage(dir / "dir.exr");
    for (size_t k = 0; k < a.pixels.size(); ++k)
        ASSERT_NEAR(a.pixels[k], b.pixels[k], 1e-6f * maxAbs(a.pixels)) << k;  // as ABakedDirection...
    r = run("render six.firelook --frame 1 --light-dir 0,1,0 -o other.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(image::readImage(dir / "other.exr").pixels, b.pixels);

    for (const char* bad : {"--light-dir 0,0,0", "--light-dir 0,nan,1", "--light-dir 1,0,0 --light-irradiance 1,-1,1",
                                   "--light-irradiance 1,1,1"}) {
        r = run(std::string("render six.firelook --frame 1 ") + bad + " -o bad.exr");
        EXPECT_NE(r.exit_code, 0) << bad;
        EXPECT_EQ(firelook::testing::lines(r.err).size(), 1u) << r.err;
        EXPECT_NE(r.err.find("--light-"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir / "bad.exr"));
    }
    r = run("render plain.firelook --frame 1 --light-dir 0,-1,0 -o bad.exr");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(firelook::testing::lines(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find("plain.firelook"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("six-way"), std::string::npos) << r.err;
}

// `firelook render` with --light-dir repeated on a sphere package: the image of the look whose sphere
// lights carry the sum of each light's weighted irradiance; --light-irradiance once for all or once
// per light, any other count refused.
TEST(RelightCli, RenderSeveralLightDirections) {
    const TempDir dir;
    writeSpherePackage(dir / "sphere.firelook");
    const basis::BasisReader p = basis::BasisReader::open(dir / "sphere.firelook");
    const std::vector<glm::dvec3> sphere = tiltedSphere();
    const auto triangles = basis::geodesicSphere(kSphere).triangles;
    const glm::dvec3 a(0.3, -0.8, 0.45), b(-0.6, 0.2, -0.5);
    const Rgb ea(1.0f, 2.0f, 0.5f), eb(0.25f, 0.5f, 3.0f);
    Look look = parseLook(p.description().default_look_json, "default");
    const std::vector<double> wa = basis::sphereWeights(sphere, triangles, a),
                              wb = basis::sphereWeights(sphere, triangles, b);
    for (int k = 0; k < kSphere; ++k)
        look.light_irradiance[1 + k] = static_cast<float>(wa[k]) * ea + static_cast<float>(wb[k]) * eb;
    saveLook(dir / "two.json", look);
    const auto run = [&](const std::string& args) { return firelook::testing::runFirelook(dir, args); };
    auto r = run("render sphere.firelook --frame 1 --look two.json -o look.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r =
        run("render sphere.firelook --frame 1 --light-dir 0.3,-0.8,0.45 --light-irradiance 1,2,0.5 "
            "--light-dir -0.6,0.2,-0.5 --light-irradiance 0.25,0.5,3 -o dirs.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const image::ImageRGBA x = image::readImage(dir / "look.exr"), y = image::readImage(dir / "dirs.exr");
    for (size_t k = 0; k < x.pixels.size(); ++k)
        ASSERT_NEAR(x.pixels[k], y.pixels[k], 1e-6f * maxAbs(x.pixels)) << k;  // float sums in another order
    for (const char* bad :
         {"--light-dir 0,1,0 --light-dir 1,0,0 --light-irradiance 1,1,1 --light-irradiance 1,1,1 "
          "--light-irradiance 1,1,1",
          "--light-dir 0,1", "--light-dir 0,1,0,1", "--light-dir a,b,c"}) {
        r = run(std::string("render sphere.firelook --frame 1 ") + bad + " -o bad.exr");
        EXPECT_NE(r.exit_code, 0) << bad;
        EXPECT_EQ(firelook::testing::lines(r.err).size(), 1u) << r.err;
        EXPECT_NE(r.err.find("--light-"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir / "bad.exr"));
    }
}

// `firelook reference --light-dir` traces that light itself in place of the six-way lights: at the
// six-way "top" light's direction (world -Z for the sample's default Z-up camera) it is that
// light's reference, within the two renders' noise; from another direction it is not. Without
// --lights six-way it is refused. 16x16 pixels, the light alone (no emission, key light off).
TEST(RelightCli, ReferenceLightDirection) {
    const TempDir dir;
    std::string bins;
    for (int b = 0; b < 16; ++b) bins += std::string(b ? ", " : "") + "[0, 0, 0]";
    const auto look = [&](const std::string& top) {
        return R"({"format": "firelook-look", "version": 1, "temperature_threshold": 1.4, "smoke_extinction": 6,
                   "flame_extinction": 1.5, "albedo": 0.7, "emission": {"bins": [)" +
               bins + R"(]}, "light_irradiance": [[0, 0, 0], [0, 0, 0], )" + top +
               R"(, [0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]]})";
    };
    std::ofstream(dir / "dark.json") << look("[0, 0, 0]");
    std::ofstream(dir / "top.json") << look("[1, 1, 1]");
    const std::string common = "reference '" + std::string(FIRELOOK_SAMPLE_DIR) + "' --up z --frame 6 --size 16x16 --spp 8192 ";
    const auto run = [&](const std::string& args) { return firelook::testing::runFirelook(dir, common + args); };
    auto r = run("--lights six-way --look top.json --seed 1 -o top.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run("--lights six-way --look dark.json --light-dir 0,0,-3 --seed 2 -o dir.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run("--lights six-way --look dark.json --light-dir 1,0,0 --seed 3 -o side.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto read = [&](const char* name) {
        const image::ImageRGBA i = image::readImage(dir / name);
        return render::RenderImage{i.width, i.height, i.pixels};
    };
    const render::RenderImage top = read("top.exr"), lit = read("dir.exr"), side = read("side.exr");
    // Two independent renders of the same image differ by sqrt(2) times each one's noise: measured
    // 6.2% at 2048 spp, so about 3% at 8192 (the limit leaves 2x); the side light's image differs from
    // the top light's by about 10% beyond the noise (measured), over 3x the same light's difference.
    const double same = render::relativeRmse(lit, top), other = render::relativeRmse(side, top);
    EXPECT_LT(same, 0.06) << "the light at the top light's direction is that light";
    EXPECT_GT(other, 2.0 * same) << "another direction gives another image";

    r = run("--light-dir 0,0,-1 -o bad.exr");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(firelook::testing::lines(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find("--lights six-way"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "bad.exr"));
}

// `reference --lights sphere --light-dir`: the basis' lights are replaced by the --light-dir lights,
// so the scene is the one `--lights six-way --light-dir` traces (the key light, dark in the look, then
// the light): the same seed gives the same image, which is why scripts/bench/relight.sh judges every
// basis against one set of references. Two lights at once are traced too. 16x16 at 64 spp.
TEST(RelightCli, ReferenceLightDirectionOfASphereBake) {
    const TempDir dir;
    std::string bins;
    for (int b = 0; b < 16; ++b) bins += std::string(b ? ", " : "") + "[0, 0, 0]";
    const auto look = [&](int lights) {
        std::string irradiance;
        for (int l = 0; l < lights; ++l) irradiance += std::string(l ? ", " : "") + "[0, 0, 0]";
        return R"({"format": "firelook-look", "version": 1, "temperature_threshold": 1.4, "smoke_extinction": 6,
                   "flame_extinction": 1.5, "albedo": 0.7, "emission": {"bins": [)" +
               bins + R"(]}, "light_irradiance": [)" + irradiance + "]}";
    };
    std::ofstream(dir / "six.json") << look(7);
    std::ofstream(dir / "sphere.json") << look(43);
    const std::string common = "reference '" + std::string(FIRELOOK_SAMPLE_DIR) +
                               "' --up z --frame 6 --size 16x16 --spp 64 --seed 5 ";
    const auto run = [&](const std::string& args) {
        return firelook::testing::runFirelook(dir, common + args);
    };
    const std::string light = "--light-dir 0.3,-0.8,-0.5 --light-irradiance 2,1,0.5 ";
    auto r = run("--lights six-way --look six.json " + light + "-o six.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run("--lights sphere --look sphere.json " + light + "-o sphere.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const image::ImageRGBA a = image::readImage(dir / "six.exr"), b = image::readImage(dir / "sphere.exr");
    EXPECT_EQ(a.pixels, b.pixels);
    EXPECT_GT(maxAbs(a.pixels), 0.0f) << "the light lights the volume";
    r = run("--lights sphere:12 --look six.json " + light + "-o bad.exr");  // 13 lights, 7 in the look
    EXPECT_NE(r.exit_code, 0);
    r = run("--lights sphere --look sphere.json " + light + "--light-dir 0,0,-1 -o two.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(image::readImage(dir / "two.exr").pixels, b.pixels);
}

}  // namespace
