// Streaming costs of a package (issue 12): the time to decode one frame for reconstruction
// (section read + zstd + frame codec, median of repeated runs on one thread), and the resident
// memory of a world playing the package with many instances at different frames.
//   bench_frame_decode PACKAGE [runs=15] [instances=100] [budget_mib=512]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "world/world.h"

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    using namespace firelook;
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s PACKAGE [runs] [instances] [budget_mib]\n", argv[0]);
        return 2;
    }
    const int runs = argc > 2 ? std::atoi(argv[2]) : 15;
    const int instances = argc > 3 ? std::atoi(argv[3]) : 100;
    const size_t budget = (argc > 4 ? std::strtoull(argv[4], nullptr, 10) : 512) << 20;
    const auto package = runtime::Package::open(argv[1]);
    const auto& d = package->description();
    std::printf("package %s: %d frames, %dx%d, %d footprint rays, %zu thresholds\n", argv[1], package->frameCount(),
                d.width, d.height, d.footprint_samples, d.alpha_thresholds.size());
    std::printf("%6s %5s %12s %12s %14s\n", "frame", "rank", "decode ms", "min ms", "decoded MiB");
    std::vector<double> all;
    for (int slot = 0; slot < package->frameCount(); ++slot) {
        std::vector<double> ms;
        size_t bytes = 0;
        for (int r = 0; r < runs; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            const basis::FrameFactors f = package->loadSlot(slot);
            ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            bytes = f.u_half.size() * 2 + f.svt.size() * 4 + (f.depth_density.size() + f.depth_sigmoid.size()) * 4;
        }
        all.push_back(median(ms));
        std::printf("%6d %5d %12.2f %12.2f %14.2f\n", package->frameNumber(slot), package->frameRank(slot), median(ms),
                    *std::min_element(ms.begin(), ms.end()), bytes / 1048576.0);
    }
    std::printf("decode per frame: median over frames %.2f ms\n", median(all));

    // A world with `instances` instances spread over the frames, CPU images on.
    runtime::WorldSettings settings;
    settings.frame_cache_bytes = budget;
    runtime::World world(settings);
    for (int i = 0; i < instances; ++i) {
        const runtime::InstanceHandle h = world.create(package);
        runtime::PlaybackSettings playback;
        playback.time = double(i % package->frameCount()) / playback.rate;
        world.setPlayback(h, playback);
        runtime::OutputSettings outputs;
        outputs.image = true;
        world.setOutputs(h, outputs);
    }
    const auto t0 = std::chrono::steady_clock::now();
    world.update(0.0);
    const double first = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::printf("world: %d instances over %d frames, frame cache budget %.0f MiB: resident %.1f MiB in %zu frames "
                "(first update %.0f ms)%s\n",
                instances, package->frameCount(), budget / 1048576.0, world.cacheBytes() / 1048576.0,
                world.cachedFrames(), first,
                world.cacheBytes() <= budget ? "" : "  OVER BUDGET (frames in use are never evicted)");
    return 0;
}
