// bench_fire_probes PACKAGE SEQUENCE FRAME [SAMPLES] [POINTS] [RESOLUTIONS] [UP] [LOOKS]: the fire's light
// on the scene as the probe grid (runtime/basis/fire_probes.h) and the point lights
// (runtime/basis/fire_lights.h) give it, against the full model.
//
// Points, drawn with a fixed seed: POINTS (default 100) uniform in the box 1.5x the volume's world
// bounds about their centre and outside those bounds ("random": fluence, and irradiance on a
// surface facing the volume's centre); POINTS on the ground plane, the bounds' bottom face along UP
// (default z) extended to the box, normal up ("ground"); POINTS / 2 on a wall, the plane a tenth of
// the volume's size beyond its +x face, normal -x ("wall"). The reference is the fluence and
// irradiance probe (baker/render/fluence_probe.h) of the full model (emission, extinction, every
// order of scattering) for the package's default look and LOOKS - 1 (default LOOKS 1) random
// extinctions within the baked axes, lights off, SAMPLES (default 16384) paths a point; its own noise
// is printed. Errors are relative, on the mean of R, G and B: median and worst per set over the
// points and looks. Probe grids are traced here with the bake's own code (fire_probe_tracer.h) at each
// of RESOLUTIONS (default "4,6"), timed; "lights" are the package's stored fire lights (K = 8;
// bake with --fire-lights), irradiance sum I max(0, n.l) / d^2. Variants of the grid: without the
// falloff weighting ("plain"), marched with the full extinction ("direct"), and with as many terms of
// the factorisation over the grid points as it may keep, 64 ("64 terms").
// Cost: per grid, the seconds to trace it, its rank and raw bytes, and the median microseconds of one
// look's probes (evaluateFireProbes, grid weights included).
// Built, not run by ctest; scripts/bench/fire_probes.sh runs it on the bundled sample.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "../support/bench_timing.h"
#include "bake/fire_probe_tracer.h"
#include "basis/basis_package.h"
#include "basis/fire_lights.h"
#include "basis/fire_probes.h"
#include "look/look.h"
#include "reference/frame_medium.h"
#include "render/fluence_probe.h"
#include "render/random.h"
#include "vdb/vdb_sequence.h"
#include "world/look_track.h"

using namespace firelook;

namespace {

double meanRgb(const glm::dvec3& v) { return (v.x + v.y + v.z) / 3.0; }

struct Site {
    glm::dvec3 x, normal;
    double fluence = 0.0, irradiance = 0.0;  // the reference's for the look at hand, mean RGB
};

struct Errors {
    std::vector<double> fluence, irradiance;
};

// One way of giving the fire's light: the point lights or a probe grid, and its errors over the looks.
struct Method {
    std::string name, cost;
    std::optional<basis::FireProbeTable> probes;  // none: the point lights
    Errors random, ground, wall;
};

std::string summary(std::vector<double> e) {
    if (e.empty()) return "-";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%5.1f%% / %5.1f%%", 100 * testing::median(e),
                  100 * *std::max_element(e.begin(), e.end()));
    return buf;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr,
                     "usage: bench_fire_probes PACKAGE SEQUENCE FRAME [SAMPLES] [POINTS] [RESOLUTIONS] [UP] "
                     "[LOOKS]\n");
        return 2;
    }
    const int frame = std::atoi(argv[3]);
    const int samples = argc > 4 ? std::atoi(argv[4]) : 16384;
    const int count = argc > 5 ? std::atoi(argv[5]) : 100;
    std::vector<int> resolutions;
    {
        std::stringstream list(argc > 6 ? argv[6] : "4,6");
        for (std::string item; std::getline(list, item, ',');) resolutions.push_back(std::atoi(item.c_str()));
    }
    const int up = argc > 7 ? (argv[7][0] == 'x' ? 0 : argv[7][0] == 'y' ? 1 : 2) : 2;
    const int looks = argc > 8 ? std::max(1, std::atoi(argv[8])) : 1;
    try {
        const basis::BasisReader package = basis::BasisReader::open(argv[1]);
        const basis::BakeDescription& d = package.description();
        const std::optional<basis::FireLightTable> lights_table = package.loadFireLights(frame);
        const vdb::VdbSequence sequence = vdb::VdbSequence::open(argv[2], {});
        const render::Medium medium = reference::mediumFromFrame(sequence.load(frame));
        const render::WorldBox box = medium.worldBounds();
        const glm::dvec3 centre = 0.5 * (box.min + box.max), size = box.max - box.min, half = 0.75 * size;

        // The sites.
        render::Pcg32 rng(29);
        const auto inBox = [&] {
            return centre +
                   half * glm::dvec3(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
        };
        std::vector<Site> random, ground, wall;
        while (static_cast<int>(random.size()) < count) {
            const glm::dvec3 x = inBox();
            if (glm::all(glm::greaterThanEqual(x, box.min)) && glm::all(glm::lessThanEqual(x, box.max)))
                continue;
            random.push_back({x, glm::normalize(centre - x)});
        }
        glm::dvec3 n_up(0.0);
        n_up[up] = 1.0;
        for (int i = 0; i < count; ++i) {
            glm::dvec3 x = inBox();
            x[up] = box.min[up];
            ground.push_back({x, n_up});
        }
        for (int i = 0; i < count / 2; ++i) {
            glm::dvec3 x = inBox();
            x.x = box.max.x + 0.1 * size.x;
            wall.push_back({x, glm::dvec3(-1.0, 0.0, 0.0)});
        }

        const Look base = parseLook(d.default_look_json, "default look");
        // The methods: the point lights, then per resolution the grid as baked and its variants,
        // traced once (the tables do not depend on the look).
        std::vector<Method> methods;
        if (lights_table)
            methods.push_back(
                {"point lights K=" + std::to_string(lights_table->clusters), "", {}, {}, {}, {}});
        for (int n : resolutions)
            for (int variant = 0; variant < 4; ++variant) {
                bake::FireProbeSettings settings;
                settings.resolution = n;
                settings.falloff = variant != 1;
                settings.absorption_only = variant != 2;
                if (variant == 3) settings.rank_error = 0.0;
                const auto t0 = testing::Clock::now();
                basis::FireProbeTable table = bake::traceFireProbes(medium, d, settings);
                const double seconds = testing::msSince(t0) / 1000;
                // One look's probes (grid weights included): the median of 21 batches of 200.
                const world::ResolvedLook resolved = world::resolveLook(base, d);
                std::vector<Rgb> values(static_cast<size_t>(table.grid.probes()) *
                                        basis::kFireProbeCoefficients);
                std::vector<double> us;
                for (int batch = 0; batch < 21; ++batch) {
                    const auto b0 = testing::Clock::now();
                    for (int r = 0; r < 200; ++r) {
                        ExtinctionParams e = resolved.extinction;
                        e.smoke_extinction += 1e-9 * r;  // keeps the compiler from hoisting the work
                        basis::evaluateFireProbes(table, basis::interpolationWeights(d.axes, e), resolved.rbf,
                                                  values.data());
                    }
                    us.push_back(testing::msSince(b0) * 1000.0 / 200);
                }
                char cost[160];
                std::snprintf(cost, sizeof cost, "%.1f s, rank %d, %zu bytes raw, a look's probes %.1f us",
                              seconds, table.rank, basis::encodeFireProbes(table).size(),
                              testing::median(us));
                methods.push_back({"probes " + std::to_string(n) + "^3" +
                                       (variant == 1   ? " plain"
                                        : variant == 2 ? " direct"
                                        : variant == 3 ? " 64 terms"
                                                       : ""),
                                   cost,
                                   std::move(table),
                                   {},
                                   {},
                                   {}});
            }

        render::Pcg32 look_rng(7);
        const auto pick = [&](const std::vector<double>& axis) {
            return axis.front() + (axis.back() - axis.front()) * look_rng.uniform();
        };
        const auto t_ref = testing::Clock::now();
        std::vector<double> noise;
        uint64_t seed = 1;
        for (int n = 0; n < looks; ++n) {
            // The default look, then random extinctions within the baked axes; the fire alone.
            Look look = base;
            if (n > 0) {
                look.temperature_threshold = pick(d.axes.temperature_threshold);
                look.smoke_extinction = pick(d.axes.smoke_extinction);
                look.flame_extinction = pick(d.axes.flame_extinction);
            }
            for (Rgb& e : look.light_irradiance) e = Rgb(0.0f);
            const world::ResolvedLook resolved = world::resolveLook(look, d);
            const basis::GridWeights weights = basis::interpolationWeights(d.axes, resolved.extinction);
            const render::VolumeScene scene(medium,
                                            makeLookModel(look, d.bins, d.rbf_width, d.light_directions));
            for (std::vector<Site>* set : {&random, &ground, &wall})
                for (Site& s : *set) {
                    const render::FluenceEstimate e =
                        render::estimateIrradiance(scene, s.x, s.normal, samples, seed++);
                    s.irradiance = meanRgb(e.fluence);
                    if (s.irradiance > 0.0) noise.push_back(meanRgb(e.standard_error) / s.irradiance);
                    if (set == &random)
                        s.fluence = meanRgb(render::estimateFluence(scene, s.x, samples, seed++).fluence);
                }
            std::vector<basis::FireLight> lights(lights_table ? lights_table->clusters : 0);
            if (lights_table)
                basis::evaluateFireLights(*lights_table, weights, resolved.rbf, lights_table->clusters,
                                          lights.data());
            for (Method& m : methods) {
                std::vector<Rgb> values;
                if (m.probes) {
                    values.resize(static_cast<size_t>(m.probes->grid.probes()) *
                                  basis::kFireProbeCoefficients);
                    basis::evaluateFireProbes(*m.probes, weights, resolved.rbf, values.data());
                }
                // Fluence (normal null) or irradiance at x, mean RGB.
                const auto light = [&](const glm::dvec3& x, const glm::dvec3* normal) {
                    if (m.probes) {
                        Rgb sh[basis::kFireProbeCoefficients];
                        basis::sampleFireProbes(m.probes->grid, values, x, sh);
                        return meanRgb(glm::dvec3(normal ? basis::irradianceFromSh(sh, *normal)
                                                         : basis::fluenceFromSh(sh)));
                    }
                    double sum = 0.0;
                    for (const basis::FireLight& l : lights) {
                        const glm::dvec3 v = l.position - x;
                        const double d2 = glm::dot(v, v);
                        const double cosine =
                            normal ? std::max(0.0, glm::dot(*normal, v) / std::sqrt(d2)) : 1.0;
                        sum += meanRgb(glm::dvec3(l.intensity)) * cosine / d2;
                    }
                    return sum;
                };
                for (const Site& s : random) {
                    if (s.fluence > 0.0)
                        m.random.fluence.push_back(std::abs(light(s.x, nullptr) / s.fluence - 1.0));
                    if (s.irradiance > 0.0)
                        m.random.irradiance.push_back(std::abs(light(s.x, &s.normal) / s.irradiance - 1.0));
                }
                for (const auto& [set, errors] : {std::pair{&ground, &m.ground}, std::pair{&wall, &m.wall}})
                    for (const Site& s : *set)
                        if (s.irradiance > 0.0)
                            errors->irradiance.push_back(
                                std::abs(light(s.x, &s.normal) / s.irradiance - 1.0));
            }
            std::fprintf(stderr, "look %d/%d done\n", n + 1, looks);
        }
        std::printf(
            "frame %d: %zu random points (fluence, and irradiance facing the centre), %zu on the ground "
            "plane, "
            "%zu on a wall; %d look(s) (the default, then random extinctions); reference %d paths a point "
            "(%.0f s), its noise (relative standard error of the irradiance) median %.2f%%, worst %.2f%%\n",
            frame, random.size(), ground.size(), wall.size(), looks, samples, testing::msSince(t_ref) / 1000,
            100 * testing::median(noise), 100 * *std::max_element(noise.begin(), noise.end()));
        std::printf("%-26s %-17s %-17s %-17s %-17s  (median / worst relative error over points and looks)\n",
                    "", "random fluence", "random irradiance", "ground irradiance", "wall irradiance");
        for (const Method& m : methods)
            std::printf("%-26s %-17s %-17s %-17s %-17s  %s\n", m.name.c_str(),
                        summary(m.random.fluence).c_str(), summary(m.random.irradiance).c_str(),
                        summary(m.ground.irradiance).c_str(), summary(m.wall.irradiance).c_str(),
                        m.cost.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_fire_probes: %s\n", e.what());
        return 1;
    }
    return 0;
}
