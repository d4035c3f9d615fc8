// fl_package_get_fire_lights and fl_instance_get_fire_lights (firelook.h): the lights of the
// runtime's own evaluation (basis/fire_lights.h) for the package's and an instance's look, the
// caller's stride, bad handles and arguments, and packages without fire lights.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "../support/temp_dir.h"
#include "basis/basis_package.h"
#include "basis/fire_lights.h"
#include "firelook/firelook.h"
#include "struct_rule.h"
#include "synthetic_package.h"
#include "world/look_track.h"
#include "world/package.h"

namespace {

using firelook::testing::TempDir;
namespace basis = firelook::basis;

// A synthetic package (synthetic_package.h) whose frames carry fire lights of 4 clusters with
// pseudo-random, consistent moments (each cluster's power spread with RMS radius 0.2 around an
// offset of its reference), or none.
void writeFireLightPackage(const std::filesystem::path& file, bool with_lights) {
    firelook::testing::SyntheticShape shape;
    basis::BakeDescription d = firelook::testing::syntheticDescription(shape);
    firelook::package::ContainerWriter writer(file, firelook::package::WriterOptions{1});
    uint64_t state = 5;
    for (int frame : shape.frames) {
        basis::writeFrameFactors(writer, d, firelook::testing::syntheticFrame(d, frame, 4, 3));
        d.frames.push_back({frame, 4});
        if (!with_lights) continue;
        basis::FireLightTable t =
            basis::emptyFireLightTable(4, d.axes.pointCount(), d.bins.count, 0.3f, glm::dvec3(0.0));
        for (int c = 0; c < 4; ++c) {
            t.reference[c] = glm::dvec3(c, 0.5 * frame, -1.0);
            for (int g = 0; g < t.points; ++g)
                for (int i = 0; i < t.bins; ++i) {
                    float* m = t.at(c, g, i);
                    const float p = firelook::testing::syntheticValue(state);
                    const glm::vec3 offset(0.1f * c, 0.05f * i, -0.02f * g);
                    m[0] = p;
                    m[1] = p * offset.x;
                    m[2] = p * offset.y;
                    m[3] = p * offset.z;
                    m[4] = p * (glm::dot(offset, offset) + 0.04f);
                }
        }
        writer.addSection(basis::kSectionFireLights, static_cast<uint32_t>(frame), basis::encodeFireLights(t),
                          firelook::package::Codec::Zstd, false);
    }
    writer.addMetadata(basis::makeMetadata(d, R"({"provenance": {"tool": "fire_lights_api_test"}})"));
    writer.commit();
}

class FireLightsApi : public ::testing::Test {
  protected:
    void SetUp() override {
        fl_init_desc desc = fl_init_desc_defaults();
        ASSERT_EQ(fl_init(&desc), FL_OK) << fl_last_error();
        path_ = dir_ / "lights.firelook";
        writeFireLightPackage(path_, true);
        ASSERT_EQ(fl_package_load(path_.c_str(), &package_), FL_OK) << fl_last_error();
    }
    void TearDown() override { EXPECT_EQ(fl_shutdown(), FL_OK); }

    // The runtime's lights for frame slot `slot` and a look.
    std::vector<basis::FireLight> expected(int slot, const firelook::Look& look, int count) {
        const auto p = firelook::world::Package::open(path_);
        const firelook::world::ResolvedLook r = firelook::world::resolveLook(look, p->description());
        std::vector<basis::FireLight> out(count);
        basis::evaluateFireLights(*p->fireLights(slot), basis::interpolationWeights(p->description().axes, r.extinction),
                                  r.rbf, count, out.data());
        return out;
    }

    TempDir dir_;
    std::filesystem::path path_;
    fl_package package_{};
};

void expectSame(const fl_fire_light& got, const basis::FireLight& want) {
    for (int i = 0; i < 3; ++i) {
        EXPECT_DOUBLE_EQ(got.position[i], want.position[i]);
        EXPECT_FLOAT_EQ(got.intensity[i], want.intensity[i]);
    }
    EXPECT_FLOAT_EQ(got.radius, static_cast<float>(want.radius));
}

TEST_F(FireLightsApi, PackageLightsAreTheRuntimesForTheLookAndRespectTheStride) {
    uint32_t stored = 0;
    ASSERT_EQ(fl_package_get_fire_lights(package_, 2, fl_look{}, 0, nullptr, sizeof(fl_fire_light), 0, &stored), FL_OK);
    EXPECT_EQ(stored, 4u);
    const firelook::Look custom = [&] {
        firelook::Look l = firelook::world::Package::open(path_)->defaultLook();
        l.smoke_extinction = 5.0;
        l.temperature_threshold = 1.3;
        return l;
    }();
    fl_look handle{};
    const std::string json = firelook::lookToJson(custom);
    ASSERT_EQ(fl_look_from_json(json.c_str(), 0, "custom", &handle), FL_OK) << fl_last_error();
    for (uint32_t count : {1u, 2u, 4u}) {
        // A caller's struct 16 bytes larger than ours: written at its stride, the tail untouched.
        struct Bigger {
            fl_fire_light light;
            unsigned char tail[16];
        };
        std::vector<Bigger> out(count);
        for (Bigger& b : out) std::memset(&b, 0xAB, sizeof b);
        ASSERT_EQ(fl_package_get_fire_lights(package_, 2, handle, count, &out[0].light, sizeof(Bigger), count, nullptr),
                  FL_OK)
            << fl_last_error();
        const std::vector<basis::FireLight> want = expected(1, firelook::parseLook(json, "custom"), static_cast<int>(count));
        for (uint32_t l = 0; l < count; ++l) {
            expectSame(out[l].light, want[l]);
            for (unsigned char t : out[l].tail) EXPECT_EQ(t, 0xAB);
            EXPECT_GT(out[l].light.radius, 0.0f);
        }
    }
    // The default look (handle 0) is the package's.
    fl_fire_light one{};
    ASSERT_EQ(fl_package_get_fire_lights(package_, 1, fl_look{}, 1, &one, sizeof one, 1, nullptr), FL_OK);
    expectSame(one, expected(0, firelook::world::Package::open(path_)->defaultLook(), 1)[0]);
    EXPECT_EQ(fl_look_release(handle), FL_OK);
}

TEST_F(FireLightsApi, RefusesBadHandlesArgumentsAndSizes) {
    fl_fire_light lights[4] = {};
    const uint32_t size = sizeof(fl_fire_light);
    EXPECT_EQ(fl_package_get_fire_lights(fl_package{}, 1, fl_look{}, 1, lights, size, 4, nullptr), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_package_get_fire_lights(package_, 1, fl_look{12345}, 1, lights, size, 4, nullptr), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_package_get_fire_lights(package_, 9, fl_look{}, 1, lights, size, 4, nullptr), FL_ERROR_NOT_FOUND);
    EXPECT_EQ(fl_package_get_fire_lights(package_, 1, fl_look{}, 3, lights, size, 4, nullptr), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_package_get_fire_lights(package_, 1, fl_look{}, 8, lights, size, 8, nullptr), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_package_get_fire_lights(package_, 1, fl_look{}, 4, lights, size, 2, nullptr), FL_ERROR_BUFFER_TOO_SMALL);
    EXPECT_EQ(fl_package_get_fire_lights(package_, 1, fl_look{}, 2, nullptr, size, 4, nullptr), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_package_get_fire_lights(package_, 1, fl_look{}, 1, lights,
                                         firelook::plugin::FirstSize<fl_fire_light>::value - 1, 4, nullptr),
              FL_ERROR_STRUCT_SIZE);
    fl_look other_albedo{};
    firelook::Look wrong = firelook::world::Package::open(path_)->defaultLook();
    wrong.albedo = 0.2;
    const std::string wrong_json = firelook::lookToJson(wrong);
    ASSERT_EQ(fl_look_from_json(wrong_json.c_str(), 0, "a", &other_albedo), FL_OK) << fl_last_error();
    EXPECT_EQ(fl_package_get_fire_lights(package_, 1, other_albedo, 1, lights, size, 4, nullptr), FL_ERROR_LOOK);
    EXPECT_NE(std::string(fl_last_error()).find("albedo"), std::string::npos) << fl_last_error();
    ASSERT_EQ(fl_package_release(package_), FL_OK);
    EXPECT_EQ(fl_package_get_fire_lights(package_, 1, fl_look{}, 1, lights, size, 4, nullptr), FL_ERROR_INVALID_HANDLE);
}

TEST_F(FireLightsApi, InstanceLightsFollowItsFrameAndLook) {
    fl_world world{};
    ASSERT_EQ(fl_world_create(nullptr, &world), FL_OK);
    fl_instance_desc d = fl_instance_desc_defaults();
    d.package = package_;
    fl_instance instance{};
    ASSERT_EQ(fl_instance_create(world, &d, &instance), FL_OK);
    fl_fire_light lights[2] = {};
    EXPECT_EQ(fl_instance_get_fire_lights(world, instance, 2, lights, sizeof lights[0], 2, nullptr), FL_ERROR_NO_DATA);
    fl_playback_desc pb = fl_playback_desc_defaults();
    pb.paused = 1;
    pb.rate = 1.0;
    pb.time = 1.0;  // frame 2
    ASSERT_EQ(fl_instance_set_playback(world, instance, &pb), FL_OK);
    ASSERT_EQ(fl_world_update(world, 0.0), FL_OK);
    fl_instance_state state = fl_instance_state_defaults();
    ASSERT_EQ(fl_instance_get_state(world, instance, &state), FL_OK);
    ASSERT_EQ(state.frame, 2);
    uint32_t stored = 0;
    ASSERT_EQ(fl_instance_get_fire_lights(world, instance, 2, lights, sizeof lights[0], 2, &stored), FL_OK) << fl_last_error();
    EXPECT_EQ(stored, 4u);
    fl_fire_light same[2] = {};
    ASSERT_EQ(fl_package_get_fire_lights(package_, 2, fl_look{}, 2, same, sizeof same[0], 2, nullptr), FL_OK);
    for (int l = 0; l < 2; ++l) {
        for (int i = 0; i < 3; ++i) {
            EXPECT_NEAR(lights[l].position[i], same[l].position[i], 1e-9);
            EXPECT_NEAR(lights[l].intensity[i], same[l].intensity[i], 1e-6 * same[l].intensity[i]);
        }
        EXPECT_NEAR(lights[l].radius, same[l].radius, 1e-6);
    }
    fl_world other{};
    ASSERT_EQ(fl_world_create(nullptr, &other), FL_OK);
    EXPECT_EQ(fl_instance_get_fire_lights(other, instance, 2, lights, sizeof lights[0], 2, nullptr), FL_ERROR_INVALID_HANDLE);
}

TEST_F(FireLightsApi, APackageWithoutFireLightsReportsNone) {
    const auto old = dir_ / "old.firelook";
    writeFireLightPackage(old, false);
    fl_package p{};
    ASSERT_EQ(fl_package_load(old.c_str(), &p), FL_OK) << fl_last_error();
    uint32_t stored = 99;
    EXPECT_EQ(fl_package_get_fire_lights(p, 1, fl_look{}, 0, nullptr, sizeof(fl_fire_light), 0, &stored), FL_OK);
    EXPECT_EQ(stored, 0u);
    fl_fire_light light{};
    EXPECT_EQ(fl_package_get_fire_lights(p, 1, fl_look{}, 1, &light, sizeof light, 1, &stored), FL_ERROR_NOT_FOUND);
    EXPECT_NE(std::string(fl_last_error()).find("old.firelook"), std::string::npos) << fl_last_error();
}

}  // namespace
