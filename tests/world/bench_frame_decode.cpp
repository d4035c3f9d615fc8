// Streaming costs of a package: the time to decode one frame for reconstruction into the form the
// world keeps (section read + checksum + zstd + frame codec, median of repeated runs on one
// thread), split by section kind (UFAC U codes, SVTF, ODEP depth codes) into the zstd part and the
// frame codec's part; and the memory of a world playing the package with many instances at
// different frames: its frame cache against the budget, and its per-instance buffers.
//   bench_frame_decode PACKAGE [runs=15] [instances=100] [budget_mib=512] [BASELINE_PACKAGE]
// A BASELINE_PACKAGE (the same frames stored another way, e.g. by an older codec version) is
// decoded in the same runs, interleaved, and the ratio of the two medians printed per frame.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include "../support/bench_timing.h"
#include "basis/basis_package.h"
#include "basis/frame_codec.h"
#include "world/world.h"

namespace {

using firelook::testing::Clock;
using firelook::testing::median;
using firelook::testing::msSince;

// Median ms of the parts of one frame's decode, section by section.
struct Parts {
    std::vector<double> zstd[3], codec[3];
};

constexpr uint32_t kTypes[3] = {firelook::basis::kSectionU, firelook::basis::kSectionSVt,
                                firelook::basis::kSectionDepths};

// One run of the parts: each section read (checksum + zstd) into its buffer, then decoded from it.
void timeParts(const firelook::world::Package& package, int slot, firelook::basis::ResidentFrame& out,
               firelook::basis::FrameReadBuffers& buffers, Parts& parts) {
    using namespace firelook;
    const package::ContainerReader& reader = package.basis().reader();
    const basis::BakeDescription& d = package.description();
    const int frame = package.frameNumber(slot), rank = package.frameRank(slot);
    package::SectionBuffer* section_buffers[3] = {&buffers.u, &buffers.svt, &buffers.depths};
    std::span<const std::byte> bytes[3];
    for (int i = 0; i < 3; ++i) {
        const package::SectionInfo* s = reader.find(kTypes[i], static_cast<uint32_t>(frame));
        if (!s) return;  // a layout-1 package has other sections: no split
        const auto t0 = Clock::now();
        bytes[i] = reader.read(*s, *section_buffers[i]);
        parts.zstd[i].push_back(msSince(t0));
    }
    const std::string name = package.basis().file().string();
    auto t0 = Clock::now();
    basis::decodeResidentU(d, frame, rank, bytes[0], name, out);
    parts.codec[0].push_back(msSince(t0));
    t0 = Clock::now();
    basis::decodeResidentSvt(d, frame, rank, bytes[1], name, out);
    parts.codec[1].push_back(msSince(t0));
    t0 = Clock::now();
    basis::decodeResidentDepths(d, frame, rank, bytes[2], name, out);
    parts.codec[2].push_back(msSince(t0));
}

}  // namespace

int main(int argc, char** argv) {
    using namespace firelook;
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s PACKAGE [runs] [instances] [budget_mib] [BASELINE_PACKAGE]\n", argv[0]);
        return 2;
    }
    const int runs = argc > 2 ? std::atoi(argv[2]) : 15;
    const int instances = argc > 3 ? std::atoi(argv[3]) : 100;
    const size_t budget = (argc > 4 ? std::strtoull(argv[4], nullptr, 10) : 512) << 20;
    const auto package = world::Package::open(argv[1]);
    const std::shared_ptr<const world::Package> baseline = argc > 5 ? world::Package::open(argv[5]) : nullptr;
    const auto& d = package->description();
    std::printf("package %s: %d frames, %dx%d, %d footprint rays, %zu thresholds\n", argv[1], package->frameCount(),
                d.width, d.height, d.footprint_samples, d.alpha_thresholds.size());
    if (baseline && baseline->frameCount() != package->frameCount()) {
        std::fprintf(stderr, "%s: %d frames, the package %d\n", argv[5], baseline->frameCount(), package->frameCount());
        return 2;
    }
    // decode ms: into the buffers of a frame decoded before (what a streaming world does: it keeps an
    // evicted frame's buffers for the next load); fresh ms: into newly allocated memory. Then the
    // same decode's parts by section: zstd (read + checksum + decompression) and the frame codec.
    std::printf("%5s %4s %9s %8s %8s | %7s %7s %7s | %7s %7s %7s | %8s %8s", "frame", "rank", "decode ms", "min ms",
                "fresh ms", "zstd U", "zstd S", "zstd D", "codec U", "codec S", "codec D", "res MiB", "detailed");
    if (baseline) std::printf(" | %11s %6s", "baseline ms", "ratio");
    std::printf("\n");
    basis::ResidentFrame reused, reused_baseline, parts_frame;
    basis::FrameReadBuffers buffers, baseline_buffers, parts_buffers;
    std::vector<double> all, all_zstd, all_codec, all_baseline, ratios;
    std::shared_ptr<const basis::DepthTable> table;  // shared between frames, as the world does
    for (int slot = 0; slot < package->frameCount(); ++slot) {
        std::vector<double> ms, fresh_ms, baseline_ms, zstd_sum, codec_sum;
        Parts parts;
        size_t bytes = 0, detailed = 0;
        const int other = (slot + 1) % package->frameCount();
        for (int r = 0; r < runs; ++r) {
            auto t0 = Clock::now();
            const basis::ResidentFrame f = package->loadResidentSlot(slot, std::pmr::get_default_resource(), table);
            fresh_ms.push_back(msSince(t0));
            table = f.depth_table;
            bytes = f.bytes();
            detailed = f.detailed_pixels.size();
            // Warm the reused frame on another frame first, so each run decodes over stale values.
            package->loadResidentSlot(other, reused, buffers);
            t0 = Clock::now();
            package->loadResidentSlot(slot, reused, buffers);
            ms.push_back(msSince(t0));
            if (baseline) {
                baseline->loadResidentSlot(other, reused_baseline, baseline_buffers);
                t0 = Clock::now();
                baseline->loadResidentSlot(slot, reused_baseline, baseline_buffers);
                baseline_ms.push_back(msSince(t0));
            }
            package->loadResidentSlot(other, parts_frame, parts_buffers);
            timeParts(*package, slot, parts_frame, parts_buffers, parts);
        }
        for (size_t r = 0; r < parts.zstd[0].size(); ++r) {
            zstd_sum.push_back(parts.zstd[0][r] + parts.zstd[1][r] + parts.zstd[2][r]);
            codec_sum.push_back(parts.codec[0][r] + parts.codec[1][r] + parts.codec[2][r]);
        }
        all.push_back(median(ms));
        all_zstd.push_back(median(zstd_sum));
        all_codec.push_back(median(codec_sum));
        std::printf("%5d %4d %9.3f %8.3f %8.3f | %7.3f %7.3f %7.3f | %7.3f %7.3f %7.3f | %8.2f %8zu",
                    package->frameNumber(slot), package->frameRank(slot), median(ms),
                    *std::min_element(ms.begin(), ms.end()), median(fresh_ms), median(parts.zstd[0]),
                    median(parts.zstd[1]), median(parts.zstd[2]), median(parts.codec[0]), median(parts.codec[1]),
                    median(parts.codec[2]), bytes / 1048576.0, detailed);
        if (baseline) {
            all_baseline.push_back(median(baseline_ms));
            ratios.push_back(median(ms) / median(baseline_ms));
            std::printf(" | %11.3f %6.3f", median(baseline_ms), ratios.back());
        }
        std::printf("\n");
    }
    std::printf("zstd part (section reads): median over frames %.3f ms; frame codec part %.3f ms\n", median(all_zstd),
                median(all_codec));
    std::printf("decode per frame: median over frames %.3f ms, largest %.3f ms (%.2f x the zstd part alone, same run)\n",
                median(all), *std::max_element(all.begin(), all.end()), median(all) / median(all_zstd));
    if (baseline)
        std::printf("baseline %s: median over frames %.3f ms, largest %.3f ms; per-frame ratio median %.3f "
                    "(package / baseline, same runs)\n",
                    argv[5], median(all_baseline), *std::max_element(all_baseline.begin(), all_baseline.end()),
                    median(ratios));

    // A world with `instances` instances spread over the frames, CPU images on.
    world::WorldSettings settings;
    settings.frame_cache_bytes = budget;
    world::World world(settings);
    for (int i = 0; i < instances; ++i) {
        const world::InstanceHandle h = world.create(package);
        world::PlaybackSettings playback;
        playback.time = double(i % package->frameCount()) / playback.rate;
        world.setPlayback(h, playback);
        world::OutputSettings outputs;
        outputs.image = true;
        world.setOutputs(h, outputs);
    }
    const auto t0 = Clock::now();
    world.update(0.0);
    const double first = msSince(t0);
    std::printf("world: %d instances over %d frames, frame cache budget %.0f MiB: resident %.1f MiB in %zu frames, "
                "instance buffers %.1f MiB (first update %.0f ms)%s\n",
                instances, package->frameCount(), budget / 1048576.0, world.cacheBytes() / 1048576.0,
                world.cachedFrames(), world.instanceBytes() / 1048576.0, first,
                world.cacheBytes() <= budget ? "" : "  OVER BUDGET (frames in use are never evicted)");
    return 0;
}
