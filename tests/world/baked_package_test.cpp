// End to end: a small package baked from the bundled sample by the `firelook` CLI, played by the world,
// equals basis::renderLookImage (what `firelook render` writes) for the same frame and look.
// Tolerance as in world_test.cpp: 1e-5 of the peak radiance plus 1e-5 relative; alpha exact.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "../support/temp_dir.h"
#include "basis/look_renderer.h"
#include "world/world.h"

namespace firelook::world {
namespace {

TEST(BakedPackage, WorldImagesEqualRenderLookImage) {
    firelook::testing::TempDir dir;
    std::ofstream(dir / "c.json") << R"({"trace": {"photons_primary": 4000, "photons_per_order": 2000, "photon_noise_target": 0}})";
    const std::string command = std::string(FIRELOOK_CLI) + " bake " + FIRELOOK_SAMPLE_DIR +
                                " --up z --size 24x20 --frames 1-2 -o " + (dir / "small.firelook").string() +
                                " --config " + (dir / "c.json").string() + " > " + (dir / "bake.log").string() +
                                " 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    auto package = Package::open(dir / "small.firelook");
    const auto& d = package->description();
    ASSERT_EQ(package->frameCount(), 2);

    World world;
    const std::vector<Look> looks = {
        parseLook(d.default_look_json, "default"),
        loadLook(std::string(FIRELOOK_SAMPLE_DIR) + "/../../looks/fireball.json"),
        loadLook(std::string(FIRELOOK_SAMPLE_DIR) + "/../../looks/smoky.json"),
    };
    for (int frame : {1, 2}) {
        const basis::ResidentFrame f = package->basis().loadResidentFrame(frame, std::pmr::get_default_resource());
        for (const Look& look : looks) {
            const InstanceHandle h = world.create(package);
            world.setLook(h, look);
            PlaybackSettings pb;
            pb.playing = false;
            pb.rate = 1.0;
            pb.time = frame - 1;
            world.setPlayback(h, pb);
            world.setOutputs(h, {true, true, {}});
            world.update(0.0);
            const InstanceState s = world.state(h);
            ASSERT_EQ(s.frame, frame);
            std::vector<float> want(static_cast<size_t>(d.pixelCount()) * 4);
            basis::renderLookImage(d, f, look, want);
            double peak = 0.0;
            for (size_t i = 0; i < want.size(); ++i)
                if (i % 4 != 3) peak = std::max(peak, static_cast<double>(want[i]));
            ASSERT_GT(peak, 0.0) << look.source_name;
            for (size_t i = 0; i < want.size(); ++i) {
                if (i % 4 == 3)
                    ASSERT_EQ(s.image[i], want[i]);
                else
                    ASSERT_NEAR(s.image[i], want[i], 1e-5 * peak + 1e-5 * std::abs(want[i]))
                        << look.source_name << " frame " << frame << " value " << i;
                ASSERT_TRUE(std::isfinite(s.flare[i]));
            }
            world.destroy(h);
        }
    }
}

}  // namespace
}  // namespace firelook::world
