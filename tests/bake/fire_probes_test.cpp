// The fire's probe grid (baker/bake/fire_probe_tracer.h, runtime/basis/fire_probes.h): against the
// irradiance probe of the full model at and between probes, linear in the emission, exact at the
// probes and finite everywhere, stored and read back (and absent from packages baked without it),
// and the irradiance probe itself (baker/render/fluence_probe.h) against a closed form.
#include "basis/fire_probes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "../support/temp_dir.h"
#include "bake/bake_config.h"
#include "bake/bake_pipeline.h"
#include "bake/fire_probe_tracer.h"
#include "basis/basis_package.h"
#include "render/fluence_probe.h"
#include "render/random.h"
#include "render/volume_scene.h"
#include "tiny_sample_bake.h"
#include "world/package.h"

namespace firelook::bake {
namespace {

using firelook::testing::TempDir;

// A 16^3 ball of voxels 0.1 apart, hot and dense in the middle and cooler, smokier to one side
// (+x), off the world origin: its light is not symmetric about its centre.
render::Medium probeBall() {
    const int n = 16;
    std::vector<float> density(n * n * n), temperature(n * n * n);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double r = glm::length(glm::dvec3(i, j, k) - 7.5) / 7.5;
                density[i + n * (j + n * k)] =
                    static_cast<float>(std::max(0.0, 2.0 * (1.0 - r)) * (1.0 + i / 8.0));
                temperature[i + n * (j + n * k)] =
                    static_cast<float>(std::clamp(3.2 * (1.0 - r) - 0.1 * i, 0.0, 3.0));
            }
    glm::dmat4 index_to_world(0.1);
    index_to_world[3] = glm::dvec4(1.0, 2.0, 3.0, 1.0);
    return render::Medium({0, 0, 0}, {n, n, n}, density, temperature, index_to_world, 0.0f);
}

BasisModel probeModel(double albedo) {
    BasisModel m;
    m.bins = {0.0, 3.0, 4};
    m.rbf_width = kDefaultRbfWidth;
    m.albedo = albedo;
    m.axes = {{1.0, 2.0}, {1.0, 4.0}, {0.5, 2.0}};
    return m;
}

const std::vector<Rgb> kProbeCoefficients = {
    {0.5f, 0.2f, 0.1f}, {1.0f, 0.6f, 0.2f}, {4.0f, 3.0f, 1.0f}, {8.0f, 7.0f, 5.0f}};

basis::GridWeights onePoint(int point) {
    basis::GridWeights w;
    w.count = 1;
    w.point[0] = point;
    w.weight[0] = 1.0f;
    return w;
}

std::vector<Rgb> probeValues(const basis::FireProbeTable& t, const basis::GridWeights& w,
                             const std::vector<Rgb>& c) {
    std::vector<Rgb> out(static_cast<size_t>(t.grid.probes()) * basis::kFireProbeCoefficients);
    basis::evaluateFireProbes(t, w, c, out.data());
    return out;
}

// The scene of grid point `point` with the given emission: what the reference renders.
LookModel lookAt(const BasisModel& m, int point, const std::vector<Rgb>& c) {
    LookModel look;
    look.bins = m.bins;
    look.albedo = m.albedo;
    look.extinction = m.axes.point(point);
    look.emission.basis = {m.bins, m.rbf_width, true};
    look.emission.coefficients = c;
    return look;
}

double meanOf(const glm::dvec3& v) { return (v.x + v.y + v.z) / 3.0; }

TEST(IrradianceProbe, FollowsTheCosineLawOfAThinEmitter) {
    // An optically thin 1x1x1 box of emission j, 20 units away: irradiance j V cos / d^2 up to the
    // box's self-absorption (about 0.5%) and size against the distance (0.1%), as the fluence test.
    LookModel look;
    look.bins = {0.0, 3.0, 4};
    look.albedo = 0.0;
    look.extinction = {1.5, 0.01, 0.01};
    look.emission.basis = {look.bins, kDefaultRbfWidth, true};
    look.emission.coefficients = {Rgb(0.0f), Rgb(0.0f), Rgb(2.0f, 1.0f, 0.5f), Rgb(0.0f)};
    const render::Medium box = render::Medium::homogeneousBox(glm::dvec3(1.0), glm::ivec3(8), 1.0f, 2.0f);
    const render::VolumeScene scene(box, look);
    const glm::dvec3 j(look.emission.evaluate(2.0));
    const glm::dvec3 point(0.0, 0.0, 20.0);
    for (double angle : {0.0, 60.0}) {
        const double a = angle * std::numbers::pi / 180.0;
        const render::FluenceEstimate e =
            render::estimateIrradiance(scene, point, {std::sin(a), 0.0, -std::cos(a)}, 40000, 5);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(e.fluence[c] / (j[c] * std::cos(a) / 400.0), 1.0,
                        0.01 + 3.0 * e.standard_error[c] / e.fluence[c])
                << angle << " degrees";
    }
    // Facing away, and a zero normal: nothing.
    EXPECT_EQ(render::estimateIrradiance(scene, point, {0.0, 0.0, 1.0}, 1000, 5).fluence, glm::dvec3(0.0));
    EXPECT_EQ(render::estimateIrradiance(scene, point, glm::dvec3(0.0), 1000, 5).fluence, glm::dvec3(0.0));
}

TEST(IrradianceProbe, InsideAThinBoxBothSidesAgreeAndBoundTheFluence) {
    // At the centre of a thin box (the hemisphere branch: cosine-distributed directions) the
    // irradiance on +z and on -z agree by symmetry (within 3 standard errors), and their sum, the
    // integral of L |cos|, is below the fluence, the integral of L.
    LookModel look;
    look.bins = {0.0, 3.0, 4};
    look.albedo = 0.0;
    look.extinction = {1.5, 0.01, 0.01};
    look.emission.basis = {look.bins, kDefaultRbfWidth, true};
    look.emission.coefficients = {Rgb(0.0f), Rgb(0.0f), Rgb(1.0f), Rgb(0.0f)};
    const render::Medium box = render::Medium::homogeneousBox(glm::dvec3(1.0), glm::ivec3(8), 1.0f, 2.0f);
    const render::VolumeScene scene(box, look);
    const glm::dvec3 centre(0.5 * (box.worldBounds().min + box.worldBounds().max));
    const render::FluenceEstimate up = render::estimateIrradiance(scene, centre, {0, 0, 1}, 20000, 1);
    const render::FluenceEstimate down = render::estimateIrradiance(scene, centre, {0, 0, -1}, 20000, 2);
    const render::FluenceEstimate all = render::estimateFluence(scene, centre, 20000, 3);
    EXPECT_GT(up.fluence.x, 0.0);
    EXPECT_NEAR(up.fluence.x, down.fluence.x, 3.0 * std::hypot(up.standard_error.x, down.standard_error.x));
    EXPECT_LT(up.fluence.x + down.fluence.x, all.fluence.x);
}

TEST(FireProbes, MatchTheReferenceAtTheProbesWithoutScattering) {
    // Albedo 0: the probes' marches are the whole model, so what is left is the SH truncation
    // (irradiance; the fluence is exact in L00) and the quadrature of 1024 directions.
    const render::Medium medium = probeBall();
    const BasisModel m = probeModel(0.0);
    FireProbeSettings settings;
    settings.resolution = 3;
    const basis::FireProbeTable table = traceFireProbes(medium, m, settings);
    for (int point : {0, 7}) {
        const std::vector<Rgb> values = probeValues(table, onePoint(point), kProbeCoefficients);
        const render::VolumeScene scene(medium, lookAt(m, point, kProbeCoefficients));
        for (int probe : {0, 5, 13, 22}) {  // corners, an edge, the centre (inside the ball), a face
            const glm::dvec3 x = table.grid.position(probe % 3, (probe / 3) % 3, probe / 9);
            const Rgb* sh = values.data() + probe * basis::kFireProbeCoefficients;
            const render::FluenceEstimate f = render::estimateFluence(scene, x, 60000, 10 + probe);
            fprintf(stderr, "probe %d point %d ratio %.4f se %.4f\n", probe, point,
                    meanOf(glm::dvec3(basis::fluenceFromSh(values.data() + probe * 9))) / meanOf(f.fluence),
                    meanOf(f.standard_error) / meanOf(f.fluence));
            // 1% for the directions' quadrature and the march (200000 paths measured all eight within
            // 1.5%, each within 1.3 of its standard errors) besides 3 of the reference's standard errors
            // (0.1-2.3% here: a corner sees the ball's sharp edge).
            EXPECT_NEAR(meanOf(glm::dvec3(basis::fluenceFromSh(sh))) / meanOf(f.fluence), 1.0,
                        0.01 + 3.0 * meanOf(f.standard_error) / meanOf(f.fluence))
                << "probe " << probe << " point " << point;
            const glm::dvec3 normal =
                probe == 13 ? glm::dvec3(0, 0, 1) : glm::normalize(table.grid.falloff_centre - x);
            const render::FluenceEstimate e = render::estimateIrradiance(scene, x, normal, 60000, 20 + probe);
            // 8%: order-2 SH of a source covering a cone of 40-70 degrees overshoots the cosine lobe by
            // up to 6% facing it (+6.25% for a point source); measured here within 4%.
            EXPECT_NEAR(meanOf(glm::dvec3(basis::irradianceFromSh(sh, normal))) / meanOf(e.fluence), 1.0,
                        0.08)
                << "probe " << probe << " point " << point;
        }
    }
}

// The irradiance rule (basis/fire_probes.h, irradianceFromSh) on uniform cones of light of half-angle
// 1-120 degrees about a tilted axis: the SH projection and the exact irradiance from the same
// quadrature of the cone (so both see the same light), at normals 0, 45 and 80 degrees from the axis.
// Facing the cone within 1.2% at every size (measured 1.03% at most, the 60-degree cone, where the
// split has no weight and order 2's own error is left) and within 0.5% for cones up to 30 degrees,
// where order 2 alone is 4-6% high (the bands it cuts); at 45 and 80 degrees within 5% (measured 4.3%
// at most, the 15-degree cone at 80 degrees, where order 2 alone is 15% off), and never more than
// 1.5 points worse than order 2 alone (measured 1.2 points worse at most: the 45-degree cone at 80
// degrees, 1.6% against 0.4%). A light from all around (L00 only) is order 2's, exactly.
TEST(FireProbes, IrradianceOfAConeOfLight) {
    const glm::dvec3 axis = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
    const glm::dvec3 u = glm::normalize(glm::cross(axis, glm::dvec3(1, 0, 0))), v = glm::cross(axis, u);
    const glm::dvec3 w_tilt = u;  // normals tilt from the axis towards u
    for (double degrees : {1.0, 5.0, 15.0, 30.0, 45.0, 60.0, 90.0, 120.0}) {
        const double c = std::cos(degrees * std::numbers::pi / 180.0);
        const int rings = 200, sectors = 400;
        const double d_omega = 2.0 * std::numbers::pi * (1.0 - c) / (rings * sectors);
        std::vector<glm::dvec3> directions;
        for (int i = 0; i < rings; ++i)
            for (int j = 0; j < sectors; ++j) {
                const double mu = c + (1.0 - c) * (i + 0.5) / rings, s = std::sqrt(1.0 - mu * mu);
                const double phi = 2.0 * std::numbers::pi * (j + 0.5) / sectors;
                directions.push_back(mu * axis + s * std::cos(phi) * u + s * std::sin(phi) * v);
            }
        Rgb sh[basis::kFireProbeCoefficients];
        std::fill(sh, sh + basis::kFireProbeCoefficients, Rgb(0.0f));
        double y[basis::kFireProbeCoefficients];
        for (const glm::dvec3& d : directions) {
            basis::shBasis(d, y);
            for (int k = 0; k < basis::kFireProbeCoefficients; ++k) sh[k] += Rgb(static_cast<float>(y[k] * d_omega));
        }
        for (double tilt : {0.0, 45.0, 80.0}) {
            const double t = tilt * std::numbers::pi / 180.0;
            const glm::dvec3 n = std::cos(t) * axis + std::sin(t) * w_tilt;
            double exact = 0.0;
            for (const glm::dvec3& d : directions) exact += std::max(0.0, glm::dot(n, d)) * d_omega;
            const double got = basis::irradianceFromSh(sh, n).g;
            basis::shBasis(n, y);
            double sh_only = 0.0;
            for (int k = 0; k < basis::kFireProbeCoefficients; ++k)
                sh_only += (k == 0 ? 1.0 : k < 4 ? 2.0 / 3.0 : 0.25) * std::numbers::pi * y[k] * sh[k].g;
            std::printf("[measured] cone %g deg, normal %g deg: irradiance / exact %.4f (order 2 alone %.4f)\n",
                        degrees, tilt, got / exact, sh_only / exact);
            const double bound = tilt != 0.0 ? 0.05 : degrees <= 30.0 ? 0.005 : 0.012;
            EXPECT_NEAR(got / exact, 1.0, bound) << degrees << " deg cone, normal " << tilt;
            EXPECT_LE(std::abs(got / exact - 1.0), std::abs(sh_only / exact - 1.0) + 0.015)
                << degrees << " deg cone, normal " << tilt;
        }
    }
    Rgb ambient[basis::kFireProbeCoefficients];
    std::fill(ambient, ambient + basis::kFireProbeCoefficients, Rgb(0.0f));
    ambient[0] = Rgb(2.0f);
    EXPECT_FLOAT_EQ(basis::irradianceFromSh(ambient, glm::dvec3(0, 0, 1)).r,
                    static_cast<float>(std::numbers::pi * 2.0 * 0.28209479177387814));
    EXPECT_EQ(basis::directionalShare(1.0, 0.0), 0.0);
    EXPECT_EQ(basis::directionalShare(1.0, std::sqrt(3.0)), 1.0);
}

TEST(FireProbes, BetweenProbesMatchTheFullModelWithinTheStatedMargin) {
    // The guard of the README's figure, small and fast: a 5^3 grid around the ball with albedo 0.5
    // (scattering marched as absorption only), 40 random points outside the ball within the grid,
    // irradiance facing the emission's centre against the full model (8000 paths a point: 1-3%
    // noise). Measured 2.3% median, 13.6% worst (4.7% / 13.3% with order-2 SH alone, before the
    // directional split of irradianceFromSh; albedo 0: 2.6% / 8.2%; marched with the full
    // extinction instead, 26% / 36%: this ball is optically thick, 2 to 9, and scatters much); the
    // bounds, 7% and 20%, leave room for the reference's noise, and catch a grid that loses the
    // scattered light or the blend's falloff (without it 9.2% / 43%).
    const render::Medium medium = probeBall();
    const BasisModel m = probeModel(0.5);
    FireProbeSettings settings;
    settings.resolution = 5;
    const basis::FireProbeTable table = traceFireProbes(medium, m, settings);
    const int point = 0;
    const std::vector<Rgb> values = probeValues(table, onePoint(point), kProbeCoefficients);
    const render::VolumeScene scene(medium, lookAt(m, point, kProbeCoefficients));
    const render::WorldBox box = medium.worldBounds();
    render::Pcg32 rng(3);
    std::vector<double> errors;
    while (errors.size() < 40) {
        const glm::dvec3 x = table.grid.origin + table.grid.spacing * double(settings.resolution - 1) *
                                                     glm::dvec3(rng.uniform(), rng.uniform(), rng.uniform());
        if (glm::all(glm::greaterThanEqual(x, box.min)) && glm::all(glm::lessThanEqual(x, box.max))) continue;
        const glm::dvec3 n = glm::normalize(table.grid.falloff_centre - x);
        const render::FluenceEstimate e = render::estimateIrradiance(scene, x, n, 8000, errors.size());
        Rgb sh[basis::kFireProbeCoefficients];
        basis::sampleFireProbes(table.grid, values, x, sh);
        errors.push_back(
            std::abs(meanOf(glm::dvec3(basis::irradianceFromSh(sh, n))) / meanOf(e.fluence) - 1.0));
    }
    std::sort(errors.begin(), errors.end());
    std::printf("[measured] irradiance between probes: median %.4f, worst %.4f\n", errors[errors.size() / 2],
                errors.back());
    EXPECT_LT(errors[errors.size() / 2], 0.07);
    EXPECT_LT(errors.back(), 0.20);
}

TEST(FireProbes, AreLinearInTheEmissionAndExactAtTheProbes) {
    FireProbeSettings settings;
    settings.resolution = 3;
    const basis::FireProbeTable table = traceFireProbes(probeBall(), probeModel(0.5), settings);
    basis::GridWeights w;
    w.count = 2;
    w.point = {1, 6};
    w.weight = {0.3f, 0.7f};
    std::vector<Rgb> other(4), sum(4);
    for (int i = 0; i < 4; ++i) {
        other[i] = Rgb(float(i == 0), 0.5f, float(3 - i));
        sum[i] = kProbeCoefficients[i] + other[i];
    }
    const auto a = probeValues(table, w, kProbeCoefficients), b = probeValues(table, w, other),
               ab = probeValues(table, w, sum);
    for (size_t v = 0; v < a.size(); ++v)
        for (int c = 0; c < 3; ++c)  // float tables summed in double: relative rounding about 1e-6
            EXPECT_NEAR(ab[v][c], a[v][c] + b[v][c], 1e-5 * (std::abs(a[v][c]) + std::abs(b[v][c])) + 1e-12);
    // At a probe the blend is the probe's own values, with the falloff weighting or without.
    for (double radius : {table.grid.falloff_radius, 0.0}) {
        basis::FireProbeGrid grid = table.grid;
        grid.falloff_radius = radius;
        for (int probe : {0, 4, 26}) {
            Rgb sh[basis::kFireProbeCoefficients];
            basis::sampleFireProbes(grid, a, grid.position(probe % 3, (probe / 3) % 3, probe / 9), sh);
            for (int k = 0; k < basis::kFireProbeCoefficients; ++k)
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(sh[k][c], a[probe * basis::kFireProbeCoefficients + k][c],
                                1e-5 * std::abs(sh[k][c]) + 1e-9);
        }
    }
    // Beyond the grid the falloff weighting carries the inverse square law: twice as far from the
    // falloff centre along a ray through a face's middle probe, a quarter of the fluence (within the
    // falloff radius's share).
    const glm::dvec3 face = table.grid.position(2, 1, 1), c = table.grid.falloff_centre;
    Rgb near_sh[basis::kFireProbeCoefficients], far_sh[basis::kFireProbeCoefficients];
    basis::sampleFireProbes(table.grid, a, c + 2.0 * (face - c), near_sh);
    basis::sampleFireProbes(table.grid, a, c + 4.0 * (face - c), far_sh);
    const double ratio =
        meanOf(glm::dvec3(basis::fluenceFromSh(far_sh))) / meanOf(glm::dvec3(basis::fluenceFromSh(near_sh)));
    EXPECT_GT(ratio, 0.25);
    EXPECT_LT(ratio, 0.30);
}

TEST(FireProbes, KeepAFewTermsOfTheGridPointsWithinTheirBound) {
    // The factored table against every term kept (exact up to float rounding): within rank_error
    // (1e-3) of the whole table's norm, with fewer than the 8 terms (5 here).
    const render::Medium medium = probeBall();
    FireProbeSettings settings;
    settings.resolution = 3;
    const basis::FireProbeTable table = traceFireProbes(medium, probeModel(0.5), settings);
    settings.rank_error = 0.0;
    const basis::FireProbeTable exact = traceFireProbes(medium, probeModel(0.5), settings);
    EXPECT_EQ(exact.rank, 8);
    EXPECT_LT(table.rank, 8);
    double error = 0.0, norm = 0.0;
    for (int point = 0; point < 8; ++point) {
        const std::vector<Rgb> a = probeValues(table, onePoint(point), kProbeCoefficients),
                               b = probeValues(exact, onePoint(point), kProbeCoefficients);
        for (size_t v = 0; v < a.size(); ++v) {
            error += glm::dot(glm::dvec3(a[v] - b[v]), glm::dvec3(a[v] - b[v]));
            norm += glm::dot(glm::dvec3(b[v]), glm::dvec3(b[v]));
        }
    }
    EXPECT_GT(norm, 0.0);
    // 2e-3: the bound is on the table per bin; the look's colours weigh the bins unevenly.
    EXPECT_LT(std::sqrt(error / norm), 2e-3);
}

TEST(FireProbes, AreFiniteForEmptyFramesZeroEmissionAndBadNormalsAndPoints) {
    FireProbeSettings settings;
    settings.resolution = 2;
    const std::vector<Rgb> zero(4, Rgb(0.0f));
    for (const basis::FireProbeTable& table : {traceFireProbes(render::Medium(), probeModel(0.5), settings),
                                               traceFireProbes(probeBall(), probeModel(0.5), settings)})
        for (const auto& c : {zero, kProbeCoefficients}) {
            const std::vector<Rgb> values = probeValues(table, onePoint(2), c);
            for (const glm::dvec3& x :
                 {table.grid.origin, table.grid.falloff_centre, glm::dvec3(1e6), glm::dvec3(-3.0, 40.0, 0.5),
                  glm::dvec3(std::nan(""), 0.0, 0.0), glm::dvec3(0.0, INFINITY, 0.0)}) {
                Rgb sh[basis::kFireProbeCoefficients];
                basis::sampleFireProbes(table.grid, values, x, sh);
                for (const glm::dvec3& n : {glm::dvec3(0, 0, 1), glm::dvec3(0.0), glm::dvec3(std::nan(""))}) {
                    const Rgb e = basis::irradianceFromSh(sh, n), f = basis::fluenceFromSh(sh);
                    for (int i = 0; i < 3; ++i) {
                        EXPECT_TRUE(std::isfinite(e[i]) && e[i] >= 0.0f);
                        EXPECT_TRUE(std::isfinite(f[i]) && f[i] >= 0.0f);
                        if (c == zero) {
                            EXPECT_EQ(f[i], 0.0f);
                        }
                    }
                }
            }
        }
}

TEST(FireProbes, RoundTripThroughTheSectionAndRefuseDamage) {
    FireProbeSettings settings;
    settings.resolution = 3;
    const basis::FireProbeTable table = traceFireProbes(probeBall(), probeModel(0.5), settings);
    const std::vector<std::byte> bytes = basis::encodeFireProbes(table);
    EXPECT_EQ(bytes, basis::encodeFireProbes(
                         traceFireProbes(probeBall(), probeModel(0.5), settings)));  // deterministic
    const basis::FireProbeTable back = basis::decodeFireProbes(bytes, 8, 4, "x.firelook: frame 1");
    EXPECT_EQ(back.sh, table.sh);
    EXPECT_EQ(back.factors, table.factors);
    EXPECT_EQ(back.rank, table.rank);
    EXPECT_EQ(back.grid.counts, table.grid.counts);
    EXPECT_EQ(back.grid.origin, table.grid.origin);
    EXPECT_EQ(back.grid.spacing, table.grid.spacing);
    EXPECT_EQ(back.grid.falloff_centre, table.grid.falloff_centre);
    EXPECT_EQ(back.grid.falloff_radius, table.grid.falloff_radius);
    EXPECT_EQ(back.extinction_scale, 0.5f);
    const auto message = [](const std::vector<std::byte>& b, int points) {
        try {
            basis::decodeFireProbes(b, points, 4, "x.firelook: frame 1");
        } catch (const std::runtime_error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_EQ(message(std::vector<std::byte>(bytes.begin(), bytes.end() - 4), 8),
              "x.firelook: frame 1: fire probes section is " + std::to_string(bytes.size() - 4) +
                  " bytes, expected " + std::to_string(bytes.size()));
    EXPECT_EQ(message(bytes, 9),
              "x.firelook: frame 1: fire probes are for 8 grid points and 4 bins, the package has 9 and 4");
    std::vector<std::byte> nan = bytes;
    const float bad = std::nanf("");
    std::memcpy(nan.data() + nan.size() - 4, &bad, 4);
    EXPECT_EQ(message(nan, 8), "x.firelook: frame 1: fire probes have a non-finite value");
    std::vector<std::byte> one = bytes;
    const uint32_t count = 1;
    std::memcpy(one.data() + 4, &count, 4);
    EXPECT_EQ(message(one, 8), "x.firelook: frame 1: fire probes have 1 probes along an axis, not 2 to 64");
    std::vector<std::byte> ranked = bytes;
    const uint32_t nine = 9;
    std::memcpy(ranked.data() + 28, &nine, 4);  // rank
    EXPECT_EQ(message(ranked, 8), "x.firelook: frame 1: fire probes have rank 9, not 1 to 8");
    std::vector<std::byte> flat = bytes;
    const double zero = 0.0;
    std::memcpy(flat.data() + 40 + 24, &zero, 8);  // spacing.x
    EXPECT_EQ(message(flat, 8), "x.firelook: frame 1: fire probes have a spacing that is not positive");
}

TEST(FireProbes, AreBakedIntoPackagesOnlyWhenAskedFor) {
    TempDir dir;
    BakeConfig config = test::tinyConfig();
    config.fire_probes = 2;
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / "probes.firelook", config, "test");
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / "none.firelook", test::tinyConfig(), "test");
    EXPECT_FALSE(basis::BasisReader::open(dir / "none.firelook").loadFireProbes(1));
    EXPECT_EQ(world::Package::open(dir / "none.firelook")->fireProbes(0), nullptr);
    // The setting is recorded only when set: other bakes keep their settings hash.
    EXPECT_EQ(configToJson(test::tinyConfig()).find("fire_probes"), std::string::npos);
    EXPECT_NE(configToJson(config).find("\"fire_probes\":2"), std::string::npos);
    const basis::BasisReader baked = basis::BasisReader::open(dir / "probes.firelook");
    const std::optional<basis::FireProbeTable> table = baked.loadFireProbes(1);
    ASSERT_TRUE(table);
    EXPECT_EQ(table->grid.counts, glm::ivec3(2));
    EXPECT_EQ(table->points, baked.description().axes.pointCount());
    const package::SectionInfo* section = baked.reader().find(basis::kSectionFireProbes, 1);
    ASSERT_NE(section, nullptr);
    EXPECT_FALSE(section->required());
    ASSERT_NE(world::Package::open(dir / "probes.firelook")->fireProbes(0), nullptr);
    const std::vector<Rgb> values = probeValues(*table, onePoint(0), std::vector<Rgb>(4, Rgb(1.0f)));
    EXPECT_GT(values[0].x, 0.0f);
}

}  // namespace
}  // namespace firelook::bake
