// The thread-safety promise of firelook.h: calls on different worlds may run in parallel, package and
// look calls are safe from any thread. Two worlds share one package and are updated on two threads
// at once, each creating and destroying instances, evicting and reloading frames (a frame cache of
// one byte) and querying the package. Built and run in every flavour, and under ThreadSanitizer by
// scripts/test.sh (the tsan flavour builds only this test and the libraries it needs).
#include "firelook/firelook.h"

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "../support/temp_dir.h"
#include "synthetic_package.h"

namespace {

struct WorldRun {
    fl_world world{};
    fl_instance shown{};       // paused on frame 4, compared across the worlds at the end
    fl_result failure = FL_OK;  // the first failure on the thread
    std::string message;
};

void check(WorldRun& run, fl_result r, const char* what) {
    if (r != FL_OK && run.failure == FL_OK) {
        run.failure = r;
        run.message = std::string(what) + ": " + fl_result_string(r) + " " + fl_last_error();
    }
}

// One thread's work on its own world: updates, a short-lived playing instance per iteration, and the
// package and look calls that the header says are safe from any thread.
void drive(WorldRun& run, fl_package package, int iterations) {
    const size_t pixels = 16 * 12;
    std::vector<float> image(pixels * 4);
    std::vector<uint16_t> u(2 * pixels * 4 * 2);
    fl_package_info info = fl_package_info_defaults();
    for (int i = 0; i < iterations && run.failure == FL_OK; ++i) {
        fl_instance_desc d = fl_instance_desc_defaults();
        d.package = package;
        fl_instance extra{};
        check(run, fl_instance_create(run.world, &d, &extra), "fl_instance_create");
        fl_outputs_desc out = fl_outputs_desc_defaults();
        out.image = 1;
        out.lens_flare = 1;
        check(run, fl_instance_set_outputs(run.world, extra, &out), "fl_instance_set_outputs");
        fl_playback_desc pb = fl_playback_desc_defaults();
        pb.time = 0.05 * i;
        check(run, fl_instance_set_playback(run.world, extra, &pb), "fl_instance_set_playback");
        check(run, fl_world_update(run.world, 1.0 / 30.0), "fl_world_update");
        check(run, fl_instance_get_image(run.world, extra, image.data(), image.size()), "fl_instance_get_image");
        check(run, fl_instance_destroy(run.world, extra), "fl_instance_destroy");
        check(run, fl_package_get_info(package, &info), "fl_package_get_info");
        size_t n = 0;
        check(run, fl_package_get_frame_u(package, 3 + i % 3, u.data(), u.size(), &n), "fl_package_get_frame_u");
        fl_look look{};
        check(run, fl_package_default_look(package, &look), "fl_package_default_look");
        check(run, fl_look_release(look), "fl_look_release");
    }
}

TEST(PluginApiThreads, TwoWorldsSharingOnePackageUpdateOnTwoThreadsAtOnce) {
    firelook::testing::TempDir dir;
    firelook::testing::SyntheticShape shape;
    shape.frames = {3, 4, 5};
    const std::string path = (dir.path() / "shared.firelook").string();
    firelook::testing::writeSyntheticPackage(path, shape);

    fl_init_desc init = fl_init_desc_defaults();
    ASSERT_EQ(fl_init(&init), FL_OK) << fl_last_error();
    fl_package package{};
    ASSERT_EQ(fl_package_load(path.c_str(), &package), FL_OK) << fl_last_error();
    WorldRun runs[2];
    for (WorldRun& run : runs) {
        fl_world_desc wd = fl_world_desc_defaults();
        wd.frame_cache_bytes = 1;  // every update evicts: frames are reloaded from the shared package
        ASSERT_EQ(fl_world_create(&wd, &run.world), FL_OK);
        fl_instance_desc d = fl_instance_desc_defaults();
        d.package = package;
        ASSERT_EQ(fl_instance_create(run.world, &d, &run.shown), FL_OK);
        fl_outputs_desc out = fl_outputs_desc_defaults();
        out.image = 1;
        ASSERT_EQ(fl_instance_set_outputs(run.world, run.shown, &out), FL_OK);
        fl_playback_desc pb = fl_playback_desc_defaults();
        pb.paused = 1;
        pb.rate = 1.0;
        pb.time = 1.0;  // frame 4
        ASSERT_EQ(fl_instance_set_playback(run.world, run.shown, &pb), FL_OK);
    }

    const int iterations = 40;
    std::thread a(drive, std::ref(runs[0]), package, iterations);
    std::thread b(drive, std::ref(runs[1]), package, iterations);
    a.join();
    b.join();
    for (const WorldRun& run : runs) EXPECT_EQ(run.failure, FL_OK) << run.message;

    // Both worlds show the same frame with the same look: the same image, bit for bit.
    std::vector<float> image[2];
    for (int w = 0; w < 2; ++w) {
        image[w].resize(16 * 12 * 4);
        ASSERT_EQ(fl_instance_get_image(runs[w].world, runs[w].shown, image[w].data(), image[w].size()), FL_OK);
        uint32_t count = 0;
        ASSERT_EQ(fl_world_instance_count(runs[w].world, &count), FL_OK);
        EXPECT_EQ(count, 1u);  // every short-lived instance was destroyed
    }
    EXPECT_EQ(image[0], image[1]);
    for (WorldRun& run : runs) EXPECT_EQ(fl_world_destroy(run.world), FL_OK);
    EXPECT_EQ(fl_package_release(package), FL_OK);
    EXPECT_EQ(fl_shutdown(), FL_OK);
}

}  // namespace
