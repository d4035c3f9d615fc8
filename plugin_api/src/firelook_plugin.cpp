// The C API (include/firelook/firelook.h) over firelook::runtime. Every entry
// point runs inside guarded(): exceptions become result codes plus a
// per-thread message, so nothing C++ crosses the boundary.
#include "firelook/firelook.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <type_traits>
#include <vector>

#include "look/emission_fit.h"
#include "look/look.h"
#include "package/error.h"
#include "world/world.h"

namespace {

using namespace firelook;

// ---- errors -----------------------------------------------------------------

struct ApiError {
    fl_result code;
    std::string message;
};

[[noreturn]] void fail(fl_result code, std::string message) { throw ApiError{code, std::move(message)}; }

thread_local std::string t_last_error;

// ---- the library context ---------------------------------------------------

// Index + generation pool: id = generation << 20 | (index + 1), generation 1..4095.
template <typename T>
class Pool {
  public:
    uint32_t add(T value) {
        uint32_t index;
        if (!free_.empty()) {
            index = free_.back();
            free_.pop_back();
        } else {
            if (items_.size() >= kMask) fail(FL_ERROR_LIMIT, "too many objects of one kind");
            index = static_cast<uint32_t>(items_.size());
            items_.emplace_back();
            generation_.push_back(1);
        }
        items_[index] = std::move(value);
        live_.resize(items_.size(), 0);
        live_[index] = 1;
        return (static_cast<uint32_t>(generation_[index]) << 20) | (index + 1);
    }
    T* find(uint32_t id) {
        const uint32_t low = id & kMask;
        if (low == 0) return nullptr;
        const uint32_t index = low - 1;
        if (index >= items_.size() || !live_[index] || generation_[index] != (id >> 20)) return nullptr;
        return &items_[index];
    }
    T take(uint32_t id) {  // caller checked find(id)
        const uint32_t index = (id & kMask) - 1;
        T value = std::move(items_[index]);
        items_[index] = T{};
        live_[index] = 0;
        uint16_t g = static_cast<uint16_t>((generation_[index] + 1) & 0xFFF);
        generation_[index] = g == 0 ? 1 : g;
        free_.push_back(index);
        return value;
    }
    void clear() {  // keeps the generations so that old handles stay stale
        for (uint32_t i = 0; i < items_.size(); ++i)
            if (live_[i]) take((static_cast<uint32_t>(generation_[i]) << 20) | (i + 1));
    }

  private:
    static constexpr uint32_t kMask = (1u << 20) - 1;
    std::vector<T> items_;
    std::vector<uint16_t> generation_;
    std::vector<uint8_t> live_;
    std::vector<uint32_t> free_;
};

struct Context {
    std::mutex mutex;
    bool initialized = false;
    runtime::MemoryHooks memory;
    fl_log_fn log = nullptr;
    void* log_user = nullptr;
    int32_t log_level = 0;
    Pool<std::shared_ptr<const runtime::Package>> packages;
    Pool<std::shared_ptr<const Look>> looks;
    Pool<std::shared_ptr<runtime::World>> worlds;
};

Context& context() {
    static Context* c = new Context;  // never destroyed: safe to use from late static destructors
    return *c;
}

void logMessage(int32_t level, const std::string& message) {
    Context& c = context();
    if (c.log && level >= c.log_level) c.log(level, message.c_str(), c.log_user);
}

fl_result packageErrorCode(package::ErrorCode code) {
    switch (code) {
        case package::ErrorCode::IoError: return FL_ERROR_IO;
        case package::ErrorCode::NotAPackage: return FL_ERROR_NOT_A_PACKAGE;
        case package::ErrorCode::Truncated:
        case package::ErrorCode::Corrupt: return FL_ERROR_CORRUPT;
        case package::ErrorCode::NewerMajorVersion:
        case package::ErrorCode::UnsupportedFeature: return FL_ERROR_UNSUPPORTED;
        case package::ErrorCode::OutOfMemory: return FL_ERROR_OUT_OF_MEMORY;
        default: return FL_ERROR_INTERNAL;
    }
}

template <typename F>
fl_result guarded(const char* function, F&& body) noexcept {
    fl_result code = FL_OK;
    std::string message;
    try {
        body();
        t_last_error.clear();
        return FL_OK;
    } catch (const ApiError& e) {
        code = e.code;
        message = e.message;
    } catch (const runtime::InvalidHandle& e) {
        code = FL_ERROR_INVALID_HANDLE;
        message = e.what();
    } catch (const LookError& e) {
        code = FL_ERROR_LOOK;
        message = e.what();
    } catch (const EmissionFitError& e) {
        code = FL_ERROR_LOOK;
        message = e.what();
    } catch (const package::PackageError& e) {
        code = packageErrorCode(e.code());
        message = e.what();
    } catch (const std::bad_alloc&) {
        code = FL_ERROR_OUT_OF_MEMORY;
        message = "out of memory";
    } catch (const std::invalid_argument& e) {
        code = FL_ERROR_INVALID_ARGUMENT;
        message = e.what();
    } catch (const std::runtime_error& e) {
        code = FL_ERROR_CORRUPT;  // inconsistent package content (BasisPackage checks)
        message = e.what();
    } catch (const std::exception& e) {
        code = FL_ERROR_INTERNAL;
        message = e.what();
    } catch (...) {
        code = FL_ERROR_INTERNAL;
        message = "unknown exception";
    }
    try {
        t_last_error = std::string(function) + ": " + message;
        logMessage(FL_LOG_ERROR, t_last_error);
    } catch (...) {
        t_last_error.clear();
    }
    return code;
}

void requireInit(Context& c) {
    if (!c.initialized) fail(FL_ERROR_NOT_INITIALIZED, "fl_init has not been called (or failed)");
}

template <typename T>
void checkIn(const T* p, const char* what) {
    if (!p) fail(FL_ERROR_INVALID_ARGUMENT, std::string(what) + " is null");
    // Version 1 is the first published layout: every field must be there.
    if (p->struct_size < sizeof(T))
        fail(FL_ERROR_STRUCT_SIZE, std::string(what) + "->struct_size is " + std::to_string(p->struct_size) +
                                       ", expected at least " + std::to_string(sizeof(T)) +
                                       " (initialise it with the *_defaults() function)");
}

template <typename T>
void checkOut(T* p, const char* what) {
    checkIn(p, what);
}

template <typename T>
void checkPointer(T* p, const char* what) {
    if (!p) fail(FL_ERROR_INVALID_ARGUMENT, std::string(what) + " is null");
}

std::shared_ptr<const runtime::Package> findPackage(fl_package h) {
    Context& c = context();
    std::lock_guard lock(c.mutex);
    requireInit(c);
    auto* p = c.packages.find(h.id);
    if (!p) fail(FL_ERROR_INVALID_HANDLE, "invalid or released package handle " + std::to_string(h.id));
    return *p;
}

std::shared_ptr<const Look> findLook(fl_look h) {
    Context& c = context();
    std::lock_guard lock(c.mutex);
    requireInit(c);
    auto* p = c.looks.find(h.id);
    if (!p) fail(FL_ERROR_INVALID_HANDLE, "invalid or released look handle " + std::to_string(h.id));
    return *p;
}

runtime::World& findWorld(fl_world h) {
    Context& c = context();
    std::lock_guard lock(c.mutex);
    requireInit(c);
    auto* p = c.worlds.find(h.id);
    if (!p) fail(FL_ERROR_INVALID_HANDLE, "invalid or destroyed world handle " + std::to_string(h.id));
    return **p;  // caller guarantees the world is not destroyed concurrently
}

void checkFinite(double v, const char* what) {
    if (!std::isfinite(v)) fail(FL_ERROR_INVALID_ARGUMENT, std::string(what) + " is not finite");
}

// Writes text + NUL into a caller buffer with the size convention of the header.
void writeText(const std::string& text, char* buffer, size_t capacity, size_t* out_size) {
    const size_t needed = text.size() + 1;
    if (out_size) *out_size = needed;
    if (capacity == 0) return;
    if (!buffer) fail(FL_ERROR_INVALID_ARGUMENT, "buffer is null");
    if (capacity < needed)
        fail(FL_ERROR_BUFFER_TOO_SMALL, "buffer holds " + std::to_string(capacity) + " bytes, " +
                                            std::to_string(needed) + " needed");
    std::memcpy(buffer, text.data(), text.size());
    buffer[text.size()] = '\0';
}

void checkCapacity(size_t capacity, size_t needed, const char* unit) {
    if (capacity < needed)
        fail(FL_ERROR_BUFFER_TOO_SMALL, "buffer holds " + std::to_string(capacity) + " " + unit + ", " +
                                            std::to_string(needed) + " needed");
}

int slotOrFail(const runtime::Package& p, int32_t frame) {
    const int slot = p.slotOf(frame);
    if (slot < 0) fail(FL_ERROR_NOT_FOUND, p.name() + ": no frame " + std::to_string(frame) + " in the package");
    return slot;
}

runtime::InstanceHandle instanceHandle(fl_instance h) { return h.id; }

}  // namespace

extern "C" {

FIRELOOK_API const char* fl_result_string(fl_result r) {
    switch (r) {
        case FL_OK: return "FL_OK";
        case FL_ERROR_INVALID_ARGUMENT: return "FL_ERROR_INVALID_ARGUMENT";
        case FL_ERROR_INVALID_HANDLE: return "FL_ERROR_INVALID_HANDLE";
        case FL_ERROR_STRUCT_SIZE: return "FL_ERROR_STRUCT_SIZE";
        case FL_ERROR_VERSION_MISMATCH: return "FL_ERROR_VERSION_MISMATCH";
        case FL_ERROR_NOT_INITIALIZED: return "FL_ERROR_NOT_INITIALIZED";
        case FL_ERROR_ALREADY_INITIALIZED: return "FL_ERROR_ALREADY_INITIALIZED";
        case FL_ERROR_IO: return "FL_ERROR_IO";
        case FL_ERROR_NOT_A_PACKAGE: return "FL_ERROR_NOT_A_PACKAGE";
        case FL_ERROR_CORRUPT: return "FL_ERROR_CORRUPT";
        case FL_ERROR_UNSUPPORTED: return "FL_ERROR_UNSUPPORTED";
        case FL_ERROR_LOOK: return "FL_ERROR_LOOK";
        case FL_ERROR_BUFFER_TOO_SMALL: return "FL_ERROR_BUFFER_TOO_SMALL";
        case FL_ERROR_OUT_OF_MEMORY: return "FL_ERROR_OUT_OF_MEMORY";
        case FL_ERROR_NO_DATA: return "FL_ERROR_NO_DATA";
        case FL_ERROR_NOT_FOUND: return "FL_ERROR_NOT_FOUND";
        case FL_ERROR_LIMIT: return "FL_ERROR_LIMIT";
        case FL_ERROR_INTERNAL: return "FL_ERROR_INTERNAL";
        default: return "FL_ERROR_UNKNOWN";
    }
}

FIRELOOK_API const char* fl_last_error(void) { return t_last_error.c_str(); }

FIRELOOK_API uint32_t fl_version(void) { return FIRELOOK_HEADER_VERSION; }

FIRELOOK_API fl_result fl_init(const fl_init_desc* desc) {
    return guarded("fl_init", [&] {
        if (!desc) fail(FL_ERROR_INVALID_ARGUMENT, "desc is null");
        // Check the version before anything else: a mismatched header may lay the struct out differently.
        const uint32_t major = desc->header_version / 10000, minor = desc->header_version / 100 % 100;
        if (desc->struct_size < 2 * sizeof(uint32_t) || major != FIRELOOK_VERSION_MAJOR ||
            minor > FIRELOOK_VERSION_MINOR)
            fail(FL_ERROR_VERSION_MISMATCH,
                 "the caller was compiled against FireLook header version " + std::to_string(desc->header_version) +
                     ", this library is " + std::to_string(FIRELOOK_HEADER_VERSION) +
                     " (same major and a minor no newer required)");
        checkIn(desc, "desc");
        const struct {
            uint32_t given, expected;
            const char* name;
        } sizes[] = {{desc->sizeof_world_desc, sizeof(fl_world_desc), "fl_world_desc"},
                     {desc->sizeof_instance_desc, sizeof(fl_instance_desc), "fl_instance_desc"},
                     {desc->sizeof_playback_desc, sizeof(fl_playback_desc), "fl_playback_desc"},
                     {desc->sizeof_outputs_desc, sizeof(fl_outputs_desc), "fl_outputs_desc"},
                     {desc->sizeof_package_info, sizeof(fl_package_info), "fl_package_info"},
                     {desc->sizeof_instance_state, sizeof(fl_instance_state), "fl_instance_state"},
                     {desc->sizeof_keyframe, sizeof(fl_keyframe), "fl_keyframe"}};
        for (const auto& s : sizes)
            if (s.given != s.expected)
                fail(FL_ERROR_VERSION_MISMATCH, std::string("sizeof(") + s.name + ") is " + std::to_string(s.given) +
                                                    " in the caller and " + std::to_string(s.expected) +
                                                    " in the library: header and library do not match");
        if ((desc->allocator.alloc == nullptr) != (desc->allocator.free == nullptr))
            fail(FL_ERROR_INVALID_ARGUMENT, "allocator: set both alloc and free, or neither");
        Context& c = context();
        std::lock_guard lock(c.mutex);
        if (c.initialized) fail(FL_ERROR_ALREADY_INITIALIZED, "fl_init called twice without fl_shutdown");
        c.memory = {desc->allocator.alloc, desc->allocator.free, desc->allocator.user};
        c.log = desc->log;
        c.log_user = desc->log_user;
        c.log_level = desc->log_level;
        c.initialized = true;
        logMessage(FL_LOG_INFO, "FireLook runtime " + std::to_string(FIRELOOK_HEADER_VERSION) + " initialised");
    });
}

FIRELOOK_API fl_result fl_shutdown(void) {
    return guarded("fl_shutdown", [&] {
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        c.worlds.clear();  // worlds first: their instances hold packages
        c.looks.clear();
        c.packages.clear();
        c.initialized = false;
        c.log = nullptr;
    });
}

// ---- packages -----------------------------------------------------------------

FIRELOOK_API fl_result fl_package_load(const char* path, fl_package* out) {
    return guarded("fl_package_load", [&] {
        checkPointer(path, "path");
        checkPointer(out, "out_package");
        out->id = 0;
        {
            Context& c = context();
            std::lock_guard lock(c.mutex);
            requireInit(c);
        }
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec))
            fail(FL_ERROR_IO, std::string(path) + ": no such file (or not a regular file)");
        std::shared_ptr<const runtime::Package> package = runtime::Package::open(path);  // outside the lock: I/O
        const auto& d = package->description();
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        out->id = c.packages.add(std::move(package));
        logMessage(FL_LOG_INFO, std::string("loaded ") + path + " (" + std::to_string(d.width) + "x" +
                                    std::to_string(d.height) + ", " + std::to_string(d.frames.size()) + " frames)");
    });
}

FIRELOOK_API fl_result fl_package_release(fl_package h) {
    return guarded("fl_package_release", [&] {
        std::shared_ptr<const runtime::Package> doomed;
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        if (!c.packages.find(h.id))
            fail(FL_ERROR_INVALID_HANDLE, "invalid or released package handle " + std::to_string(h.id));
        doomed = c.packages.take(h.id);
    });
}

FIRELOOK_API fl_result fl_package_get_info(fl_package h, fl_package_info* out) {
    return guarded("fl_package_get_info", [&] {
        checkOut(out, "out_info");
        const auto p = findPackage(h);
        const basis::BakeDescription& d = p->description();
        fl_package_info info = {};
        info.struct_size = out->struct_size;
        info.width = d.width;
        info.height = d.height;
        info.frame_count = p->frameCount();
        info.first_frame = p->frameNumber(0);
        info.last_frame = p->frameNumber(p->frameCount() - 1);
        info.max_rank = p->maxRank();
        info.bin_count = d.bins.count;
        info.light_count = static_cast<int32_t>(d.light_directions.size());
        info.alpha_threshold_count = static_cast<int32_t>(d.alpha_thresholds.size());
        info.footprint_samples = d.footprint_samples;
        info.temperature_lo = d.bins.t_lo;
        info.temperature_hi = d.bins.t_hi;
        info.rbf_width = d.rbf_width;
        info.albedo = d.albedo;
        info.temperature_threshold_min = d.axes.temperature_threshold.front();
        info.temperature_threshold_max = d.axes.temperature_threshold.back();
        info.smoke_extinction_min = d.axes.smoke_extinction.front();
        info.smoke_extinction_max = d.axes.smoke_extinction.back();
        info.flame_extinction_min = d.axes.flame_extinction.front();
        info.flame_extinction_max = d.axes.flame_extinction.back();
        *out = info;
    });
}

FIRELOOK_API fl_result fl_package_get_frames(fl_package h, int32_t* numbers, int32_t* ranks, uint32_t capacity,
                                             uint32_t* out_count) {
    return guarded("fl_package_get_frames", [&] {
        const auto p = findPackage(h);
        const uint32_t n = static_cast<uint32_t>(p->frameCount());
        if (out_count) *out_count = n;
        if (!numbers && !ranks) return;
        checkCapacity(capacity, n, "entries");
        for (uint32_t i = 0; i < n; ++i) {
            if (numbers) numbers[i] = p->frameNumber(static_cast<int>(i));
            if (ranks) ranks[i] = p->frameRank(static_cast<int>(i));
        }
    });
}

FIRELOOK_API fl_result fl_package_get_alpha_thresholds(fl_package h, double* thresholds, uint32_t capacity) {
    return guarded("fl_package_get_alpha_thresholds", [&] {
        checkPointer(thresholds, "thresholds");
        const auto p = findPackage(h);
        const auto& t = p->description().alpha_thresholds;
        checkCapacity(capacity, t.size(), "entries");
        std::copy(t.begin(), t.end(), thresholds);
    });
}

FIRELOOK_API fl_result fl_package_get_default_look_json(fl_package h, char* buffer, size_t capacity,
                                                        size_t* out_size) {
    return guarded("fl_package_get_default_look_json", [&] {
        const auto p = findPackage(h);
        writeText(p->description().default_look_json, buffer, capacity, out_size);
    });
}

FIRELOOK_API fl_result fl_package_get_frame_u(fl_package h, int32_t frame, uint16_t* buffer, size_t capacity,
                                              size_t* out_count) {
    return guarded("fl_package_get_frame_u", [&] {
        const auto p = findPackage(h);
        const int slot = slotOrFail(*p, frame);
        const basis::BakeDescription& d = p->description();
        const size_t rank = static_cast<size_t>(p->frameRank(slot));
        const size_t layers = (rank + 3) / 4;
        const size_t pixels = static_cast<size_t>(d.pixelCount());
        const size_t needed = layers * pixels * 4;
        if (out_count) *out_count = needed;
        if (capacity == 0 && !buffer) return;
        checkPointer(buffer, "buffer");
        checkCapacity(capacity, needed, "uint16_t elements");
        const basis::FrameFactors f = p->loadSlot(slot);
        std::fill(buffer, buffer + needed, uint16_t{0});
        for (size_t px = 0; px < pixels; ++px)
            for (size_t k = 0; k < rank; ++k) buffer[((k / 4) * pixels + px) * 4 + k % 4] = f.u_half[px * rank + k];
    });
}

FIRELOOK_API fl_result fl_package_get_frame_depths(fl_package h, int32_t frame, float* buffer, size_t capacity,
                                                   size_t* out_count) {
    return guarded("fl_package_get_frame_depths", [&] {
        const auto p = findPackage(h);
        const int slot = slotOrFail(*p, frame);
        const basis::BakeDescription& d = p->description();
        const size_t pixels = static_cast<size_t>(d.pixelCount());
        const size_t needed = pixels * static_cast<size_t>(d.footprint_samples) * (1 + d.alpha_thresholds.size());
        if (out_count) *out_count = needed;
        if (capacity == 0 && !buffer) return;
        checkPointer(buffer, "buffer");
        checkCapacity(capacity, needed, "floats");
        const basis::FrameFactors f = p->loadSlot(slot);
        std::copy(f.depth_density.begin(), f.depth_density.end(), buffer);
        if (f.depth_density.size() + f.depth_sigmoid.size() != needed)
            fail(FL_ERROR_CORRUPT, p->name() + ": optical depths of frame " + std::to_string(frame) + " have the wrong size");
        std::copy(f.depth_sigmoid.begin(), f.depth_sigmoid.end(), buffer + f.depth_density.size());
    });
}

// ---- looks --------------------------------------------------------------------

FIRELOOK_API fl_result fl_look_from_json(const char* json, size_t length, const char* source_name, fl_look* out) {
    return guarded("fl_look_from_json", [&] {
        checkPointer(json, "json");
        checkPointer(out, "out_look");
        out->id = 0;
        const std::string_view text(json, length ? length : std::strlen(json));
        auto look = std::make_shared<const Look>(parseLook(text, source_name ? source_name : "look"));
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        out->id = c.looks.add(std::move(look));
    });
}

FIRELOOK_API fl_result fl_package_default_look(fl_package h, fl_look* out) {
    return guarded("fl_package_default_look", [&] {
        checkPointer(out, "out_look");
        out->id = 0;
        const auto p = findPackage(h);
        auto look = std::make_shared<const Look>(
            parseLook(p->description().default_look_json, p->name() + " (default look)"));
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        out->id = c.looks.add(std::move(look));
    });
}

FIRELOOK_API fl_result fl_look_release(fl_look h) {
    return guarded("fl_look_release", [&] {
        std::shared_ptr<const Look> doomed;
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        if (!c.looks.find(h.id)) fail(FL_ERROR_INVALID_HANDLE, "invalid or released look handle " + std::to_string(h.id));
        doomed = c.looks.take(h.id);
    });
}

FIRELOOK_API fl_result fl_look_to_json(fl_look h, char* buffer, size_t capacity, size_t* out_size) {
    return guarded("fl_look_to_json", [&] { writeText(lookToJson(*findLook(h)), buffer, capacity, out_size); });
}

// ---- worlds -------------------------------------------------------------------

FIRELOOK_API fl_result fl_world_create(const fl_world_desc* desc, fl_world* out) {
    return guarded("fl_world_create", [&] {
        checkPointer(out, "out_world");
        out->id = 0;
        runtime::WorldSettings settings;
        if (desc) {
            checkIn(desc, "desc");
            if (desc->frame_cache_bytes) settings.frame_cache_bytes = static_cast<size_t>(desc->frame_cache_bytes);
        }
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        settings.memory = c.memory;
        out->id = c.worlds.add(std::make_shared<runtime::World>(settings));
    });
}

FIRELOOK_API fl_result fl_world_destroy(fl_world h) {
    return guarded("fl_world_destroy", [&] {
        std::shared_ptr<runtime::World> doomed;
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        if (!c.worlds.find(h.id)) fail(FL_ERROR_INVALID_HANDLE, "invalid or destroyed world handle " + std::to_string(h.id));
        doomed = c.worlds.take(h.id);
    });
}

FIRELOOK_API fl_result fl_world_update(fl_world h, double dt) {
    return guarded("fl_world_update", [&] {
        checkFinite(dt, "dt");
        findWorld(h).update(dt);
    });
}

FIRELOOK_API fl_result fl_world_instance_count(fl_world h, uint32_t* out_count) {
    return guarded("fl_world_instance_count", [&] {
        checkPointer(out_count, "out_count");
        *out_count = static_cast<uint32_t>(findWorld(h).size());
    });
}

FIRELOOK_API fl_result fl_instance_create(fl_world w, const fl_instance_desc* desc, fl_instance* out) {
    return guarded("fl_instance_create", [&] {
        checkPointer(out, "out_instance");
        out->id = 0;
        checkIn(desc, "desc");
        runtime::World& world = findWorld(w);
        auto package = findPackage(desc->package);
        std::shared_ptr<const Look> look;
        if (desc->look.id != 0) look = findLook(desc->look);
        const runtime::InstanceHandle instance = world.create(std::move(package));
        if (look) {
            try {
                world.setLook(instance, *look);
            } catch (...) {
                world.destroy(instance);
                throw;
            }
        }
        out->id = instance;
    });
}

FIRELOOK_API fl_result fl_instance_destroy(fl_world w, fl_instance i) {
    return guarded("fl_instance_destroy", [&] { findWorld(w).destroy(instanceHandle(i)); });
}

FIRELOOK_API fl_result fl_instance_set_look(fl_world w, fl_instance i, fl_look l) {
    return guarded("fl_instance_set_look", [&] {
        runtime::World& world = findWorld(w);
        if (!world.valid(instanceHandle(i))) fail(FL_ERROR_INVALID_HANDLE, "stale or invalid instance handle");
        world.setLook(instanceHandle(i), *findLook(l));
    });
}

FIRELOOK_API fl_result fl_instance_set_keyframes(fl_world w, fl_instance i, const fl_keyframe* keys, uint32_t count) {
    return guarded("fl_instance_set_keyframes", [&] {
        runtime::World& world = findWorld(w);
        if (!world.valid(instanceHandle(i))) fail(FL_ERROR_INVALID_HANDLE, "stale or invalid instance handle");
        checkPointer(keys, "keys");
        if (count == 0) fail(FL_ERROR_INVALID_ARGUMENT, "count is 0: at least one key is required");
        std::vector<std::pair<double, Look>> resolved;
        resolved.reserve(count);
        for (uint32_t k = 0; k < count; ++k) {
            checkFinite(keys[k].frame, "keys[].frame");
            resolved.emplace_back(keys[k].frame, *findLook(keys[k].look));
        }
        world.setKeyframes(instanceHandle(i), resolved);
    });
}

FIRELOOK_API fl_result fl_instance_set_playback(fl_world w, fl_instance i, const fl_playback_desc* desc) {
    return guarded("fl_instance_set_playback", [&] {
        checkIn(desc, "desc");
        checkFinite(desc->time, "desc->time");
        checkFinite(desc->rate, "desc->rate");
        runtime::PlaybackSettings pb;
        pb.time = desc->time;
        pb.rate = desc->rate != 0.0 ? desc->rate : 24.0;
        pb.playing = desc->paused == 0;
        pb.loop = desc->no_loop == 0;
        if (desc->use_frame_range) {
            pb.first_frame = desc->first_frame;
            pb.last_frame = desc->last_frame;
        }
        findWorld(w).setPlayback(instanceHandle(i), pb);
    });
}

FIRELOOK_API fl_result fl_instance_set_outputs(fl_world w, fl_instance i, const fl_outputs_desc* desc) {
    return guarded("fl_instance_set_outputs", [&] {
        checkIn(desc, "desc");
        runtime::OutputSettings out;
        out.image = desc->image != 0;
        out.lens_flare = desc->lens_flare != 0;
        runtime::LensFlareSettings& f = out.flare;
        const runtime::LensFlareSettings defaults;
        // 0 = default, negative = off (gains and counts); every value must be finite.
        const auto value = [](float given, float fallback, bool negative_is_off, const char* name) {
            if (!std::isfinite(given)) fail(FL_ERROR_INVALID_ARGUMENT, std::string(name) + " is not finite");
            if (given == 0.0f) return fallback;
            if (given < 0.0f) {
                if (negative_is_off) return 0.0f;
                fail(FL_ERROR_INVALID_ARGUMENT, std::string(name) + " must not be negative");
            }
            return given;
        };
        f.threshold = value(desc->flare_threshold, defaults.threshold, false, "flare_threshold");
        f.intensity = value(desc->flare_intensity, defaults.intensity, true, "flare_intensity");
        f.ghost_count = desc->ghost_count == 0 ? defaults.ghost_count : std::clamp(desc->ghost_count, 0, 8);
        f.ghost_spacing = value(desc->ghost_spacing, defaults.ghost_spacing, false, "ghost_spacing");
        f.halo_radius = value(desc->halo_radius, defaults.halo_radius, false, "halo_radius");
        f.halo_width = value(desc->halo_width, defaults.halo_width, false, "halo_width");
        f.halo_intensity = value(desc->halo_intensity, defaults.halo_intensity, true, "halo_intensity");
        f.streak_length = value(desc->streak_length, defaults.streak_length, false, "streak_length");
        f.streak_intensity = value(desc->streak_intensity, defaults.streak_intensity, true, "streak_intensity");
        f.streaks = desc->streaks == 0 ? defaults.streaks : std::clamp(desc->streaks, 0, 2);
        findWorld(w).setOutputs(instanceHandle(i), out);
    });
}

FIRELOOK_API fl_result fl_instance_get_state(fl_world w, fl_instance i, fl_instance_state* out) {
    return guarded("fl_instance_get_state", [&] {
        checkOut(out, "out_state");
        runtime::World& world = findWorld(w);
        const runtime::InstanceState s = world.state(instanceHandle(i));
        const basis::BakeDescription& d = world.package(instanceHandle(i)).description();
        fl_instance_state r = {};
        r.struct_size = out->struct_size;
        r.updated = s.updated ? 1 : 0;
        r.frame = s.frame;
        r.rank = s.rank;
        r.frame_position = s.frame_position;
        r.time = s.time;
        r.temperature_threshold = s.extinction.temperature_threshold;
        r.smoke_extinction = s.extinction.smoke_extinction;
        r.flame_extinction = s.extinction.flame_extinction;
        r.extinction_a = static_cast<float>(s.extinction.a());
        r.extinction_b = static_cast<float>(s.extinction.b());
        // The same O_a interpolation as basis::reconstructImage (linear in T_c, clamped at the ends).
        const std::vector<double>& t = d.alpha_thresholds;
        const double tc = s.extinction.temperature_threshold;
        const int last = static_cast<int>(t.size()) - 1;
        if (last <= 0 || !(tc > t.front())) {
            r.alpha_layer_lower = r.alpha_layer_upper = 0;
        } else if (tc >= t.back()) {
            r.alpha_layer_lower = r.alpha_layer_upper = last;
        } else {
            const int upper = static_cast<int>(std::upper_bound(t.begin(), t.end(), tc) - t.begin());
            r.alpha_layer_lower = upper - 1;
            r.alpha_layer_upper = upper;
            r.alpha_layer_t = static_cast<float>((tc - t[upper - 1]) / (t[upper] - t[upper - 1]));
        }
        *out = r;
    });
}

FIRELOOK_API fl_result fl_instance_get_coefficients(fl_world w, fl_instance i, float* z, size_t capacity,
                                                    int32_t* out_rank) {
    return guarded("fl_instance_get_coefficients", [&] {
        const runtime::InstanceState s = findWorld(w).state(instanceHandle(i));
        if (out_rank) *out_rank = s.rank;
        if (capacity == 0 && !z) return;
        checkPointer(z, "z");
        if (!s.updated) fail(FL_ERROR_NO_DATA, "no fl_world_update since the instance was created");
        const size_t needed = static_cast<size_t>(s.rank) * 3;
        checkCapacity(capacity, needed, "floats");
        std::copy(s.z, s.z + needed, z);
    });
}

namespace {
fl_result copyImage(const char* function, fl_world w, fl_instance i, float* rgba, size_t capacity, bool flare) {
    return guarded(function, [&] {
        checkPointer(rgba, "rgba");
        runtime::World& world = findWorld(w);
        const runtime::InstanceState s = world.state(instanceHandle(i));
        const float* src = flare ? s.flare : s.image;
        if (!src)
            fail(FL_ERROR_NO_DATA, flare ? "the lens flare output is off or no update ran since it was turned on"
                                         : "the image output is off or no update ran since it was turned on");
        const size_t needed = static_cast<size_t>(world.package(instanceHandle(i)).description().pixelCount()) * 4;
        checkCapacity(capacity, needed, "floats");
        std::copy(src, src + needed, rgba);
    });
}
}  // namespace

FIRELOOK_API fl_result fl_instance_get_image(fl_world w, fl_instance i, float* rgba, size_t capacity) {
    return copyImage("fl_instance_get_image", w, i, rgba, capacity, false);
}

FIRELOOK_API fl_result fl_instance_get_flare(fl_world w, fl_instance i, float* rgba, size_t capacity) {
    return copyImage("fl_instance_get_flare", w, i, rgba, capacity, true);
}

}  // extern "C"
