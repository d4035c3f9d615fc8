#include "render/medium.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <random>
#include <vector>

#include "render/render_error.h"

namespace firelook::render {
namespace {

// A small medium with distinct values per voxel and a rotated, scaled, translated transform.
struct Fixture {
    glm::ivec3 origin{3, -2, 5};
    glm::ivec3 dims{4, 3, 2};
    std::vector<float> density, temperature;
    glm::dmat4 index_to_world;

    Fixture() {
        for (int k = 0; k < dims.z; ++k)
            for (int j = 0; j < dims.y; ++j)
                for (int i = 0; i < dims.x; ++i) {
                    density.push_back(1.0f + i + 10.0f * j + 100.0f * k);
                    temperature.push_back(0.5f * i - j + 2.0f * k);
                }
        index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(1.0, -2.0, 0.5)) *
                         glm::rotate(glm::dmat4(1.0), 0.7, glm::normalize(glm::dvec3(1.0, 2.0, -1.0))) *
                         glm::scale(glm::dmat4(1.0), glm::dvec3(0.1, 0.2, 0.05));
    }
    Medium make(float background = -7.0f) const {
        return Medium(origin, dims, density, temperature, index_to_world, background);
    }
    float rho(int i, int j, int k) const { return density[i + dims.x * (j + dims.y * k)]; }
};

// Interpolation reproduces stored values to float rounding of the arithmetic (values up to ~200).
constexpr float kFloatTolerance = 1e-4f;

TEST(Medium, VoxelSitsAtItsIndexPointInWorldSpace) {
    const Fixture f;
    const Medium medium = f.make();
    for (int k = 0; k < f.dims.z; ++k)
        for (int j = 0; j < f.dims.y; ++j)
            for (int i = 0; i < f.dims.x; ++i) {
                const glm::dvec3 index = glm::dvec3(f.origin + glm::ivec3(i, j, k));
                const glm::dvec3 world(f.index_to_world * glm::dvec4(index, 1.0));
                const MediumSample s = medium.sampleWorld(world);
                EXPECT_NEAR(s.density, f.rho(i, j, k), kFloatTolerance);
                EXPECT_NEAR(s.temperature, 0.5f * i - j + 2.0f * k, kFloatTolerance);
            }
}

TEST(Medium, InterpolatesTrilinearlyBetweenVoxels) {
    const Fixture f;
    const Medium medium = f.make();
    const glm::dvec3 p = glm::dvec3(f.origin) + glm::dvec3(1.25, 0.5, 0.75);
    // Density is affine in (i, j, k) here, so trilinear interpolation is exact: 1 + i + 10 j + 100 k.
    EXPECT_NEAR(medium.sampleIndex(p).density, 1.0f + 1.25f + 5.0f + 75.0f, kFloatTolerance);
    EXPECT_NEAR(medium.sampleIndex(p).temperature, 0.625f - 0.5f + 1.5f, kFloatTolerance);
}

TEST(Medium, OutsideTheBoxReadsTheBackground) {
    const Fixture f;
    const Medium medium = f.make(-7.0f);
    const glm::dvec3 o(f.origin);
    // Half-way between the background layer and voxel (0,1,1): half the voxel, half the background.
    const MediumSample ramp = medium.sampleIndex(o + glm::dvec3(-0.5, 1.0, 1.0));
    EXPECT_NEAR(ramp.density, 0.5f * f.rho(0, 1, 1), kFloatTolerance);
    EXPECT_NEAR(ramp.temperature, 0.5f * (-7.0f) + 0.5f * (0.0f - 1.0f + 2.0f), kFloatTolerance);
    for (const glm::dvec3 outside :
         {o + glm::dvec3(-1.0, 1, 1), o + glm::dvec3(4.0, 0, 0), o + glm::dvec3(0, 0, 9.5),
          glm::dvec3(std::numeric_limits<double>::quiet_NaN())}) {
        EXPECT_EQ(medium.sampleIndex(outside).density, 0.0f);
        EXPECT_EQ(medium.sampleIndex(outside).temperature, -7.0f);
    }
}

TEST(Medium, SanitisesNonFiniteAndNegativeInput) {
    Fixture f;
    f.density[0] = std::numeric_limits<float>::quiet_NaN();
    f.density[1] = std::numeric_limits<float>::infinity();
    f.density[2] = -3.0f;
    f.temperature[3] = std::numeric_limits<float>::quiet_NaN();
    f.temperature[4] = -std::numeric_limits<float>::infinity();
    const Medium medium = f.make(-7.0f);
    EXPECT_EQ(medium.sanitizedValues(), 5u);
    const glm::dvec3 o(f.origin);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(medium.sampleIndex(o + glm::dvec3(i, 0, 0)).density, 0.0f);
    EXPECT_EQ(medium.sampleIndex(o + glm::dvec3(3, 0, 0)).temperature, -7.0f);
    EXPECT_EQ(medium.sampleIndex(o + glm::dvec3(0, 1, 0)).temperature, -7.0f);
    // Interpolating next to a cleaned voxel stays finite.
    EXPECT_TRUE(std::isfinite(medium.sampleIndex(o + glm::dvec3(0.5, 0.5, 0.5)).temperature));
}

TEST(Medium, RejectsMalformedInput) {
    const Fixture f;
    std::vector<float> short_density(f.density.begin(), f.density.end() - 1);
    EXPECT_THROW(Medium(f.origin, f.dims, short_density, f.temperature, f.index_to_world, 0.0f), RenderError);
    EXPECT_THROW(Medium(f.origin, f.dims, f.density, f.temperature, glm::dmat4(0.0), 0.0f), RenderError);
    glm::dmat4 projective(1.0);
    projective[2][3] = 1.0;
    EXPECT_THROW(Medium(f.origin, f.dims, f.density, f.temperature, projective, 0.0f), RenderError);
    EXPECT_THROW(Medium(f.origin, glm::ivec3(-1, 1, 1), {}, {}, glm::dmat4(1.0), 0.0f), RenderError);
}

TEST(Medium, EmptyMediumHasNoDensity) {
    const Medium medium(glm::ivec3(0), glm::ivec3(0, 5, 5), {}, {}, glm::dmat4(1.0), 2.0f);
    EXPECT_TRUE(medium.empty());
    EXPECT_EQ(medium.sampleIndex(glm::dvec3(0.0)).density, 0.0f);
    EXPECT_EQ(medium.brickCounts(), glm::ivec3(0));
}

TEST(Medium, BricksBoundEveryInterpolatedValue) {
    // Random voxels on a box that is not a multiple of the brick size; points anywhere the density
    // can be non-zero must lie inside their brick's ranges.
    const glm::ivec3 dims(19, 11, 9), origin(-4, 2, 0);
    std::mt19937 gen(7);
    std::uniform_real_distribution<float> value(0.0f, 1.0f);
    std::vector<float> density, temperature;
    for (int n = 0; n < dims.x * dims.y * dims.z; ++n) {
        density.push_back(value(gen) < 0.7f ? 0.0f : 5.0f * value(gen));
        temperature.push_back(3.0f * value(gen) - 1.0f);
    }
    const Medium medium(origin, dims, density, temperature, glm::dmat4(1.0), 0.25f);
    // ceil((dims + 1) / brick size): points from origin - 1 to origin + dims see stored voxels.
    const glm::ivec3 expected_counts = (dims + 1 + Medium::kBrickSize - 1) / Medium::kBrickSize;
    EXPECT_EQ(medium.brickCounts(), expected_counts);
    EXPECT_GT(expected_counts.x, 1);  // several bricks per axis, so borders between them are tested
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int n = 0; n < 20000; ++n) {
        const glm::dvec3 p =
            glm::dvec3(origin) - 1.0 + glm::dvec3(u(gen), u(gen), u(gen)) * glm::dvec3(dims + 1);
        const glm::ivec3 b =
            glm::ivec3(glm::floor((p - medium.brickGridOrigin()) / double(Medium::kBrickSize)));
        const BrickRange& range = medium.brick(b);
        const MediumSample s = medium.sampleIndex(p);
        ASSERT_LE(s.density, range.max_density);
        ASSERT_GE(s.temperature, range.min_temperature);
        ASSERT_LE(s.temperature, range.max_temperature);
    }
}

// The byte a brick the marches test (brickHasDensity) says what its range says: density in one
// corner of a 17^3 box leaves most bricks empty, and a brick next to a dense voxel holds density (it
// interpolates from it) even where its own voxels are all 0.
TEST(Medium, BrickBytesSayWhichBricksHoldDensity) {
    const glm::ivec3 dims(17);
    std::vector<float> density(static_cast<std::size_t>(dims.x) * dims.y * dims.z, 0.0f);
    std::vector<float> temperature(density.size(), 1.0f);
    for (int z = 0; z < 5; ++z)
        for (int y = 0; y < 5; ++y)
            for (int x = 0; x < 5; ++x) density[x + dims.x * (y + dims.y * z)] = 2.0f;
    const Medium medium(glm::ivec3(0), dims, density, temperature, glm::dmat4(1.0), 0.0f);
    const glm::ivec3 n = medium.brickCounts();
    int holding = 0, empty = 0;
    for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
            for (int x = 0; x < n.x; ++x) {
                const bool has = medium.brickHasDensity({x, y, z});
                ASSERT_EQ(has, medium.brick({x, y, z}).max_density > 0.0f) << x << " " << y << " " << z;
                (has ? holding : empty)++;
            }
    // Voxels 0-4 reach index points up to 5 (bricks of points -1..2, 3..6): bricks 0 and 1 per axis.
    EXPECT_EQ(holding, 8);
    EXPECT_EQ(empty, n.x * n.y * n.z - 8);
}

TEST(Medium, HomogeneousBoxHasTheStatedSizeAndUniformTemperature) {
    const glm::dvec3 size(2.0, 1.0, 4.0);
    const Medium box = Medium::homogeneousBox(size, glm::ivec3(4, 2, 8), 3.0f, 0.6f);
    // The faces of the equivalent box sit half-way up the one-voxel ramps: density / 2.
    EXPECT_NEAR(box.sampleWorld({1.0, 0.0, 0.0}).density, 1.5f, kFloatTolerance);
    EXPECT_NEAR(box.sampleWorld({0.0, 0.0, -2.0}).density, 1.5f, kFloatTolerance);
    EXPECT_NEAR(box.sampleWorld({0.3, -0.2, 1.1}).density, 3.0f, kFloatTolerance);
    EXPECT_EQ(box.sampleWorld({0.0, 0.0, 9.0}).density, 0.0f);
    EXPECT_NEAR(box.sampleWorld({1.2, 0.0, 0.0}).temperature, 0.6f, kFloatTolerance);
    // Density can be non-zero half a voxel beyond each face.
    const WorldBox bounds = box.worldBounds();
    EXPECT_NEAR(bounds.min.x, -1.25, 1e-12);
    EXPECT_NEAR(bounds.max.z, 2.25, 1e-12);
    EXPECT_NEAR(box.minVoxelEdge(), 0.5, 1e-12);
}

}  // namespace
}  // namespace firelook::render
