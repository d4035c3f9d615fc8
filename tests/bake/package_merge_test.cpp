// mergePackages (baker/bake/package_merge.h): shards of one bake merge into the one-shot bake's
// bytes; parts that overlap, leave a gap or were baked differently are refused, writing nothing.
#include "bake/package_merge.h"

#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <memory>

#include "../support/temp_dir.h"
#include "bake/bake_pipeline.h"
#include "package/container_writer.h"
#include "tiny_sample_bake.h"

namespace firelook::bake {
namespace {

using firelook::testing::TempDir;
using test::fileBytes;
using test::tinyConfig;

std::filesystem::path bakeFrames(const TempDir& dir, const std::string& name, const std::string& frames,
                                 uint64_t seed = 1, int threads = 0) {
    BakeConfig c = tinyConfig(seed);
    c.frames = frames;
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
    bakePackage(FIRELOOK_SAMPLE_DIR, dir / name, c, "test");
    return dir / name;
}

// The message of what mergePackages threw, or "" when it did not throw.
std::string mergeError(const std::vector<std::filesystem::path>& parts, const std::filesystem::path& out,
                       MergeOptions options = {}) {
    try {
        mergePackages(parts, out, options);
    } catch (const std::exception& e) {
        return e.what();
    }
    return {};
}

// Per-frame seeds, the whole sequence's temperature range, camera and axis analysis make a frame's
// bytes independent of the shard; photon chunks summed in a fixed order make them independent of
// the thread count. The parts are given out of order on purpose.
TEST(PackageMerge, ShardsMergeIntoTheOneShotBakesBytes) {
    TempDir dir;
    const std::string one_shot = fileBytes(bakeFrames(dir, "one.firelook", "1-3"));
    ASSERT_FALSE(one_shot.empty());
    const auto a = bakeFrames(dir, "a.firelook", "1", 1, 1);
    const auto b = bakeFrames(dir, "b.firelook", "2", 1, 2);
    const auto c = bakeFrames(dir, "c.firelook", "3");
    const MergeResult result = mergePackages({c, a, b}, dir / "merged.firelook");
    EXPECT_EQ(result.frames, (std::vector<int>{1, 2, 3}));
    EXPECT_TRUE(fileBytes(dir / "merged.firelook") == one_shot) << "merged shards differ from the one-shot bake";
    EXPECT_EQ(result.package_bytes, one_shot.size());
    // Merging a merged package again changes nothing either.
    mergePackages({dir / "merged.firelook"}, dir / "again.firelook");
    EXPECT_TRUE(fileBytes(dir / "again.firelook") == one_shot);
}

TEST(PackageMerge, RefusesOverlappingParts) {
    TempDir dir;
    const auto a = bakeFrames(dir, "a.firelook", "1-2");
    const auto b = bakeFrames(dir, "b.firelook", "2-3");
    const std::string error = mergeError({a, b}, dir / "out.firelook");
    EXPECT_NE(error.find("frame 2 is also in"), std::string::npos) << error;
    EXPECT_NE(error.find("a.firelook"), std::string::npos) << error;
    EXPECT_NE(error.find("b.firelook"), std::string::npos) << error;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.firelook"));
}

TEST(PackageMerge, RefusesAMissingFrameUnlessAllowed) {
    TempDir dir;
    const auto a = bakeFrames(dir, "a.firelook", "1");
    const auto c = bakeFrames(dir, "c.firelook", "3-4");
    const std::string error = mergeError({a, c}, dir / "out.firelook");
    EXPECT_NE(error.find("no part holds frame 2 "), std::string::npos) << error;
    EXPECT_NE(error.find("--allow-gaps"), std::string::npos) << error;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.firelook"));
    EXPECT_EQ(mergeError({a, c}, dir / "out.firelook", {.allow_gaps = true, .only = {}}), "");
    EXPECT_TRUE(fileBytes(dir / "out.firelook") == fileBytes(bakeFrames(dir, "gappy.firelook", "1,3-4")));
}

TEST(PackageMerge, RefusesPartsBakedDifferently) {
    TempDir dir;
    const auto a = bakeFrames(dir, "a.firelook", "1", 1);
    const auto b = bakeFrames(dir, "b.firelook", "2", 2);
    const std::string error = mergeError({a, b}, dir / "out.firelook");
    EXPECT_NE(error.find("b.firelook: not baked like"), std::string::npos) << error;
    EXPECT_NE(error.find("provenance.settings.seed: 1 vs 2"), std::string::npos) << error;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.firelook"));
}

TEST(PackageMerge, RefusesAPackageNotWrittenByABake) {
    TempDir dir;
    const auto a = bakeFrames(dir, "a.firelook", "1");
    package::ContainerWriter writer(dir / "other.firelook");
    writer.addMetadata(R"({"format": "firelook-basis", "version": 2})");
    writer.commit();
    const std::string error = mergeError({a, dir / "other.firelook"}, dir / "out.firelook");
    EXPECT_NE(error.find("other.firelook: its metadata has no provenance"), std::string::npos) << error;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.firelook"));
}

}  // namespace
}  // namespace firelook::bake
