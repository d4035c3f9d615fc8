// Streaming costs of a package: the time to decode one frame for reconstruction into the form the
// world keeps (section read + checksum + zstd + frame codec, median of repeated runs on one
// thread; the zstd part alone beside it), and the memory of a world playing the package with many
// instances at different frames: its frame cache against the budget, and its per-instance buffers.
//   bench_frame_decode PACKAGE [runs=15] [instances=100] [budget_mib=512]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "basis/basis_package.h"
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
    // decode ms: into the buffers of a frame decoded before (what a streaming world does: it keeps an
    // evicted frame's buffers for the next load); fresh ms: into newly allocated memory.
    std::printf("%6s %5s %12s %12s %12s %12s %14s %12s\n", "frame", "rank", "decode ms", "min ms", "fresh ms",
                "zstd ms", "resident MiB", "detailed px");
    basis::ResidentFrame reused;
    basis::FrameReadBuffers buffers;
    package::SectionBuffer zstd_buffer;
    std::vector<double> all, all_zstd;
    const package::PackageReader& reader = package->basis().reader();
    std::shared_ptr<const basis::DepthTable> table;  // shared between frames, as the world does
    for (int slot = 0; slot < package->frameCount(); ++slot) {
        std::vector<double> ms, fresh_ms, zstd_ms;
        size_t bytes = 0, detailed = 0;
        for (int r = 0; r < runs; ++r) {
            auto t0 = std::chrono::steady_clock::now();
            const basis::ResidentFrame f = package->loadResidentSlot(slot, std::pmr::get_default_resource(), table);
            fresh_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            table = f.depth_table;
            bytes = f.bytes();
            detailed = f.detailed_pixels.size();
            // Warm the reused frame on another frame first, so each run decodes over stale values.
            package->loadResidentSlot((slot + 1) % package->frameCount(), reused, buffers);
            t0 = std::chrono::steady_clock::now();
            package->loadResidentSlot(slot, reused, buffers);
            ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            t0 = std::chrono::steady_clock::now();
            for (const uint32_t type : {basis::kSectionU, basis::kSectionSVt, basis::kSectionDepths})
                if (const package::SectionInfo* s = reader.find(type, static_cast<uint32_t>(package->frameNumber(slot))))
                    (void)reader.read(*s, zstd_buffer);
            zstd_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
        all.push_back(median(ms));
        all_zstd.push_back(median(zstd_ms));
        std::printf("%6d %5d %12.3f %12.3f %12.3f %12.3f %14.2f %12zu\n", package->frameNumber(slot),
                    package->frameRank(slot), median(ms), *std::min_element(ms.begin(), ms.end()), median(fresh_ms),
                    median(zstd_ms), bytes / 1048576.0, detailed);
    }
    std::printf("zstd alone (section reads): median over frames %.3f ms\n", median(all_zstd));
    std::printf("decode per frame: median over frames %.3f ms, largest %.3f ms (%.2f x the zstd part alone, same run)\n",
                median(all), *std::max_element(all.begin(), all.end()), median(all) / median(all_zstd));

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
    std::printf("world: %d instances over %d frames, frame cache budget %.0f MiB: resident %.1f MiB in %zu frames, "
                "instance buffers %.1f MiB (first update %.0f ms)%s\n",
                instances, package->frameCount(), budget / 1048576.0, world.cacheBytes() / 1048576.0,
                world.cachedFrames(), world.instanceBytes() / 1048576.0, first,
                world.cacheBytes() <= budget ? "" : "  OVER BUDGET (frames in use are never evicted)");
    return 0;
}
