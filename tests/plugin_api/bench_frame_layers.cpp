// The GPU upload's data for one frame, both ways the C API gives it: fl_package_get_frame_u +
// fl_package_get_frame_depths (read, decompress and expand the frame for each call) against
// fl_instance_get_frame_u + fl_instance_get_frame_depths (copied from the frame the world decoded in
// its update). Per frame, median ms of `runs` interleaved runs of each, and the same-run ratio.
//   bench_frame_layers PACKAGE [runs=9]
// Built, not run by ctest (timings on a shared machine are noisy). Only the C API is used.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "../support/bench_timing.h"
#include "firelook/firelook.h"

namespace {

using firelook::testing::Clock;
using firelook::testing::median;
using firelook::testing::msSince;

bool ok(fl_result r, const char* call) {
    if (r == FL_OK) return true;
    std::fprintf(stderr, "bench_frame_layers: %s: %s (%s)\n", call, fl_last_error(), fl_result_string(r));
    return false;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bench_frame_layers PACKAGE [runs=9]\n");
        return 2;
    }
    const int runs = argc > 2 ? std::max(1, std::atoi(argv[2])) : 9;
    fl_init_desc init = fl_init_desc_defaults();
    fl_package package{};
    fl_package_info info = fl_package_info_defaults();
    fl_world world{};
    fl_instance instance{};
    if (!ok(fl_init(&init), "fl_init") || !ok(fl_package_load(argv[1], &package), "fl_package_load") ||
        !ok(fl_package_get_info(package, &info), "fl_package_get_info") ||
        !ok(fl_world_create(nullptr, &world), "fl_world_create"))
        return 1;
    fl_instance_desc desc = fl_instance_desc_defaults();
    desc.package = package;
    if (!ok(fl_instance_create(world, &desc, &instance), "fl_instance_create")) return 1;
    uint32_t count = 0;
    fl_package_get_frames(package, nullptr, nullptr, 0, &count);
    std::vector<int32_t> frames(count);
    fl_package_get_frames(package, frames.data(), nullptr, count, &count);
    std::vector<uint16_t> u;
    std::vector<float> depths;
    std::printf("%dx%d, %u frames, %d runs each (ms, medians)\n", info.width, info.height, count, runs);
    std::printf("frame  package (decode)  instance (cache)  ratio\n");
    std::vector<double> ratios;
    for (int32_t frame : frames) {
        fl_playback_desc pb = fl_playback_desc_defaults();
        pb.paused = 1;
        pb.rate = 1.0;
        pb.time = frame - info.first_frame;
        if (!ok(fl_instance_set_playback(world, instance, &pb), "fl_instance_set_playback") ||
            !ok(fl_world_update(world, 0.0), "fl_world_update"))
            return 1;
        size_t nu = 0, nd = 0;
        fl_package_get_frame_u(package, frame, nullptr, 0, &nu);
        fl_package_get_frame_depths(package, frame, nullptr, 0, &nd);
        u.resize(nu);
        depths.resize(nd);
        std::vector<double> from_package, from_cache;
        for (int r = 0; r < runs; ++r) {  // interleaved, so load changes hit both alike
            auto t0 = Clock::now();
            if (!ok(fl_package_get_frame_u(package, frame, u.data(), nu, &nu), "fl_package_get_frame_u") ||
                !ok(fl_package_get_frame_depths(package, frame, depths.data(), nd, &nd), "fl_package_get_frame_depths"))
                return 1;
            from_package.push_back(msSince(t0));
            t0 = Clock::now();
            if (!ok(fl_instance_get_frame_u(world, instance, u.data(), nu, &nu), "fl_instance_get_frame_u") ||
                !ok(fl_instance_get_frame_depths(world, instance, depths.data(), nd, &nd), "fl_instance_get_frame_depths"))
                return 1;
            from_cache.push_back(msSince(t0));
        }
        const double a = median(from_package), b = median(from_cache);
        ratios.push_back(a / b);
        std::printf("%5d  %16.2f  %16.2f  %5.1f\n", frame, a, b, a / b);
    }
    std::printf("median ratio package / instance: %.1f\n", median(ratios));
    fl_world_destroy(world);
    fl_package_release(package);
    fl_shutdown();
    return 0;
}
