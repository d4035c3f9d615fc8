// The lens flare (runtime/world/lens_flare.h): deterministic, finite, only light above the threshold
// feeds it, ghosts land where the definition puts them, streaks spread along rows.
#include "world/lens_flare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace firelook::runtime {
namespace {

struct Flare {
    int w, h;
    std::vector<float> in, out, scratch;
    Flare(int w_, int h_) : w(w_), h(h_), in(size_t(w_) * h_ * 4, 0.0f), out(in.size(), -1.0f),
                            scratch(lensFlareScratchFloats(w_, h_)) {}
    void set(int x, int y, float v) {
        float* p = &in[(size_t(y) * w + x) * 4];
        p[0] = p[1] = p[2] = v;
        p[3] = 1.0f;
    }
    float at(int x, int y, int c = 0) const { return out[(size_t(y) * w + x) * 4 + c]; }
    void run(const LensFlareSettings& s) { renderLensFlare(in.data(), w, h, s, scratch.data(), out.data()); }
};

TEST(LensFlare, DarkImageGivesNoFlare) {
    Flare f(32, 24);
    f.set(5, 5, 0.9f);  // below the default threshold of 1
    f.run({});
    for (size_t i = 0; i < f.out.size(); ++i) ASSERT_EQ(f.out[i], 0.0f);
}

TEST(LensFlare, DeterministicFiniteAndAlphaZero) {
    Flare f(40, 30);
    f.set(10, 8, 50.0f);
    f.set(30, 20, 1e30f);
    f.in[0] = NAN;
    f.in[5] = INFINITY;
    f.in[9] = -5.0f;
    LensFlareSettings s;
    s.streaks = 2;
    f.run(s);
    const std::vector<float> first = f.out;
    f.run(s);
    EXPECT_EQ(first, f.out);
    for (size_t i = 0; i < f.out.size(); ++i) {
        ASSERT_TRUE(std::isfinite(f.out[i])) << i;
        ASSERT_GE(f.out[i], 0.0f);
        if (i % 4 == 3) {
            ASSERT_EQ(f.out[i], 0.0f);
        }
    }
}

TEST(LensFlare, FirstGhostIsTheFlippedScaledCopy) {
    // Ghost 0 has scale -s: the pixel p shows b(c - s (p - c)). A bright pixel at q shows up at
    // p = c - (q - c) / s. With s = 0.5 and c = (32, 32), q = (40.5, 36.5) (pixel 40, 36) maps to
    // p = (15, 23) -> pixel centres around (14.5..15.5, 22.5..23.5).
    Flare f(64, 64);
    f.set(40, 36, 100.0f);
    LensFlareSettings s;
    s.ghost_count = 1;
    s.ghost_spacing = 0.5f;
    s.halo_intensity = 0.0f;
    s.streaks = 0;
    f.run(s);
    EXPECT_GT(f.at(14, 22), 0.0f);
    EXPECT_GT(f.at(15, 23), 0.0f);
    EXPECT_EQ(f.at(40, 36), 0.0f);  // no ghost over the source itself
    EXPECT_EQ(f.at(50, 50), 0.0f);
}

TEST(LensFlare, StreaksSpreadAlongTheRow) {
    Flare f(64, 16);
    f.set(32, 8, 100.0f);
    LensFlareSettings s;
    s.ghost_count = -1;
    s.halo_intensity = 0.0f;
    s.streaks = 1;
    f.run(s);
    EXPECT_GT(f.at(10, 8), 0.0f);
    EXPECT_GT(f.at(54, 8), 0.0f);
    EXPECT_NEAR(f.at(22, 8), f.at(42, 8), 1e-6f);  // symmetric kernel
    EXPECT_GT(f.at(30, 8), f.at(20, 8));           // decays with distance
    EXPECT_EQ(f.at(32, 2), 0.0f);                  // nothing across rows
}

TEST(LensFlare, TinyImagesAreSafe) {
    for (auto [w, h] : {std::pair{1, 1}, std::pair{1, 7}, std::pair{7, 1}, std::pair{2, 2}}) {
        Flare f(w, h);
        f.set(0, 0, 1000.0f);
        LensFlareSettings s;
        s.streaks = 2;
        f.run(s);
        for (float v : f.out) ASSERT_TRUE(std::isfinite(v));
    }
}

}  // namespace
}  // namespace firelook::runtime
