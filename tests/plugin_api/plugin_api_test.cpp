// The C plugin API (plugin_api/include/firelook/firelook.h) through the shared library: version and
// struct-size checks, the struct rule for older and newer callers, stale/invalid/wrong-kind/
// wrong-world handles, error codes and messages, images equal to the runtime's renderLookImage
// (tolerance: 1e-5 of the peak radiance + 1e-5 relative, as in tests/world), the GPU layouts, host
// allocator and log callbacks, dlopen, and the plain-C translation unit. Worlds on two threads:
// plugin_api_threads_test.cpp.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <glm/gtc/packing.hpp>
#include <map>
#include <memory_resource>
#include <mutex>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "../support/temp_dir.h"
#include "basis/look_renderer.h"
#include "common/error.h"
#include "firelook/firelook.h"
#include "fit/look_fit.h"
#include "result_table.h"  // plugin_api/src: the error table and the struct rule, tested directly
#include "struct_rule.h"
#include "synthetic_package.h"

extern "C" int firelook_c_smoke(const char* package_path);

namespace {

using firelook::testing::TempDir;

std::atomic<long> g_allocs{0}, g_frees{0}, g_logs{0};
std::mutex g_sizes_mutex;
std::vector<size_t> g_alloc_sizes;  // every size asked of countingAlloc, in order
void* countingAlloc(size_t size, void*) {
    ++g_allocs;
    {
        const std::lock_guard<std::mutex> lock(g_sizes_mutex);
        g_alloc_sizes.push_back(size);
    }
    return std::aligned_alloc(16, (size + 15) / 16 * 16);
}
// The number of countingAlloc calls so far, and the largest size asked since call `first`.
size_t allocationCount() {
    const std::lock_guard<std::mutex> lock(g_sizes_mutex);
    return g_alloc_sizes.size();
}
size_t largestAllocationSince(size_t first) {
    const std::lock_guard<std::mutex> lock(g_sizes_mutex);
    size_t largest = 0;
    for (size_t i = first; i < g_alloc_sizes.size(); ++i) largest = std::max(largest, g_alloc_sizes[i]);
    return largest;
}
void countingFree(void* p, void*) {
    if (p) ++g_frees;
    std::free(p);
}
std::string g_last_log;
void logger(int32_t level, const char* message, void*) {
    ++g_logs;
    if (level >= FL_LOG_ERROR) g_last_log = message;
}

class PluginApi : public ::testing::Test {
  protected:
    void SetUp() override {
        fl_init_desc desc = fl_init_desc_defaults();
        desc.allocator = {countingAlloc, countingFree, nullptr};
        desc.log = logger;
        ASSERT_EQ(fl_init(&desc), FL_OK) << fl_last_error();
        firelook::testing::SyntheticShape shape;
        shape.frames = {3, 4, 5};
        path_ = (dir_ / "p.firelook").string();
        firelook::testing::writeSyntheticPackage(path_, shape);
    }
    void TearDown() override { EXPECT_EQ(fl_shutdown(), FL_OK); }

    fl_package load() {
        fl_package p{};
        EXPECT_EQ(fl_package_load(path_.c_str(), &p), FL_OK) << fl_last_error();
        return p;
    }

    TempDir dir_;
    std::string path_;
};

// The desc of an instance of `package` with `look` (0: the package's default look).
fl_instance_desc instanceDesc(fl_package package, fl_look look = {}) {
    fl_instance_desc d = fl_instance_desc_defaults();
    d.package = package;
    d.look = look;
    return d;
}

// An instance of `package` in `world`, expected to be created.
fl_instance createInstance(fl_world world, fl_package package) {
    const fl_instance_desc d = instanceDesc(package);
    fl_instance i{};
    EXPECT_EQ(fl_instance_create(world, &d, &i), FL_OK) << fl_last_error();
    return i;
}

// Paused on frame 4 of the synthetic package (frames 3, 4, 5): time 1 s at rate 1.
fl_playback_desc pausedOnFrame4() {
    fl_playback_desc pb = fl_playback_desc_defaults();
    pb.paused = 1;
    pb.rate = 1.0;
    pb.time = 1.0;
    return pb;
}

fl_outputs_desc imageOutputs() {
    fl_outputs_desc out = fl_outputs_desc_defaults();
    out.image = 1;
    return out;
}

// PluginApi with the synthetic package loaded and an empty world: what most tests start from. A
// test that destroys the world or releases the package itself does it through destroyWorld() /
// releasePackage(), which expect FL_OK and keep the (then stale) handles; TearDown gives back
// whatever is left, expecting FL_OK as well.
class PluginApiWorld : public PluginApi {
  protected:
    void SetUp() override {
        PluginApi::SetUp();
        if (HasFatalFailure()) return;
        package_ = load();
        package_live_ = package_.id != 0;
        allocs_before_world_ = g_allocs;
        frees_before_world_ = g_frees;
        sizes_before_world_ = allocationCount();
        ASSERT_EQ(fl_world_create(nullptr, &world_), FL_OK) << fl_last_error();
        world_live_ = true;
    }
    void TearDown() override {
        if (world_live_) {
            EXPECT_EQ(fl_world_destroy(world_), FL_OK);
        }
        if (package_live_) {
            EXPECT_EQ(fl_package_release(package_), FL_OK);
        }
        PluginApi::TearDown();
    }

    void destroyWorld() {
        world_live_ = false;
        EXPECT_EQ(fl_world_destroy(world_), FL_OK);
    }
    void releasePackage() {
        package_live_ = false;
        EXPECT_EQ(fl_package_release(package_), FL_OK);
    }
    // The allocator promise of firelook.h: destroying the world gives back every host allocation
    // made since just before it was created.
    void destroyWorldExpectingEveryAllocationBack() {
        destroyWorld();
        EXPECT_EQ(g_frees - frees_before_world_, g_allocs - allocs_before_world_);
    }

    fl_package package_{};
    fl_world world_{};
    long allocs_before_world_ = 0, frees_before_world_ = 0;
    size_t sizes_before_world_ = 0;  // allocationCount() then

  private:
    bool package_live_ = false, world_live_ = false;
};

const char* kLookJson = R"({
  "format": "firelook-look", "version": 1,
  "temperature_threshold": 1.45, "smoke_extinction": 5.0, "flame_extinction": 1.2, "albedo": 0.7,
  "emission": { "stops": [[1.3, 0,0,0], [1.7, 2.0,0.6,0.08], [2.3, 8.0,4.0,0.9], [3.0, 14.0,11.0,6.0]] },
  "light_irradiance": [[2.5, 2.4, 2.25]]
})";

TEST(PluginApiInit, VersionAndStructSizesAreChecked) {
    EXPECT_EQ(fl_version(), static_cast<uint32_t>(FIRELOOK_HEADER_VERSION));
    fl_package p{};
    EXPECT_EQ(fl_package_load("x", &p), FL_ERROR_NOT_INITIALIZED);
    EXPECT_EQ(fl_init(nullptr), FL_ERROR_INVALID_ARGUMENT);
    fl_init_desc desc = fl_init_desc_defaults();
    desc.header_version = FIRELOOK_HEADER_VERSION + 10000;  // another major
    EXPECT_EQ(fl_init(&desc), FL_ERROR_VERSION_MISMATCH);
    EXPECT_NE(std::string(fl_last_error()).find("header version"), std::string::npos);
    desc = fl_init_desc_defaults();
    desc.header_version = FIRELOOK_HEADER_VERSION + 100;  // a newer minor
    EXPECT_EQ(fl_init(&desc), FL_ERROR_VERSION_MISMATCH);
    desc = fl_init_desc_defaults();
    desc.sizeof_outputs_desc -= 4;
    EXPECT_EQ(fl_init(&desc), FL_ERROR_VERSION_MISMATCH);
    EXPECT_NE(std::string(fl_last_error()).find("fl_outputs_desc"), std::string::npos);
    // The desc's own struct_size follows the struct rule, also where it is too small to hold the
    // header version (issue 28: 0 and 4 read as version 0 and were refused as a version mismatch).
    for (const uint32_t size : {0u, 4u, 12u}) {
        desc = fl_init_desc_defaults();
        desc.struct_size = size;
        EXPECT_EQ(fl_init(&desc), FL_ERROR_STRUCT_SIZE) << "struct_size " << size;
        EXPECT_NE(std::string(fl_last_error()).find("struct_size"), std::string::npos) << fl_last_error();
    }
    desc = fl_init_desc_defaults();
    desc.allocator.alloc = countingAlloc;  // free missing
    EXPECT_EQ(fl_init(&desc), FL_ERROR_INVALID_ARGUMENT);
    desc = fl_init_desc_defaults();
    ASSERT_EQ(fl_init(&desc), FL_OK);
    EXPECT_EQ(fl_init(&desc), FL_ERROR_ALREADY_INITIALIZED);
    EXPECT_EQ(fl_shutdown(), FL_OK);
    EXPECT_EQ(fl_shutdown(), FL_ERROR_NOT_INITIALIZED);
}

TEST(PluginApiInit, ResultStrings) {
    for (fl_result r = FL_ERROR_CANCELLED; r <= FL_OK; ++r) EXPECT_STRNE(fl_result_string(r), "FL_ERROR_UNKNOWN") << r;
    EXPECT_STREQ(fl_result_string(12345), "FL_ERROR_UNKNOWN");
    EXPECT_STREQ(fl_result_string(FL_ERROR_INVALID_HANDLE), "FL_ERROR_INVALID_HANDLE");
}

// Every result in FIRELOOK_RESULTS is named after itself, values are distinct, and unknown values
// (between, above and below the list) read FL_ERROR_UNKNOWN.
TEST(PluginApiInit, EveryResultInTheListHasItsOwnName) {
    struct Entry {
        fl_result value;
        const char* name;
    };
#define ENTRY(name, value) {name, #name},
    const Entry entries[] = {FIRELOOK_RESULTS(ENTRY)};
#undef ENTRY
    std::set<fl_result> values;
    for (const Entry& e : entries) {
        EXPECT_STREQ(fl_result_string(e.value), e.name);
        EXPECT_TRUE(values.insert(e.value).second) << e.name << " repeats a value";
    }
    EXPECT_EQ(values.size(), 19u);
    for (fl_result unknown : {-19, 1, INT32_MIN, INT32_MAX, -1000})
        EXPECT_STREQ(fl_result_string(unknown), "FL_ERROR_UNKNOWN") << unknown;
}

// The one table (result_table.h) from the coded errors to fl_result: every code of the list maps to
// a named error (never FL_OK); each code has a result of its own except the many-to-one rows that
// result_table.h documents; and every FL_ERROR_* of the header is reached, so the plugin needs no
// second way to produce one.
TEST(PluginApiInit, EveryErrorCodeMapsToADocumentedResult) {
    using firelook::ErrorCode;
    using firelook::plugin::toResult;
    std::map<fl_result, std::vector<std::string>> by_result;
    int count = 0;
#define CHECK_CODE(name, value, text)                                                \
    {                                                                                \
        const fl_result r = toResult(ErrorCode::name);                               \
        EXPECT_LT(r, FL_OK) << #name;                                                \
        EXPECT_STRNE(fl_result_string(r), "FL_ERROR_UNKNOWN") << #name;              \
        EXPECT_STRNE(firelook::toString(ErrorCode::name), "unknown error") << #name; \
        by_result[r].push_back(#name);                                               \
        ++count;                                                                     \
    }
    FIRELOOK_ERROR_CODES(CHECK_CODE)
#undef CHECK_CODE
    EXPECT_EQ(count, 25);
    const std::map<fl_result, std::vector<std::string>> shared = {
        {FL_ERROR_CORRUPT, {"Truncated", "Corrupt"}},
        {FL_ERROR_UNSUPPORTED, {"NewerMajorVersion", "UnsupportedFeature"}},
        {FL_ERROR_INTERNAL,
         {"InvalidState", "CompressionFailed", "BadVolume", "BadImage", "BadScene", "Internal"}},
    };
    for (const auto& [result, names] : by_result) {
        const auto documented = shared.find(result);
        if (documented == shared.end())
            EXPECT_EQ(names.size(), 1u) << fl_result_string(result) << " is reached by more than one code";
        else
            EXPECT_EQ(names, documented->second) << fl_result_string(result);
    }
#define CHECK_REACHED(name, value)                                               \
    if ((value) != FL_OK) {                                                      \
        EXPECT_TRUE(by_result.contains(name)) << #name " is reached by no code"; \
    }
    FIRELOOK_RESULTS(CHECK_REACHED)
#undef CHECK_REACHED
    EXPECT_EQ(toResult(ErrorCode::Look), FL_ERROR_LOOK);
    EXPECT_EQ(toResult(ErrorCode::InvalidArgument), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(toResult(static_cast<ErrorCode>(999)), FL_ERROR_INTERNAL);
}

// fl_init's version rule as the header writes it: same major, a minor no newer, any patch; 0 (unset)
// and a newer minor are refused. Struct sizes above the first published ones (a newer caller) are
// accepted.
TEST(PluginApiInit, OlderMinorNewerPatchAndLargerStructSizesAreAccepted) {
    const uint32_t accepted[] = {FIRELOOK_HEADER_VERSION, FIRELOOK_HEADER_VERSION + 1,
                                 FIRELOOK_VERSION_MAJOR * 10000u + 1u /* minor 0: older than ours (1) */};
    static_assert(FIRELOOK_VERSION_MINOR >= 1, "the older-minor case needs a minor above 0");
    for (uint32_t version : accepted) {
        fl_init_desc desc = fl_init_desc_defaults();
        desc.header_version = version;
        ASSERT_EQ(fl_init(&desc), FL_OK) << version << ": " << fl_last_error();
        EXPECT_EQ(fl_shutdown(), FL_OK);
    }
    fl_init_desc desc = fl_init_desc_defaults();
    desc.header_version = 0;
    EXPECT_EQ(fl_init(&desc), FL_ERROR_VERSION_MISMATCH);
    desc = fl_init_desc_defaults();
    // Too small to hold header_version: refused by the struct rule (FL_ERROR_STRUCT_SIZE, as the header's
    // struct rule says; this returned FL_ERROR_VERSION_MISMATCH until issue 28), never read past.
    desc.struct_size = 4;
    EXPECT_EQ(fl_init(&desc), FL_ERROR_STRUCT_SIZE);

    // A newer caller: every struct larger, fl_init_desc itself with extra zeroed fields.
    struct NewerInitDesc {
        fl_init_desc base;
        uint64_t added[4];
    } newer{};
    newer.base = fl_init_desc_defaults();
    newer.base.struct_size = sizeof newer;
    newer.base.sizeof_world_desc += 16;
    newer.base.sizeof_instance_desc += 16;
    newer.base.sizeof_playback_desc += 16;
    newer.base.sizeof_outputs_desc += 16;
    newer.base.sizeof_package_info += 16;
    newer.base.sizeof_instance_state += 16;
    newer.base.sizeof_keyframe += 16;
    ASSERT_EQ(fl_init(&newer.base), FL_OK) << fl_last_error();
    EXPECT_EQ(fl_shutdown(), FL_OK);
}

// An instance of `package` drawing its CPU image, paused on frame 4; look 0 is the package's default.
void createPausedImageInstance(fl_world world, fl_package package, fl_look look, fl_instance* inst) {
    const fl_instance_desc idesc = instanceDesc(package, look);
    ASSERT_EQ(fl_instance_create(world, &idesc, inst), FL_OK) << fl_last_error();
    const fl_outputs_desc out = imageOutputs();
    ASSERT_EQ(fl_instance_set_outputs(world, *inst, &out), FL_OK);
    const fl_playback_desc pb = pausedOnFrame4();
    ASSERT_EQ(fl_instance_set_playback(world, *inst, &pb), FL_OK);
}

TEST_F(PluginApi, PackageInfoFramesAndDefaultLook) {
    const fl_package p = load();
    fl_package_info info = fl_package_info_defaults();
    ASSERT_EQ(fl_package_get_info(p, &info), FL_OK);
    EXPECT_EQ(info.width, 16);
    EXPECT_EQ(info.height, 12);
    EXPECT_EQ(info.frame_count, 3);
    EXPECT_EQ(info.first_frame, 3);
    EXPECT_EQ(info.last_frame, 5);
    EXPECT_EQ(info.max_rank, 8);
    EXPECT_EQ(info.bin_count, 16);
    EXPECT_EQ(info.light_count, 1);
    EXPECT_EQ(info.alpha_threshold_count, 5);
    EXPECT_DOUBLE_EQ(info.albedo, 0.7);
    EXPECT_DOUBLE_EQ(info.smoke_extinction_min, 2.0);
    EXPECT_DOUBLE_EQ(info.smoke_extinction_max, 16.0);
    uint32_t count = 0;
    int32_t numbers[3], ranks[3];
    ASSERT_EQ(fl_package_get_frames(p, numbers, ranks, 3, &count), FL_OK);
    EXPECT_EQ(count, 3u);
    EXPECT_EQ(numbers[2], 5);
    EXPECT_EQ(ranks[0], 8);
    EXPECT_EQ(ranks[1], 7);
    EXPECT_EQ(fl_package_get_frames(p, numbers, ranks, 2, &count), FL_ERROR_BUFFER_TOO_SMALL);
    size_t size = 0;
    ASSERT_EQ(fl_package_get_default_look_json(p, nullptr, 0, &size), FL_OK);
    ASSERT_GT(size, 10u);
    std::string text(size, '\0');
    EXPECT_EQ(fl_package_get_default_look_json(p, text.data(), size - 1, &size), FL_ERROR_BUFFER_TOO_SMALL);
    ASSERT_EQ(fl_package_get_default_look_json(p, text.data(), size, &size), FL_OK);
    EXPECT_NE(text.find("firelook-look"), std::string::npos);
    fl_look look{};
    EXPECT_EQ(fl_look_from_json(text.c_str(), 0, "default", &look), FL_OK) << fl_last_error();
    EXPECT_EQ(fl_look_release(look), FL_OK);
}

// The allocator promise of firelook.h (fl_allocator): a world's large buffers (images, flare images,
// coefficients, decoded factor copies) come from the host allocator, and nothing is left for the
// caller to free, so destroying the world gives every one of them back. Measured: fl_instance_create
// takes 4 (96, 192, 12 and 96 bytes: the per-instance coefficients, 16 bin weights, light, scratch),
// fl_instance_set_outputs 1 (the 16 x 12 x 4-float image, 3072 bytes), fl_world_update none here
// (see DecodedFactorsComeFromTheHostAllocator for the decoded U it should take), and
// fl_world_destroy frees all 5.
TEST_F(PluginApiWorld, ImageEqualsRenderLookImageAndGpuDataReproducesIt) {
    fl_look look{};
    ASSERT_EQ(fl_look_from_json(kLookJson, 0, "test look", &look), FL_OK) << fl_last_error();
    fl_instance inst{};
    ASSERT_NO_FATAL_FAILURE(createPausedImageInstance(world_, package_, look, &inst));
    std::vector<float> image(16 * 12 * 4);
    EXPECT_EQ(fl_instance_get_image(world_, inst, image.data(), image.size()), FL_ERROR_NO_DATA);
    ASSERT_EQ(fl_world_update(world_, 0.0), FL_OK);
    EXPECT_GT(g_allocs.load(), 0);
    // The world's buffers came from the host allocator, the image (3072 bytes) among them.
    EXPECT_GE(g_allocs - allocs_before_world_, 2);
    EXPECT_GE(largestAllocationSince(sizes_before_world_), 16u * 12u * 4u * sizeof(float));
    // What the world reports holding: one resident frame (more than its W codes, 16x12 x 8 int16)
    // and at least the instance's image.
    uint64_t cache_bytes = 0, instance_bytes = 0;
    ASSERT_EQ(fl_world_memory(world_, &cache_bytes, &instance_bytes), FL_OK);
    EXPECT_GT(cache_bytes, 16u * 12u * 8u * sizeof(int16_t));
    EXPECT_GE(instance_bytes, 16u * 12u * 4u * sizeof(float));
    EXPECT_EQ(fl_world_memory(world_, nullptr, nullptr), FL_OK);
    EXPECT_EQ(fl_world_memory(fl_world{}, &cache_bytes, nullptr), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_get_image(world_, inst, image.data(), image.size() - 1), FL_ERROR_BUFFER_TOO_SMALL);
    ASSERT_EQ(fl_instance_get_image(world_, inst, image.data(), image.size()), FL_OK);
    fl_package_info info = fl_package_info_defaults();
    ASSERT_EQ(fl_package_get_info(package_, &info), FL_OK);
    ASSERT_GE(info.footprint_samples, 1);

    // Reference: the runtime's renderLookImage of the same package, frame and look (the resident
    // form, as the world draws it).
    const auto package = firelook::basis::BasisReader::open(path_);
    const auto& d = package.description();
    const firelook::basis::ResidentFrame f = package.loadResidentFrame(4, std::pmr::get_default_resource());
    std::vector<float> want(image.size());
    firelook::basis::renderLookImage(d, f, firelook::parseLook(kLookJson, "x"), want);
    double peak = 0.0;
    for (size_t i = 0; i < want.size(); ++i)
        if (i % 4 != 3) peak = std::max(peak, static_cast<double>(want[i]));
    for (size_t i = 0; i < want.size(); ++i)
        ASSERT_NEAR(image[i], want[i], 1e-5 * peak + 1e-5 * std::abs(want[i])) << i;

    // GPU path: U layers + depth layers + z + state reproduce the image.
    fl_instance_state st = fl_instance_state_defaults();
    ASSERT_EQ(fl_instance_get_state(world_, inst, &st), FL_OK);
    EXPECT_EQ(st.frame, 4);
    EXPECT_EQ(st.rank, 7);
    std::vector<float> z(st.rank * 3);
    int32_t rank = 0;
    ASSERT_EQ(fl_instance_get_coefficients(world_, inst, z.data(), z.size(), &rank), FL_OK);
    size_t n_u = 0, n_d = 0;
    ASSERT_EQ(fl_package_get_frame_u(package_, 4, nullptr, 0, &n_u), FL_OK);
    EXPECT_EQ(n_u, size_t(2) * 16 * 12 * 4);  // ceil(7 / 4) = 2 layers
    std::vector<uint16_t> u(n_u);
    ASSERT_EQ(fl_package_get_frame_u(package_, 4, u.data(), u.size(), &n_u), FL_OK);
    ASSERT_EQ(fl_package_get_frame_depths(package_, 4, nullptr, 0, &n_d), FL_OK);
    std::vector<float> depths(n_d);
    ASSERT_EQ(fl_package_get_frame_depths(package_, 4, depths.data(), depths.size(), &n_d), FL_OK);
    const size_t pixels = 16 * 12;
    for (size_t px = 0; px < pixels; ++px) {
        float rgb[3] = {0, 0, 0}, magnitude[3] = {0, 0, 0};
        for (int k = 0; k < rank; ++k) {
            const float uk = glm::unpackHalf1x16(u[((k / 4) * pixels + px) * 4 + k % 4]);
            for (int c = 0; c < 3; ++c) {
                rgb[c] += uk * z[k * 3 + c];
                magnitude[c] += std::abs(uk * z[k * 3 + c]);
            }
        }
        // The GPU's U is half (relative 2^-11 per value); the world's image uses the codec's grid
        // values, so a channel may differ by 2^-11 sum_k |U_k z_k|, plus float rounding.
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(std::max(rgb[c], 0.0f), image[px * 4 + c],
                        std::ldexp(magnitude[c], -11) + 1e-5 * peak + 1e-5 * std::abs(image[px * 4 + c]));
        // alpha = mean over the footprint samples s of 1 - exp(-(a O_a(s) + b O_b(s))).
        const size_t samples = static_cast<size_t>(info.footprint_samples), thresholds = 5;
        float alpha = 0.0f;
        for (size_t s = 0; s < samples; ++s) {
            const float* oa = depths.data() + samples * pixels + s * thresholds * pixels;
            const float o_a = (1 - st.alpha_layer_t) * oa[st.alpha_layer_lower * pixels + px] +
                              st.alpha_layer_t * oa[st.alpha_layer_upper * pixels + px];
            alpha += 1.0f - std::exp(-(st.extinction_a * o_a + st.extinction_b * depths[s * pixels + px]));
        }
        ASSERT_NEAR(alpha / samples, image[px * 4 + 3], 1e-5f);
    }
    // The padding channel of the last layer is 0 (rank 7 -> channel 3 of layer 1).
    EXPECT_EQ(u[(1 * pixels + 0) * 4 + 3], 0);
    EXPECT_EQ(fl_package_get_frame_u(package_, 99, u.data(), u.size(), &n_u), FL_ERROR_NOT_FOUND);
    destroyWorldExpectingEveryAllocationBack();
    EXPECT_EQ(fl_look_release(look), FL_OK);
}

// The world's float copy of a frame's U (decoded from the package's halfs for the CPU image) is one
// of the "decoded factor copies" that fl_allocator says come from the host allocator; for frame 4
// (rank 7: 2 layers x 4 channels x 16 x 12 pixels) it is 1536 floats, 6144 bytes, made in the first
// fl_world_update that shows the frame. Measured: that update made no host allocation at all.
// The header's size rule (firelook.h, "Memory"): a call with capacity 0 only asks for the size,
// whatever the buffer pointer; it writes nothing and succeeds (issue 28: a non-null buffer with
// capacity 0 used to be refused as too small).
TEST_F(PluginApiWorld, CapacityZeroIsASizeQueryWithAnyBuffer) {
    fl_look look{};
    ASSERT_EQ(fl_look_from_json(kLookJson, 0, "test look", &look), FL_OK) << fl_last_error();
    fl_instance inst{};
    ASSERT_NO_FATAL_FAILURE(createPausedImageInstance(world_, package_, look, &inst));
    ASSERT_EQ(fl_world_update(world_, 0.0), FL_OK);
    constexpr uint16_t kUntouched16 = 0xBEEF;
    constexpr float kUntouched = -12345.0f;
    uint16_t u_scratch[4] = {kUntouched16, kUntouched16, kUntouched16, kUntouched16};
    float f_scratch[4] = {kUntouched, kUntouched, kUntouched, kUntouched};
    int32_t i_scratch[2] = {-7, -7};
    double d_scratch[3] = {-7.0, -7.0, -7.0};
    char c_scratch[2] = {'x', 'x'};
    size_t n = 0;
    uint32_t count = 0;
    int32_t rank = 0;
    ASSERT_EQ(fl_package_get_frame_u(package_, 4, u_scratch, 0, &n), FL_OK) << fl_last_error();
    EXPECT_EQ(n, size_t(2) * 16 * 12 * 4);
    ASSERT_EQ(fl_package_get_frame_depths(package_, 4, f_scratch, 0, &n), FL_OK) << fl_last_error();
    EXPECT_GT(n, 0u);
    ASSERT_EQ(fl_package_get_frames(package_, i_scratch, i_scratch, 0, &count), FL_OK) << fl_last_error();
    EXPECT_EQ(count, 3u);
    ASSERT_EQ(fl_package_get_lights(package_, d_scratch, f_scratch, 0, &count), FL_OK) << fl_last_error();
    EXPECT_EQ(count, 1u);
    ASSERT_EQ(fl_package_get_default_look_json(package_, c_scratch, 0, &n), FL_OK) << fl_last_error();
    EXPECT_GT(n, 10u);
    ASSERT_EQ(fl_instance_get_coefficients(world_, inst, f_scratch, 0, &rank), FL_OK) << fl_last_error();
    EXPECT_EQ(rank, 7);
    ASSERT_EQ(fl_instance_get_frame_u(world_, inst, u_scratch, 0, &n), FL_OK) << fl_last_error();
    EXPECT_GT(n, 0u);
    ASSERT_EQ(fl_instance_get_frame_depths(world_, inst, f_scratch, 0, &n), FL_OK) << fl_last_error();
    EXPECT_GT(n, 0u);
    for (uint16_t v : u_scratch) EXPECT_EQ(v, kUntouched16) << "a size query writes nothing";
    for (float v : f_scratch) EXPECT_EQ(v, kUntouched) << "a size query writes nothing";
    for (int32_t v : i_scratch) EXPECT_EQ(v, -7);
    for (double v : d_scratch) EXPECT_EQ(v, -7.0);
    EXPECT_EQ(c_scratch[0], 'x');
    // A capacity that is not 0 and too small is still refused.
    EXPECT_EQ(fl_package_get_frame_u(package_, 4, u_scratch, 4, &n), FL_ERROR_BUFFER_TOO_SMALL);
    EXPECT_EQ(fl_look_release(look), FL_OK);
}

TEST_F(PluginApiWorld, DecodedFactorsComeFromTheHostAllocator) {
    fl_instance inst{};
    ASSERT_NO_FATAL_FAILURE(createPausedImageInstance(world_, package_, fl_look{}, &inst));
    const size_t before_update = allocationCount();
    ASSERT_EQ(fl_world_update(world_, 0.0), FL_OK);
    // The decoded U is pixels x rank floats (fl_package_get_frame_u's texture layout pads the rank
    // to a multiple of 4, so it is not the size to expect).
    fl_package_info info{};
    info.struct_size = sizeof info;
    ASSERT_EQ(fl_package_get_info(package_, &info), FL_OK);
    int32_t numbers[16] = {}, ranks[16] = {};
    uint32_t frames = 0;
    ASSERT_EQ(fl_package_get_frames(package_, numbers, ranks, 16, &frames), FL_OK);
    int32_t rank = 0;
    for (uint32_t f = 0; f < frames && f < 16; ++f)
        if (numbers[f] == 4) rank = ranks[f];
    ASSERT_GT(rank, 0);
    const size_t n_u = static_cast<size_t>(info.width) * info.height * rank;
    EXPECT_GE(largestAllocationSince(before_update), n_u * sizeof(float))
        << "the decoded U of frame 4 (" << n_u << " floats) did not come from the host allocator";
    destroyWorldExpectingEveryAllocationBack();
}

TEST_F(PluginApiWorld, StaleAndInvalidHandlesAndWrongStructSizesNeverCrash) {
    fl_instance_desc idesc = instanceDesc(package_);
    fl_instance inst{};
    ASSERT_EQ(fl_instance_create(world_, &idesc, &inst), FL_OK);
    fl_outputs_desc out = fl_outputs_desc_defaults();
    fl_playback_desc pb = fl_playback_desc_defaults();
    fl_instance_state st = fl_instance_state_defaults();
    fl_package_info info = fl_package_info_defaults();
    float buf[16];

    // Wrong struct sizes.
    idesc.struct_size = 4;
    fl_instance other{};
    EXPECT_EQ(fl_instance_create(world_, &idesc, &other), FL_ERROR_STRUCT_SIZE);
    EXPECT_EQ(other.id, 0u);
    idesc.struct_size = 0;
    EXPECT_EQ(fl_instance_create(world_, &idesc, &other), FL_ERROR_STRUCT_SIZE);
    out.struct_size = 3;
    EXPECT_EQ(fl_instance_set_outputs(world_, inst, &out), FL_ERROR_STRUCT_SIZE);
    pb.struct_size = sizeof(pb) - 8;
    EXPECT_EQ(fl_instance_set_playback(world_, inst, &pb), FL_ERROR_STRUCT_SIZE);
    st.struct_size = 0;
    EXPECT_EQ(fl_instance_get_state(world_, inst, &st), FL_ERROR_STRUCT_SIZE);
    info.struct_size = 8;
    EXPECT_EQ(fl_package_get_info(package_, &info), FL_ERROR_STRUCT_SIZE);
    EXPECT_NE(std::string(fl_last_error()).find("struct_size"), std::string::npos);
    info = fl_package_info_defaults();
    fl_world_desc wd = fl_world_desc_defaults();
    wd.struct_size = 1;
    fl_world w2{};
    EXPECT_EQ(fl_world_create(&wd, &w2), FL_ERROR_STRUCT_SIZE);

    // Null pointers.
    EXPECT_EQ(fl_instance_create(world_, nullptr, &other), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_instance_create(world_, &idesc, nullptr), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_package_load(nullptr, &package_), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_instance_get_image(world_, inst, nullptr, 100), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_instance_set_keyframes(world_, inst, nullptr, 1), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fl_world_update(world_, NAN), FL_ERROR_INVALID_ARGUMENT);

    // Invalid handles: 0, garbage, another kind's id, stale after release/destroy.
    const uint32_t garbage[] = {0u, 1u << 20, 0xFFFFFFFFu, 0x12345u, world_.id + 1};
    for (uint32_t id : garbage) {
        EXPECT_EQ(fl_world_update(fl_world{id}, 0.0), FL_ERROR_INVALID_HANDLE) << id;
        EXPECT_EQ(fl_package_get_info(fl_package{id}, &info), FL_ERROR_INVALID_HANDLE) << id;
        EXPECT_EQ(fl_look_release(fl_look{id}), FL_ERROR_INVALID_HANDLE) << id;
        EXPECT_EQ(fl_instance_get_image(world_, fl_instance{id == inst.id ? 0 : id}, buf, 16),
                  FL_ERROR_INVALID_HANDLE) << id;
        EXPECT_EQ(fl_instance_destroy(world_, fl_instance{id == inst.id ? 0 : id}), FL_ERROR_INVALID_HANDLE) << id;
    }
    EXPECT_EQ(fl_instance_destroy(world_, inst), FL_OK);
    EXPECT_EQ(fl_instance_destroy(world_, inst), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_get_state(world_, inst, &st), FL_ERROR_STRUCT_SIZE);  // checked first
    st = fl_instance_state_defaults();
    EXPECT_EQ(fl_instance_get_state(world_, inst, &st), FL_ERROR_INVALID_HANDLE);
    fl_look look{};
    ASSERT_EQ(fl_look_from_json(kLookJson, 0, nullptr, &look), FL_OK);
    EXPECT_EQ(fl_instance_set_look(world_, inst, look), FL_ERROR_INVALID_HANDLE);
    // A new instance reuses the slot: the old handle stays stale.
    fl_instance again{};
    idesc = instanceDesc(package_);
    ASSERT_EQ(fl_instance_create(world_, &idesc, &again), FL_OK);
    EXPECT_NE(again.id, inst.id);
    EXPECT_EQ(fl_instance_set_look(world_, inst, look), FL_ERROR_INVALID_HANDLE);
    // Released package: the handle dies, the instance keeps working.
    releasePackage();
    EXPECT_EQ(fl_package_release(package_), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_package_get_info(package_, &info), FL_ERROR_INVALID_HANDLE);
    idesc.package = package_;
    EXPECT_EQ(fl_instance_create(world_, &idesc, &other), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_world_update(world_, 0.1), FL_OK);
    // Released look.
    EXPECT_EQ(fl_look_release(look), FL_OK);
    EXPECT_EQ(fl_instance_set_look(world_, again, look), FL_ERROR_INVALID_HANDLE);
    // Destroyed world.
    destroyWorld();
    EXPECT_EQ(fl_world_update(world_, 0.0), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_destroy(world_, again), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_world_destroy(world_), FL_ERROR_INVALID_HANDLE);
    EXPECT_GT(g_logs.load(), 0);
    EXPECT_NE(g_last_log.find("invalid"), std::string::npos);
}

TEST_F(PluginApiWorld, AReleasedHandleStaysInvalidAfterItsSlotIsReused100000Times) {
    // The 11-bit generation used to wrap: the 2047th look made in a released look's slot gave the
    // released handle back its meaning (issue 28). Spent slots are retired now (handle_pool.h).
    fl_look first{};
    ASSERT_EQ(fl_look_from_json(kLookJson, 0, nullptr, &first), FL_OK) << fl_last_error();
    ASSERT_EQ(fl_look_release(first), FL_OK);
    size_t size = 0;
    for (int n = 1; n <= 100000; ++n) {
        fl_look look{};
        ASSERT_EQ(fl_look_from_json(kLookJson, 0, nullptr, &look), FL_OK) << fl_last_error();
        ASSERT_NE(look.id, first.id) << "reuse " << n;
        ASSERT_EQ(fl_look_to_json(first, nullptr, 0, &size), FL_ERROR_INVALID_HANDLE) << "reuse " << n;
        ASSERT_EQ(fl_look_release(look), FL_OK);
        ASSERT_EQ(fl_look_release(look), FL_ERROR_INVALID_HANDLE) << "reuse " << n;
    }
}

TEST_F(PluginApiWorld, LooksAndPackagesWithErrorsReportCodesAndMessages) {
    fl_look look{};
    EXPECT_EQ(fl_look_from_json("{ not json", 0, "broken.json", &look), FL_ERROR_LOOK);
    EXPECT_NE(std::string(fl_last_error()).find("broken.json"), std::string::npos);
    const std::string wrong_albedo = std::string(kLookJson).replace(std::string(kLookJson).find("0.7"), 3, "0.9");
    ASSERT_EQ(fl_look_from_json(wrong_albedo.c_str(), 0, "pale.json", &look), FL_OK);
    const fl_instance_desc idesc = instanceDesc(package_, look);
    fl_instance inst{};
    EXPECT_EQ(fl_instance_create(world_, &idesc, &inst), FL_ERROR_LOOK);
    EXPECT_NE(std::string(fl_last_error()).find("albedo"), std::string::npos);
    uint32_t count = 99;
    ASSERT_EQ(fl_world_instance_count(world_, &count), FL_OK);
    EXPECT_EQ(count, 0u);  // the failed create left nothing behind

    fl_package q{};
    EXPECT_EQ(fl_package_load((dir_ / "missing.firelook").c_str(), &q), FL_ERROR_IO);
    EXPECT_NE(std::string(fl_last_error()).find("missing.firelook"), std::string::npos);
    std::ofstream(dir_ / "text.firelook") << "this is not a package at all, just some text to read";
    EXPECT_EQ(fl_package_load((dir_ / "text.firelook").c_str(), &q), FL_ERROR_NOT_A_PACKAGE);
    // Truncated copy of a real package.
    std::ifstream in(path_, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir_ / "cut.firelook", std::ios::binary).write(bytes.data(), bytes.size() / 2);
    const fl_result cut = fl_package_load((dir_ / "cut.firelook").c_str(), &q);
    EXPECT_TRUE(cut == FL_ERROR_CORRUPT || cut == FL_ERROR_NOT_A_PACKAGE) << fl_result_string(cut);
    EXPECT_EQ(q.id, 0u);
}

TEST_F(PluginApi, PlainCTranslationUnitRunsTheWholeCycle) {
    EXPECT_EQ(firelook_c_smoke(path_.c_str()), 0) << fl_last_error();
}

TEST(PluginApiLibrary, LoadsWithDlopenAndExportsOnlyTheApi) {
    void* lib = dlopen(FIRELOOK_PLUGIN_PATH, RTLD_NOW | RTLD_LOCAL);
    ASSERT_NE(lib, nullptr) << dlerror();
    using VersionFn = uint32_t (*)();
    auto version = reinterpret_cast<VersionFn>(dlsym(lib, "fl_version"));
    ASSERT_NE(version, nullptr) << dlerror();
    EXPECT_EQ(version(), static_cast<uint32_t>(FIRELOOK_HEADER_VERSION));
    EXPECT_NE(dlsym(lib, "fl_init"), nullptr);
    EXPECT_NE(dlsym(lib, "fl_world_update"), nullptr);
    // Runtime internals stay hidden (the version script exports fl_* only).
    EXPECT_EQ(dlsym(lib, "_ZN8firelook7runtime5World6updateEd"), nullptr);
    dlclose(lib);
}

// ---- the struct rule (struct_rule.h) --------------------------------------------------------------

// Every fl_* struct is still at its first published layout, so an older caller is stood for by a
// struct that has since "grown": Grown is a library struct whose first published size ends at b.
struct Grown {
    uint32_t struct_size;
    int32_t a;
    double b;
    int32_t added;  // not in the first published version: 0 (default) for an older caller
    int32_t added2;
};
struct Older {  // what an older caller compiled: Grown up to b
    uint32_t struct_size;
    int32_t a;
    double b;
};
struct Newer {  // a newer caller: Grown plus a field this library does not know
    Grown base;
    double unknown;
};
}  // namespace
template <>
struct firelook::plugin::FirstSize<Grown> {
    static constexpr size_t value = offsetof(Grown, b) + sizeof(double);
};
namespace {

TEST(PluginApiStructRule, AnOlderCallersStructReadsWithDefaultsAndIsWrittenOnlyAsFarAsItReaches) {
    static_assert(sizeof(Older) == firelook::plugin::FirstSize<Grown>::value);
    // In: the fields an older caller lacks read as 0 (their default), whatever follows its struct.
    unsigned char memory[sizeof(Grown) + 8];
    std::memset(memory, 0xAB, sizeof memory);
    const Older older{sizeof(Older), 7, 2.5};
    std::memcpy(memory, &older, sizeof older);
    const Grown in = firelook::plugin::copyIn<Grown>(memory, firelook::plugin::callerStructSize(memory));
    EXPECT_EQ(in.struct_size, sizeof(Older));
    EXPECT_EQ(in.a, 7);
    EXPECT_EQ(in.b, 2.5);
    EXPECT_EQ(in.added, 0);
    EXPECT_EQ(in.added2, 0);
    // Out: only the older struct's bytes are written; its struct_size is kept.
    Grown value{};
    value.struct_size = 999;
    value.a = 1;
    value.b = -1.0;
    value.added = 5;
    firelook::plugin::copyOut(memory, sizeof(Older), value);
    Older out;
    std::memcpy(&out, memory, sizeof out);
    EXPECT_EQ(out.struct_size, sizeof(Older));
    EXPECT_EQ(out.a, 1);
    EXPECT_EQ(out.b, -1.0);
    for (size_t i = sizeof(Older); i < sizeof memory; ++i) ASSERT_EQ(memory[i], 0xAB) << i;
}

TEST(PluginApiStructRule, ANewerCallersAdditionsAreIgnoredAndLeftUntouched) {
    Newer newer{};
    newer.base = {sizeof(Newer), 3, 4.0, 5, 6};
    newer.unknown = 123.0;
    const Grown in = firelook::plugin::copyIn<Grown>(&newer, newer.base.struct_size);
    EXPECT_EQ(in.a, 3);
    EXPECT_EQ(in.added2, 6);
    Grown value{};
    value.a = 9;
    firelook::plugin::copyOut(&newer, newer.base.struct_size, value);
    EXPECT_EQ(newer.base.struct_size, sizeof(Newer));
    EXPECT_EQ(newer.base.a, 9);
    EXPECT_EQ(newer.unknown, 123.0);
}

// The first published sizes the header documents ("through <field>") are today's sizes up to padding.
TEST(PluginApiStructRule, FirstPublishedSizesAreTheDocumentedFieldEnds) {
    using firelook::plugin::FirstSize;
    EXPECT_EQ(FirstSize<fl_world_desc>::value, sizeof(fl_world_desc));
    EXPECT_EQ(FirstSize<fl_instance_desc>::value, sizeof(fl_instance_desc));
    EXPECT_EQ(FirstSize<fl_keyframe>::value, sizeof(fl_keyframe));
    EXPECT_EQ(FirstSize<fl_playback_desc>::value, sizeof(fl_playback_desc));
    EXPECT_EQ(FirstSize<fl_outputs_desc>::value, sizeof(fl_outputs_desc));
    EXPECT_EQ(FirstSize<fl_package_info>::value, sizeof(fl_package_info));
    EXPECT_LE(sizeof(fl_instance_state) - FirstSize<fl_instance_state>::value, 4u);
    EXPECT_EQ(FirstSize<fl_init_desc>::value, sizeof(fl_init_desc));
}

// A struct as a caller with a newer header passes it: ours, then fields this library does not know.
template <class T>
struct Larger {
    T base;
    unsigned char added[24];
};
// An input: `base`, the added fields zeroed, struct_size covering the whole.
template <class T>
Larger<T> largerInput(const T& base) {
    Larger<T> s;
    std::memset(&s, 0, sizeof s);
    s.base = base;
    s.base.struct_size = sizeof s;
    return s;
}
// An output for the library to fill: every byte 0xAB but struct_size, so a write past ours shows.
template <class T>
Larger<T> largerOutput() {
    Larger<T> s;
    std::memset(&s, 0xAB, sizeof s);
    s.base.struct_size = sizeof s;
    return s;
}

// A caller whose header is newer (its structs larger, extra fields zeroed) through the real API:
// inputs are accepted and behave as ours; outputs fill our fields and leave the caller's extra bytes
// (0xAB here) untouched; a size below the first published one is refused.
TEST_F(PluginApi, NewerCallersLargerStructsAreAcceptedAndTheirExtraBytesUntouched) {
    ASSERT_EQ(fl_shutdown(), FL_OK);
    fl_init_desc init = fl_init_desc_defaults();
    init.sizeof_keyframe = sizeof(Larger<fl_keyframe>);  // the stride of the newer keyframe array below
    ASSERT_EQ(fl_init(&init), FL_OK);
    const fl_package p = load();

    const auto wd = largerInput(fl_world_desc_defaults());
    fl_world world{};
    ASSERT_EQ(fl_world_create(&wd.base, &world), FL_OK) << fl_last_error();
    const auto id = largerInput(instanceDesc(p));
    fl_instance inst{};
    ASSERT_EQ(fl_instance_create(world, &id.base, &inst), FL_OK) << fl_last_error();
    const auto out = largerInput(imageOutputs());
    ASSERT_EQ(fl_instance_set_outputs(world, inst, &out.base), FL_OK) << fl_last_error();
    const auto pb = largerInput(pausedOnFrame4());
    ASSERT_EQ(fl_instance_set_playback(world, inst, &pb.base), FL_OK) << fl_last_error();
    Larger<fl_keyframe> keys[2] = {};
    fl_look look{};
    ASSERT_EQ(fl_package_default_look(p, &look), FL_OK);
    keys[0].base.frame = 3.0;
    keys[0].base.look = look;
    keys[1].base.frame = 5.0;
    keys[1].base.look = look;
    ASSERT_EQ(fl_instance_set_keyframes(world, inst, &keys[0].base, 2), FL_OK) << fl_last_error();
    ASSERT_EQ(fl_world_update(world, 0.0), FL_OK) << fl_last_error();

    auto st = largerOutput<fl_instance_state>();
    ASSERT_EQ(fl_instance_get_state(world, inst, &st.base), FL_OK) << fl_last_error();
    EXPECT_EQ(st.base.struct_size, sizeof st);
    EXPECT_EQ(st.base.updated, 1);
    EXPECT_EQ(st.base.frame, 4);
    EXPECT_EQ(st.base.rank, 7);
    for (unsigned char b : st.added) ASSERT_EQ(b, 0xAB);
    auto info = largerOutput<fl_package_info>();
    ASSERT_EQ(fl_package_get_info(p, &info.base), FL_OK) << fl_last_error();
    EXPECT_EQ(info.base.struct_size, sizeof info);
    EXPECT_EQ(info.base.width, 16);
    EXPECT_EQ(info.base.frame_count, 3);
    EXPECT_DOUBLE_EQ(info.base.flame_extinction_max, 4.0);
    for (unsigned char b : info.added) ASSERT_EQ(b, 0xAB);

    // The same instance driven with structs of today's size gives the same state.
    fl_instance_state now = fl_instance_state_defaults();
    ASSERT_EQ(fl_instance_get_state(world, inst, &now), FL_OK);
    EXPECT_EQ(std::memcmp(&now.updated, &st.base.updated, offsetof(fl_instance_state, reserved) - 4), 0);

    // One byte below the first published size is refused.
    fl_package_info short_info = fl_package_info_defaults();
    short_info.struct_size = static_cast<uint32_t>(firelook::plugin::FirstSize<fl_package_info>::value - 1);
    EXPECT_EQ(fl_package_get_info(p, &short_info), FL_ERROR_STRUCT_SIZE);
    fl_outputs_desc short_out = fl_outputs_desc_defaults();
    short_out.struct_size = static_cast<uint32_t>(firelook::plugin::FirstSize<fl_outputs_desc>::value - 4);
    EXPECT_EQ(fl_instance_set_outputs(world, inst, &short_out), FL_ERROR_STRUCT_SIZE);
    EXPECT_EQ(fl_look_release(look), FL_OK);
    EXPECT_EQ(fl_world_destroy(world), FL_OK);
    EXPECT_EQ(fl_package_release(p), FL_OK);
}

// ---- handles ---------------------------------------------------------------------------------------

// The issue's reproduction: with two worlds holding one instance each, world B is handed world A's
// instance. Every instance call refuses it, and world B's own instance survives.
TEST_F(PluginApiWorld, AnInstanceOfAnotherWorldIsRefusedAndTheOtherWorldsInstanceSurvives) {
    const fl_world a = world_;
    fl_world b{};
    ASSERT_EQ(fl_world_create(nullptr, &b), FL_OK);
    const fl_instance of_a = createInstance(a, package_), of_b = createInstance(b, package_);
    fl_look look{};
    ASSERT_EQ(fl_package_default_look(package_, &look), FL_OK);
    fl_instance_state st = fl_instance_state_defaults();
    fl_outputs_desc out = fl_outputs_desc_defaults();
    fl_playback_desc pb = fl_playback_desc_defaults();
    const fl_keyframe key = {3.0, look, 0};
    float buf[16];
    int32_t rank = 0;

    EXPECT_EQ(fl_instance_destroy(b, of_a), FL_ERROR_INVALID_HANDLE);
    EXPECT_NE(std::string(fl_last_error()).find("another world"), std::string::npos) << fl_last_error();
    EXPECT_EQ(fl_instance_set_look(b, of_a, look), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_set_keyframes(b, of_a, &key, 1), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_set_playback(b, of_a, &pb), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_set_outputs(b, of_a, &out), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_get_state(b, of_a, &st), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_get_coefficients(b, of_a, buf, 16, &rank), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_get_image(b, of_a, buf, 16), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_get_flare(b, of_a, buf, 16), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_destroy(a, of_b), FL_ERROR_INVALID_HANDLE);

    uint32_t count = 0;
    ASSERT_EQ(fl_world_instance_count(b, &count), FL_OK);
    EXPECT_EQ(count, 1u);
    ASSERT_EQ(fl_world_update(b, 0.0), FL_OK);
    EXPECT_EQ(fl_instance_get_state(b, of_b, &st), FL_OK);
    EXPECT_EQ(st.updated, 1);
    EXPECT_EQ(fl_instance_get_state(a, of_a, &st), FL_OK);  // A's own still answers through A

    // Destroying world A makes its instance's handle stale everywhere; B's is unaffected.
    destroyWorld();  // A
    EXPECT_EQ(fl_instance_get_state(b, of_a, &st), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_destroy(b, of_b), FL_OK);
    EXPECT_EQ(fl_instance_destroy(b, of_b), FL_ERROR_INVALID_HANDLE);  // stale after destroy
    EXPECT_EQ(fl_look_release(look), FL_OK);
    EXPECT_EQ(fl_world_destroy(b), FL_OK);
}

// Ids carry their kind: a live id of one kind is refused as every other kind, the message saying so.
TEST_F(PluginApiWorld, AHandleOfAnotherKindIsRefused) {
    fl_look look{};
    ASSERT_EQ(fl_package_default_look(package_, &look), FL_OK);
    const fl_instance inst = createInstance(world_, package_);
    fl_package_info info = fl_package_info_defaults();
    size_t size = 0;
    uint32_t count = 0;

    EXPECT_EQ(fl_package_get_info(fl_package{world_.id}, &info), FL_ERROR_INVALID_HANDLE);  // a world as a package
    EXPECT_NE(std::string(fl_last_error()).find("a world handle, not a package handle"), std::string::npos) << fl_last_error();
    EXPECT_EQ(fl_world_update(fl_world{package_.id}, 0.0), FL_ERROR_INVALID_HANDLE);  // a package as a world
    EXPECT_EQ(fl_world_instance_count(fl_world{package_.id}, &count), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_world_destroy(fl_world{look.id}), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_world_update(fl_world{inst.id}, 0.0), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_look_to_json(fl_look{package_.id}, nullptr, 0, &size), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_look_release(fl_look{world_.id}), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_package_release(fl_package{look.id}), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_package_release(fl_package{inst.id}), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_destroy(world_, fl_instance{package_.id}), FL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(fl_instance_destroy(world_, fl_instance{world_.id}), FL_ERROR_INVALID_HANDLE);
    fl_instance_desc d = instanceDesc(fl_package{world_.id});
    fl_instance other{};
    EXPECT_EQ(fl_instance_create(world_, &d, &other), FL_ERROR_INVALID_HANDLE);
    d.package = package_;
    d.look = fl_look{package_.id};
    EXPECT_EQ(fl_instance_create(world_, &d, &other), FL_ERROR_INVALID_HANDLE);
    ASSERT_EQ(fl_world_instance_count(world_, &count), FL_OK);
    EXPECT_EQ(count, 1u);  // the refused creates left nothing behind

    // The refused calls changed nothing: every object still works through its own kind.
    EXPECT_EQ(fl_package_get_info(package_, &info), FL_OK);
    EXPECT_EQ(fl_world_update(world_, 0.0), FL_OK);
    EXPECT_EQ(fl_look_to_json(look, nullptr, 0, &size), FL_OK);
    EXPECT_EQ(fl_instance_destroy(world_, inst), FL_OK);
    EXPECT_EQ(fl_look_release(look), FL_OK);
    destroyWorld();
    releasePackage();
}

// ---- coded errors ----------------------------------------------------------------------------------

// A package whose content is wrong is FL_ERROR_CORRUPT, with a message naming the file: META that is
// not a bake description (open), and frames whose sections are missing (the frame's shape check on
// every read: fl_package_get_frame_u/_depths and the world's update).
TEST_F(PluginApiWorld, ABadPackageIsCorruptAndTheMessageNamesTheFile) {
    const std::string bad_meta = (dir_ / "bad-meta.firelook").string();
    {
        firelook::package::ContainerWriter writer(bad_meta, firelook::package::WriterOptions{1});
        writer.addMetadata(R"({"format": "firelook-basis", "bake": {"width": 16}})");
        writer.commit();
    }
    fl_package q{};
    EXPECT_EQ(fl_package_load(bad_meta.c_str(), &q), FL_ERROR_CORRUPT) << fl_last_error();
    EXPECT_NE(std::string(fl_last_error()).find("bad-meta.firelook"), std::string::npos) << fl_last_error();

    const std::string no_frames = (dir_ / "no-frame-sections.firelook").string();
    {
        firelook::testing::SyntheticShape shape;
        firelook::basis::BakeDescription d = firelook::testing::syntheticDescription(shape);
        d.frames = {{3, 4}};  // listed, but its sections were never written
        firelook::package::ContainerWriter writer(no_frames, firelook::package::WriterOptions{1});
        writer.addMetadata(firelook::basis::makeMetadata(d, "{}"));
        writer.commit();
    }
    fl_package p{};
    ASSERT_EQ(fl_package_load(no_frames.c_str(), &p), FL_OK) << fl_last_error();  // frames read on demand
    size_t n = 0;
    ASSERT_EQ(fl_package_get_frame_u(p, 3, nullptr, 0, &n), FL_OK);
    std::vector<uint16_t> u(n);
    EXPECT_EQ(fl_package_get_frame_u(p, 3, u.data(), u.size(), &n), FL_ERROR_CORRUPT) << fl_last_error();
    EXPECT_NE(std::string(fl_last_error()).find("no-frame-sections.firelook"), std::string::npos) << fl_last_error();
    ASSERT_EQ(fl_package_get_frame_depths(p, 3, nullptr, 0, &n), FL_OK);
    std::vector<float> depths(n);
    EXPECT_EQ(fl_package_get_frame_depths(p, 3, depths.data(), depths.size(), &n), FL_ERROR_CORRUPT);
    createInstance(world_, p);
    EXPECT_EQ(fl_world_update(world_, 0.0), FL_ERROR_CORRUPT) << fl_last_error();
    destroyWorld();
    EXPECT_EQ(fl_package_release(p), FL_OK);
}

// One failure from each layer under the plugin reaches the C API by its code through the one table
// (result_table.h), with the layer's own message: the package reader (not a package), the basis
// reader (a layout version this build does not read), the look parser (a newer look file) and the
// world (an argument only the world checks: a lens flare without the image).
TEST_F(PluginApiWorld, AFailureOfEachLayerReachesTheCApiByItsCode) {
    fl_package q{};
    const std::string text = (dir_ / "text.firelook").string();
    std::ofstream(text) << "this is not a package at all, just some text to read";
    EXPECT_EQ(fl_package_load(text.c_str(), &q), FL_ERROR_NOT_A_PACKAGE) << fl_last_error();
    EXPECT_NE(std::string(fl_last_error()).find("text.firelook"), std::string::npos) << fl_last_error();

    const std::string newer = (dir_ / "newer-layout.firelook").string();
    {
        firelook::package::ContainerWriter writer(newer, firelook::package::WriterOptions{1});
        writer.addMetadata(R"({"format": "firelook-basis", "version": 99, "bake": {}})");
        writer.commit();
    }
    EXPECT_EQ(fl_package_load(newer.c_str(), &q), FL_ERROR_UNSUPPORTED) << fl_last_error();
    EXPECT_NE(std::string(fl_last_error()).find("basis layout version 99"), std::string::npos)
        << fl_last_error();
    EXPECT_EQ(q.id, 0u);

    std::string newer_look = kLookJson;
    newer_look.replace(newer_look.find("\"version\": 1"), 12, "\"version\": 9");
    fl_look look{};
    EXPECT_EQ(fl_look_from_json(newer_look.c_str(), 0, "newer.json", &look), FL_ERROR_LOOK)
        << fl_last_error();
    EXPECT_NE(std::string(fl_last_error()).find("newer.json"), std::string::npos) << fl_last_error();

    const fl_instance inst = createInstance(world_, package_);
    fl_outputs_desc out = fl_outputs_desc_defaults();
    out.image = 0;
    out.lens_flare = 1;
    EXPECT_EQ(fl_instance_set_outputs(world_, inst, &out), FL_ERROR_INVALID_ARGUMENT) << fl_last_error();
    EXPECT_NE(std::string(fl_last_error()).find("lens flare"), std::string::npos) << fl_last_error();
}

// Frame 4's image of `look`, as an instance paused there shows it.
std::vector<float> shownImage(fl_world world, fl_package package, fl_look look) {
    fl_instance inst{};
    createPausedImageInstance(world, package, look, &inst);
    std::vector<float> image(16 * 12 * 4);
    EXPECT_EQ(fl_world_update(world, 0.0), FL_OK) << fl_last_error();
    EXPECT_EQ(fl_instance_get_image(world, inst, image.data(), image.size()), FL_OK) << fl_last_error();
    EXPECT_EQ(fl_instance_destroy(world, inst), FL_OK);
    return image;
}

// fl_package_fit_look (issue 17): the runtime's fit (runtime/fit/look_fit.h, whose accuracy tests/fit
// measures on a baked package: the synthetic package's random basis images render mostly clamped
// negative radiance, which no linear fit reproduces) on the package's frame, bit for bit, and a look
// that draws the error the report gives; progress is reported and can stop the fit.
TEST_F(PluginApiWorld, FitLookIsTheRuntimesFit) {
    fl_look look{};
    ASSERT_EQ(fl_look_from_json(kLookJson, 0, "test look", &look), FL_OK) << fl_last_error();
    const std::vector<float> target = shownImage(world_, package_, look);
    EXPECT_EQ(fl_look_release(look), FL_OK);
    struct Progress {
        int calls = 0;
        double last = -1.0;
        bool monotone = true;
    } progress;
    fl_fit_desc desc = fl_fit_desc_defaults();
    desc.frame = 4;
    desc.target_rgba = target.data();
    desc.progress = [](double fraction, void* user) -> int32_t {
        auto& p = *static_cast<Progress*>(user);
        ++p.calls;
        p.monotone = p.monotone && fraction >= p.last && fraction <= 1.0;
        p.last = fraction;
        return 0;
    };
    desc.progress_user = &progress;
    fl_fit_report report = fl_fit_report_defaults();
    fl_look fitted{};
    ASSERT_EQ(fl_package_fit_look(package_, &desc, &fitted, &report), FL_OK) << fl_last_error();
    EXPECT_GT(progress.calls, 2);
    EXPECT_TRUE(progress.monotone);
    EXPECT_EQ(progress.last, 1.0);
    EXPECT_GE(report.evaluations, 6 * 4 * 3) << "every grid point of the synthetic package, then the local search";

    const auto package = firelook::basis::BasisReader::open(path_);
    const firelook::basis::ResidentFrame frame = package.loadResidentFrame(4, std::pmr::get_default_resource());
    const firelook::basis::ResidentFrame* frames[] = {&frame};
    firelook::fit::FrameTarget t;
    t.frame = 4;
    t.rgba = target;
    const firelook::fit::FitResult expected = firelook::fit::fitLook(package.description(), frames, std::span(&t, 1));
    std::string json(4096, '\0');
    size_t size = 0;
    ASSERT_EQ(fl_look_to_json(fitted, json.data(), json.size(), &size), FL_OK) << fl_last_error();
    json.resize(size - 1);
    EXPECT_EQ(json, firelook::lookToJson(expected.look));
    EXPECT_EQ(report.relative_rmse, expected.relative_rmse);
    EXPECT_EQ(report.alpha_max_error, expected.alpha_max_error);
    EXPECT_EQ(report.evaluations, expected.evaluations);

    // The look handle draws the reported error (the world's image is the runtime's render, bit for bit).
    const std::vector<float> again = shownImage(world_, package_, fitted);
    double squared = 0.0, energy = 0.0;
    for (size_t i = 0; i < target.size(); ++i) {
        if (i % 4 == 3) continue;
        squared += (double(again[i]) - target[i]) * (double(again[i]) - target[i]);
        energy += double(target[i]) * target[i];
    }
    EXPECT_NEAR(std::sqrt(squared / energy), report.relative_rmse, 1e-6 + 1e-4 * report.relative_rmse);
    EXPECT_EQ(fl_look_release(fitted), FL_OK);

    // A callback that asks to stop: FL_ERROR_CANCELLED and no look.
    desc.progress = [](double, void*) -> int32_t { return 1; };
    fitted.id = 7;
    EXPECT_EQ(fl_package_fit_look(package_, &desc, &fitted, nullptr), FL_ERROR_CANCELLED);
    EXPECT_EQ(fitted.id, 0u);
    EXPECT_NE(std::string(fl_last_error()).find("stopped"), std::string::npos) << fl_last_error();
}

TEST_F(PluginApiWorld, FitLookRefusesBadInput) {
    std::vector<float> target(16 * 12 * 4, 0.1f);
    const std::vector<float> no_weight(16 * 12, 0.0f);
    fl_look fitted{};
    const auto fitWith = [&](auto change) {
        fl_fit_desc desc = fl_fit_desc_defaults();
        desc.frame = 4;
        desc.target_rgba = target.data();
        change(desc);
        return fl_package_fit_look(package_, &desc, &fitted, nullptr);
    };
    EXPECT_EQ(fitWith([](fl_fit_desc& d) { d.frame = 9; }), FL_ERROR_NOT_FOUND);
    EXPECT_EQ(fitWith([](fl_fit_desc& d) { d.flags = 1u << 7; }), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fitWith([](fl_fit_desc& d) { d.target_rgba = nullptr; }), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fitWith([&](fl_fit_desc& d) { d.weights = no_weight.data(); }), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(fl_last_error()).find("no target pixel"), std::string::npos) << fl_last_error();
    EXPECT_EQ(fitWith([](fl_fit_desc& d) {
                  d.flags = FL_FIT_HOLD_SMOKE_EXTINCTION;
                  d.smoke_extinction = 30.0;  // the axis is [2, 16]
              }),
              FL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(fl_last_error()).find("k_s"), std::string::npos) << fl_last_error();
    EXPECT_EQ(fitWith([](fl_fit_desc& d) { d.struct_size = 8; }), FL_ERROR_STRUCT_SIZE);
    target[5] = std::nanf("");
    EXPECT_EQ(fitWith([](fl_fit_desc&) {}), FL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(fitted.id, 0u);
}

}  // namespace
