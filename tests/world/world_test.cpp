// The runtime world (runtime/world): images against basis::renderLookImage, keyframes, playback,
// the shared frame cache, handles, hard looks, several packages.
//
// "Equal to renderLookImage": the world batches the coefficients of the instances that show one
// frame (basis::coefficientBatch), which gives each instance the bits the one-look kernel gives it,
// and draws with the same reconstruction, so the image is bit for bit the same
// (ImageEqualsRenderLookImage, InstancesSharingAFrameGetTheirOwnBits). Where a test compares with a
// look re-fitted or blended another way, it allows 1e-5 of the image's peak radiance plus 1e-5
// relative (float rounding in another order).
#include "world/world.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "../support/error_code.h"
#include "../support/temp_dir.h"
#include "basis/look_renderer.h"
#include "basis/recombine.h"
#include "look/emission_fit.h"
#include "look/look_blend.h"
#include "synthetic_package.h"

namespace firelook::world {
namespace {

using firelook::testing::SyntheticShape;
using firelook::testing::TempDir;

std::shared_ptr<const Package> makePackage(const TempDir& dir, const SyntheticShape& shape = {},
                                           const std::string& name = "p.firelook") {
    firelook::testing::writeSyntheticPackage(dir / name, shape);
    return Package::open(dir / name);
}

Look lookA(double albedo = 0.7) {
    Look l = defaultLook();
    l.albedo = albedo;
    l.temperature_threshold = 1.3;
    l.smoke_extinction = 5.0;
    l.flame_extinction = 1.0;
    l.emission = EmissionPreset{"fire", 3.0};
    l.source_name = "A";
    return l;
}

Look lookB(double albedo = 0.7) {
    Look l = defaultLook();
    l.albedo = albedo;
    l.temperature_threshold = 1.9;
    l.smoke_extinction = 12.0;
    l.flame_extinction = 3.0;
    l.emission = EmissionPreset{"blackbody", 5.0};
    l.light_irradiance = {Rgb(0.5f, 1.0f, 3.0f)};
    l.source_name = "B";
    return l;
}

std::vector<float> referenceZ(const Package& p, int frame, const Look& look) {
    const auto& d = p.description();
    const basis::ResidentFrame f = p.basis().loadResidentFrame(frame, std::pmr::get_default_resource());
    const LookModel model = makeLookModel(look, d.bins, d.rbf_width, d.light_directions);
    std::vector<float> z(static_cast<size_t>(f.rank) * 3);
    basis::computeCoefficients(d, f, {look.extinction(), model.emission.coefficients, look.light_irradiance}, z);
    return z;
}

void expectClose(const float* got, const std::vector<float>& want, double relative = 1e-5) {
    double peak = 0.0;
    for (float v : want) peak = std::max(peak, std::abs(static_cast<double>(v)));
    for (size_t i = 0; i < want.size(); ++i)
        ASSERT_NEAR(got[i], want[i], relative * peak + relative * std::abs(want[i])) << "at " << i;
}

PlaybackSettings pausedAt(double frame_offset_seconds) {
    PlaybackSettings pb;
    pb.playing = false;
    pb.rate = 1.0;  // one frame per second: time = offset in frames
    pb.time = frame_offset_seconds;
    return pb;
}

TEST(World, ImageEqualsRenderLookImage) {
    TempDir dir;
    auto package = makePackage(dir);
    World world;
    const InstanceHandle h = world.create(package);
    world.setLook(h, lookA());
    world.setPlayback(h, pausedAt(1.0));  // frame 2
    world.setOutputs(h, {true, false, {}});
    world.update(0.0);
    const InstanceState s = world.state(h);
    ASSERT_EQ(s.frame, 2);
    ASSERT_NE(s.image, nullptr);

    const auto& d = package->description();
    // The world draws the resident form; the tools render the same (basis/look_renderer.h).
    const basis::ResidentFrame f = package->basis().loadResidentFrame(2, std::pmr::get_default_resource());
    std::vector<float> want(static_cast<size_t>(d.pixelCount()) * 4);
    basis::renderLookImage(d, f, lookA(), want);
    double peak = 0.0;
    for (size_t i = 0; i < want.size(); ++i)
        if (i % 4 != 3) peak = std::max(peak, static_cast<double>(want[i]));
    ASSERT_GT(peak, 0.0);
    for (size_t i = 0; i < want.size(); ++i) ASSERT_EQ(s.image[i], want[i]) << "at " << i;
    const std::vector<float> z = referenceZ(*package, 2, lookA());
    for (size_t i = 0; i < z.size(); ++i) ASSERT_EQ(s.z[i], z[i]) << "z at " << i;
}

TEST(World, KeyframesAtTheKeysEqualTheKeys) {
    TempDir dir;
    SyntheticShape shape;
    shape.frames = {1, 2, 3, 4, 5};
    auto package = makePackage(dir, shape);
    World world;
    const InstanceHandle h = world.create(package);
    const std::vector<std::pair<double, Look>> keys = {{4.0, lookB()}, {1.0, lookA()}};  // unsorted on purpose
    world.setKeyframes(h, keys);
    const auto& d = package->description();
    for (const auto& [frame, look] : keys) {
        world.setPlayback(h, pausedAt(frame - 1.0));
        world.update(0.0);
        const InstanceState s = world.state(h);
        ASSERT_EQ(s.frame_position, frame);
        const LookModel model = makeLookModel(look, d.bins, d.rbf_width, d.light_directions);
        for (int i = 0; i < d.bins.count; ++i) EXPECT_EQ(s.rbf[i], model.emission.coefficients[i]) << look.source_name;
        EXPECT_EQ(s.lights[0], look.light_irradiance[0]);
        EXPECT_EQ(s.extinction.temperature_threshold, look.temperature_threshold);
        EXPECT_EQ(s.extinction.smoke_extinction, look.smoke_extinction);
        EXPECT_EQ(s.extinction.flame_extinction, look.flame_extinction);
        expectClose(s.z, referenceZ(*package, static_cast<int>(frame), look));
    }
    // Held before the first key and after the last.
    world.setPlayback(h, pausedAt(4.5));
    world.update(0.0);
    EXPECT_EQ(world.state(h).extinction.smoke_extinction, lookB().smoke_extinction);
}

// Between keys whose fits are exact interpolants, the world's coefficients are the fit of the blended
// look (interpolateLooks + makeLookModel) up to float rounding, and that look is linear per bin.
TEST(World, BetweenKeysMatchesInterpolateLooksForExactFits) {
    TempDir dir;
    SyntheticShape shape;
    shape.frames = {1, 2, 3, 4, 5};
    auto package = makePackage(dir, shape);
    const auto& d = package->description();
    Look a = lookA(), b = lookB();
    // Smooth, non-negative bin emissivity whose interpolants are non-negative.
    std::vector<Rgb> ea, eb;
    for (int i = 0; i < d.bins.count; ++i) {
        const float x = static_cast<float>(i) / (d.bins.count - 1);
        ea.push_back(Rgb(1.0f + x, 0.5f + 0.5f * x * x, 0.3f));
        eb.push_back(Rgb(4.0f - 2.0f * x, 2.0f, 0.2f + x));
    }
    a.emission = EmissionBins{ea};
    b.emission = EmissionBins{eb};
    ASSERT_TRUE(resolveLook(a, d).exact_interpolant);
    ASSERT_TRUE(resolveLook(b, d).exact_interpolant);
    World world;
    const InstanceHandle h = world.create(package);
    const std::vector<std::pair<double, Look>> keys = {{1.0, a}, {5.0, b}};
    world.setKeyframes(h, keys);
    for (double frame : {1.5, 2.0, 3.3, 4.9}) {
        world.setPlayback(h, pausedAt(frame - 1.0));
        world.update(0.0);
        const InstanceState s = world.state(h);
        const Look blended = interpolateLooks(a, b, (frame - 1.0) / 4.0, d.bins, d.rbf_width);
        const LookModel model = makeLookModel(blended, d.bins, d.rbf_width, d.light_directions);
        for (int i = 0; i < d.bins.count; ++i)
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(s.rbf[i][c], model.emission.coefficients[i][c], 1e-4) << "frame " << frame << " bin " << i;
        expectClose(s.z, referenceZ(*package, s.frame, blended), 1e-4);
    }
}

// Where a key needs the non-negative fit (a sharp emissivity step), the blend of fits (the one rule,
// look/look_blend.h) differs from the fit of the per-bin blended emissivity (the rule `firelook
// animate` used before). This measures by how much, as L_e at the bin centres relative to the peak
// emissivity, records it as a test property, and checks that interpolateLooks now is the blend of
// fits and stays non-negative.
TEST(World, BetweenKeysWithNonNegativeFitsMeasured) {
    TempDir dir;
    auto package = makePackage(dir);
    const auto& d = package->description();
    Look a = lookA(), b = lookB();
    std::vector<Rgb> ea(d.bins.count, Rgb(0.0f)), eb(d.bins.count, Rgb(0.0f));
    for (int i = d.bins.count / 2; i < d.bins.count; ++i) ea[i] = Rgb(10.0f, 5.0f, 1.0f);  // a sharp step
    for (int i = 0; i < d.bins.count; ++i) eb[i] = Rgb(2.0f + 0.1f * i);
    a.emission = EmissionBins{ea};
    b.emission = EmissionBins{eb};
    ASSERT_FALSE(resolveLook(a, d).exact_interpolant);
    const ResolvedLook ra = resolveLook(a, d), rb = resolveLook(b, d);
    const EmissionBasis basis{d.bins, d.rbf_width};
    double worst = 0.0, worst_single = 0.0;
    // Key a's own fit misses its step at the bin centres by this (of the peak, 10).
    double own_miss = 0.0;
    for (int j = 0; j < d.bins.count; ++j) {
        const Rgb x = EmissionFunction{basis, ra.rbf}.evaluate(d.bins.center(j));
        for (int c = 0; c < 3; ++c) own_miss = std::max(own_miss, std::abs(static_cast<double>(x[c] - ea[j][c])) / 10.0);
    }
    for (double t = 0.0; t <= 1.0; t += 0.125) {
        std::vector<Rgb> per_bin;
        for (int j = 0; j < d.bins.count; ++j)
            per_bin.push_back(static_cast<float>(1 - t) * ea[j] + static_cast<float>(t) * eb[j]);
        const EmissionFunction fit_of_blend{basis, fitEmissionCoefficients(basis, per_bin)};
        EmissionFunction blend_of_fits{basis, {}};
        for (int i = 0; i < d.bins.count; ++i) {
            blend_of_fits.coefficients.push_back(static_cast<float>(1 - t) * ra.rbf[i] + static_cast<float>(t) * rb.rbf[i]);
            for (int c = 0; c < 3; ++c) ASSERT_GE(blend_of_fits.coefficients.back()[c], 0.0f);
        }
        const std::vector<Rgb> single = resolveBinEmissivity(interpolateLooks(a, b, t, d.bins, d.rbf_width), d.bins);
        for (int j = 0; j < d.bins.count; ++j) {
            const Rgb x = blend_of_fits.evaluate(d.bins.center(j)), y = fit_of_blend.evaluate(d.bins.center(j));
            for (int c = 0; c < 3; ++c) {
                worst = std::max(worst, std::abs(static_cast<double>(x[c] - y[c])) / 10.0);
                worst_single = std::max(worst_single, std::abs(static_cast<double>(x[c] - single[j][c])) / 10.0);
                ASSERT_GE(single[j][c], 0.0f);
            }
        }
    }
    RecordProperty("blend_of_fits_vs_fit_of_blend_max_rel", std::to_string(worst));
    std::printf("step key: blend of fits vs fit of blend, max |dL_e| at bin centres = %.4f of the peak emissivity "
                "(key a's own fit misses by %.4f)\n",
                worst, own_miss);
    // At the centres the blend of fits misses the blended emissivity by (1 - t) times key a's own
    // miss (key b's fit is exact), and the fit of the blend by at most about as much, so the two
    // differ by at most ~2 (1 - t) own_miss; the fit of a step misses the centres next to it by ~11%
    // (look_model.h). Measured: own_miss 0.1149; the fit of the blend misses by 0.074 at t = 0.125,
    // 0.035 at 0.25 and is exact from t = 0.375 on, where the difference peaks at 0.0718 =
    // 0.625 * 0.1149. No sampling: the figure is deterministic up to float rounding in the
    // non-negative fit, so 0.08 (11% over it) only fails if the fits change.
    EXPECT_LT(worst, 0.08);
    EXPECT_LT(worst, 2.0 * own_miss);
    // The one rule: interpolateLooks is the blend of fits (evaluated at the centres, float rounding).
    EXPECT_LT(worst_single, 1e-6);
}

TEST(World, PlaybackPicksBakedFramesAndLoops) {
    TempDir dir;
    SyntheticShape shape;
    shape.frames = {10, 11, 12, 14};  // a gap: 13 was not baked
    auto package = makePackage(dir, shape);
    World world;
    const InstanceHandle h = world.create(package);
    PlaybackSettings pb;
    pb.rate = 2.0;  // 2 frames per second
    world.setPlayback(h, pb);
    std::vector<int> frames;
    for (int i = 0; i < 12; ++i) {
        world.update(0.25);  // half a frame
        frames.push_back(world.state(h).frame);
    }
    // Positions 10.5, 11, 11.5, ..., 14.5 (range 10..14 spans 5 frames), then wrap to 10.
    const std::vector<int> want = {10, 11, 11, 12, 12, 12, 12, 14, 14, 10, 10, 11};
    EXPECT_EQ(frames, want);

    pb = {};
    pb.rate = 24.0;
    pb.loop = false;
    world.setPlayback(h, pb);
    world.update(100.0);
    EXPECT_EQ(world.state(h).frame, 14);
    EXPECT_EQ(world.state(h).frame_position, 14.0);

    pb = {};
    pb.rate = -1.0;  // backwards, looping within 11..12
    pb.first_frame = 11;
    pb.last_frame = 12;
    world.setPlayback(h, pb);
    world.update(0.5);
    EXPECT_EQ(world.state(h).frame, 12);  // 11 + (2 - 0.5)
    EXPECT_NEAR(world.state(h).frame_position, 12.5, 1e-12);
    world.update(1.0);
    EXPECT_EQ(world.state(h).frame, 11);
    for (int i = 0; i < 1000; ++i) world.update(0.37);
    const InstanceState s = world.state(h);
    EXPECT_GE(s.frame_position, 11.0);
    EXPECT_LT(s.frame_position, 13.0);
    EXPECT_LE(std::abs(s.time), 2.0);  // wrapped, not growing
}

TEST(World, InstancesShareOneCachedCopyPerFrameAndTheCacheIsBounded) {
    TempDir dir;
    SyntheticShape shape;
    shape.frames = {1, 2, 3, 4, 5, 6};
    auto package = makePackage(dir, shape);
    World world;
    std::vector<InstanceHandle> hs;
    for (int i = 0; i < 50; ++i) hs.push_back(world.create(package));
    world.update(0.0);
    // Every instance on frame 1, one copy; frame 2 decoded ahead (they play forwards).
    EXPECT_EQ(world.frameLoads(), 2u);
    EXPECT_EQ(world.prefetches(), 1u);
    EXPECT_EQ(world.cachedFrames(), 2u);
    for (int i = 0; i < 50; ++i) world.setPlayback(hs[i], pausedAt(i % 3));  // frames 1..3
    world.update(0.0);
    EXPECT_EQ(world.frameLoads(), 3u);

    // A budget of one byte: after each update only the frames in use remain.
    WorldSettings tight;
    tight.frame_cache_bytes = 1;
    World small(tight);
    const InstanceHandle h = small.create(package);
    PlaybackSettings pb;
    pb.rate = 1.0;
    small.setPlayback(h, pb);
    for (int i = 0; i < 10; ++i) {
        small.update(1.0);
        EXPECT_EQ(small.cachedFrames(), 1u);
    }
}

// Streaming through more frames than the budget holds: each evicted frame's buffers serve the
// next load (one spare, counted in cacheBytes and kept only within the budget), and the images
// drawn from reused buffers equal those of freshly decoded frames.
TEST(World, StreamingReusesAnEvictedFramesBuffersWithinTheBudget) {
    TempDir dir;
    SyntheticShape shape;
    shape.frames = {1, 2, 3, 4, 5, 6};
    auto package = makePackage(dir, shape);
    const auto& d = package->description();
    const size_t frame_bytes = package->basis().loadResidentFrame(1, std::pmr::get_default_resource()).bytes();
    WorldSettings settings;
    settings.frame_cache_bytes = 3 * frame_bytes + frame_bytes / 2;  // about three of the six frames
    World world(settings);
    const InstanceHandle h = world.create(package);
    world.setLook(h, lookA());
    world.setOutputs(h, {true, false, {}});
    PlaybackSettings pb;
    pb.rate = 1.0;
    world.setPlayback(h, pb);
    std::vector<float> want(static_cast<size_t>(d.pixelCount()) * 4);
    for (int step = 0; step < 14; ++step) {
        world.update(step == 0 ? 0.0 : 1.0);
        const InstanceState s = world.state(h);
        EXPECT_LE(world.cacheBytes(), settings.frame_cache_bytes) << step;
        const basis::ResidentFrame fresh = package->basis().loadResidentFrame(s.frame, std::pmr::get_default_resource());
        basis::renderLookImage(d, fresh, lookA(), want);
        // Alpha bit for bit; rgb as in ImageEqualsRenderLookImage (z's summation order differs).
        double peak = 0.0;
        for (size_t i = 0; i < want.size(); ++i)
            if (i % 4 != 3) peak = std::max(peak, static_cast<double>(want[i]));
        for (size_t i = 0; i < want.size(); ++i) {
            if (i % 4 == 3)
                ASSERT_EQ(s.image[i], want[i]) << "step " << step << " alpha at " << i;
            else
                ASSERT_NEAR(s.image[i], want[i], 1e-5 * peak + 1e-5 * std::abs(want[i])) << "step " << step << " at " << i;
        }
    }
    EXPECT_EQ(world.frameLoads(), 14u);  // a new frame each step once the cache has turned over
}

// The next frame in the direction of play is decoded one update ahead, so showing it decodes
// nothing; at the end of a looping range the next frame is the first; paused instances and a full
// cache prefetch nothing.
TEST(World, TheNextFrameIsDecodedAhead) {
    TempDir dir;
    SyntheticShape shape;
    shape.frames = {1, 2, 3, 4};
    auto package = makePackage(dir, shape);
    World world;
    const InstanceHandle h = world.create(package);
    PlaybackSettings pb;
    pb.rate = 1.0;
    world.setPlayback(h, pb);
    world.update(0.0);
    EXPECT_EQ(world.state(h).frame, 1);
    EXPECT_EQ(world.frameLoads(), 2u);  // frame 1 shown, frame 2 ahead
    for (int step = 1; step < 3; ++step) {
        world.update(1.0);
        EXPECT_EQ(world.state(h).frame, 1 + step);
        EXPECT_EQ(world.frameLoads(), static_cast<uint64_t>(2 + step));  // only the one ahead
        EXPECT_EQ(world.prefetches(), static_cast<uint64_t>(1 + step)) << step;
    }
    world.update(1.0);
    EXPECT_EQ(world.state(h).frame, 4);
    EXPECT_EQ(world.frameLoads(), 4u);  // frame 1, next after the wrap, is still cached
    EXPECT_EQ(world.cachedFrames(), 4u);
    // Backwards: the frame below.
    World backwards;
    const InstanceHandle b = backwards.create(package);
    pb.rate = -1.0;
    pb.time = 0.0;
    backwards.setPlayback(b, pb);
    backwards.update(0.0);
    EXPECT_EQ(backwards.state(b).frame, 1);
    EXPECT_EQ(backwards.cachedFrames(), 2u);
    backwards.update(1.0);
    EXPECT_EQ(backwards.state(b).frame, 4);  // wrapped below frame 1
    EXPECT_EQ(backwards.frameLoads(), 3u);   // 4 was ahead; now 3 is
    // Paused, or no room: nothing ahead.
    World paused;
    const InstanceHandle q = paused.create(package);
    paused.setPlayback(q, pausedAt(0.0));
    paused.update(0.0);
    EXPECT_EQ(paused.prefetches(), 0u);
    WorldSettings tight;
    tight.frame_cache_bytes = 1;
    World full(tight);
    const InstanceHandle f = full.create(package);
    pb.rate = 1.0;
    full.setPlayback(f, pb);
    full.update(0.0);
    EXPECT_EQ(full.prefetches(), 0u);
    EXPECT_EQ(full.cachedFrames(), 1u);
}

TEST(World, StaleAndInvalidHandlesAreDetected) {
    TempDir dir;
    auto package = makePackage(dir);
    World world;
    const InstanceHandle a = world.create(package);
    EXPECT_TRUE(world.valid(a));
    EXPECT_FALSE(world.valid(0));
    EXPECT_THROW(world.state(0), InvalidHandle);
    world.destroy(a);
    EXPECT_FALSE(world.valid(a));
    EXPECT_THROW(world.destroy(a), InvalidHandle);
    EXPECT_THROW(world.setLook(a, lookA()), InvalidHandle);
    const InstanceHandle b = world.create(package);  // reuses the slot with a new generation
    EXPECT_NE(a, b);
    EXPECT_FALSE(world.valid(a));
    EXPECT_TRUE(world.valid(b));
    EXPECT_THROW(world.state(b + (1u << 20)), InvalidHandle);
    EXPECT_THROW(world.state(0xFFFFF), InvalidHandle);
}

TEST(HandlePool, AReleasedHandleNeverBecomesValidAgain) {
    // One slot released and reused 100,000 times: with an 11-bit generation that wraps, the first
    // handle would be valid again at the 2047th reuse. A spent slot is retired instead (handle_pool.h).
    HandlePool<int> pool(HandleKind::Look);
    const uint32_t first = pool.add(0);
    pool.take(first);
    uint32_t previous = first;
    for (int n = 1; n <= 100000; ++n) {
        const uint32_t id = pool.add(n);
        ASSERT_EQ(pool.find(first), nullptr) << "reuse " << n;
        ASSERT_EQ(pool.find(previous), nullptr) << "reuse " << n;
        ASSERT_NE(id, first) << "reuse " << n;
        ASSERT_EQ(*pool.find(id), n);
        pool.take(id);
        previous = id;
    }
    EXPECT_EQ(pool.size(), 0u);
    // Each slot serves generations 1..2047: 100,001 objects retire 48 slots (48 x 2047 = 98,256).
    EXPECT_EQ(pool.retired(), 100001u / 2047u);
}

TEST(World, SwapRemoveKeepsOtherInstancesIntact) {
    TempDir dir;
    auto package = makePackage(dir);
    World world;
    const InstanceHandle a = world.create(package), b = world.create(package), c = world.create(package);
    world.setLook(c, lookB());
    world.setOutputs(c, {true, false, {}});
    world.destroy(a);  // c moves into a's dense slot
    world.update(0.0);
    EXPECT_EQ(world.size(), 2u);
    EXPECT_TRUE(world.valid(b));
    expectClose(world.state(c).z, referenceZ(*package, 1, lookB()));
    EXPECT_NE(world.state(c).image, nullptr);
    EXPECT_EQ(world.state(b).image, nullptr);
}

TEST(World, LooksThatDoNotFitThePackageAreRefusedAndChangeNothing) {
    TempDir dir;
    auto package = makePackage(dir);
    World world;
    const InstanceHandle h = world.create(package);
    world.setLook(h, lookA());
    EXPECT_THROW(world.setLook(h, lookA(0.9)), LookError);  // albedo differs from the baked one
    Look two_lights = lookA();
    two_lights.light_irradiance.push_back(Rgb(1.0f));
    EXPECT_THROW(world.setLook(h, two_lights), LookError);
    Look wrong_bins = lookA();
    wrong_bins.emission = EmissionBins{{Rgb(1.0f), Rgb(2.0f)}};
    EXPECT_THROW(world.setLook(h, wrong_bins), LookError);
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, world.setKeyframes(h, {}));
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument,
                      world.setOutputs(h, {false, true, {}}));  // flare without image
    PlaybackSettings bad;
    bad.rate = NAN;
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, world.setPlayback(h, bad));
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, world.update(INFINITY));
    world.update(0.0);
    expectClose(world.state(h).z, referenceZ(*package, 1, lookA()));
}

TEST(World, HardLooksNeverProduceNaN) {
    TempDir dir;
    auto package = makePackage(dir);
    World world;
    std::vector<Look> looks;
    Look zero_extinction = lookA();
    zero_extinction.smoke_extinction = zero_extinction.flame_extinction = 0.0;
    looks.push_back(zero_extinction);
    Look huge = lookA();
    huge.smoke_extinction = huge.flame_extinction = 1e30;
    looks.push_back(huge);
    Look no_emission = lookA();
    no_emission.emission = EmissionPreset{"fire", 0.0};
    no_emission.light_irradiance = {Rgb(0.0f)};
    looks.push_back(no_emission);
    Look extreme_threshold = lookB();
    extreme_threshold.temperature_threshold = -1e6;
    looks.push_back(extreme_threshold);
    extreme_threshold.temperature_threshold = 1e6;
    looks.push_back(extreme_threshold);
    Look bright = lookA();
    bright.emission = EmissionPreset{"fire", 1e30};
    looks.push_back(bright);
    std::vector<InstanceHandle> handles;  // one per look, in order
    for (const Look& look : looks) {
        const InstanceHandle h = handles.emplace_back(world.create(package));
        world.setLook(h, look);
        OutputSettings out{true, true, {}};
        world.setOutputs(h, out);
    }
    world.update(0.0);
    world.update(1.0 / 24);
    const size_t floats = static_cast<size_t>(package->description().pixelCount()) * 4;
    for (size_t i = 0; i < world.size(); ++i) {
        const InstanceState s = world.state(handles[i]);
        for (int k = 0; k < s.rank * 3; ++k) ASSERT_FALSE(std::isnan(s.z[k])) << i;
        for (size_t p = 0; p < floats; ++p) {
            ASSERT_TRUE(std::isfinite(s.image[p])) << "look " << i << " value " << p;
            ASSERT_TRUE(std::isfinite(s.flare[p])) << "look " << i << " flare " << p;
            ASSERT_GE(s.image[p], 0.0f);
            if (p % 4 == 3) {
                ASSERT_LE(s.image[p], 1.0f);
            }
        }
    }
    // Zero extinction: transparent. Huge extinction: opaque wherever there is density.
    const InstanceState clear = world.state(handles[0]), opaque = world.state(handles[1]);
    for (size_t p = 3; p < floats; p += 4) {
        EXPECT_EQ(clear.image[p], 0.0f);
        EXPECT_EQ(opaque.image[p], 1.0f);
    }
}

TEST(World, SeveralPackagesCoexist) {
    TempDir dir;
    SyntheticShape small;
    small.bins = 4;
    small.rank = 3;
    small.lights = 0;
    small.axes = {{1.5}, {4.0}, {1.5}};
    SyntheticShape big;
    big.rank = 12;
    big.lights = 2;
    big.width = 20;
    auto p1 = makePackage(dir, small, "small.firelook");
    World world;
    Look l1 = lookA();
    l1.light_irradiance.clear();
    const InstanceHandle h1 = world.create(p1);
    world.setLook(h1, l1);
    world.setOutputs(h1, {true, false, {}});
    world.update(0.0);
    // A package with more bins, lights and rank arrives later: the strides grow, h1 keeps its state.
    auto p2 = makePackage(dir, big, "big.firelook");
    const InstanceHandle h2 = world.create(p2);
    Look l2 = lookB();
    l2.light_irradiance = {Rgb(1.0f), Rgb(0.5f)};
    world.setLook(h2, l2);
    world.setOutputs(h2, {true, false, {}});
    world.update(0.0);
    expectClose(world.state(h1).z, referenceZ(*p1, 1, l1));
    expectClose(world.state(h2).z, referenceZ(*p2, 1, l2));
    EXPECT_EQ(world.state(h2).rank, 12);
    EXPECT_EQ(world.state(h1).rank, 3);
}

// Many instances on a few frames, with different looks, keys and times (so different grid points):
// the update batches each frame's instances, and every instance's z is exactly what
// basis::computeCoefficients gives its look alone.
TEST(World, InstancesSharingAFrameGetTheirOwnBits) {
    TempDir dir;
    SyntheticShape shape;
    shape.frames = {1, 2, 3};
    shape.rank = 21;
    auto package = makePackage(dir, shape);
    const auto& d = package->description();
    World world;
    std::vector<InstanceHandle> handles;
    for (int i = 0; i < 23; ++i) {
        const InstanceHandle h = world.create(package);
        Look a = lookA(), b = lookB();
        a.temperature_threshold = 1.0 + 0.045 * i;
        a.smoke_extinction = 2.0 + 0.6 * i;
        b.flame_extinction = 0.5 + 0.15 * i;
        const std::vector<std::pair<double, Look>> keys = {{1.0, a}, {3.5, b}};
        world.setKeyframes(h, keys);
        world.setPlayback(h, pausedAt(0.13 * i));
        handles.push_back(h);
    }
    world.update(0.0);
    std::set<int> frames;
    for (const InstanceHandle h : handles) {
        const InstanceState s = world.state(h);
        frames.insert(s.frame);
        const basis::ResidentFrame f = package->basis().loadResidentFrame(s.frame, std::pmr::get_default_resource());
        std::vector<float> z(static_cast<size_t>(f.rank) * 3);
        basis::computeCoefficients(d, f, {s.extinction, s.rbf, s.lights}, z);
        for (size_t i = 0; i < z.size(); ++i) ASSERT_EQ(s.z[i], z[i]) << "instance " << h << " frame " << s.frame;
    }
    EXPECT_EQ(frames.size(), 3u);
}

}  // namespace
}  // namespace firelook::world
