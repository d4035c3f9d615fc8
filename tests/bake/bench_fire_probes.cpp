// bench_fire_probes PACKAGE SEQUENCE FRAME [SAMPLES] [POINTS] [RESOLUTIONS] [UP]: the fire's light
// on the scene as the probe grid (runtime/basis/fire_probes.h) and the point lights
// (runtime/basis/fire_lights.h) give it, against the full model.
//
// Points, drawn with a fixed seed: POINTS (default 100) uniform in the box 1.5x the volume's world
// bounds about their centre and outside those bounds ("random": fluence, and irradiance on a
// surface facing the volume's centre); POINTS on the ground plane, the bounds' bottom face along UP
// (default z) extended to the box, normal up ("ground"); POINTS / 2 on a wall, the plane a tenth of
// the volume's size beyond its +x face, normal -x ("wall"). The reference is the fluence and
// irradiance probe (baker/render/fluence_probe.h) of the full model (emission, extinction, every
// order of scattering) for the package's default look with its lights off, SAMPLES (default 16384)
// paths a point; its own noise is printed. Errors are relative, on the mean of R, G and B: median and
// worst per set. Probe grids are traced here with the bake's own code (fire_probe_tracer.h) at each
// of RESOLUTIONS (default "4,6"), timed; "lights" are the package's stored fire lights (K = 8;
// bake with --fire-lights), irradiance sum I max(0, n.l) / d^2. Variants of the grid: without the
// falloff weighting ("plain"), marched with the full extinction ("direct"), and with as many terms of
// the factorisation over the grid points as it may keep, 64 ("64 terms").
// Built, not run by ctest; scripts/bench/fire_probes.sh runs it on the bundled sample.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
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
    double fluence = 0.0, irradiance = 0.0;  // the reference's, mean RGB
};

struct Errors {
    std::vector<double> fluence, irradiance;
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
        std::fprintf(
            stderr,
            "usage: bench_fire_probes PACKAGE SEQUENCE FRAME [SAMPLES] [POINTS] [RESOLUTIONS] [UP]\n");
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
    try {
        const basis::BasisReader package = basis::BasisReader::open(argv[1]);
        const basis::BakeDescription& d = package.description();
        const std::optional<basis::FireLightTable> lights_table = package.loadFireLights(frame);
        const vdb::VdbSequence sequence = vdb::VdbSequence::open(argv[2], {});
        const render::Medium medium = reference::mediumFromFrame(sequence.load(frame));
        const render::WorldBox box = medium.worldBounds();
        const glm::dvec3 centre = 0.5 * (box.min + box.max), size = box.max - box.min, half = 0.75 * size;

        Look look = parseLook(d.default_look_json, "default look");
        for (Rgb& e : look.light_irradiance) e = Rgb(0.0f);  // the fire alone
        const world::ResolvedLook resolved = world::resolveLook(look, d);
        const basis::GridWeights weights = basis::interpolationWeights(d.axes, resolved.extinction);
        const render::VolumeScene scene(medium, makeLookModel(look, d.bins, d.rbf_width, d.light_directions));

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
        const auto t_ref = testing::Clock::now();
        std::vector<double> noise;
        uint64_t seed = 1;
        for (std::vector<Site>* set : {&random, &ground, &wall})
            for (Site& s : *set) {
                const render::FluenceEstimate e =
                    render::estimateIrradiance(scene, s.x, s.normal, samples, seed++);
                s.irradiance = meanRgb(e.fluence);
                if (s.irradiance > 0.0) noise.push_back(meanRgb(e.standard_error) / s.irradiance);
                if (set == &random)
                    s.fluence = meanRgb(render::estimateFluence(scene, s.x, samples, seed++).fluence);
            }
        std::printf(
            "frame %d: %zu random points (fluence, and irradiance facing the centre), %zu on the ground "
            "plane, "
            "%zu on a wall; reference %d paths a point (%.0f s), its noise (relative standard error of the "
            "irradiance) median %.2f%%, worst %.2f%%\n",
            frame, random.size(), ground.size(), wall.size(), samples, testing::msSince(t_ref) / 1000,
            100 * testing::median(noise), 100 * *std::max_element(noise.begin(), noise.end()));
        std::printf("%-26s %-17s %-17s %-17s %-17s  (median / worst relative error)\n", "", "random fluence",
                    "random irradiance", "ground irradiance", "wall irradiance");

        const auto report = [&](const std::string& name, auto&& fluence_at, auto&& irradiance_at,
                                const std::string& cost) {
            Errors r, g, w;
            for (const Site& s : random) {
                if (s.fluence > 0.0) r.fluence.push_back(std::abs(fluence_at(s.x) / s.fluence - 1.0));
                if (s.irradiance > 0.0)
                    r.irradiance.push_back(std::abs(irradiance_at(s.x, s.normal) / s.irradiance - 1.0));
            }
            for (const auto& [set, errors] : {std::pair{&ground, &g}, std::pair{&wall, &w}})
                for (const Site& s : *set)
                    if (s.irradiance > 0.0)
                        errors->irradiance.push_back(
                            std::abs(irradiance_at(s.x, s.normal) / s.irradiance - 1.0));
            std::printf("%-26s %-17s %-17s %-17s %-17s  %s\n", name.c_str(), summary(r.fluence).c_str(),
                        summary(r.irradiance).c_str(), summary(g.irradiance).c_str(),
                        summary(w.irradiance).c_str(), cost.c_str());
            std::fflush(stdout);
        };

        if (lights_table) {
            std::vector<basis::FireLight> lights(lights_table->clusters);
            basis::evaluateFireLights(*lights_table, weights, resolved.rbf, lights_table->clusters,
                                      lights.data());
            report(
                "point lights K=" + std::to_string(lights_table->clusters),
                [&](const glm::dvec3& x) {
                    double sum = 0.0;
                    for (const basis::FireLight& l : lights) {
                        const glm::dvec3 v = l.position - x;
                        sum += meanRgb(glm::dvec3(l.intensity)) / glm::dot(v, v);
                    }
                    return sum;
                },
                [&](const glm::dvec3& x, const glm::dvec3& n) {
                    double sum = 0.0;
                    for (const basis::FireLight& l : lights) {
                        const glm::dvec3 v = l.position - x;
                        const double d2 = glm::dot(v, v);
                        sum += meanRgb(glm::dvec3(l.intensity)) *
                               std::max(0.0, glm::dot(n, v) / std::sqrt(d2)) / d2;
                    }
                    return sum;
                },
                "");
        }
        for (int n : resolutions)
            for (int variant = 0; variant < 4; ++variant) {
                bake::FireProbeSettings settings;
                settings.resolution = n;
                settings.falloff = variant != 1;
                settings.absorption_only = variant != 2;
                if (variant == 3) settings.rank_error = 0.0;
                const auto t0 = testing::Clock::now();
                const basis::FireProbeTable table = bake::traceFireProbes(medium, d, settings);
                const double seconds = testing::msSince(t0) / 1000;
                std::vector<Rgb> values(static_cast<size_t>(table.grid.probes()) *
                                        basis::kFireProbeCoefficients);
                basis::evaluateFireProbes(table, weights, resolved.rbf, values.data());
                Rgb sh[basis::kFireProbeCoefficients];
                char cost[160];
                std::snprintf(cost, sizeof cost, "%.1f s, rank %d, %zu bytes raw", seconds, table.rank,
                              basis::encodeFireProbes(table).size());
                report(
                    "probes " + std::to_string(n) + "^3" +
                        (variant == 1   ? " plain"
                         : variant == 2 ? " direct"
                         : variant == 3 ? " 64 terms"
                                        : ""),
                    [&](const glm::dvec3& x) {
                        basis::sampleFireProbes(table.grid, values, x, sh);
                        return meanRgb(glm::dvec3(basis::fluenceFromSh(sh)));
                    },
                    [&](const glm::dvec3& x, const glm::dvec3& normal) {
                        basis::sampleFireProbes(table.grid, values, x, sh);
                        return meanRgb(glm::dvec3(basis::irradianceFromSh(sh, normal)));
                    },
                    cost);
            }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_fire_probes: %s\n", e.what());
        return 1;
    }
    return 0;
}
