// bench_runtime: timings of the runtime's hot paths (plain timing, medians over repetitions).
//   bench_runtime [--quick] [--package P]...
// Uses a synthetic package of the shape the brief asks for (rank 64, 16 bins, the default full
// parameter grid 6 x 4 x 3, one light, 512 x 512), written through the real package writer to a
// temporary folder, and each --package P beside it (a baked one: scripts/bench/runtime_real.sh
// bakes the bundled sample at 256x256 and 512x512): its coefficients, 10,000 instances, and each
// frame's CPU image from the resident form, which reads only the pixels the frame holds.
// Single-threaded throughout. The machine may be shared: compare ratios taken in the same run
// (reconstruction vs plain memory read), not absolute figures across runs.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory_resource>
#include <numeric>
#include <vector>

#include <time.h>
#include <unistd.h>

#include "basis/parameter_grid.h"
#include "basis/coefficients.h"
#include "basis/recombine.h"
#include "look/look_blend.h"
#include "synthetic_package.h"
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

// Sum of n floats with 16 independent partial sums, so the loop is bound by memory, not by the add
// latency; built for AVX2 too where the CPU has it (as the reconstruction kernel is).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
float plainRead(const float* data, size_t n) {
    float acc[16] = {};
    size_t i = 0;
    for (; i + 16 <= n; i += 16)
        for (int j = 0; j < 16; ++j) acc[j] += data[i + j];
    for (; i < n; ++i) acc[0] += data[i];
    float sum = 0.0f;
    for (float v : acc) sum += v;
    return sum;
}

// The bytes a CPU image of frame f reads: the W rows of u_runs, the mean rays of depth_runs and the
// detailed pixels' rays (2 bytes a value, padding included), and the share of pixels it skips
// (in neither kind of run: written as 0 unread).
struct FrameRead {
    double u_bytes = 0.0, depth_bytes = 0.0;
    double skipped = 0.0;
};
FrameRead frameRead(const basis::ResidentFrame& f) {
    FrameRead r;
    std::vector<uint8_t> read(static_cast<size_t>(f.pixels), 0);
    for (const basis::PixelRun& run : f.u_runs) {
        r.u_bytes += static_cast<double>(run.count) * f.rank_stride * sizeof(int16_t);
        std::fill_n(read.begin() + run.first, run.count, 1);
    }
    for (const basis::PixelRun& run : f.depth_runs) {
        r.depth_bytes += static_cast<double>(run.count) * f.depth_stride * sizeof(int16_t);
        std::fill_n(read.begin() + run.first, run.count, 1);
    }
    r.depth_bytes += static_cast<double>(f.detailed_depth.size()) * sizeof(int16_t);
    for (int32_t p : f.detailed_pixels) read[p] = 1;
    r.skipped = 1.0 - static_cast<double>(std::count(read.begin(), read.end(), 1)) / static_cast<double>(f.pixels);
    return r;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// One reconstruction against the plain read, alternating repetition by repetition so that both see
// the same load on a shared machine: the median time and CPU time of the reconstruction, and the
// median of the per-repetition ratios of its bandwidth (bytes / time) to the plain read's.
struct ReadRatio {
    double seconds = 0.0, cpu = 0.0, read_gbs = 0.0, read_cpu_gbs = 0.0, ratio = 0.0, ratio_cpu = 0.0;
};
template <typename F>
ReadRatio againstPlainRead(int reps, double bytes, const std::vector<float>& big, F&& reconstruct) {
    const double big_bytes = static_cast<double>(big.size()) * sizeof(float);
    reconstruct();  // warm-up
    std::vector<double> t_rec, c_rec, t_read, c_read, ratio, ratio_cpu;
    for (int r = 0; r < reps; ++r) {
        t_read.push_back(medianSeconds(1, [&] { g_sink = plainRead(big.data(), big.size()); }));
        c_read.push_back(g_cpu);
        t_rec.push_back(medianSeconds(1, reconstruct));
        c_rec.push_back(g_cpu);
        ratio.push_back((bytes / t_rec.back()) / (big_bytes / t_read.back()));
        ratio_cpu.push_back((bytes / c_rec.back()) / (big_bytes / c_read.back()));
    }
    return {median(t_rec), median(c_rec), big_bytes / median(t_read) / 1e9, big_bytes / median(c_read) / 1e9,
            median(ratio), median(ratio_cpu)};
}

Look benchLook(double tc, double ks, double kf, float scale) {
    Look l = defaultLook();
    l.temperature_threshold = tc;  // between grid samples on every axis
    l.smoke_extinction = ks;
    l.flame_extinction = kf;
    l.emission = EmissionPreset{"fire", scale};
    return l;
}

// Sections 1 and 2: one instance's coefficients through World::update and the kernels alone, and one
// update of 10,000 instances with different looks and times, all on the package's first frame.
void coefficientFigures(const std::shared_ptr<const world::Package>& package, const basis::ResidentFrame& factors,
                        int reps) {
    // 1. One instance: playback + keyframe interpolation + coefficients, through World::update.
    const basis::BakeDescription& d = package->description();
    const double f0 = package->frameNumber(0);  // keys at f0 and f0 + 0.9: the instances play between them
    const Look a = benchLook(1.3, 3.0, 1.0, 2.0), b = benchLook(1.75, 10.0, 2.5, 4.0);
    {
        world::World world;
        const world::InstanceHandle h = world.create(package);
        const std::vector<std::pair<double, Look>> keys = {{f0, a}, {f0 + 0.9, b}};
        world.setKeyframes(h, keys);
        world::PlaybackSettings pb;
        pb.playing = false;  // paused between the keys
        pb.rate = 1.0;
        pb.time = 0.37;
        world.setPlayback(h, pb);
        world.update(0.0);
        const int inner = 2000;
        const double s = medianSeconds(reps, [&] {
            for (int i = 0; i < inner; ++i) world.update(0.0);
        });
        // The look the instance shows (between the keys): what the kernel is timed on below.
        const world::InstanceState shown = world.state(h);
        const int points = basis::interpolationWeights(d.axes, shown.extinction).count;
        std::printf("coefficients, one instance (keyframe blend + emission + z, rank %d, %d bins, %d grid points): "
                    "median %.2f us per update (CPU time %.2f us)\n", factors.rank, d.bins.count, points, s / inner * 1e6, g_cpu / inner * 1e6);

        // For comparison: the kernel alone, basis::computeCoefficients (its checks + the kernel), and
        // the uncached path (interpolateLooks + makeLookModel, i.e. the keys' and the blend's fits per update +
        // computeCoefficients).
        std::vector<float> z(static_cast<size_t>(factors.rank) * 3);
        const basis::LookWeights weights{shown.extinction, shown.rbf, shown.lights};
        const double s_basis = medianSeconds(reps, [&] {
            for (int i = 0; i < inner; ++i) basis::computeCoefficients(d, factors, weights, z);
        });
        const double c_basis = g_cpu;
        const double s_fast = medianSeconds(reps, [&] {
            for (int i = 0; i < inner; ++i)
                basis::coefficientKernel(d, factors.svt.data(), factors.rank, shown.extinction, shown.rbf.data(),
                                         shown.lights.data(), z.data());
        });
        const double c_fast = g_cpu;
        const int slow_inner = 200;
        const double s_uncached = medianSeconds(reps, [&] {
            for (int i = 0; i < slow_inner; ++i) {
                const Look l = interpolateLooks(a, b, 0.37 / 0.9, d.bins, d.rbf_width);
                const LookModel m = makeLookModel(l, d.bins, d.rbf_width, d.light_directions);
                basis::computeCoefficients(d, factors, {l.extinction(), m.emission.coefficients, l.light_irradiance}, z);
            }
        });
        const double c_uncached = g_cpu;
        std::printf("  of which: coefficient kernel %.2f us (CPU %.2f); basis::computeCoefficients %.2f us (CPU %.2f); "
                    "uncached path (interpolateLooks + fit + computeCoefficients) %.2f us (CPU %.2f)\n",
                    s_fast / inner * 1e6, c_fast / inner * 1e6, s_basis / inner * 1e6, c_basis / inner * 1e6,
                    s_uncached / slow_inner * 1e6, c_uncached / slow_inner * 1e6);
    }

    // 2. 10,000 instances, one update.
    {
        world::World world;
        std::vector<world::InstanceHandle> handles;
        for (int i = 0; i < 10000; ++i) {
            const world::InstanceHandle h = world.create(package);
            handles.push_back(h);
            const Look ka = benchLook(1.1 + 0.0001 * i, 2.5 + 0.001 * i, 0.6 + 0.0002 * i, 1.0f + 0.001f * i);
            const std::vector<std::pair<double, Look>> keys = {{f0, ka}, {f0 + 0.9, b}};
            world.setKeyframes(h, keys);
            world::PlaybackSettings pb;
            pb.time = 0.001 * i;
            pb.rate = 1.0;
            world.setPlayback(h, pb);
        }
        world.update(0.0);
        const double s = medianSeconds(reps, [&] { world.update(1.0 / 600); });
        std::printf("10,000 instances, one update (playback + keyframes + coefficients, rank %d): median %.2f ms (CPU time %.2f ms)\n",
                    factors.rank, s * 1e3, g_cpu * 1e3);
        // The kernel alone on the looks the instances show: one batch (what the update runs) against one
        // instance at a time.
        std::vector<basis::CoefficientJob> jobs;
        std::vector<float> z(static_cast<size_t>(factors.rank) * 3 * 10000);
        for (int i = 0; i < 10000; ++i) {
            const world::InstanceState st = world.state(handles[i]);
            jobs.push_back({st.extinction, st.rbf.data(), st.lights.data(), z.data() + static_cast<size_t>(i) * factors.rank * 3});
        }
        const double s_batch = medianSeconds(reps, [&] { basis::coefficientBatch(d, factors.svt.data(), factors.rank, jobs); });
        const double c_batch = g_cpu;
        const double s_single = medianSeconds(reps, [&] {
            for (const basis::CoefficientJob& j : jobs)
                basis::coefficientKernel(d, factors.svt.data(), factors.rank, j.extinction, j.rbf, j.lights, j.z_out);
        });
        std::printf("  of which: coefficientBatch of the 10,000 looks %.2f ms (CPU %.2f), one at a time %.2f ms (CPU %.2f)\n",
                    s_batch * 1e3, c_batch * 1e3, s_single * 1e3, g_cpu * 1e3);
    }

}

// Section 5, per --package: each frame's CPU image with a look between grid points (T_c between two
// alpha-threshold samples), against the plain read.
void realFrameFigures(const world::Package& package, const std::vector<float>& big, int reps) {
    const basis::BakeDescription& d = package.description();
    const Look a = benchLook(1.3, 3.0, 1.0, 2.0);
    ExtinctionParams extinction = a.extinction();
    extinction.temperature_threshold = 1.3125;
    const LookModel model = makeLookModel(a, d.bins, d.rbf_width, d.light_directions);
    std::vector<float> image(static_cast<size_t>(d.pixelCount()) * 4);
    for (int slot = 0; slot < package.frameCount(); ++slot) {
        const basis::ResidentFrame f = package.loadResidentSlot(slot, std::pmr::get_default_resource(), nullptr);
        std::vector<float> z(static_cast<size_t>(f.rank) * 3);
        basis::computeCoefficients(d, f, {extinction, model.emission.coefficients, a.light_irradiance}, z);
        const FrameRead read = frameRead(f);
        const double bytes = read.u_bytes + read.depth_bytes;
        const ReadRatio r =
            againstPlainRead(reps, bytes, big, [&] { basis::reconstructImage(d, f, z, extinction, image); });
        std::printf("  frame %d %dx%d, rank %d, %zu alpha thresholds, %zu detailed pixels: skips %.1f%% of the pixels; "
                    "reads %.2f MiB (W %.2f + depth codes %.2f) in median %.3f ms (CPU %.3f ms) = %.2f GB/s; plain read "
                    "alongside %.2f GB/s (CPU %.2f); ratio %.2f (by CPU time %.2f)\n",
                    package.frameNumber(slot), d.width, d.height, f.rank, d.alpha_thresholds.size(),
                    f.detailed_pixels.size(), 100.0 * read.skipped, bytes / (1 << 20), read.u_bytes / (1 << 20),
                    read.depth_bytes / (1 << 20), r.seconds * 1e3, r.cpu * 1e3, bytes / r.seconds / 1e9, r.read_gbs,
                    r.read_cpu_gbs, r.ratio, r.ratio_cpu);
    }
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false;
    std::vector<std::filesystem::path> real;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quick") == 0) {
            quick = true;
        } else if (std::strcmp(argv[i], "--package") == 0 && i + 1 < argc) {
            real.emplace_back(argv[++i]);
        } else {
            std::fprintf(stderr, "bench_runtime: unknown argument '%s' (usage: bench_runtime [--quick] [--package P]...)\n",
                         argv[i]);
            return 2;
        }
    }
    const int reps = quick ? 5 : 15;
    std::vector<std::shared_ptr<const world::Package>> real_packages;
    for (const std::filesystem::path& p : real) {
        try {
            real_packages.push_back(world::Package::open(p));
        } catch (const std::exception& e) {
            std::fprintf(stderr, "bench_runtime: %s\n", e.what());
            return 1;
        }
    }
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
    auto package = world::Package::open(dir / "bench.firelook");
    const basis::BakeDescription& d = package->description();
    const basis::ResidentFrame factors = package->basis().loadResidentFrame(1, std::pmr::get_default_resource());
    std::printf("bench_runtime: synthetic package %dx%d, rank %d, %d bins, %d lights, grid %zux%zux%zu (%d columns)\n",
                d.width, d.height, factors.rank, d.bins.count, static_cast<int>(d.light_directions.size()),
                d.axes.temperature_threshold.size(), d.axes.smoke_extinction.size(), d.axes.flame_extinction.size(),
                d.columnCount());
    std::printf("single thread; the machine is shared and timings are noisy: medians of %d repetitions\n\n", reps);

    const Look a = benchLook(1.3, 3.0, 1.0, 2.0);
    coefficientFigures(package, factors, reps);

    // 3. CPU reconstruction of a 512 x 512 image (the resident form) vs a plain read of memory, both
    //    in this run. Throughput = the bytes the reconstruction reads (W, rank_stride x 2 bytes per
    //    pixel of u_runs, and the depth codes, depth_stride x 2 bytes per mean ray of depth_runs and
    //    per ray of a detailed pixel; the synthetic frame has no empty pixel) divided by its time. The
    //    16 bytes per pixel it writes are not counted. Plain read: summing a 256 MiB float array (8 x
    //    the L3 of the machine this was written on). The two alternate, repetition by repetition
    //    (againstPlainRead).
    std::vector<float> image(static_cast<size_t>(d.pixelCount()) * 4);
    std::vector<float> big(static_cast<size_t>(64) << 20, 1.0f);
    {
        const LookModel model = makeLookModel(a, d.bins, d.rbf_width, d.light_directions);
        std::vector<float> z(static_cast<size_t>(factors.rank) * 3);
        basis::computeCoefficients(d, factors, {a.extinction(), model.emission.coefficients, a.light_irradiance}, z);
        const size_t pixels = static_cast<size_t>(factors.pixels);
        const size_t thresholds = d.alpha_thresholds.size();
        // T_c between two alpha-threshold samples (the general case: O_a interpolated from two layers).
        ExtinctionParams extinction = a.extinction();
        extinction.temperature_threshold = 1.3125;
        const double tc = extinction.temperature_threshold;
        const bool between = tc > d.alpha_thresholds.front() && tc < d.alpha_thresholds.back() &&
                             std::find(d.alpha_thresholds.begin(), d.alpha_thresholds.end(), tc) == d.alpha_thresholds.end();
        std::printf("reconstruction look: T_c %.4f (%s), k_s %.2f, k_f %.2f; %zu alpha thresholds; plain read: "
                    "sum of a %.0f MiB float array\n", tc,
                    between ? "between two threshold samples: 2 O_a layers per ray" : "on a sample: 1 O_a layer per ray",
                    extinction.smoke_extinction, extinction.flame_extinction, thresholds,
                    static_cast<double>(big.size()) * sizeof(float) / (1 << 20));
        for (const int samples : {1, 4, 16}) {
            // The same frame with `samples` footprint rays per pixel, every pixel detailed (each ray
            // a copy of the pixel's mean ray: the most a frame reads).
            basis::BakeDescription ds = d;
            ds.footprint_samples = samples;
            basis::ResidentFrame fs = factors;
            fs.samples = samples;
            fs.detailed_pixels.clear();
            fs.detailed_depth.clear();
            const size_t stride = static_cast<size_t>(fs.depth_stride);
            for (size_t p = 0; samples > 1 && p < pixels; ++p) {
                fs.detailed_pixels.push_back(static_cast<int32_t>(p));
                for (int s = 0; s < samples; ++s)
                    fs.detailed_depth.insert(fs.detailed_depth.end(), factors.mean_depth.begin() + p * stride,
                                             factors.mean_depth.begin() + (p + 1) * stride);
            }
            const FrameRead read = frameRead(fs);
            const double bytes = read.u_bytes + read.depth_bytes;
            const ReadRatio r =
                againstPlainRead(reps, bytes, big, [&] { basis::reconstructImage(ds, fs, z, extinction, image); });
            std::printf("CPU reconstruction 512x512, rank %d, footprint_samples %d: median %.2f ms (CPU %.2f ms), "
                        "%.1f MiB read (W int16 %.1f MiB + depth codes %.1f MiB) = %.2f GB/s; plain read alongside %.2f GB/s "
                        "(CPU %.2f GB/s); ratio %.2f (by CPU time %.2f)\n",
                        factors.rank, samples, r.seconds * 1e3, r.cpu * 1e3, bytes / (1 << 20), read.u_bytes / (1 << 20),
                        read.depth_bytes / (1 << 20), bytes / r.seconds / 1e9, r.read_gbs, r.read_cpu_gbs, r.ratio,
                        r.ratio_cpu);
        }
        basis::reconstructImage(d, factors, z, extinction, image);  // the S = 1 image feeds the flare
    }
    {
        // 4. Lens flare on that image (scaled so the flame crosses the threshold).
        for (size_t i = 0; i < image.size(); ++i) image[i] *= 4.0f;
        size_t above = 0;
        for (size_t p = 0; p + 3 < image.size(); p += 4)
            above += 0.2126f * image[p] + 0.7152f * image[p + 1] + 0.0722f * image[p + 2] > 1.0f;
        std::printf("lens flare input: the reconstructed image x 4, %.1f%% of pixels above the threshold 1\n",
                    100.0 * static_cast<double>(above) / static_cast<double>(image.size() / 4));
        std::vector<float> scratch(world::lensFlareScratchFloats(d.width, d.height)), flare(image.size());
        world::LensFlareSettings fs;
        const double s_flare = medianSeconds(reps, [&] {
            world::renderLensFlare(image.data(), d.width, d.height, fs, scratch.data(), flare.data());
        });
        const double c_flare = g_cpu;
        fs.streaks = 2;
        const double s_flare2 = medianSeconds(reps, [&] {
            world::renderLensFlare(image.data(), d.width, d.height, fs, scratch.data(), flare.data());
        });
        std::printf("lens flare 512x512 (4 ghosts, halo, horizontal streak): median %.2f ms (CPU %.2f ms); "
                    "with vertical streak too: %.2f ms (CPU %.2f ms)\n",
                    s_flare * 1e3, c_flare * 1e3, s_flare2 * 1e3, g_cpu * 1e3);
    }
    std::filesystem::remove_all(dir);

    // 5. The real packages: coefficients, 10,000 instances and every frame's CPU image.
    for (size_t i = 0; i < real_packages.size(); ++i) {
        const world::Package& p = *real_packages[i];
        const basis::BakeDescription& dp = p.description();
        const basis::ResidentFrame first = p.loadResidentSlot(0, std::pmr::get_default_resource(), nullptr);
        std::printf("\npackage %s: %dx%d, %d frames, %d bins, %d lights, grid %zux%zux%zu (%d columns)\n",
                    real[i].string().c_str(), dp.width, dp.height, p.frameCount(), dp.bins.count,
                    static_cast<int>(dp.light_directions.size()), dp.axes.temperature_threshold.size(),
                    dp.axes.smoke_extinction.size(), dp.axes.flame_extinction.size(), dp.columnCount());
        coefficientFigures(real_packages[i], first, reps);
        realFrameFigures(p, big, reps);
    }
    return 0;
}
