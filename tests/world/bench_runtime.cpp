// bench_runtime: timings of the runtime's hot paths (plain timing, medians over repetitions).
//   bench_runtime [--quick]
// Uses a synthetic package of the shape the brief asks for (rank 64, 16 bins, the default full
// parameter grid 6 x 4 x 3, one light, 512 x 512), written through the real package writer to a
// temporary folder. Single-threaded throughout. The machine may be shared: compare ratios taken in
// the same run (reconstruction vs plain memory read), not absolute figures across runs.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numeric>
#include <vector>

#include <time.h>
#include <unistd.h>

#include "basis/recombine.h"
#include "synthetic_package.h"
#include "world/coefficient_kernel.h"
#include "world/world.h"

using namespace firelook;
using Clock = std::chrono::steady_clock;

namespace {

double threadCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

// Median wall time; the median thread CPU time of the same repetitions is left in g_cpu (on a shared
// machine the CPU time is the better estimate of what the code costs, the wall time what it took).
double g_cpu = 0.0;
template <typename F>
double medianSeconds(int repetitions, F&& f) {
    std::vector<double> t, c;
    for (int r = 0; r < repetitions; ++r) {
        const double cpu = threadCpuSeconds();
        const auto start = Clock::now();
        f();
        t.push_back(std::chrono::duration<double>(Clock::now() - start).count());
        c.push_back(threadCpuSeconds() - cpu);
    }
    std::sort(t.begin(), t.end());
    std::sort(c.begin(), c.end());
    g_cpu = c[c.size() / 2];
    return t[t.size() / 2];
}

volatile float g_sink;

Look benchLook(double tc, double ks, double kf, float scale) {
    Look l = defaultLook();
    l.temperature_threshold = tc;  // between grid samples on every axis: 8 grid points
    l.smoke_extinction = ks;
    l.flame_extinction = kf;
    l.emission = EmissionPreset{"fire", scale};
    return l;
}

}  // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    const int reps = quick ? 5 : 15;
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("firelook-bench-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    testing::SyntheticShape shape;
    shape.width = shape.height = 512;
    shape.rank = 64;
    shape.bins = 16;
    shape.lights = 1;
    shape.frames = {1};
    shape.alpha_thresholds = 41;
    testing::writeSyntheticPackage(dir / "bench.firelook", shape);
    auto package = runtime::Package::open(dir / "bench.firelook");
    const basis::BakeDescription& d = package->description();
    const basis::FrameFactors factors = package->basis().loadFrame(1);
    std::printf("bench_runtime: synthetic package %dx%d, rank %d, %d bins, %d lights, grid %zux%zux%zu (%d columns)\n",
                d.width, d.height, factors.rank, d.bins.count, static_cast<int>(d.light_directions.size()),
                d.axes.temperature_threshold.size(), d.axes.smoke_extinction.size(), d.axes.flame_extinction.size(),
                d.columnCount());
    std::printf("single thread; the machine is shared and timings are noisy: medians of %d repetitions\n\n", reps);

    // 1. One instance: playback + keyframe interpolation + coefficients, through World::update.
    const Look a = benchLook(1.3, 3.0, 1.0, 2.0), b = benchLook(1.75, 10.0, 2.5, 4.0);
    {
        runtime::World world;
        const runtime::InstanceHandle h = world.create(package);
        const std::vector<std::pair<double, Look>> keys = {{1.0, a}, {1.9, b}};
        world.setKeyframes(h, keys);
        runtime::PlaybackSettings pb;
        pb.rate = 0.0;  // position stays at 1 + 0 -> use a paused time between the keys instead
        pb.playing = false;
        pb.rate = 1.0;
        pb.time = 0.37;
        world.setPlayback(h, pb);
        world.update(0.0);
        const int inner = 2000;
        const double s = medianSeconds(reps, [&] {
            for (int i = 0; i < inner; ++i) world.update(0.0);
        });
        std::printf("coefficients, one instance (keyframe blend + emission + z, rank 64, 16 bins, 8 grid points): "
                    "median %.2f us per update (CPU time %.2f us)\n", s / inner * 1e6, g_cpu / inner * 1e6);

        // For comparison: basis::computeCoefficients alone, and the uncached path (interpolateLooks +
        // makeLookModel, i.e. the NNLS fit per update + computeCoefficients).
        const LookModel model = makeLookModel(a, d.bins, d.rbf_width, d.light_directions);
        std::vector<float> z(static_cast<size_t>(factors.rank) * 3);
        const basis::LookWeights weights{a.extinction(), model.emission.coefficients, a.light_irradiance};
        const double s_basis = medianSeconds(reps, [&] {
            for (int i = 0; i < inner; ++i) basis::computeCoefficients(d, factors, weights, z);
        });
        const double c_basis = g_cpu;
        std::vector<float> scratch(z.size());
        const double s_fast = medianSeconds(reps, [&] {
            for (int i = 0; i < inner; ++i)
                runtime::computeCoefficientsFast(d, factors, a.extinction(), model.emission.coefficients.data(),
                                                 a.light_irradiance.data(), scratch.data(), z.data());
        });
        const double c_fast = g_cpu;
        const int slow_inner = 200;
        const double s_uncached = medianSeconds(reps, [&] {
            for (int i = 0; i < slow_inner; ++i) {
                const Look l = interpolateLooks(a, b, 0.37 / 0.9, d.bins);
                const LookModel m = makeLookModel(l, d.bins, d.rbf_width, d.light_directions);
                basis::computeCoefficients(d, factors, {l.extinction(), m.emission.coefficients, l.light_irradiance}, z);
            }
        });
        const double c_uncached = g_cpu;
        std::printf("  of which: runtime coefficient kernel %.2f us (CPU %.2f); basis::computeCoefficients %.2f us (CPU %.2f); "
                    "uncached path (interpolateLooks + fit + computeCoefficients) %.2f us (CPU %.2f)\n",
                    s_fast / inner * 1e6, c_fast / inner * 1e6, s_basis / inner * 1e6, c_basis / inner * 1e6,
                    s_uncached / slow_inner * 1e6, c_uncached / slow_inner * 1e6);
    }

    // 2. 10,000 instances, one update.
    {
        runtime::World world;
        for (int i = 0; i < 10000; ++i) {
            const runtime::InstanceHandle h = world.create(package);
            const Look ka = benchLook(1.1 + 0.0001 * i, 2.5 + 0.001 * i, 0.6 + 0.0002 * i, 1.0f + 0.001f * i);
            const std::vector<std::pair<double, Look>> keys = {{1.0, ka}, {1.9, b}};
            world.setKeyframes(h, keys);
            runtime::PlaybackSettings pb;
            pb.time = 0.001 * i;
            pb.rate = 1.0;
            world.setPlayback(h, pb);
        }
        world.update(0.0);
        const double s = medianSeconds(reps, [&] { world.update(1.0 / 600); });
        std::printf("10,000 instances, one update (playback + keyframes + coefficients): median %.2f ms (CPU time %.2f ms)\n",
                    s * 1e3, g_cpu * 1e3);
    }

    // 3. CPU reconstruction of a 512 x 512 image vs a plain read of memory.
    {
        const std::vector<float> u = basis::decodeU(factors);
        const LookModel model = makeLookModel(a, d.bins, d.rbf_width, d.light_directions);
        std::vector<float> z(static_cast<size_t>(factors.rank) * 3);
        basis::computeCoefficients(d, factors, {a.extinction(), model.emission.coefficients, a.light_irradiance}, z);
        std::vector<float> image(static_cast<size_t>(d.pixelCount()) * 4);
        const double bytes = static_cast<double>(u.size()) * sizeof(float);
        const double s_rec = medianSeconds(reps, [&] { basis::reconstructImage(d, factors, u, z, a.extinction(), image); });
        const double c_rec = g_cpu;
        // Plain read bandwidth: sum a float array of the same size as U (8 partial sums so the loop is
        // bound by memory, not by the add latency).
        std::vector<float> big(u.size(), 1.0f);
        const double s_read = medianSeconds(reps, [&] {
            float acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
            for (size_t i = 0; i + 8 <= big.size(); i += 8)
                for (int j = 0; j < 8; ++j) acc[j] += big[i + j];
            g_sink = std::accumulate(acc, acc + 8, 0.0f);
        });
        const double c_read = g_cpu;
        const double gbs_rec = bytes / s_rec / 1e9, gbs_read = bytes / s_read / 1e9;
        std::printf("CPU reconstruction 512x512, rank 64 (U float, %.1f MiB read): median %.2f ms = %.2f GB/s of U; "
                    "plain read of %.1f MiB: %.2f GB/s; ratio %.2f\n",
                    bytes / (1 << 20), s_rec * 1e3, gbs_rec, bytes / (1 << 20), gbs_read, gbs_rec / gbs_read);
        std::printf("  by CPU time: reconstruction %.2f GB/s, plain read %.2f GB/s, ratio %.2f\n", bytes / c_rec / 1e9,
                    bytes / c_read / 1e9, c_read / c_rec);

        // 4. Lens flare on that image (scaled so the flame crosses the threshold).
        for (size_t i = 0; i < image.size(); ++i) image[i] *= 4.0f;
        std::vector<float> scratch(runtime::lensFlareScratchFloats(d.width, d.height)), flare(image.size());
        runtime::LensFlareSettings fs;
        const double s_flare = medianSeconds(reps, [&] {
            runtime::renderLensFlare(image.data(), d.width, d.height, fs, scratch.data(), flare.data());
        });
        const double c_flare = g_cpu;
        fs.streaks = 2;
        const double s_flare2 = medianSeconds(reps, [&] {
            runtime::renderLensFlare(image.data(), d.width, d.height, fs, scratch.data(), flare.data());
        });
        std::printf("lens flare 512x512 (4 ghosts, halo, horizontal streak): median %.2f ms (CPU %.2f ms); "
                    "with vertical streak too: %.2f ms (CPU %.2f ms)\n",
                    s_flare * 1e3, c_flare * 1e3, s_flare2 * 1e3, g_cpu * 1e3);
    }
    std::filesystem::remove_all(dir);
    return 0;
}
