// The structure check run before OpenVDB parses a file (vdb/file_structure.h): every layout
// OpenVDB 10 writes passes and loads; damaged files, including the inputs that crashed OpenVDB
// under fuzzing (tests/fuzz/crashes/vdb_sequence), get a VdbError naming the file and the problem.
#include "vdb/file_structure.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "vdb/vdb_sequence.h"
#include "vdb_test_files.h"

namespace firelook::vdb {
namespace {

using namespace testing;  // vdb_test_files.h
using ::testing::HasSubstr;

std::vector<std::byte> readBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> chars{std::istreambuf_iterator<char>(in), {}};
    std::vector<std::byte> bytes(chars.size());
    std::memcpy(bytes.data(), chars.data(), chars.size());
    return bytes;
}

// A density grid with voxels in two root children, several leaves, an internal-node tile and
// inactive values, and a temperature grid, written with the given compression.
void writeLayoutFrame(const std::filesystem::path& path, uint32_t compression, bool half = false) {
    Voxels density = kDensity;
    for (int i = 0; i < 40; ++i) density.push_back({{i * 7, -i * 3, i * 5}, 0.1f * float(i % 9)});
    density.push_back({{5000, 10, -9000}, 2.0f});
    openvdb::FloatGrid::Ptr d = makeGrid("density", density);
    d->tree().addTile(/*level=*/1, openvdb::Coord(256, 256, 256), 0.5f, /*active=*/true);  // 8^3 voxels
    d->tree().setValueOff(openvdb::Coord(1, 2, 3), 0.25f);  // an inactive non-background value
    openvdb::FloatGrid::Ptr t = makeGrid("temperature", kTemperature);
    d->setSaveFloatAsHalf(half);
    t->setSaveFloatAsHalf(half);
    openvdb::initialize();
    openvdb::io::File file(path.string());
    file.setCompression(compression);
    file.write({d, t});
    file.close();
}

TEST(VdbFileStructure, EveryLayoutOpenVdbWritesPassesAndLoads) {
    using namespace openvdb::io;
    struct Variant {
        const char* name;
        uint32_t compression;
        bool half;
    };
    std::vector<Variant> variants = {{"zip+mask", COMPRESS_ZIP | COMPRESS_ACTIVE_MASK, false},
                                     {"zip", COMPRESS_ZIP, false},
                                     {"mask", COMPRESS_ACTIVE_MASK, false},
                                     {"none", COMPRESS_NONE, false},
                                     {"zip+mask half", COMPRESS_ZIP | COMPRESS_ACTIVE_MASK, true},
                                     {"none half", COMPRESS_NONE, true}};
    if (Archive::hasBloscCompression()) {
        variants.push_back({"blosc+mask", COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK, false});
        variants.push_back({"blosc", COMPRESS_BLOSC, false});
        variants.push_back({"blosc+mask half", COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK, true});
    }
    for (const Variant& variant : variants) {
        SCOPED_TRACE(variant.name);
        TempDir dir;
        writeLayoutFrame(dir / "f_1.vdb", variant.compression, variant.half);
        EXPECT_NO_THROW(checkFileStructure(dir / "f_1.vdb"));
        const VolumeFrame frame = VdbSequence::open(dir.path().string()).load(1);
        EXPECT_EQ(frame.density_stats.active_voxels, 43u + 8u * 8u * 8u);
    }
}

TEST(VdbFileStructure, RootTilesInstancesAndOtherGridTypesPass) {
    TempDir dir;
    openvdb::FloatGrid::Ptr density = makeGrid("density", kDensity);
    density->tree().addTile(/*level=*/3, openvdb::Coord(-4096, 0, 4096), 1.0f, /*active=*/false);
    openvdb::FloatGrid::Ptr instance = makeGrid("temperature", {});
    instance->setTree(density->treePtr());  // io::File writes a grid that shares a tree as an instance
    openvdb::Vec3SGrid::Ptr velocity = openvdb::Vec3SGrid::create();
    velocity->setName("velocity");
    velocity->tree().setValueOn(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1, 2, 3));
    openvdb::FloatGrid::Ptr frustum = makeGrid("frustum", kDensity);
    frustum->setTransform(openvdb::math::Transform::createFrustumTransform(
        openvdb::BBoxd(openvdb::Vec3d(0), openvdb::Vec3d(10)), 0.5, 2.0, 0.1));
    writeVdb(dir / "f_1.vdb", {density, instance, velocity, frustum});
    EXPECT_NO_THROW(checkFileStructure(dir / "f_1.vdb"));
    const VolumeFrame frame = VdbSequence::open(dir.path().string()).load(1);
    EXPECT_EQ(frame.temperature_stats.active_voxels, kDensity.size());

    // A vector grid named density is refused from its metadata, with the usual message.
    TempDir vector_dir;
    velocity->setName("density");
    writeVdb(vector_dir / "f_1.vdb", {velocity, makeGrid("temperature", kTemperature)});
    EXPECT_THAT(errorOf([&] { VdbSequence::open(vector_dir.path().string()); }), HasSubstr("holds vec3s values"));
}

TEST(VdbFileStructure, EveryTruncationIsRefusedNamingTheFile) {
    TempDir dir;
    writeLayoutFrame(dir / "f_1.vdb", openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
    const std::vector<std::byte> bytes = readBytes(dir / "f_1.vdb");
    ASSERT_NO_THROW(checkFileStructure(bytes, "f_1.vdb"));
    for (std::size_t size = 0; size < bytes.size(); ++size) {
        const std::string error = errorOf([&] { checkFileStructure(std::span(bytes).first(size), "f_1.vdb"); });
        ASSERT_THAT(error, HasSubstr("f_1.vdb: not a readable VDB file: ")) << "cut at " << size;
    }
}

TEST(VdbFileStructure, HeaderProblemsAreNamed) {
    TempDir dir;
    writeLayoutFrame(dir / "f_1.vdb", openvdb::io::COMPRESS_ZIP);
    const std::vector<std::byte> good = readBytes(dir / "f_1.vdb");
    const auto errorWith = [&](std::size_t offset, std::vector<uint8_t> patch) {
        std::vector<std::byte> bytes = good;
        for (std::size_t i = 0; i < patch.size(); ++i) bytes[offset + i] = std::byte{patch[i]};
        return errorOf([&] { checkFileStructure(bytes, "f_1.vdb"); });
    };
    EXPECT_THAT(errorOf([&] { checkFileStructure({}, "f_1.vdb"); }), HasSubstr("the file is empty"));
    EXPECT_THAT(errorWith(0, {'X'}), HasSubstr("no OpenVDB magic number"));
    EXPECT_THAT(errorWith(8, {221, 0, 0, 0}), HasSubstr("version 221 predates 222"));
    EXPECT_THAT(errorWith(8, {225, 0, 0, 0}), HasSubstr("version 225 is newer"));
    EXPECT_THAT(errorWith(20, {0}), HasSubstr("no grid offsets"));
    EXPECT_THAT(errorWith(21, {'g'}), HasSubstr("UUID"));
    EXPECT_THAT(errorWith(57, {0xff, 0xff, 0xff, 0x7f}), HasSubstr("file metadata"));  // item count
    // The first grid descriptor's name length (after 4 bytes of file metadata count and 4 of grid count).
    EXPECT_THAT(errorWith(65, {0xff, 0xff, 0xff, 0x0f}), HasSubstr("grid name (268435455 characters)"));
}

// The heap overflow of tests/fuzz/crashes (io::unzipFromStream copies a stored chunk of the size
// the file gives into a buffer of the size the tree needs), in a file that is not truncated.
TEST(VdbFileStructure, AStoredChunkOfAnotherSizeIsRefused) {
    TempDir dir;
    // One active voxel: under mask compression its leaf holds one value, which zip cannot shrink,
    // so it is stored (size field -4), the first such field in the file.
    {
        openvdb::io::File file((dir / "f_1.vdb").string());
        file.setCompression(openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
        file.write({makeGrid("density", {{{1, 2, 3}, 1.0f}}), makeGrid("temperature", kTemperature)});
    }
    std::vector<std::byte> bytes = readBytes(dir / "f_1.vdb");
    ASSERT_NO_THROW(checkFileStructure(bytes, "f_1.vdb"));
    const int64_t stored = -4;
    std::byte pattern[8];
    std::memcpy(pattern, &stored, 8);
    const auto at = std::search(bytes.begin(), bytes.end(), std::begin(pattern), std::end(pattern));
    ASSERT_NE(at, bytes.end()) << "no stored leaf chunk";
    const int64_t larger = -8;
    std::memcpy(&*at, &larger, 8);
    EXPECT_THAT(errorOf([&] { checkFileStructure(bytes, "f_1.vdb"); }),
                HasSubstr("grid 'density': leaf values holds 8 stored bytes, 4 expected"));
}

TEST(VdbFileStructure, InputsThatCrashedOpenVdbAreRefusedByTheReader) {
    const std::filesystem::path crashes = FIRELOOK_FUZZ_CRASHES_DIR;
    int replayed = 0;
    for (const auto& entry : std::filesystem::directory_iterator(crashes)) {
        SCOPED_TRACE(entry.path().filename().string());
        TempDir dir;
        std::filesystem::copy_file(entry.path(), dir / "fire_0001.vdb");
        const std::string error = errorOf([&] {
            const VdbSequence sequence = VdbSequence::open(dir.path().string());
            sequence.load(1);
        });
        EXPECT_THAT(error, HasSubstr("fire_0001.vdb: not a readable VDB file: "));
        ++replayed;
    }
    EXPECT_GE(replayed, 4);
}

}  // namespace
}  // namespace firelook::vdb
