// The one keyframe bracketing rule (runtime/world/keyframe_bracket.h) that the runtime's keyframes,
// the viewer's keyed reference look and `firelook animate` share: its edges, and the runtime's
// sampleKeyframes following it.
#include "world/keyframe_bracket.h"

#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <vector>

#include "world/look_track.h"

namespace firelook::world {
namespace {

struct Key {
    double frame;
};

void expectBracket(const KeyframeBracket& got, size_t lo, size_t hi, double t, const char* what) {
    EXPECT_EQ(got.lo, lo) << what;
    EXPECT_EQ(got.hi, hi) << what;
    EXPECT_DOUBLE_EQ(got.t, t) << what;
}

const std::vector<Key> kKeys = {{2.0}, {5.0}, {9.0}};

TEST(KeyframeBracket, BeforeTheFirstKeyTheFirstHolds) {
    expectBracket(bracketKeyframes(kKeys, 1.999), 0, 0, 0.0, "just before");
    expectBracket(bracketKeyframes(kKeys, -1e9), 0, 0, 0.0, "far before");
}

TEST(KeyframeBracket, FromTheLastKeyOnTheLastHolds) {
    expectBracket(bracketKeyframes(kKeys, 9.0), 2, 2, 0.0, "on the last");
    expectBracket(bracketKeyframes(kKeys, 9.001), 2, 2, 0.0, "just after");
    expectBracket(bracketKeyframes(kKeys, 1e9), 2, 2, 0.0, "far after");
}

TEST(KeyframeBracket, ExactlyOnAKeyThatKeyHolds) {
    expectBracket(bracketKeyframes(kKeys, 2.0), 0, 0, 0.0, "first");
    expectBracket(bracketKeyframes(kKeys, 5.0), 1, 1, 0.0, "middle");
}

TEST(KeyframeBracket, BetweenKeysTheWeightIsLinear) {
    expectBracket(bracketKeyframes(kKeys, 3.5), 0, 1, 0.5, "3.5");
    expectBracket(bracketKeyframes(kKeys, 2.75), 0, 1, 0.25, "2.75");
    expectBracket(bracketKeyframes(kKeys, 8.0), 1, 2, 0.75, "8");
    const KeyframeBracket near_next = bracketKeyframes(kKeys, std::nextafter(5.0, 0.0));
    EXPECT_EQ(near_next.lo, 0u);
    EXPECT_EQ(near_next.hi, 1u);
    EXPECT_LE(near_next.t, 1.0);
    EXPECT_GT(near_next.t, 0.999999);
}

// Two keys at one frame: the value runs up to the first of them, then the second holds from that
// frame on (a cut), and the blend after it starts from the second.
TEST(KeyframeBracket, OfDuplicateFramesTheLastHoldsFromThatFrameOn) {
    const std::vector<Key> keys = {{2.0}, {5.0}, {5.0}, {9.0}};
    expectBracket(bracketKeyframes(keys, 3.5), 0, 1, 0.5, "before the pair");
    expectBracket(bracketKeyframes(keys, 5.0), 2, 2, 0.0, "on the pair");
    expectBracket(bracketKeyframes(keys, 6.0), 2, 3, 0.25, "after the pair");
    const std::vector<Key> all_equal = {{4.0}, {4.0}, {4.0}};
    expectBracket(bracketKeyframes(all_equal, 3.0), 0, 0, 0.0, "before all");
    expectBracket(bracketKeyframes(all_equal, 4.0), 2, 2, 0.0, "on all");
    expectBracket(bracketKeyframes(all_equal, 5.0), 2, 2, 0.0, "after all");
}

TEST(KeyframeBracket, OneKeyAlwaysHoldsAndANaNFrameHoldsTheFirst) {
    const std::vector<Key> one = {{3.0}};
    for (double frame : {-1.0, 3.0, 7.5}) expectBracket(bracketKeyframes(one, frame), 0, 0, 0.0, "one key");
    expectBracket(bracketKeyframes(kKeys, std::nan("")), 0, 0, 0.0, "NaN frame");
}

// animate's keys are whole frames; the runtime's are a span.
TEST(KeyframeBracket, IntegerFramesAndSpansBracketAlike) {
    struct WholeKey {
        int frame;
    };
    const std::vector<WholeKey> whole = {{2}, {5}, {9}};
    expectBracket(bracketKeyframes(whole, 3.5), 0, 1, 0.5, "int frames");
    expectBracket(bracketKeyframes(whole, 5.0), 1, 1, 0.0, "int frames, on a key");
    expectBracket(bracketKeyframes(std::span<const Key>(kKeys), 8.0), 1, 2, 0.75, "span");
}

// sampleKeyframes takes the keys and weight from the bracket: on a duplicated frame the later key
// exactly, between keys the blend.
TEST(KeyframeBracket, SampleKeyframesFollowsTheBracket) {
    const auto key = [](double frame, double k_s, float light) {
        Keyframe k;
        k.frame = frame;
        k.look.extinction.smoke_extinction = k_s;
        k.look.rbf = {Rgb(static_cast<float>(k_s))};
        k.look.lights = {Rgb(light)};
        return k;
    };
    const std::vector<Keyframe> keys = {key(1.0, 2.0, 1.0f), key(3.0, 4.0, 3.0f), key(3.0, 6.0, 5.0f),
                                        key(5.0, 10.0, 9.0f)};
    ExtinctionParams extinction;
    Rgb rbf, light;
    sampleKeyframes(keys, 3.0, extinction, &rbf, &light);
    EXPECT_EQ(extinction.smoke_extinction, 6.0);
    EXPECT_EQ(rbf, Rgb(6.0f));
    EXPECT_EQ(light, Rgb(5.0f));
    sampleKeyframes(keys, 2.0, extinction, &rbf, &light);
    EXPECT_DOUBLE_EQ(extinction.smoke_extinction, 3.0);
    EXPECT_FLOAT_EQ(light.x, 2.0f);
    sampleKeyframes(keys, 4.5, extinction, &rbf, &light);
    EXPECT_DOUBLE_EQ(extinction.smoke_extinction, 9.0);
    EXPECT_FLOAT_EQ(rbf.x, 9.0f);
    sampleKeyframes(keys, 0.0, extinction, &rbf, &light);
    EXPECT_EQ(extinction.smoke_extinction, 2.0);
    sampleKeyframes(keys, 6.0, extinction, &rbf, &light);
    EXPECT_EQ(extinction.smoke_extinction, 10.0);
}

}  // namespace
}  // namespace firelook::world
