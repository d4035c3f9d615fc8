// fl_package_get_fire_probes, fl_instance_get_fire_probes and fl_fire_probes_sample (firelook.h): the
// probes of the runtime's own evaluation (basis/fire_probes.h) for the package's and an instance's
// look, the placement, the size query, the sampler against the runtime's blend, bad handles and
// arguments, and packages without fire probes.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../support/temp_dir.h"
#include "basis/basis_package.h"
#include "basis/fire_probes.h"
#include "firelook/firelook.h"
#include "struct_rule.h"
#include "synthetic_package.h"
#include "world/look_track.h"
#include "world/package.h"

namespace {

using firelook::testing::TempDir;
namespace basis = firelook::basis;

// A synthetic package whose frames carry a 3x2x2 probe grid of rank 2 with pseudo-random values,
// or none.
void writeFireProbePackage(const std::filesystem::path& file, bool with_probes) {
    firelook::testing::SyntheticShape shape;
    basis::BakeDescription d = firelook::testing::syntheticDescription(shape);
    firelook::package::ContainerWriter writer(file, firelook::package::WriterOptions{1});
    uint64_t state = 9;
    for (int frame : shape.frames) {
        basis::writeFrameFactors(writer, d, firelook::testing::syntheticFrame(d, frame, 4, 3));
        d.frames.push_back({frame, 4});
        if (!with_probes) continue;
        basis::FireProbeTable t;
        t.grid.counts = {3, 2, 2};
        t.grid.origin = {-1.0, 0.5 * frame, 0.0};
        t.grid.spacing = {0.5, 1.0, 2.0};
        t.grid.falloff_centre = {0.0, 1.0, 1.0};
        t.grid.falloff_radius = 0.3;
        t.points = d.axes.pointCount();
        t.bins = d.bins.count;
        t.rank = 2;
        for (int v = 0; v < t.points * t.rank; ++v)
            t.factors.push_back(firelook::testing::syntheticValue(state));
        const size_t values = size_t(t.grid.probes()) * t.rank * t.bins * basis::kFireProbeCoefficients;
        for (size_t v = 0; v < values; ++v) t.sh.push_back(firelook::testing::syntheticValue(state) - 0.3f);
        writer.addSection(basis::kSectionFireProbes, static_cast<uint32_t>(frame), basis::encodeFireProbes(t),
                          firelook::package::Codec::Zstd, false);
    }
    writer.addMetadata(basis::makeMetadata(d, R"({"provenance": {"tool": "fire_probes_api_test"}})"));
    writer.commit();
}

class FireProbesApi : public ::testing::Test {
  protected:
    void SetUp() override {
        fl_init_desc desc = fl_init_desc_defaults();
        ASSERT_EQ(fl_init(&desc), FL_OK) << fl_last_error();
        path_ = dir_ / "probes.firelook";
        writeFireProbePackage(path_, true);
        ASSERT_EQ(fl_package_load(path_.c_str(), &package_), FL_OK) << fl_last_error();
    }
    void TearDown() override { EXPECT_EQ(fl_shutdown(), FL_OK); }

    // The runtime's probe values for frame slot `slot` and a look.
    std::vector<firelook::Rgb> expectedProbes(int slot, const firelook::Look& look) {
        const auto p = firelook::world::Package::open(path_);
        const firelook::world::ResolvedLook r = firelook::world::resolveLook(look, p->description());
        const basis::FireProbeTable& t = *p->fireProbes(slot);
        std::vector<firelook::Rgb> out(size_t(t.grid.probes()) * basis::kFireProbeCoefficients);
        basis::evaluateFireProbes(t, basis::interpolationWeights(p->description().axes, r.extinction), r.rbf,
                                  out.data());
        return out;
    }

    TempDir dir_;
    std::filesystem::path path_;
    fl_package package_{};
};

TEST_F(FireProbesApi, PackageProbesAreTheRuntimesForTheLookWithTheirPlacement) {
    size_t count = 0;
    fl_fire_probe_grid grid{};
    grid.struct_size = sizeof grid;
    ASSERT_EQ(fl_package_get_fire_probes(package_, 2, fl_look{}, &grid, nullptr, 0, &count), FL_OK)
        << fl_last_error();
    EXPECT_EQ(count, 12u * 27u);
    EXPECT_EQ(grid.counts[0], 3);
    EXPECT_EQ(grid.counts[1], 2);
    EXPECT_EQ(grid.counts[2], 2);
    EXPECT_EQ(grid.origin[1], 1.0);  // 0.5 * frame 2
    EXPECT_EQ(grid.spacing[2], 2.0);
    EXPECT_EQ(grid.falloff_radius, 0.3);
    EXPECT_EQ(grid.struct_size, sizeof grid);
    firelook::Look custom = firelook::world::Package::open(path_)->defaultLook();
    custom.smoke_extinction = 5.0;
    fl_look handle{};
    const std::string json = firelook::lookToJson(custom);
    ASSERT_EQ(fl_look_from_json(json.c_str(), 0, "custom", &handle), FL_OK) << fl_last_error();
    for (const fl_look look : {fl_look{}, handle}) {
        std::vector<float> values(count + 1, -7.0f);
        ASSERT_EQ(
            fl_package_get_fire_probes(package_, 2, look, nullptr, values.data(), values.size(), nullptr),
            FL_OK)
            << fl_last_error();
        const std::vector<firelook::Rgb> want =
            expectedProbes(1, look.id ? firelook::parseLook(json, "custom")
                                      : firelook::world::Package::open(path_)->defaultLook());
        for (size_t v = 0; v < want.size(); ++v)
            for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(values[3 * v + c], want[v][c]);
        EXPECT_EQ(values.back(), -7.0f);  // nothing written past the count
    }
    EXPECT_EQ(fl_look_release(handle), FL_OK);
}

TEST_F(FireProbesApi, SampleIsTheRuntimesBlendAndItsIrradiance) {
    fl_fire_probe_grid grid{};
    grid.struct_size = sizeof grid;
    std::vector<float> values(12 * 27);
    ASSERT_EQ(
        fl_package_get_fire_probes(package_, 1, fl_look{}, &grid, values.data(), values.size(), nullptr),
        FL_OK);
    basis::FireProbeGrid g;
    for (int a = 0; a < 3; ++a) {
        g.counts[a] = grid.counts[a];
        g.origin[a] = grid.origin[a];
        g.spacing[a] = grid.spacing[a];
        g.falloff_centre[a] = grid.falloff_centre[a];
    }
    g.falloff_radius = grid.falloff_radius;
    std::vector<firelook::Rgb> rgb(12 * 9);
    for (size_t v = 0; v < rgb.size(); ++v) rgb[v] = {values[3 * v], values[3 * v + 1], values[3 * v + 2]};
    for (const glm::dvec3& x :
         {glm::dvec3(-0.7, 0.8, 1.1), glm::dvec3(0.0, 0.5, 0.0), glm::dvec3(9.0, -3.0, 4.0)}) {
        firelook::Rgb sh[9];
        basis::sampleFireProbes(g, rgb, x, sh);
        const double point[3] = {x.x, x.y, x.z}, normal[3] = {0.0, 0.0, 2.0};  // not unit: normalised
        float fluence[3], irradiance[3];
        ASSERT_EQ(fl_fire_probes_sample(&grid, values.data(), values.size(), point, nullptr, fluence), FL_OK)
            << fl_last_error();
        ASSERT_EQ(fl_fire_probes_sample(&grid, values.data(), values.size(), point, normal, irradiance),
                  FL_OK);
        const firelook::Rgb f = basis::fluenceFromSh(sh), e = basis::irradianceFromSh(sh, {0.0, 0.0, 1.0});
        for (int c = 0; c < 3; ++c) {
            EXPECT_FLOAT_EQ(fluence[c], f[c]);
            EXPECT_FLOAT_EQ(irradiance[c], e[c]);
            EXPECT_GE(irradiance[c], 0.0f);
        }
    }
    // A zero normal: nothing arrives, and nothing non-finite.
    const double point[3] = {0.0, 1.0, 1.0}, zero[3] = {0.0, 0.0, 0.0};
    float out[3] = {-1.0f, -1.0f, -1.0f};
    ASSERT_EQ(fl_fire_probes_sample(&grid, values.data(), values.size(), point, zero, out), FL_OK);
    EXPECT_EQ(out[0], 0.0f);
}

TEST_F(FireProbesApi, RefusesBadHandlesArgumentsAndSizes) {
    std::vector<float> values(12 * 27);
    EXPECT_EQ(fl_package_get_fire_probes(fl_package{}, 1, fl_look{}, nullptr, values.data(), values.size(),
                                         nullptr),
              FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_package_get_fire_probes(package_, 1, fl_look{12345}, nullptr, values.data(), values.size(),
                                         nullptr),
              FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(
        fl_package_get_fire_probes(package_, 9, fl_look{}, nullptr, values.data(), values.size(), nullptr),
        FL_ERROR_NOT_FOUND);
    EXPECT_EQ(
        fl_package_get_fire_probes(package_, 1, fl_look{}, nullptr, values.data(), 12 * 27 - 1, nullptr),
        FL_ERROR_BUFFER_TOO_SMALL);
    EXPECT_EQ(fl_package_get_fire_probes(package_, 1, fl_look{}, nullptr, nullptr, values.size(), nullptr),
              FL_ERROR_INVALID_ARGUMENT);
    fl_fire_probe_grid small{};
    small.struct_size = firelook::plugin::FirstSize<fl_fire_probe_grid>::value - 1;
    EXPECT_EQ(
        fl_package_get_fire_probes(package_, 1, fl_look{}, &small, values.data(), values.size(), nullptr),
        FL_ERROR_STRUCT_SIZE);

    fl_fire_probe_grid grid{};
    grid.struct_size = sizeof grid;
    ASSERT_EQ(
        fl_package_get_fire_probes(package_, 1, fl_look{}, &grid, values.data(), values.size(), nullptr),
        FL_OK);
    const double point[3] = {0.0, 0.0, 0.0}, nan_point[3] = {0.0, std::nan(""), 0.0};
    float out[3];
    EXPECT_EQ(fl_fire_probes_sample(&grid, values.data(), values.size() - 1, point, nullptr, out),
              FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_fire_probes_sample(&grid, values.data(), values.size(), nan_point, nullptr, out),
              FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_fire_probes_sample(&grid, nullptr, values.size(), point, nullptr, out),
              FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_fire_probes_sample(nullptr, values.data(), values.size(), point, nullptr, out),
              FL_ERROR_INVALID_ARGUMENT);
    for (int bad = 0; bad < 3; ++bad) {
        fl_fire_probe_grid g = grid;
        if (bad == 0) g.counts[1] = 1;
        if (bad == 1) g.spacing[0] = 0.0;
        if (bad == 2) g.falloff_radius = -1.0;
        EXPECT_EQ(fl_fire_probes_sample(&g, values.data(), values.size(), point, nullptr, out),
                  FL_ERROR_INVALID_ARGUMENT)
            << bad;
    }
}

TEST_F(FireProbesApi, InstanceProbesFollowItsFrameAndLook) {
    fl_world world{};
    ASSERT_EQ(fl_world_create(nullptr, &world), FL_OK);
    fl_instance_desc d = fl_instance_desc_defaults();
    d.package = package_;
    fl_instance instance{};
    ASSERT_EQ(fl_instance_create(world, &d, &instance), FL_OK);
    std::vector<float> values(12 * 27), same(12 * 27);
    EXPECT_EQ(fl_instance_get_fire_probes(world, instance, nullptr, values.data(), values.size(), nullptr),
              FL_ERROR_NO_DATA);
    fl_playback_desc pb = fl_playback_desc_defaults();
    pb.paused = 1;
    pb.rate = 1.0;
    pb.time = 1.0;  // frame 2
    ASSERT_EQ(fl_instance_set_playback(world, instance, &pb), FL_OK);
    ASSERT_EQ(fl_world_update(world, 0.0), FL_OK);
    fl_fire_probe_grid grid{};
    grid.struct_size = sizeof grid;
    ASSERT_EQ(fl_instance_get_fire_probes(world, instance, &grid, values.data(), values.size(), nullptr),
              FL_OK)
        << fl_last_error();
    EXPECT_EQ(grid.origin[1], 1.0);  // frame 2's grid
    ASSERT_EQ(fl_package_get_fire_probes(package_, 2, fl_look{}, nullptr, same.data(), same.size(), nullptr),
              FL_OK);
    for (size_t v = 0; v < values.size(); ++v)
        EXPECT_NEAR(values[v], same[v], 1e-5 * std::abs(same[v]) + 1e-7);
}

TEST_F(FireProbesApi, APackageWithoutFireProbesReportsNone) {
    const auto old = dir_ / "none.firelook";
    writeFireProbePackage(old, false);
    fl_package p{};
    ASSERT_EQ(fl_package_load(old.c_str(), &p), FL_OK) << fl_last_error();
    size_t count = 99;
    EXPECT_EQ(fl_package_get_fire_probes(p, 1, fl_look{}, nullptr, nullptr, 0, &count), FL_ERROR_NOT_FOUND);
    EXPECT_NE(std::string(fl_last_error()).find("has no fire probes"), std::string::npos) << fl_last_error();
}

}  // namespace
