// The fire's point lights (baker/bake/fire_light_tracer.h, runtime/basis/fire_lights.h): what they
// were built from is conserved, they are linear in the emission, never NaN, inside the volume,
// stored and read back (and absent from older packages), and the fluence probe they are measured
// with (baker/render/fluence_probe.h) against a closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "../support/temp_dir.h"
#include "bake/bake_pipeline.h"
#include "bake/fire_light_tracer.h"
#include "basis/basis_package.h"
#include "basis/fire_lights.h"
#include "render/fluence_probe.h"
#include "render/random.h"
#include "render/volume_scene.h"
#include "render/volume_walk.h"
#include "tiny_sample_bake.h"
#include "world/package.h"

namespace firelook::bake {
namespace {

using firelook::testing::TempDir;

// A 12^3 ball of voxels 0.1 apart, hot and dense in the middle, off the world origin.
render::Medium ball() {
    const int n = 12;
    std::vector<float> density(n * n * n), temperature(n * n * n);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double r = glm::length(glm::dvec3(i, j, k) - 5.5) / 5.5;
                density[i + n * (j + n * k)] = static_cast<float>(std::max(0.0, 3.0 * (1.0 - r)));
                temperature[i + n * (j + n * k)] = static_cast<float>(std::clamp(3.2 * (1.0 - r), 0.0, 3.0));
            }
    glm::dmat4 index_to_world(0.1);
    index_to_world[3] = glm::dvec4(1.0, 2.0, 3.0, 1.0);
    return render::Medium({0, 0, 0}, {n, n, n}, density, temperature, index_to_world, 0.0f);
}

BasisModel model() {
    BasisModel m;
    m.bins = {0.0, 3.0, 4};
    m.rbf_width = kDefaultRbfWidth;
    m.albedo = 0.5;
    m.axes = {{1.0, 2.0}, {2.0, 8.0}, {1.0, 4.0}};
    return m;
}

const std::vector<Rgb> kCoefficients = {{0.5f, 0.2f, 0.1f}, {1.0f, 0.6f, 0.2f}, {4.0f, 3.0f, 1.0f}, {8.0f, 7.0f, 5.0f}};

basis::GridWeights atPoint(int point) {
    basis::GridWeights w;
    w.count = 1;
    w.point[0] = point;
    w.weight[0] = 1.0f;
    return w;
}

std::vector<basis::FireLight> lights(const basis::FireLightTable& t, const basis::GridWeights& w,
                                     const std::vector<Rgb>& c, int count) {
    std::vector<basis::FireLight> out(count);
    basis::evaluateFireLights(t, w, c, count, out.data());
    return out;
}

glm::dvec3 total(const std::vector<basis::FireLight>& ls) {
    glm::dvec3 sum(0.0);
    for (const basis::FireLight& l : ls) sum += glm::dvec3(l.intensity);
    return sum;
}

TEST(FireLights, ConserveTheEscapingIntensityOfDirectIntegration) {
    const render::Medium medium = ball();
    const BasisModel m = model();
    const basis::FireLightTable table = traceFireLights(medium, m);
    ASSERT_EQ(table.clusters, 8);
    const double voxel_volume = 0.001;
    for (int point : {0, 7}) {
        const ExtinctionParams theta = m.axes.point(point);
        // Direct integration, independent of the tracer's marches and directions: every voxel's
        // emission times its escape transmittance, estimated by ratio tracking along 256 random
        // directions with the extinction scaled to absorption ((1 - albedo) sigma_t).
        LookModel absorbing;
        absorbing.bins = m.bins;
        absorbing.albedo = 0.0;
        absorbing.extinction = {theta.temperature_threshold, theta.smoke_extinction * (1.0 - m.albedo),
                                theta.flame_extinction * (1.0 - m.albedo)};
        absorbing.emission.basis = {m.bins, m.rbf_width, true};
        absorbing.emission.coefficients = kCoefficients;
        const render::VolumeScene scene(medium, absorbing);
        render::Pcg32 rng(11);
        glm::dvec3 direct(0.0);
        for (int k = 0; k < 12; ++k)
            for (int j = 0; j < 12; ++j)
                for (int i = 0; i < 12; ++i) {
                    const render::MediumSample v = medium.voxel({i, j, k});
                    if (v.density <= 0.0f) continue;
                    const glm::dvec3 x(medium.indexToWorld() * glm::dvec4(i, j, k, 1.0));
                    double escape = 0.0;
                    for (int s = 0; s < 256; ++s)
                        escape += render::ratioTrackingTransmittance(scene, {x, render::sampleIsotropicDirection(rng)}, rng);
                    direct += glm::dvec3(absorbing.emission.evaluate(v.temperature)) * double(v.density) *
                              voxel_volume * escape / 256.0;
                }
        for (int count : {1, 8}) {
            const glm::dvec3 proxies = total(lights(table, atPoint(point), kCoefficients, count));
            // 3%: the tracer averages the escape over 32 fixed directions (a quadrature whose error on
            // one voxel is several percent but averages out over the ball) against the reference's
            // random ones, whose own noise on this sum is about 0.2%.
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(proxies[c] / direct[c], 1.0, 0.03) << "point " << point << " count " << count << ": " << proxies[c] / direct[c];
        }
    }
}

TEST(FireLights, AreLinearInTheEmissionAndMergeWithoutLoss) {
    const basis::FireLightTable table = traceFireLights(ball(), model());
    basis::GridWeights w;
    w.count = 2;
    w.point = {1, 6};
    w.weight = {0.3f, 0.7f};
    std::vector<Rgb> other(4), sum(4), twice(4);
    for (int i = 0; i < 4; ++i) {
        other[i] = Rgb(float(i == 0), 0.5f, float(3 - i));
        sum[i] = kCoefficients[i] + other[i];
        twice[i] = 2.0f * kCoefficients[i];
    }
    for (int count : {1, 2, 4, 8}) {
        const auto a = lights(table, w, kCoefficients, count), b = lights(table, w, other, count),
                   ab = lights(table, w, sum, count), a2 = lights(table, w, twice, count);
        for (int l = 0; l < count; ++l)
            for (int c = 0; c < 3; ++c) {
                // float moments summed in double: relative rounding about 1e-6.
                EXPECT_NEAR(ab[l].intensity[c], a[l].intensity[c] + b[l].intensity[c], 1e-5 * ab[l].intensity[c] + 1e-12);
                EXPECT_NEAR(a2[l].intensity[c], 2.0 * a[l].intensity[c], 1e-5 * a2[l].intensity[c] + 1e-12);
                EXPECT_NEAR(glm::length(a2[l].position - a[l].position), 0.0, 1e-9);  // scaling moves nothing
            }
        // Coarser lights are merges of finer ones: the same total.
        const glm::dvec3 all = total(lights(table, w, kCoefficients, 8)), these = total(a);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(these[c], all[c], 1e-6 * all[c]);
    }
}

TEST(FireLights, SitInsideTheVolumeAndCarryAPlausibleRadius) {
    const render::Medium medium = ball();
    const render::WorldBox box = medium.worldBounds();
    const basis::FireLightTable table = traceFireLights(medium, model());
    for (int point = 0; point < 8; ++point)
        for (int count : {1, 2, 4, 8})
            for (const basis::FireLight& l : lights(table, atPoint(point), kCoefficients, count)) {
                for (int i = 0; i < 3; ++i) {
                    EXPECT_GE(l.position[i], box.min[i]);
                    EXPECT_LE(l.position[i], box.max[i]);
                }
                EXPECT_GT(l.radius, 0.0);
                EXPECT_LT(l.radius, glm::length(box.max - box.min));
            }
    // One light for the whole ball: at its centre (symmetric), with a radius of a ball's worth.
    const basis::FireLight one = lights(table, atPoint(0), kCoefficients, 1)[0];
    EXPECT_NEAR(glm::length(one.position - glm::dvec3(1.55, 2.55, 3.55)), 0.0, 0.05);  // half a voxel
    EXPECT_GT(one.radius, 0.1);
}

TEST(FireLights, AreFiniteForEmptyFramesAndZeroEmission) {
    const std::vector<Rgb> zero(4, Rgb(0.0f));
    for (const basis::FireLightTable& table : {traceFireLights(render::Medium(), model()), traceFireLights(ball(), model())})
        for (const auto& c : {zero, kCoefficients})
            for (int count : {1, 8})
                for (const basis::FireLight& l : lights(table, atPoint(3), c, count)) {
                    for (int i = 0; i < 3; ++i) {
                        EXPECT_TRUE(std::isfinite(l.position[i]));
                        EXPECT_TRUE(std::isfinite(l.intensity[i]));
                        EXPECT_GE(l.intensity[i], 0.0f);
                    }
                    EXPECT_TRUE(std::isfinite(l.radius));
                    if (c == zero) {
                        EXPECT_EQ(l.radius, 0.0);
                    }
                }
    const basis::FireLight empty = lights(traceFireLights(render::Medium(), model()), atPoint(0), kCoefficients, 1)[0];
    EXPECT_EQ(empty.intensity, Rgb(0.0f));
}

TEST(FireLights, RoundTripThroughTheSectionAndRefuseDamage) {
    const basis::FireLightTable table = traceFireLights(ball(), model());
    const std::vector<std::byte> bytes = basis::encodeFireLights(table);
    EXPECT_EQ(bytes, basis::encodeFireLights(traceFireLights(ball(), model())));  // deterministic
    const basis::FireLightTable back = basis::decodeFireLights(bytes, 8, 4, "x.firelook: frame 1");
    EXPECT_EQ(back.moments, table.moments);
    EXPECT_EQ(back.reference, table.reference);
    EXPECT_EQ(back.extinction_scale, 0.5f);
    EXPECT_THROW(basis::decodeFireLights(std::span(bytes).first(bytes.size() - 4), 8, 4, "x"), std::runtime_error);
    EXPECT_THROW(basis::decodeFireLights(bytes, 8, 5, "x"), std::runtime_error);
    std::vector<std::byte> nan = bytes;
    const float bad = std::nanf("");
    std::memcpy(nan.data() + nan.size() - 4, &bad, 4);
    try {
        basis::decodeFireLights(nan, 8, 4, "x.firelook: frame 1");
        ADD_FAILURE() << "a NaN was accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "x.firelook: frame 1: fire lights have a non-finite value");
    }
}

TEST(FireLights, AreBakedIntoPackagesAndAbsentFromOlderOnes) {
    TempDir dir;
    const auto path = dir / "tiny.firelook";
    BakeConfig config = test::tinyConfig();
    config.fire_lights = true;
    bakePackage(FIRELOOK_SAMPLE_DIR, path, config, "test");
    // Without --fire-lights a package holds none.
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / "none.firelook", test::tinyConfig(), "test");
    EXPECT_FALSE(basis::BasisReader::open(dir / "none.firelook").loadFireLights(1));
    const basis::BasisReader baked = basis::BasisReader::open(path);
    const std::optional<basis::FireLightTable> table = baked.loadFireLights(1);
    ASSERT_TRUE(table);
    EXPECT_EQ(table->points, baked.description().axes.pointCount());
    const package::SectionInfo* section = baked.reader().find(basis::kSectionFireLights, 1);
    ASSERT_NE(section, nullptr);
    EXPECT_FALSE(section->required());
    EXPECT_EQ(baked.reader().version().minor, package::kFormatMinor);
    const auto runtime_package = world::Package::open(path);
    ASSERT_NE(runtime_package->fireLights(0), nullptr);
    EXPECT_GT(total(lights(*table, atPoint(0), std::vector<Rgb>(4, Rgb(1.0f)), 1)).x, 0.0);

    // The same package as a 1.0 writer made it, without the section: it loads and has no lights.
    const auto old = dir / "old.firelook";
    {
        package::ContainerWriter writer(old, package::WriterOptions{.zstd_level = 1, .format_minor = 0});
        for (const package::SectionInfo& s : baked.reader().sections())
            if (s.type != basis::kSectionFireLights) writer.addStoredSection(s, baked.reader().stored(s));
        writer.commit();
    }
    EXPECT_FALSE(basis::BasisReader::open(old).loadFireLights(1));
    EXPECT_EQ(world::Package::open(old)->fireLights(0), nullptr);
}

TEST(FluenceProbe, MatchesTheInverseSquareLawOfAThinEmitter) {
    // An optically thin 1x1x1 box of emission j (sigma_t 0.01 across it): from 20 units away its
    // fluence is j V / d^2 up to the thin box's self-absorption (about 0.5%) and the box's size
    // against the distance (0.1%).
    LookModel look;
    look.bins = {0.0, 3.0, 4};
    look.albedo = 0.0;
    look.extinction = {1.5, 0.01, 0.01};
    look.emission.basis = {look.bins, kDefaultRbfWidth, true};
    look.emission.coefficients = {Rgb(0.0f), Rgb(0.0f), Rgb(2.0f, 1.0f, 0.5f), Rgb(0.0f)};
    const render::Medium box = render::Medium::homogeneousBox(glm::dvec3(1.0), glm::ivec3(8), 1.0f, 2.0f);
    const render::VolumeScene scene(box, look);
    const glm::dvec3 j(look.emission.evaluate(2.0));
    const render::FluenceEstimate e = render::estimateFluence(scene, {0.0, 0.0, 20.0}, 80000, 3);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(e.fluence[c] / (j[c] / 400.0), 1.0, 0.01 + 3.0 * e.standard_error[c] / e.fluence[c]);
        EXPECT_LT(e.standard_error[c], 0.01 * e.fluence[c]);
    }
}

}  // namespace
}  // namespace firelook::bake
