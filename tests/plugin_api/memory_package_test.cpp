// fl_package_load_memory (firelook.h): a package held only in memory, copied or borrowed, plays
// bit for bit as the same package loaded from its file; its bytes get the file path's result codes
// with the caller's source name in fl_last_error(); a borrowed buffer must be 64-byte aligned, is
// read in place on demand, and is needed until the handle is released and every instance is gone.
#include "firelook/firelook.h"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "../support/temp_dir.h"
#include "package/container_reader.h"
#include "struct_rule.h"  // plugin_api/src
#include "synthetic_package.h"

namespace {

using firelook::testing::TempDir;

constexpr const char* kSource = "engine.pak:fx/explosion.firelook";

std::vector<char> readAll(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A 64-byte aligned copy of some bytes, as an engine would hand over for borrowing.
struct AlignedBuffer {
    explicit AlignedBuffer(const std::vector<char>& bytes)
        : data(static_cast<char*>(std::aligned_alloc(64, (bytes.size() + 63) / 64 * 64))), size(bytes.size()) {
        std::memcpy(data.get(), bytes.data(), bytes.size());
    }
    struct Free {
        void operator()(char* p) const { std::free(p); }
    };
    std::unique_ptr<char, Free> data;
    size_t size;
};

fl_package_memory_desc borrowDesc() {
    fl_package_memory_desc d = fl_package_memory_desc_defaults();
    d.flags = FL_PACKAGE_MEMORY_BORROW;
    return d;
}

std::string lastError() { return fl_last_error(); }

class MemoryPackage : public ::testing::Test {
  protected:
    void SetUp() override {
        fl_init_desc desc = fl_init_desc_defaults();
        ASSERT_EQ(fl_init(&desc), FL_OK) << fl_last_error();
        firelook::testing::SyntheticShape shape;
        shape.frames = {3, 4, 5};
        path_ = dir_ / "p.firelook";
        firelook::testing::writeSyntheticPackage(path_, shape);
        bytes_ = readAll(path_);
        ASSERT_GT(bytes_.size(), 64u);
    }
    void TearDown() override { EXPECT_EQ(fl_shutdown(), FL_OK); }

    // The code fl_package_load gives for a file holding `bytes` (the package, if any, released).
    fl_result fileResult(const std::vector<char>& bytes) {
        const auto file = dir_ / "same-bytes.firelook";
        std::ofstream(file, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        fl_package p{};
        const fl_result r = fl_package_load(file.c_str(), &p);
        if (r == FL_OK) fl_package_release(p);
        return r;
    }

    TempDir dir_;
    std::filesystem::path path_;
    std::vector<char> bytes_;
};

// An instance paused on `frame` with the image output and the package's default look.
fl_instance imageInstance(fl_world world, fl_package package, double frame) {
    fl_instance_desc d = fl_instance_desc_defaults();
    d.package = package;
    fl_instance inst{};
    EXPECT_EQ(fl_instance_create(world, &d, &inst), FL_OK) << fl_last_error();
    fl_outputs_desc out = fl_outputs_desc_defaults();
    out.image = 1;
    EXPECT_EQ(fl_instance_set_outputs(world, inst, &out), FL_OK) << fl_last_error();
    fl_playback_desc pb = fl_playback_desc_defaults();
    pb.paused = 1;
    pb.rate = 1.0;
    pb.time = frame - 3.0;  // the package starts at frame 3
    EXPECT_EQ(fl_instance_set_playback(world, inst, &pb), FL_OK) << fl_last_error();
    return inst;
}

std::vector<float> image(fl_world world, fl_instance inst) {
    std::vector<float> rgba(16 * 12 * 4, -1.0f);
    EXPECT_EQ(fl_instance_get_image(world, inst, rgba.data(), rgba.size()), FL_OK) << fl_last_error();
    return rgba;
}

// U and depths of every frame, as a shader would upload them.
std::vector<std::vector<unsigned char>> gpuData(fl_package p) {
    std::vector<std::vector<unsigned char>> out;
    for (int32_t frame : {3, 4, 5}) {
        size_t n = 0;
        EXPECT_EQ(fl_package_get_frame_u(p, frame, nullptr, 0, &n), FL_OK);
        std::vector<uint16_t> u(n);
        EXPECT_EQ(fl_package_get_frame_u(p, frame, u.data(), u.size(), &n), FL_OK) << fl_last_error();
        out.emplace_back(reinterpret_cast<const unsigned char*>(u.data()),
                         reinterpret_cast<const unsigned char*>(u.data() + u.size()));
        EXPECT_EQ(fl_package_get_frame_depths(p, frame, nullptr, 0, &n), FL_OK);
        std::vector<float> d(n);
        EXPECT_EQ(fl_package_get_frame_depths(p, frame, d.data(), d.size(), &n), FL_OK) << fl_last_error();
        out.emplace_back(reinterpret_cast<const unsigned char*>(d.data()),
                         reinterpret_cast<const unsigned char*>(d.data() + d.size()));
    }
    return out;
}

// The case: the package exists only in memory (its file deleted), loaded borrowed and
// copied; instances of both draw exactly the image of the same package loaded from its file, and
// the GPU data is the same bytes. The copy's source buffer is overwritten and freed right after the
// load; the borrowed buffer keeps serving its instance after the handle is released, and is freed
// only once that instance is destroyed (under ASan a later read of it would be reported).
TEST_F(MemoryPackage, APackageHeldOnlyInMemoryPlaysBitForBitAsItsFile) {
    fl_package from_file{};
    ASSERT_EQ(fl_package_load(path_.c_str(), &from_file), FL_OK) << fl_last_error();
    const auto want_gpu = gpuData(from_file);
    fl_world world{};
    ASSERT_EQ(fl_world_create(nullptr, &world), FL_OK);
    const fl_instance file_instance = imageInstance(world, from_file, 4.0);
    ASSERT_EQ(fl_world_update(world, 0.0), FL_OK) << fl_last_error();
    const std::vector<float> want = image(world, file_instance);
    ASSERT_EQ(fl_instance_destroy(world, file_instance), FL_OK);
    ASSERT_EQ(fl_package_release(from_file), FL_OK);

    std::filesystem::remove(path_);
    ASSERT_FALSE(std::filesystem::exists(path_));

    // Copied, from an odd address (a copy takes any alignment); desc null means copy.
    auto copy_source = std::make_unique<std::vector<char>>(bytes_.size() + 1);
    std::memcpy(copy_source->data() + 1, bytes_.data(), bytes_.size());
    fl_package copied{}, copied_null_desc{};
    const fl_package_memory_desc copy_desc = fl_package_memory_desc_defaults();
    ASSERT_EQ(fl_package_load_memory(copy_source->data() + 1, bytes_.size(), kSource, &copy_desc, &copied), FL_OK)
        << fl_last_error();
    ASSERT_EQ(fl_package_load_memory(copy_source->data() + 1, bytes_.size(), kSource, nullptr, &copied_null_desc),
              FL_OK)
        << fl_last_error();
    std::memset(copy_source->data(), 0xA5, copy_source->size());
    copy_source.reset();

    auto borrowed_bytes = std::make_unique<AlignedBuffer>(bytes_);
    fl_package borrowed{};
    const fl_package_memory_desc borrow = borrowDesc();
    ASSERT_EQ(fl_package_load_memory(borrowed_bytes->data.get(), borrowed_bytes->size, kSource, &borrow, &borrowed),
              FL_OK)
        << fl_last_error();

    for (const fl_package p : {copied, copied_null_desc, borrowed}) {
        fl_package_info info = fl_package_info_defaults();
        ASSERT_EQ(fl_package_get_info(p, &info), FL_OK);
        EXPECT_EQ(info.width, 16);
        EXPECT_EQ(info.frame_count, 3);
        EXPECT_EQ(gpuData(p), want_gpu);
    }
    const fl_instance copied_instance = imageInstance(world, copied, 4.0);
    const fl_instance borrowed_instance = imageInstance(world, borrowed, 4.0);
    // The handles die now; the instances keep the packages' data (and the borrowed buffer) in use.
    ASSERT_EQ(fl_package_release(copied), FL_OK);
    ASSERT_EQ(fl_package_release(copied_null_desc), FL_OK);
    ASSERT_EQ(fl_package_release(borrowed), FL_OK);
    ASSERT_EQ(fl_world_update(world, 0.0), FL_OK) << fl_last_error();
    const std::vector<float> from_copy = image(world, copied_instance);
    const std::vector<float> from_borrow = image(world, borrowed_instance);
    ASSERT_EQ(from_copy.size(), want.size());
    EXPECT_EQ(std::memcmp(from_copy.data(), want.data(), want.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(from_borrow.data(), want.data(), want.size() * sizeof(float)), 0);

    // Frames not shown yet are read from the borrowed bytes on demand: move both to frame 5.
    fl_playback_desc pb = fl_playback_desc_defaults();
    pb.paused = 1;
    pb.rate = 1.0;
    pb.time = 2.0;
    ASSERT_EQ(fl_instance_set_playback(world, borrowed_instance, &pb), FL_OK);
    ASSERT_EQ(fl_instance_set_playback(world, copied_instance, &pb), FL_OK);
    ASSERT_EQ(fl_world_update(world, 0.0), FL_OK) << fl_last_error();
    EXPECT_EQ(image(world, borrowed_instance), image(world, copied_instance));
    fl_instance_state st = fl_instance_state_defaults();
    ASSERT_EQ(fl_instance_get_state(world, borrowed_instance, &st), FL_OK);
    EXPECT_EQ(st.frame, 5);

    // With its handle released and its last instance destroyed, the borrowed buffer is the caller's again.
    ASSERT_EQ(fl_instance_destroy(world, borrowed_instance), FL_OK);
    borrowed_bytes.reset();
    ASSERT_EQ(fl_world_update(world, 0.0), FL_OK) << fl_last_error();
    EXPECT_EQ(fl_instance_destroy(world, copied_instance), FL_OK);
    EXPECT_EQ(fl_world_destroy(world), FL_OK);
}

// A borrowed package is read in place: a frame section changed after the load (what the header
// forbids) is found by that frame's checksum on its first read, and the message names the source.
// A copy is immune to the same change.
TEST_F(MemoryPackage, ABorrowedBufferIsReadInPlaceAndACopyIsNot) {
    const auto reader = firelook::package::ContainerReader::open(path_);
    const firelook::package::SectionInfo* u5 = reader.find(firelook::basis::kSectionU, 5);
    ASSERT_NE(u5, nullptr);
    ASSERT_GT(u5->stored_size, 0u);

    AlignedBuffer borrowed_bytes(bytes_);
    std::vector<char> copy_source = bytes_;
    fl_package borrowed{}, copied{};
    const fl_package_memory_desc borrow = borrowDesc();
    ASSERT_EQ(fl_package_load_memory(borrowed_bytes.data.get(), borrowed_bytes.size, kSource, &borrow, &borrowed),
              FL_OK);
    ASSERT_EQ(fl_package_load_memory(copy_source.data(), copy_source.size(), kSource, nullptr, &copied), FL_OK);
    borrowed_bytes.data.get()[u5->offset + u5->stored_size / 2] ^= 0x01;
    copy_source[u5->offset + u5->stored_size / 2] ^= 0x01;

    size_t n = 0;
    ASSERT_EQ(fl_package_get_frame_u(borrowed, 5, nullptr, 0, &n), FL_OK);
    std::vector<uint16_t> u(n);
    EXPECT_EQ(fl_package_get_frame_u(borrowed, 4, u.data(), u.size(), &n), FL_OK) << fl_last_error();
    EXPECT_EQ(fl_package_get_frame_u(borrowed, 5, u.data(), u.size(), &n), FL_ERROR_CORRUPT);
    EXPECT_NE(lastError().find(kSource), std::string::npos) << lastError();
    EXPECT_NE(lastError().find("checksum"), std::string::npos) << lastError();
    EXPECT_EQ(fl_package_get_frame_u(copied, 5, u.data(), u.size(), &n), FL_OK) << fl_last_error();
    EXPECT_EQ(fl_package_release(borrowed), FL_OK);
    EXPECT_EQ(fl_package_release(copied), FL_OK);
}

// Borrowing promises no second copy, so a buffer that cannot be used in place is refused, with a
// message that names the source and says what to do; nothing is loaded. A copy of it loads.
TEST_F(MemoryPackage, ABorrowedBufferThatIsNot64ByteAlignedIsRefused) {
    std::vector<char> storage(bytes_.size() + 128);
    char* aligned = storage.data() + (64 - reinterpret_cast<uintptr_t>(storage.data()) % 64) % 64;
    const fl_package_memory_desc borrow = borrowDesc();
    for (size_t misalignment : {1u, 8u, 16u, 32u, 63u}) {
        char* start = aligned + misalignment;
        std::memcpy(start, bytes_.data(), bytes_.size());
        fl_package p{99};
        EXPECT_EQ(fl_package_load_memory(start, bytes_.size(), kSource, &borrow, &p), FL_ERROR_INVALID_ARGUMENT)
            << misalignment;
        EXPECT_EQ(p.id, 0u);
        EXPECT_NE(lastError().find(kSource), std::string::npos) << lastError();
        EXPECT_NE(lastError().find("64-byte aligned"), std::string::npos) << lastError();
        ASSERT_EQ(fl_package_load_memory(start, bytes_.size(), kSource, nullptr, &p), FL_OK) << fl_last_error();
        EXPECT_EQ(fl_package_release(p), FL_OK);
    }
}

// The bytes get exactly the file path's checks: for each damaged buffer, borrowed and copied, the
// result of fl_package_load on a file of the same bytes, and the source name in the message.
TEST_F(MemoryPackage, BadBytesGiveTheFilesResultAndNameTheSource) {
    std::vector<char> garbage = bytes_;  // a package's identifier, then garbage
    std::mt19937 random(7);
    for (size_t i = 16; i < garbage.size(); ++i) garbage[i] = static_cast<char>(random() & 0xFF);
    std::vector<char> noise(1000);  // not even the identifier
    for (char& c : noise) c = static_cast<char>(random() & 0xFF);
    noise[0] = 'x';
    const std::vector<char> half(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(bytes_.size() / 2));
    const std::vector<char> header_only(bytes_.begin(), bytes_.begin() + 64);
    std::vector<char> flipped_index = bytes_;
    flipped_index[bytes_.size() - 10] ^= 0x01;
    const struct {
        const char* what;
        const std::vector<char>& bytes;
        fl_result expected;
    } cases[] = {{"identifier then garbage", garbage, FL_ERROR_CORRUPT},
                 {"random bytes", noise, FL_ERROR_NOT_A_PACKAGE},
                 {"first half", half, FL_ERROR_CORRUPT},
                 {"header only", header_only, FL_ERROR_CORRUPT},
                 {"a flipped index byte", flipped_index, FL_ERROR_CORRUPT}};
    for (const auto& c : cases) {
        SCOPED_TRACE(c.what);
        EXPECT_EQ(fileResult(c.bytes), c.expected);
        const AlignedBuffer held(c.bytes);
        const fl_package_memory_desc borrow = borrowDesc();
        for (const fl_package_memory_desc* desc : {static_cast<const fl_package_memory_desc*>(nullptr), &borrow}) {
            fl_package p{99};
            EXPECT_EQ(fl_package_load_memory(held.data.get(), held.size, kSource, desc, &p), c.expected) << lastError();
            EXPECT_EQ(p.id, 0u);
            EXPECT_NE(lastError().find(kSource), std::string::npos) << lastError();
            EXPECT_EQ(lastError().rfind("fl_package_load_memory: ", 0), 0u) << lastError();
        }
    }
    // No source name: the messages still say where the bytes came from.
    const AlignedBuffer held(garbage);
    fl_package p{};
    EXPECT_EQ(fl_package_load_memory(held.data.get(), held.size, nullptr, nullptr, &p), FL_ERROR_CORRUPT);
    EXPECT_NE(lastError().find("(memory)"), std::string::npos) << lastError();
}

TEST_F(MemoryPackage, MisuseIsAnInvalidArgumentOrAStructSize) {
    fl_package p{99};
    EXPECT_EQ(fl_package_load_memory(nullptr, bytes_.size(), kSource, nullptr, &p), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find(kSource), std::string::npos) << lastError();
    EXPECT_NE(lastError().find("data is null"), std::string::npos) << lastError();
    EXPECT_EQ(fl_package_load_memory(bytes_.data(), 0, kSource, nullptr, &p), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("size is 0"), std::string::npos) << lastError();
    const fl_package_memory_desc borrow = borrowDesc();
    EXPECT_EQ(fl_package_load_memory(nullptr, 0, kSource, &borrow, &p), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_package_load_memory(bytes_.data(), bytes_.size(), kSource, nullptr, nullptr),
              FL_ERROR_INVALID_ARGUMENT);

    fl_package_memory_desc desc = fl_package_memory_desc_defaults();
    desc.struct_size = 4;  // below the first published size
    EXPECT_EQ(fl_package_load_memory(bytes_.data(), bytes_.size(), kSource, &desc, &p), FL_ERROR_STRUCT_SIZE);
    desc = fl_package_memory_desc_defaults();
    desc.flags = 2;  // a bit this library does not know: refused, not ignored
    EXPECT_EQ(fl_package_load_memory(bytes_.data(), bytes_.size(), kSource, &desc, &p), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(lastError().find("flags"), std::string::npos) << lastError();
    EXPECT_EQ(p.id, 0u);

    // A newer caller's larger desc (extra fields zeroed) is accepted.
    struct NewerDesc {
        fl_package_memory_desc base;
        uint64_t added[2];
    } newer{};
    newer.base = fl_package_memory_desc_defaults();
    newer.base.struct_size = sizeof newer;
    ASSERT_EQ(fl_package_load_memory(bytes_.data(), bytes_.size(), kSource, &newer.base, &p), FL_OK)
        << fl_last_error();
    EXPECT_EQ(fl_package_release(p), FL_OK);

    ASSERT_EQ(fl_shutdown(), FL_OK);
    EXPECT_EQ(fl_package_load_memory(bytes_.data(), bytes_.size(), kSource, nullptr, &p), FL_ERROR_NOT_INITIALIZED);
    fl_init_desc init = fl_init_desc_defaults();
    ASSERT_EQ(fl_init(&init), FL_OK);
}

// fl_shutdown releases a borrowed package with everything else; the buffer is free afterwards.
TEST_F(MemoryPackage, ShutdownReleasesABorrowedPackageAndItsInstances) {
    auto held = std::make_unique<AlignedBuffer>(bytes_);
    const fl_package_memory_desc borrow = borrowDesc();
    fl_package p{};
    ASSERT_EQ(fl_package_load_memory(held->data.get(), held->size, kSource, &borrow, &p), FL_OK);
    fl_world world{};
    ASSERT_EQ(fl_world_create(nullptr, &world), FL_OK);
    imageInstance(world, p, 3.0);
    ASSERT_EQ(fl_world_update(world, 0.0), FL_OK);
    ASSERT_EQ(fl_shutdown(), FL_OK);
    held.reset();
    fl_init_desc init = fl_init_desc_defaults();
    ASSERT_EQ(fl_init(&init), FL_OK);
}

TEST(PluginApiMemory, TheDescFollowsTheStructRuleAndTheFunctionIsExported) {
    EXPECT_EQ(firelook::plugin::FirstSize<fl_package_memory_desc>::value, sizeof(fl_package_memory_desc));
    const fl_package_memory_desc d = fl_package_memory_desc_defaults();
    EXPECT_EQ(d.struct_size, sizeof(fl_package_memory_desc));
    EXPECT_EQ(d.flags, 0u);  // the default: copy
    void* lib = dlopen(FIRELOOK_PLUGIN_PATH, RTLD_NOW | RTLD_LOCAL);
    ASSERT_NE(lib, nullptr) << dlerror();
    EXPECT_NE(dlsym(lib, "fl_package_load_memory"), nullptr);
    dlclose(lib);
}

}  // namespace
