// bench_fire_lights PACKAGE SEQUENCE FRAME [LOOKS] [SAMPLES] [BOX_SCALE]: the accuracy and cost of a
// baked frame's fire lights (runtime/basis/fire_lights.h).
//
// Accuracy: the fluence rate (radiance integrated over all directions; baker/render/fluence_probe.h)
// at the 26 points of a 3x3x3 lattice, less its centre, on a box BOX_SCALE (default 1.5) times the
// volume's world bounds, around the same centre; the lights give sum I_k / d_k^2. The reference is the
// full model (emission, extinction, all orders of scattering) with the package's lights off, SAMPLES
// (default 4096) paths per point; also the emission seen directly (no scattering) to show how much the
// scattered light matters. For the package's default look and LOOKS - 1 (default 4) random extinctions
// within the baked axes. Errors are relative, on the mean of R, G and B, per point and look: median and
// worst over all of them, for 1, 2, 4 and 8 lights.
// Cost: the frame's FLIT bytes (stored, raw) and the median microseconds of one evaluation of 8 lights
// (grid weights included), over 21 batches of 2000.
// Built, not run by ctest; scripts/bench/fire_lights.sh runs it on the bundled sample.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "../support/bench_timing.h"
#include "bake/scene_setup.h"
#include "basis/basis_package.h"
#include "basis/fire_lights.h"
#include "look/look.h"
#include "render/fluence_probe.h"
#include "render/random.h"
#include "reference/frame_medium.h"
#include "vdb/vdb_sequence.h"
#include "world/look_track.h"

using namespace firelook;

namespace {

double meanRgb(const glm::dvec3& v) { return (v.x + v.y + v.z) / 3.0; }

glm::dvec3 proxyFluence(const std::vector<basis::FireLight>& lights, const glm::dvec3& x) {
    glm::dvec3 sum(0.0);
    for (const basis::FireLight& l : lights) {
        const glm::dvec3 d = x - l.position;
        sum += glm::dvec3(l.intensity) / glm::dot(d, d);
    }
    return sum;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: bench_fire_lights PACKAGE SEQUENCE FRAME [LOOKS] [SAMPLES] [BOX_SCALE]\n");
        return 2;
    }
    const int frame = std::atoi(argv[3]);
    const int looks = argc > 4 ? std::atoi(argv[4]) : 5;
    const int samples = argc > 5 ? std::atoi(argv[5]) : 4096;
    const double box_scale = argc > 6 ? std::atof(argv[6]) : 1.5;
    try {
        const basis::BasisReader package = basis::BasisReader::open(argv[1]);
        const basis::BakeDescription& d = package.description();
        const std::optional<basis::FireLightTable> table = package.loadFireLights(frame);
        if (!table) throw std::runtime_error(std::string(argv[1]) + ": frame " + argv[3] + " has no fire lights");
        const package::SectionInfo* section = package.reader().find(basis::kSectionFireLights, static_cast<uint32_t>(frame));
        const vdb::VdbSequence sequence = vdb::VdbSequence::open(argv[2], {});
        const render::Medium medium = reference::mediumFromFrame(sequence.load(frame));
        const render::WorldBox box = medium.worldBounds();
        const glm::dvec3 centre = 0.5 * (box.min + box.max), half = 0.5 * box_scale * (box.max - box.min);
        std::vector<glm::dvec3> points;
        for (int k = -1; k <= 1; ++k)
            for (int j = -1; j <= 1; ++j)
                for (int i = -1; i <= 1; ++i)
                    if (i || j || k) points.push_back(centre + half * glm::dvec3(i, j, k));

        const Look base = parseLook(d.default_look_json, "default look");
        render::Pcg32 rng(7);
        const auto pick = [&](const std::vector<double>& axis) {
            return axis.front() + (axis.back() - axis.front()) * rng.uniform();
        };
        const std::vector<int> counts = {1, 2, 4, 8};
        std::vector<std::vector<double>> errors(counts.size()), errors_direct(counts.size());
        std::vector<double> noise, scattered_share;
        for (int n = 0; n < looks; ++n) {
            Look look = base;
            if (n > 0) {
                look.temperature_threshold = pick(d.axes.temperature_threshold);
                look.smoke_extinction = pick(d.axes.smoke_extinction);
                look.flame_extinction = pick(d.axes.flame_extinction);
            }
            for (Rgb& e : look.light_irradiance) e = Rgb(0.0f);  // the fire alone
            const world::ResolvedLook resolved = world::resolveLook(look, d);
            const basis::GridWeights weights = basis::interpolationWeights(d.axes, resolved.extinction);
            const LookModel model = makeLookModel(look, d.bins, d.rbf_width, d.light_directions);
            const render::VolumeScene scene(medium, model);
            render::WalkSettings direct_only;
            direct_only.max_scattering_order = 0;
            std::vector<std::vector<basis::FireLight>> lights;
            for (int count : counts) {
                lights.emplace_back(count);
                basis::evaluateFireLights(*table, weights, resolved.rbf, count, lights.back().data());
            }
            for (size_t p = 0; p < points.size(); ++p) {
                const uint64_t seed = 1000 * n + p;
                const render::FluenceEstimate full = render::estimateFluence(scene, points[p], samples, seed);
                const render::FluenceEstimate direct = render::estimateFluence(scene, points[p], samples, seed, direct_only);
                const double ref = meanRgb(full.fluence), ref_direct = meanRgb(direct.fluence);
                if (!(ref > 0.0)) continue;
                noise.push_back(meanRgb(full.standard_error) / ref);
                scattered_share.push_back(1.0 - ref_direct / ref);
                for (size_t c = 0; c < counts.size(); ++c) {
                    const double proxy = meanRgb(proxyFluence(lights[c], points[p]));
                    errors[c].push_back(std::abs(proxy / ref - 1.0));
                    errors_direct[c].push_back(std::abs(proxy / ref_direct - 1.0));
                }
            }
            std::fprintf(stderr, "look %d/%d done\n", n + 1, looks);
        }
        std::printf("frame %d: %zu points on a box %.2fx the volume's bounds, %d looks, %d paths per point\n", frame,
                    points.size(), box_scale, looks, samples);
        std::printf("reference noise (relative standard error) median %.2f%%; scattered light's share of the fluence "
                    "median %.1f%%, worst %.1f%%\n",
                    100 * testing::median(noise), 100 * testing::median(scattered_share),
                    100 * *std::max_element(scattered_share.begin(), scattered_share.end()));
        for (size_t c = 0; c < counts.size(); ++c)
            std::printf("K=%d: relative error vs full model median %.1f%%, worst %.1f%%; vs emission seen directly "
                        "median %.1f%%, worst %.1f%%\n",
                        counts[c], 100 * testing::median(errors[c]),
                        100 * *std::max_element(errors[c].begin(), errors[c].end()), 100 * testing::median(errors_direct[c]),
                        100 * *std::max_element(errors_direct[c].begin(), errors_direct[c].end()));

        // Cost of one evaluation of every stored light, grid weights included.
        const world::ResolvedLook resolved = world::resolveLook(base, d);
        std::vector<basis::FireLight> out(table->clusters);
        std::vector<double> us;
        double sink = 0.0;
        for (int batch = 0; batch < 21; ++batch) {
            const auto t0 = testing::Clock::now();
            for (int r = 0; r < 2000; ++r) {
                ExtinctionParams e = resolved.extinction;
                e.smoke_extinction += 1e-9 * r;  // keeps the compiler from hoisting the work
                basis::evaluateFireLights(*table, basis::interpolationWeights(d.axes, e), resolved.rbf, table->clusters,
                                          out.data());
                sink += out[0].intensity.r;
            }
            us.push_back(testing::msSince(t0) * 1000.0 / 2000);
        }
        std::printf("cost: FLIT %llu bytes stored (%llu raw) for %d lights x %d grid points x %d bins; one evaluation "
                    "of %d lights %.2f us (median of 21 batches)%s\n",
                    static_cast<unsigned long long>(section->stored_size), static_cast<unsigned long long>(section->raw_size),
                    table->clusters, table->points, table->bins, table->clusters, testing::median(us),
                    sink < 0 ? "!" : "");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_fire_lights: %s\n", e.what());
        return 1;
    }
    return 0;
}
