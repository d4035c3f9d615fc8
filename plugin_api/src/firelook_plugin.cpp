// The C API (include/firelook/firelook.h) over firelook::world. Every entry
// point runs inside guarded(): exceptions become result codes plus a
// per-thread message, so nothing C++ crosses the boundary.
#include "firelook/firelook.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <memory_resource>
#include <mutex>
#include <new>
#include <span>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "basis/fire_lights.h"
#include "basis/fire_probes.h"
#include "basis/parameter_grid.h"
#include "common/error.h"
#include "fit/look_fit.h"
#include "gpu_layers.h"
#include "image/fit_target.h"
#include "look/emission_presets.h"
#include "look/look.h"
#include "look_desc.h"
#include "result_table.h"
#include "struct_rule.h"
#include "world/handle_pool.h"
#include "world/world.h"

namespace {

using namespace firelook;
using plugin::FirstSize;

// ---- errors -----------------------------------------------------------------

// A failure the plugin itself detects is a firelook::Error like the runtime's, with the C API's own
// codes in the one list (common/error.h): guarded() maps every code by plugin::toResult.
[[noreturn]] void fail(ErrorCode code, const std::string& message) { throw Error(code, message); }

thread_local std::string t_last_error;

// ---- the library context ---------------------------------------------------

// An instance handle of the C API: which world made it, and the world's own handle for it.
struct InstanceRecord {
    uint32_t world = 0;
    world::InstanceHandle handle = 0;
};

struct Context {
    std::mutex mutex;
    bool initialized = false;
    world::MemoryHooks memory;
    fl_log_fn log = nullptr;
    void* log_user = nullptr;
    int32_t log_level = 0;
    uint32_t keyframe_stride = sizeof(fl_keyframe);  // the caller's sizeof_keyframe
    world::HandlePool<std::shared_ptr<const world::Package>> packages{world::HandleKind::Package};
    world::HandlePool<std::shared_ptr<const Look>> looks{world::HandleKind::Look};
    world::HandlePool<std::shared_ptr<world::World>> worlds{world::HandleKind::World};
    world::HandlePool<InstanceRecord> instances{world::HandleKind::Instance};
};

Context& context() {
    static Context* c = new Context;  // never destroyed: safe to use from late static destructors
    return *c;
}

void logMessage(int32_t level, const std::string& message) {
    Context& c = context();
    if (c.log && level >= c.log_level) c.log(level, message.c_str(), c.log_user);
}

template <typename F>
fl_result guarded(const char* function, F&& body) noexcept {
    fl_result code = FL_OK;
    std::string message;
    try {
        body();
        t_last_error.clear();
        return FL_OK;
    } catch (const Error& e) {
        code = plugin::toResult(e.code());
        message = e.what();
    } catch (const std::bad_alloc&) {  // the standard library's allocations (the C++ runtime's, not ours)
        code = plugin::toResult(ErrorCode::OutOfMemory);
        message = "out of memory";
    } catch (const std::exception& e) {  // uncoded: a third-party library's, or a bug
        code = plugin::toResult(ErrorCode::Internal);
        message = e.what();
    } catch (...) {
        code = plugin::toResult(ErrorCode::Internal);
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
    if (!c.initialized) fail(ErrorCode::NotInitialized, "fl_init has not been called (or failed)");
}

// Null and struct_size checks of a caller's struct (the struct rule, struct_rule.h).
template <typename T>
void checkStruct(const T* p, const char* what) {
    if (!p) fail(ErrorCode::InvalidArgument, std::string(what) + " is null");
    const uint32_t size = plugin::callerStructSize(p);
    if (size < FirstSize<T>::value)
        fail(ErrorCode::StructSize, std::string(what) + "->struct_size is " + std::to_string(size) +
                                        ", expected at least " + std::to_string(FirstSize<T>::value) +
                                        " (initialise it with the *_defaults() function)");
}

// The library's copy of a caller's input struct.
template <typename T>
T readIn(const T* p, const char* what) {
    checkStruct(p, what);
    return plugin::copyIn<T>(p, plugin::callerStructSize(p));
}

// Writes an output struct as far as the caller's struct_size reaches (checkStruct first).
template <typename T>
void writeOut(T* p, const T& value) {
    plugin::copyOut<T>(p, plugin::callerStructSize(p), value);
}

template <typename T>
void checkPointer(T* p, const char* what) {
    if (!p) fail(ErrorCode::InvalidArgument, std::string(what) + " is null");
}

// The pools' get() throws world::InvalidHandle (FL_ERROR_INVALID_HANDLE) saying why.
std::shared_ptr<const world::Package> findPackage(fl_package h) {
    Context& c = context();
    std::lock_guard lock(c.mutex);
    requireInit(c);
    return c.packages.get(h.id);
}

std::shared_ptr<const Look> findLook(fl_look h) {
    Context& c = context();
    std::lock_guard lock(c.mutex);
    requireInit(c);
    return c.looks.get(h.id);
}

world::World& findWorld(fl_world h) {
    Context& c = context();
    std::lock_guard lock(c.mutex);
    requireInit(c);
    return *c.worlds.get(h.id);  // caller guarantees the world is not destroyed concurrently
}

struct WorldInstance {
    world::World& world;
    world::InstanceHandle instance;
};

// The world and the world's handle of an instance; refuses an instance that world did not create.
WorldInstance findInstance(fl_world w, fl_instance i) {
    Context& c = context();
    std::lock_guard lock(c.mutex);
    requireInit(c);
    world::World& world = *c.worlds.get(w.id);
    const InstanceRecord& record = c.instances.get(i.id);
    if (record.world != w.id)
        throw world::InvalidHandle("invalid instance handle " + std::to_string(i.id) + ": it belongs to another world (" +
                                     std::to_string(record.world) + "), not to world " + std::to_string(w.id));
    return {world, record.handle};
}

// Adds a look to the pool (the handle goes to *out).
void addLook(std::shared_ptr<const Look> look, fl_look* out) {
    Context& c = context();
    std::lock_guard lock(c.mutex);
    requireInit(c);
    out->id = c.looks.add(std::move(look));
}

void checkFinite(double v, const char* what) {
    if (!std::isfinite(v)) fail(ErrorCode::InvalidArgument, std::string(what) + " is not finite");
}

// The header's size convention: a call with capacity 0 only asks for the size (whatever the buffer
// pointer is), so an engine can pass its one scratch pointer for both calls.
bool isSizeQuery(size_t capacity) { return capacity == 0; }

// Writes text + NUL into a caller buffer with the size convention of the header.
void writeText(const std::string& text, char* buffer, size_t capacity, size_t* out_size) {
    const size_t needed = text.size() + 1;
    if (out_size) *out_size = needed;
    if (isSizeQuery(capacity)) return;
    if (!buffer) fail(ErrorCode::InvalidArgument, "buffer is null");
    if (capacity < needed)
        fail(ErrorCode::BufferTooSmall,
             "buffer holds " + std::to_string(capacity) + " bytes, " + std::to_string(needed) + " needed");
    std::memcpy(buffer, text.data(), text.size());
    buffer[text.size()] = '\0';
}

void checkCapacity(size_t capacity, size_t needed, const char* unit) {
    if (capacity < needed)
        fail(ErrorCode::BufferTooSmall, "buffer holds " + std::to_string(capacity) + " " + unit + ", " +
                                            std::to_string(needed) + " needed");
}

int slotOrFail(const world::Package& p, int32_t frame) {
    const int slot = p.slotOf(frame);
    if (slot < 0)
        fail(ErrorCode::NotFound, p.name() + ": no frame " + std::to_string(frame) + " in the package");
    return slot;
}

// fl_package_load and fl_package_load_memory: the checks before opening, then the opened package
// (opened outside the lock: it reads and validates) into the pool.
template <typename Open>
void loadPackage(fl_package* out, Open&& open) {
    checkPointer(out, "out_package");
    out->id = 0;
    {
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
    }
    std::shared_ptr<const world::Package> package = open();
    const auto& d = package->description();
    const std::string loaded = "loaded " + package->name() + " (" + std::to_string(d.width) + "x" +
                               std::to_string(d.height) + ", " + std::to_string(d.frames.size()) + " frames)";
    Context& c = context();
    std::lock_guard lock(c.mutex);
    requireInit(c);
    out->id = c.packages.add(std::move(package));
    logMessage(FL_LOG_INFO, loaded);
}

}  // namespace

extern "C" {

FIRELOOK_API const char* fl_result_string(fl_result r) {
    switch (r) {
#define FIRELOOK_RESULT_NAME(name, value) \
    case name: return #name;
        FIRELOOK_RESULTS(FIRELOOK_RESULT_NAME)
#undef FIRELOOK_RESULT_NAME
        default: return "FL_ERROR_UNKNOWN";
    }
}

FIRELOOK_API const char* fl_last_error(void) { return t_last_error.c_str(); }

FIRELOOK_API uint32_t fl_version(void) { return FIRELOOK_HEADER_VERSION; }

FIRELOOK_API fl_result fl_init(const fl_init_desc* caller) {
    return guarded("fl_init", [&] {
        // struct_size first (every header version puts it first): 0 or below the first published
        // size is FL_ERROR_STRUCT_SIZE, as for every struct (firelook.h); then the version, before the
        // rest is read, since a mismatched header may lay the struct out differently.
        checkStruct(caller, "desc");
        uint32_t version = 0;
        std::memcpy(&version, reinterpret_cast<const char*>(caller) + offsetof(fl_init_desc, header_version),
                    sizeof version);
        if (version == 0 || version / 10000 != FIRELOOK_VERSION_MAJOR || version / 100 % 100 > FIRELOOK_VERSION_MINOR)
            fail(ErrorCode::VersionMismatch, "the caller was compiled against FireLook header version " +
                                                 std::to_string(version) + ", this library is " +
                                                 std::to_string(FIRELOOK_HEADER_VERSION) +
                                                 " (same major and a minor no newer required)");
        const fl_init_desc desc = readIn(caller, "desc");
        // The caller's struct sizes (IMGUI_CHECKVERSION): each at least its first published size.
        const struct {
            uint32_t given;
            size_t first;
            const char* name;
        } sizes[] = {{desc.sizeof_world_desc, FirstSize<fl_world_desc>::value, "fl_world_desc"},
                     {desc.sizeof_instance_desc, FirstSize<fl_instance_desc>::value, "fl_instance_desc"},
                     {desc.sizeof_playback_desc, FirstSize<fl_playback_desc>::value, "fl_playback_desc"},
                     {desc.sizeof_outputs_desc, FirstSize<fl_outputs_desc>::value, "fl_outputs_desc"},
                     {desc.sizeof_package_info, FirstSize<fl_package_info>::value, "fl_package_info"},
                     {desc.sizeof_instance_state, FirstSize<fl_instance_state>::value, "fl_instance_state"},
                     {desc.sizeof_keyframe, FirstSize<fl_keyframe>::value, "fl_keyframe"}};
        for (const auto& s : sizes)
            if (s.given < s.first)
                fail(ErrorCode::VersionMismatch,
                     std::string("sizeof(") + s.name + ") is " + std::to_string(s.given) +
                         " in the caller, below its first published size " + std::to_string(s.first) +
                         ": header and library do not match");
        if ((desc.allocator.alloc == nullptr) != (desc.allocator.free == nullptr))
            fail(ErrorCode::InvalidArgument, "allocator: set both alloc and free, or neither");
        Context& c = context();
        std::lock_guard lock(c.mutex);
        if (c.initialized) fail(ErrorCode::AlreadyInitialized, "fl_init called twice without fl_shutdown");
        c.memory = {desc.allocator.alloc, desc.allocator.free, desc.allocator.user};
        c.log = desc.log;
        c.log_user = desc.log_user;
        c.log_level = desc.log_level;
        c.keyframe_stride = desc.sizeof_keyframe;
        c.initialized = true;
        logMessage(FL_LOG_INFO, "FireLook runtime " + std::to_string(FIRELOOK_HEADER_VERSION) + " initialised");
    });
}

FIRELOOK_API fl_result fl_shutdown(void) {
    return guarded("fl_shutdown", [&] {
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        c.instances.clear();
        c.worlds.clear();  // before the packages: their instances hold packages
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
        loadPackage(out, [&] {
            std::error_code ec;
            if (!std::filesystem::is_regular_file(path, ec))
                fail(ErrorCode::IoError, std::string(path) + ": no such file (or not a regular file)");
            return world::Package::open(path);
        });
    });
}

FIRELOOK_API fl_result fl_package_load_memory(const void* data, size_t size, const char* source_name,
                                              const fl_package_memory_desc* desc, fl_package* out) {
    return guarded("fl_package_load_memory", [&] {
        if (out) out->id = 0;  // 0 on every failure, the argument checks' too
        const std::string name = source_name ? source_name : "(memory)";
        if (!data) fail(ErrorCode::InvalidArgument, name + ": data is null");
        if (size == 0) fail(ErrorCode::InvalidArgument, name + ": size is 0");
        fl_package_memory_desc d = fl_package_memory_desc_defaults();
        if (desc) d = readIn(desc, "desc");
        // Unknown bits may be a newer caller's promise this library cannot keep: refused, not ignored.
        if ((d.flags & ~uint32_t{FL_PACKAGE_MEMORY_BORROW}) != 0)
            fail(ErrorCode::InvalidArgument,
                 name + ": desc->flags has unknown bits (" + std::to_string(d.flags) + ")");
        const auto ownership = (d.flags & FL_PACKAGE_MEMORY_BORROW) != 0 ? package::ContainerReader::MemoryOwnership::Borrow
                                                                         : package::ContainerReader::MemoryOwnership::Copy;
        loadPackage(out, [&] {
            return world::Package::openMemory({static_cast<const std::byte*>(data), size}, ownership, name);
        });
    });
}

FIRELOOK_API fl_result fl_package_release(fl_package h) {
    return guarded("fl_package_release", [&] {
        std::shared_ptr<const world::Package> doomed;
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        doomed = c.packages.take(h.id);
    });
}

FIRELOOK_API fl_result fl_package_get_info(fl_package h, fl_package_info* out) {
    return guarded("fl_package_get_info", [&] {
        checkStruct(out, "out_info");
        const auto p = findPackage(h);
        const basis::BakeDescription& d = p->description();
        fl_package_info info = {};
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
        writeOut(out, info);
    });
}

FIRELOOK_API fl_result fl_package_get_frames(fl_package h, int32_t* numbers, int32_t* ranks, uint32_t capacity,
                                             uint32_t* out_count) {
    return guarded("fl_package_get_frames", [&] {
        const auto p = findPackage(h);
        const uint32_t n = static_cast<uint32_t>(p->frameCount());
        if (out_count) *out_count = n;
        if ((!numbers && !ranks) || isSizeQuery(capacity)) return;
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

namespace {
// A frame of a package outside any world, in the resident form the world keeps, so the fl_package_
// and fl_instance_ layer calls write the same bytes by the same code (gpu_layers.h).
basis::ResidentFrame residentFrame(const world::Package& p, int slot) {
    return p.loadResidentSlot(slot, std::pmr::new_delete_resource(), nullptr);
}
}  // namespace

FIRELOOK_API fl_result fl_package_get_frame_u(fl_package h, int32_t frame, uint16_t* buffer, size_t capacity,
                                              size_t* out_count) {
    return guarded("fl_package_get_frame_u", [&] {
        const auto p = findPackage(h);
        const int slot = slotOrFail(*p, frame);
        const size_t needed = plugin::uLayerElements(p->frameRank(slot), static_cast<size_t>(p->description().pixelCount()));
        if (out_count) *out_count = needed;
        if (isSizeQuery(capacity)) return;
        checkPointer(buffer, "buffer");
        checkCapacity(capacity, needed, "uint16_t elements");
        plugin::writeULayers(residentFrame(*p, slot), buffer);
    });
}

FIRELOOK_API fl_result fl_package_get_frame_depths(fl_package h, int32_t frame, float* buffer, size_t capacity,
                                                   size_t* out_count) {
    return guarded("fl_package_get_frame_depths", [&] {
        const auto p = findPackage(h);
        const int slot = slotOrFail(*p, frame);
        const size_t needed = plugin::depthLayerFloats(p->description());
        if (out_count) *out_count = needed;
        if (isSizeQuery(capacity)) return;
        checkPointer(buffer, "buffer");
        checkCapacity(capacity, needed, "floats");
        plugin::writeDepthLayers(p->description(), residentFrame(*p, slot), buffer);
    });
}

FIRELOOK_API fl_result fl_package_get_camera(fl_package h, fl_camera* out) {
    return guarded("fl_package_get_camera", [&] {
        checkStruct(out, "out_camera");
        const auto p = findPackage(h);
        const world::PackageCamera* camera = p->camera();
        if (!camera) {
            if (!p->cameraProblem().empty()) fail(ErrorCode::Corrupt, p->cameraProblem());
            fail(ErrorCode::NotFound,
                 p->name() + ": the package records no camera (its META has no \"camera\")");
        }
        fl_camera c = {};
        c.width = camera->width;
        c.height = camera->height;
        c.yfov_radians = camera->yfov_radians;  // finite and the matrix too: readPackageCamera checks
        std::copy(camera->world_from_camera.begin(), camera->world_from_camera.end(), c.world_from_camera);
        writeOut(out, c);
    });
}

FIRELOOK_API fl_result fl_package_get_lights(fl_package h, double* directions, float* irradiance, uint32_t capacity,
                                             uint32_t* out_count) {
    return guarded("fl_package_get_lights", [&] {
        const auto p = findPackage(h);
        const std::vector<glm::dvec3>& d = p->description().light_directions;
        const std::vector<Rgb>& e = p->defaultLook().light_irradiance;  // one per light (resolveLook checked)
        const uint32_t n = static_cast<uint32_t>(d.size());
        if (out_count) *out_count = n;
        if ((!directions && !irradiance) || isSizeQuery(capacity)) return;
        checkCapacity(capacity, n, "entries");
        // Every direction checked before anything is written: a failed call writes nothing.
        std::vector<double> unit(3 * size_t{n});
        for (uint32_t l = 0; l < n; ++l) {
            const double length = std::sqrt(d[l].x * d[l].x + d[l].y * d[l].y + d[l].z * d[l].z);
            if (!std::isfinite(length) || !(length > 0.0))  // a guard: Package::open refuses such lights
                fail(ErrorCode::Corrupt,
                     p->name() + ": light " + std::to_string(l) + "'s direction is zero or not finite");
            for (int i = 0; i < 3; ++i) unit[3 * l + i] = d[l][i] / length;
        }
        if (directions) std::copy(unit.begin(), unit.end(), directions);
        if (irradiance)
            for (uint32_t l = 0; l < n; ++l)
                for (int c = 0; c < 3; ++c) irradiance[3 * l + c] = e[l][c];
    });
}

FIRELOOK_API fl_result fl_package_get_metadata_json(fl_package h, char* buffer, size_t capacity, size_t* out_size) {
    return guarded("fl_package_get_metadata_json", [&] {
        const auto p = findPackage(h);
        writeText(p->basis().metadataJson(), buffer, capacity, out_size);
    });
}

// ---- looks --------------------------------------------------------------------

FIRELOOK_API fl_result fl_look_from_json(const char* json, size_t length, const char* source_name, fl_look* out) {
    return guarded("fl_look_from_json", [&] {
        checkPointer(json, "json");
        checkPointer(out, "out_look");
        out->id = 0;
        const std::string_view text(json, length ? length : std::strlen(json));
        addLook(std::make_shared<const Look>(parseLook(text, source_name ? source_name : "look")), out);
    });
}

FIRELOOK_API fl_result fl_package_default_look(fl_package h, fl_look* out) {
    return guarded("fl_package_default_look", [&] {
        checkPointer(out, "out_look");
        out->id = 0;
        const auto p = findPackage(h);
        addLook(std::make_shared<const Look>(p->defaultLook()), out);  // parsed once, by Package::open
    });
}

FIRELOOK_API fl_result fl_look_release(fl_look h) {
    return guarded("fl_look_release", [&] {
        std::shared_ptr<const Look> doomed;
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        doomed = c.looks.take(h.id);
    });
}

FIRELOOK_API fl_result fl_look_to_json(fl_look h, char* buffer, size_t capacity, size_t* out_size) {
    return guarded("fl_look_to_json", [&] { writeText(lookToJson(*findLook(h)), buffer, capacity, out_size); });
}

FIRELOOK_API fl_result fl_look_get_bin_emissivity(fl_look lh, fl_package ph, float* rgb, uint32_t capacity,
                                                  uint32_t* out_count) {
    return guarded("fl_look_get_bin_emissivity", [&] {
        const auto look = findLook(lh);
        const auto p = findPackage(ph);
        const TemperatureBins& bins = p->description().bins;
        const uint32_t n = static_cast<uint32_t>(bins.count);
        if (out_count) *out_count = n;
        if (!rgb || isSizeQuery(capacity)) return;
        checkCapacity(capacity, n, "bins");
        const std::vector<Rgb> e = resolveBinEmissivity(*look, bins);  // LookError: a bins form of another count
        for (const Rgb& v : e)
            for (int c = 0; c < 3; ++c)
                if (!std::isfinite(v[c]))  // looks are validated finite; a guard, as nothing non-finite leaves
                    fail(ErrorCode::Look, look->source_name + ": the emission is not finite at a bin centre");
        for (uint32_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) rgb[3 * i + c] = e[i][c];
    });
}

FIRELOOK_API fl_result fl_look_create(const fl_look_desc* desc_in, const char* source_name, fl_look* out) {
    return guarded("fl_look_create", [&] {
        checkPointer(out, "out_look");
        out->id = 0;
        const fl_look_desc desc = readIn(desc_in, "desc");
        addLook(std::make_shared<const Look>(plugin::lookFromDesc(desc, source_name ? source_name : "look")), out);
    });
}

FIRELOOK_API fl_result fl_look_get_desc(fl_look h, fl_look_desc* out_desc, double* stops, uint32_t stop_capacity,
                                        float* bins, uint32_t bin_capacity, float* lights, uint32_t light_capacity) {
    return guarded("fl_look_get_desc", [&] {
        checkStruct(out_desc, "out_desc");
        const auto look = findLook(h);
        const fl_look_desc desc = plugin::descOf(*look);
        // Each array: capacity 0 leaves it unwritten; else it must hold the whole array.
        const auto buffer = [](auto* pointer, uint32_t capacity, uint32_t count, size_t per, const char* what) {
            using Span = std::span<std::remove_pointer_t<decltype(pointer)>>;
            if (isSizeQuery(capacity)) return Span();
            checkPointer(pointer, what);
            checkCapacity(capacity, count, what);
            return Span(pointer, size_t{count} * per);
        };
        const auto stop_span = buffer(stops, stop_capacity, desc.stop_count, 4, "stops");
        const auto bin_span = buffer(bins, bin_capacity, desc.bin_count, 3, "bins");
        const auto light_span = buffer(lights, light_capacity, desc.light_count, 3, "lights");
        plugin::writeLookArrays(*look, stop_span, bin_span, light_span);
        writeOut(out_desc, desc);
    });
}

FIRELOOK_API fl_result fl_look_load_file(const char* path, fl_look* out) {
    return guarded("fl_look_load_file", [&] {
        checkPointer(path, "path");
        checkPointer(out, "out_look");
        out->id = 0;
        addLook(std::make_shared<const Look>(loadLook(path)), out);  // LookError coded IoError or Look
    });
}

FIRELOOK_API fl_result fl_emission_preset_count(uint32_t* out_count) {
    return guarded("fl_emission_preset_count", [&] {
        checkPointer(out_count, "out_count");
        *out_count = static_cast<uint32_t>(presetNames().size());
    });
}

FIRELOOK_API fl_result fl_emission_preset_name(uint32_t index, char* buffer, size_t capacity, size_t* out_size) {
    return guarded("fl_emission_preset_name", [&] {
        const std::vector<std::string> names = presetNames();
        if (index >= names.size())
            fail(ErrorCode::NotFound, "no emission preset " + std::to_string(index) + " (there are " +
                                         std::to_string(names.size()) + ")");
        writeText(names[index], buffer, capacity, out_size);
    });
}

// ---- inverse design -------------------------------------------------------------

FIRELOOK_API fl_result fl_package_fit_look(fl_package h, const fl_fit_desc* desc_in, fl_look* out,
                                           fl_fit_report* report) {
    return guarded("fl_package_fit_look", [&] {
        checkPointer(out, "out_look");
        out->id = 0;
        const fl_fit_desc desc = readIn(desc_in, "desc");
        if (report) checkStruct(report, "out_report");
        const auto p = findPackage(h);
        const basis::BakeDescription& d = p->description();
        const int slot = slotOrFail(*p, desc.frame);
        constexpr uint32_t known = FL_FIT_HOLD_TEMPERATURE_THRESHOLD | FL_FIT_HOLD_SMOKE_EXTINCTION |
                                   FL_FIT_HOLD_FLAME_EXTINCTION | FL_FIT_OVER_BACKGROUND;
        if (desc.flags & ~known) fail(ErrorCode::InvalidArgument, "desc->flags has unknown bits");
        checkPointer(desc.target_rgba, "desc->target_rgba");
        checkFinite(desc.smoothness, "desc->smoothness");

        const size_t pixels = static_cast<size_t>(d.pixelCount());
        fit::FrameTarget target;
        target.frame = desc.frame;
        target.rgba.assign(desc.target_rgba, desc.target_rgba + pixels * 4);
        if (desc.weights) target.weight.assign(desc.weights, desc.weights + pixels);
        target.match_alpha = !(desc.flags & FL_FIT_OVER_BACKGROUND);
        if (!target.match_alpha) target.background = Rgb(desc.background[0], desc.background[1], desc.background[2]);
        fit::FitOptions options;
        options.smoothness = desc.smoothness;
        if (desc.flags & FL_FIT_HOLD_TEMPERATURE_THRESHOLD) options.temperature_threshold = desc.temperature_threshold;
        if (desc.flags & FL_FIT_HOLD_SMOKE_EXTINCTION) options.smoke_extinction = desc.smoke_extinction;
        if (desc.flags & FL_FIT_HOLD_FLAME_EXTINCTION) options.flame_extinction = desc.flame_extinction;

        const basis::ResidentFrame frame = p->loadResidentSlot(slot, std::pmr::get_default_resource(), nullptr);
        const basis::ResidentFrame* frames[] = {&frame};
        const fit::FitResult r = fit::fitLook(d, frames, std::span(&target, 1), options, [&](double fraction) {
            if (desc.progress && desc.progress(fraction, desc.progress_user) != 0)
                fail(ErrorCode::Cancelled, "the progress callback stopped the fit");
        });
        if (report) {
            fl_fit_report out_report{};
            out_report.relative_rmse = r.relative_rmse;
            out_report.alpha_rmse = r.alpha_rmse;
            out_report.alpha_max_error = r.alpha_max_error;
            out_report.evaluations = r.evaluations;
            writeOut(report, out_report);
        }
        addLook(std::make_shared<const Look>(r.look), out);
    });
}

FIRELOOK_API fl_result fl_fit_target_load(fl_package h, const fl_fit_target_desc* desc_in, float* rgba,
                                          float* weights, size_t pixel_capacity, size_t* out_pixel_count,
                                          fl_fit_target_info* out_info) {
    return guarded("fl_fit_target_load", [&] {
        const fl_fit_target_desc desc = readIn(desc_in, "desc");
        const auto p = findPackage(h);
        const basis::BakeDescription& d = p->description();
        const size_t pixels = static_cast<size_t>(d.pixelCount());
        if (out_pixel_count) *out_pixel_count = pixels;
        if (isSizeQuery(pixel_capacity)) return;
        checkPointer(desc.target_path, "desc->target_path");
        checkPointer(rgba, "rgba");
        checkPointer(weights, "weights");
        checkStruct(out_info, "out_info");
        if (desc.flags & ~static_cast<uint32_t>(FL_FIT_OVER_BACKGROUND))
            fail(ErrorCode::InvalidArgument, "desc->flags has bits other than FL_FIT_OVER_BACKGROUND");
        checkFinite(desc.exposure, "desc->exposure");
        checkCapacity(pixel_capacity, pixels, "pixels");
        image::FitTargetRequest request;
        request.target = desc.target_path;
        if (desc.mask_path) request.mask = desc.mask_path;
        request.width = d.width;
        request.height = d.height;
        request.frame = desc.frame;
        if (desc.flags & FL_FIT_OVER_BACKGROUND) {
            for (int c = 0; c < 3; ++c) checkFinite(desc.background[c], "desc->background");
            request.background = std::array<float, 3>{desc.background[0], desc.background[1], desc.background[2]};
        }
        request.exposure = desc.exposure;
        const image::FitTargetImage target = image::readFitTarget(request);  // Error: IoError or InvalidArgument
        std::copy(target.rgba.begin(), target.rgba.end(), rgba);
        std::copy(target.weight.begin(), target.weight.end(), weights);
        fl_fit_target_info info{};
        info.flags = target.match_alpha ? 0u : static_cast<uint32_t>(FL_FIT_OVER_BACKGROUND);
        for (int c = 0; c < 3; ++c) info.background[c] = target.background[c];
        info.clipped_pixels = target.clipped_pixels;
        writeOut(out_info, info);
    });
}

FIRELOOK_API fl_result fl_fit_difference(const float* target_rgba, const float* fit_rgba, size_t pixel_count,
                                         uint32_t flags, const float* background, float* out_rgba) {
    return guarded("fl_fit_difference", [&] {
        checkPointer(target_rgba, "target_rgba");
        checkPointer(fit_rgba, "fit_rgba");
        checkPointer(out_rgba, "out_rgba");
        if (pixel_count == 0) fail(ErrorCode::InvalidArgument, "pixel_count is 0");
        if (flags & ~static_cast<uint32_t>(FL_FIT_OVER_BACKGROUND))
            fail(ErrorCode::InvalidArgument, "flags has bits other than FL_FIT_OVER_BACKGROUND");
        const bool over = flags & FL_FIT_OVER_BACKGROUND;
        if (over) checkPointer(background, "background");
        const std::array<float, 3> bg = over ? std::array<float, 3>{background[0], background[1], background[2]}
                                             : std::array<float, 3>{0.0f, 0.0f, 0.0f};
        const std::vector<float> difference =
            image::fitDifference(std::vector<float>(target_rgba, target_rgba + 4 * pixel_count), !over, bg,
                                 std::vector<float>(fit_rgba, fit_rgba + 4 * pixel_count));
        std::copy(difference.begin(), difference.end(), out_rgba);
    });
}

// ---- worlds -------------------------------------------------------------------

FIRELOOK_API fl_result fl_world_create(const fl_world_desc* desc, fl_world* out) {
    return guarded("fl_world_create", [&] {
        checkPointer(out, "out_world");
        out->id = 0;
        world::WorldSettings settings;
        if (desc) {
            const fl_world_desc d = readIn(desc, "desc");
            if (d.frame_cache_bytes) settings.frame_cache_bytes = static_cast<size_t>(d.frame_cache_bytes);
        }
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        settings.memory = c.memory;
        out->id = c.worlds.add(std::make_shared<world::World>(settings));
    });
}

FIRELOOK_API fl_result fl_world_destroy(fl_world h) {
    return guarded("fl_world_destroy", [&] {
        std::shared_ptr<world::World> doomed;
        Context& c = context();
        std::lock_guard lock(c.mutex);
        requireInit(c);
        doomed = c.worlds.take(h.id);
        c.instances.eraseIf([&](const InstanceRecord& r) { return r.world == h.id; });
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

FIRELOOK_API fl_result fl_world_memory(fl_world h, uint64_t* frame_cache_bytes, uint64_t* instance_bytes) {
    return guarded("fl_world_memory", [&] {
        const world::World& world = findWorld(h);
        if (frame_cache_bytes) *frame_cache_bytes = world.cacheBytes();
        if (instance_bytes) *instance_bytes = world.instanceBytes();
    });
}

FIRELOOK_API fl_result fl_instance_create(fl_world w, const fl_instance_desc* desc, fl_instance* out) {
    return guarded("fl_instance_create", [&] {
        checkPointer(out, "out_instance");
        out->id = 0;
        const fl_instance_desc d = readIn(desc, "desc");
        world::World& world = findWorld(w);
        auto package = findPackage(d.package);
        std::shared_ptr<const Look> look;
        if (d.look.id != 0) look = findLook(d.look);
        const world::InstanceHandle instance = world.create(std::move(package));
        try {
            if (look) world.setLook(instance, *look);
            Context& c = context();
            std::lock_guard lock(c.mutex);
            out->id = c.instances.add({w.id, instance});
        } catch (...) {
            world.destroy(instance);
            throw;
        }
    });
}

FIRELOOK_API fl_result fl_instance_destroy(fl_world w, fl_instance i) {
    return guarded("fl_instance_destroy", [&] {
        const WorldInstance wi = findInstance(w, i);
        wi.world.destroy(wi.instance);
        Context& c = context();
        std::lock_guard lock(c.mutex);
        c.instances.take(i.id);
    });
}

FIRELOOK_API fl_result fl_instance_set_look(fl_world w, fl_instance i, fl_look l) {
    return guarded("fl_instance_set_look", [&] {
        const WorldInstance wi = findInstance(w, i);
        wi.world.setLook(wi.instance, *findLook(l));
    });
}

FIRELOOK_API fl_result fl_instance_set_keyframes(fl_world w, fl_instance i, const fl_keyframe* keys, uint32_t count) {
    return guarded("fl_instance_set_keyframes", [&] {
        const WorldInstance wi = findInstance(w, i);
        checkPointer(keys, "keys");
        if (count == 0) fail(ErrorCode::InvalidArgument, "count is 0: at least one key is required");
        // The caller's fl_keyframe may be older or newer than ours: step by its size (fl_init's sizeof_keyframe).
        const size_t stride = context().keyframe_stride;
        const auto* bytes = reinterpret_cast<const unsigned char*>(keys);
        std::vector<std::pair<double, Look>> resolved;
        resolved.reserve(count);
        for (uint32_t k = 0; k < count; ++k) {
            const fl_keyframe key = plugin::copyIn<fl_keyframe>(bytes + k * stride, stride);
            checkFinite(key.frame, "keys[].frame");
            resolved.emplace_back(key.frame, *findLook(key.look));
        }
        wi.world.setKeyframes(wi.instance, resolved);
    });
}

FIRELOOK_API fl_result fl_instance_set_playback(fl_world w, fl_instance i, const fl_playback_desc* desc) {
    return guarded("fl_instance_set_playback", [&] {
        const fl_playback_desc d = readIn(desc, "desc");
        checkFinite(d.time, "desc->time");
        checkFinite(d.rate, "desc->rate");
        world::PlaybackSettings pb;
        pb.time = d.time;
        pb.rate = d.rate != 0.0 ? d.rate : 24.0;
        pb.playing = d.paused == 0;
        pb.loop = d.no_loop == 0;
        if (d.use_frame_range) {
            pb.first_frame = d.first_frame;
            pb.last_frame = d.last_frame;
        }
        const WorldInstance wi = findInstance(w, i);
        wi.world.setPlayback(wi.instance, pb);
    });
}

FIRELOOK_API fl_result fl_instance_set_outputs(fl_world w, fl_instance i, const fl_outputs_desc* desc) {
    return guarded("fl_instance_set_outputs", [&] {
        const fl_outputs_desc d = readIn(desc, "desc");
        world::OutputSettings out;
        out.image = d.image != 0;
        out.lens_flare = d.lens_flare != 0;
        world::LensFlareSettings& f = out.flare;
        const world::LensFlareSettings defaults;
        // 0 = default, negative = off (gains and counts); every value must be finite.
        const auto value = [](float given, float fallback, bool negative_is_off, const char* name) {
            if (!std::isfinite(given)) fail(ErrorCode::InvalidArgument, std::string(name) + " is not finite");
            if (given == 0.0f) return fallback;
            if (given < 0.0f) {
                if (negative_is_off) return 0.0f;
                fail(ErrorCode::InvalidArgument, std::string(name) + " must not be negative");
            }
            return given;
        };
        f.threshold = value(d.flare_threshold, defaults.threshold, false, "flare_threshold");
        f.intensity = value(d.flare_intensity, defaults.intensity, true, "flare_intensity");
        f.ghost_count = d.ghost_count == 0 ? defaults.ghost_count : std::clamp(d.ghost_count, 0, 8);
        f.ghost_spacing = value(d.ghost_spacing, defaults.ghost_spacing, false, "ghost_spacing");
        f.halo_radius = value(d.halo_radius, defaults.halo_radius, false, "halo_radius");
        f.halo_width = value(d.halo_width, defaults.halo_width, false, "halo_width");
        f.halo_intensity = value(d.halo_intensity, defaults.halo_intensity, true, "halo_intensity");
        f.streak_length = value(d.streak_length, defaults.streak_length, false, "streak_length");
        f.streak_intensity = value(d.streak_intensity, defaults.streak_intensity, true, "streak_intensity");
        f.streaks = d.streaks == 0 ? defaults.streaks : std::clamp(d.streaks, 0, 2);
        const WorldInstance wi = findInstance(w, i);
        wi.world.setOutputs(wi.instance, out);
    });
}

FIRELOOK_API fl_result fl_instance_get_state(fl_world w, fl_instance i, fl_instance_state* out) {
    return guarded("fl_instance_get_state", [&] {
        checkStruct(out, "out_state");
        const WorldInstance wi = findInstance(w, i);
        const world::InstanceState s = wi.world.state(wi.instance);
        const basis::BakeDescription& d = wi.world.package(wi.instance).description();
        fl_instance_state r = {};
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
        // The O_a layers basis::reconstructImage blends (parameter_grid.h's bracket of T_c).
        const basis::SampleBracket layers = basis::sampleBracket(d.alpha_thresholds, s.extinction.temperature_threshold);
        r.alpha_layer_lower = layers.lower;
        r.alpha_layer_upper = layers.upper;
        r.alpha_layer_t = static_cast<float>(layers.t);
        writeOut(out, r);
    });
}

FIRELOOK_API fl_result fl_instance_get_coefficients(fl_world w, fl_instance i, float* z, size_t capacity,
                                                    int32_t* out_rank) {
    return guarded("fl_instance_get_coefficients", [&] {
        const WorldInstance wi = findInstance(w, i);
        const world::InstanceState s = wi.world.state(wi.instance);
        if (out_rank) *out_rank = s.rank;
        if (isSizeQuery(capacity)) return;
        checkPointer(z, "z");
        if (!s.updated) fail(ErrorCode::NoData, "no fl_world_update since the instance was created");
        const size_t needed = static_cast<size_t>(s.rank) * 3;
        checkCapacity(capacity, needed, "floats");
        std::copy(s.z, s.z + needed, z);
    });
}

namespace {
fl_result copyImage(const char* function, fl_world w, fl_instance i, float* rgba, size_t capacity, bool flare) {
    return guarded(function, [&] {
        checkPointer(rgba, "rgba");
        const WorldInstance wi = findInstance(w, i);
        const world::InstanceState s = wi.world.state(wi.instance);
        const float* src = flare ? s.flare : s.image;
        if (!src)
            fail(ErrorCode::NoData,
                 flare ? "the lens flare output is off or no update ran since it was turned on"
                       : "the image output is off or no update ran since it was turned on");
        const size_t needed = static_cast<size_t>(wi.world.package(wi.instance).description().pixelCount()) * 4;
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

FIRELOOK_API fl_result fl_instance_get_look(fl_world w, fl_instance i, fl_look* out) {
    return guarded("fl_instance_get_look", [&] {
        checkPointer(out, "out_look");
        out->id = 0;
        const WorldInstance wi = findInstance(w, i);
        addLook(std::make_shared<const Look>(wi.world.look(wi.instance)), out);
    });
}

namespace {
void requireSixWayLights(const world::Package& p) {
    if (p.description().six_way_first_light < 0)
        fail(ErrorCode::NotFound,
             p.name() + ": baked without six-way lights (firelook bake --lights six-way)");
}
}  // namespace

FIRELOOK_API fl_result fl_package_get_six_way_lights(fl_package h, int32_t* out_first_light) {
    return guarded("fl_package_get_six_way_lights", [&] {
        checkPointer(out_first_light, "out_first_light");
        const std::shared_ptr<const world::Package> p = findPackage(h);
        requireSixWayLights(*p);
        *out_first_light = p->description().six_way_first_light;
    });
}

namespace {
void requireRelightLights(const world::Package& p) {
    if (p.description().relightFirstLight() < 0)
        fail(ErrorCode::NotFound,
             p.name() +
                 ": baked without six-way or sphere lights (firelook bake --lights six-way or "
                 "--lights sphere)");
}

basis::RunTimeLight runTimeLight(const fl_light_direction_desc& d) {
    basis::RunTimeLight light;
    light.direction = {d.direction[0], d.direction[1], d.direction[2]};
    light.irradiance = {d.irradiance[0], d.irradiance[1], d.irradiance[2]};
    return light;
}
}  // namespace

FIRELOOK_API fl_result fl_package_get_relight_lights(fl_package h, int32_t* out_first_light,
                                                     int32_t* out_count) {
    return guarded("fl_package_get_relight_lights", [&] {
        checkPointer(out_first_light, "out_first_light");
        checkPointer(out_count, "out_count");
        const std::shared_ptr<const world::Package> p = findPackage(h);
        requireRelightLights(*p);
        *out_first_light = p->description().relightFirstLight();
        *out_count = p->description().relightLightCount();
    });
}

FIRELOOK_API fl_result fl_instance_set_light_direction(fl_world w, fl_instance i, const fl_light_direction_desc* desc) {
    return guarded("fl_instance_set_light_direction", [&] {
        const WorldInstance wi = findInstance(w, i);
        if (!desc) {
            wi.world.setLightDirection(wi.instance, std::nullopt);
            return;
        }
        const fl_light_direction_desc d = readIn(desc, "desc");
        requireRelightLights(wi.world.package(wi.instance));
        wi.world.setLightDirection(wi.instance, runTimeLight(d));  // refuses a zero or non-finite light
    });
}

FIRELOOK_API fl_result fl_instance_set_light_directions(fl_world w, fl_instance i,
                                                        const fl_light_direction_desc* lights,
                                                        uint32_t count) {
    return guarded("fl_instance_set_light_directions", [&] {
        const WorldInstance wi = findInstance(w, i);
        requireRelightLights(wi.world.package(wi.instance));
        std::vector<basis::RunTimeLight> resolved;
        if (count > 0) {
            checkStruct(lights, "lights");
            // The caller's struct may be older or newer than ours: step by its size.
            const uint32_t stride = plugin::callerStructSize(lights);
            const auto* bytes = reinterpret_cast<const unsigned char*>(lights);
            resolved.reserve(count);
            for (uint32_t k = 0; k < count; ++k) {
                const unsigned char* element = bytes + static_cast<size_t>(k) * stride;
                if (plugin::callerStructSize(element) != stride)
                    fail(ErrorCode::StructSize, "lights[" + std::to_string(k) + "].struct_size is " +
                                                    std::to_string(plugin::callerStructSize(element)) +
                                                    ", lights[0]'s is " + std::to_string(stride) +
                                                    ": every element must have the array's one size");
                resolved.push_back(runTimeLight(plugin::copyIn<fl_light_direction_desc>(element, stride)));
            }
        }
        wi.world.setLightDirections(wi.instance, resolved);  // refuses a zero or non-finite light
    });
}

namespace {
// The frame the instance's last update showed, from the world's cache.
const basis::ResidentFrame& shownFrame(const WorldInstance& wi) {
    const basis::ResidentFrame* frame = wi.world.shownFrame(wi.instance);
    if (!frame || !frame->depth_table)
        fail(ErrorCode::NoData, "no fl_world_update since the instance was created or its outputs were set");
    return *frame;
}
}  // namespace

FIRELOOK_API fl_result fl_instance_get_frame_u(fl_world w, fl_instance i, uint16_t* buffer, size_t capacity,
                                               size_t* out_count) {
    return guarded("fl_instance_get_frame_u", [&] {
        const WorldInstance wi = findInstance(w, i);
        const basis::ResidentFrame& frame = shownFrame(wi);
        const size_t needed = plugin::uLayerElements(frame.rank, static_cast<size_t>(frame.pixels));
        if (out_count) *out_count = needed;
        if (isSizeQuery(capacity)) return;
        checkPointer(buffer, "buffer");
        checkCapacity(capacity, needed, "uint16_t elements");
        plugin::writeULayers(frame, buffer);
    });
}

FIRELOOK_API fl_result fl_instance_get_frame_depths(fl_world w, fl_instance i, float* buffer, size_t capacity,
                                                    size_t* out_count) {
    return guarded("fl_instance_get_frame_depths", [&] {
        const WorldInstance wi = findInstance(w, i);
        const basis::ResidentFrame& frame = shownFrame(wi);
        const basis::BakeDescription& d = wi.world.package(wi.instance).description();
        const size_t needed = plugin::depthLayerFloats(d);
        if (out_count) *out_count = needed;
        if (isSizeQuery(capacity)) return;
        checkPointer(buffer, "buffer");
        checkCapacity(capacity, needed, "floats");
        plugin::writeDepthLayers(d, frame, buffer);
    });
}

}  // extern "C"

// ---- the fire as a light source ----------------------------------------------------------------

namespace {
// The fire lights of a package's frame (by slot) for a look's extinction and emission coefficients
// (or for `look`, resolved here, when rbf is empty), written with the caller's stride.
void writeFireLights(const world::Package& p, int slot, const Look* look, ExtinctionParams extinction,
                     std::span<const Rgb> rbf, uint32_t light_count, fl_fire_light* lights, uint32_t sizeof_light,
                     uint32_t capacity, uint32_t* out_max_count) {
    const basis::FireLightTable* table = p.fireLights(slot);
    const uint32_t stored = table ? static_cast<uint32_t>(table->clusters) : 0;
    if (out_max_count) *out_max_count = stored;
    if (light_count == 0 && !lights) return;
    if (!table)
        fail(ErrorCode::NotFound, p.name() + ": frame " + std::to_string(p.frameNumber(slot)) +
                                      " has no fire lights (baked before them)");
    if (!basis::validFireLightCount(*table, static_cast<int>(light_count)))
        fail(ErrorCode::InvalidArgument, "light_count " + std::to_string(light_count) +
                                             " is not a power of two from 1 to " + std::to_string(stored));
    checkPointer(lights, "lights");
    if (sizeof_light < FirstSize<fl_fire_light>::value)
        fail(ErrorCode::StructSize, "sizeof_light is " + std::to_string(sizeof_light) +
                                        ", expected at least " +
                                        std::to_string(FirstSize<fl_fire_light>::value));
    checkCapacity(capacity, light_count, "lights");
    world::ResolvedLook resolved;
    if (look) {
        resolved = world::resolveLook(*look, p.description());  // LookError
        extinction = resolved.extinction;
        rbf = resolved.rbf;
    }
    std::vector<basis::FireLight> out(light_count);
    basis::evaluateFireLights(*table, basis::interpolationWeights(p.description().axes, extinction), rbf,
                              static_cast<int>(light_count), out.data());
    for (uint32_t l = 0; l < light_count; ++l) {
        fl_fire_light v{};
        for (int i = 0; i < 3; ++i) {
            v.position[i] = out[l].position[i];
            v.intensity[i] = out[l].intensity[i];
        }
        v.radius = static_cast<float>(out[l].radius);
        // A guard, as nothing non-finite leaves: the table and the look are checked finite.
        for (float f : {v.intensity[0], v.intensity[1], v.intensity[2], v.radius})
            if (!std::isfinite(f)) fail(ErrorCode::Internal, p.name() + ": a fire light is not finite");
        std::memcpy(reinterpret_cast<char*>(lights) + size_t{l} * sizeof_light, &v,
                    std::min<size_t>(sizeof_light, sizeof v));
    }
}
}  // namespace

FIRELOOK_API fl_result fl_package_get_fire_lights(fl_package ph, int32_t frame, fl_look lh, uint32_t light_count,
                                                  fl_fire_light* lights, uint32_t sizeof_light, uint32_t capacity,
                                                  uint32_t* out_max_count) {
    return guarded("fl_package_get_fire_lights", [&] {
        const auto p = findPackage(ph);
        const int slot = slotOrFail(*p, frame);
        const std::shared_ptr<const Look> look = lh.id ? findLook(lh) : nullptr;
        writeFireLights(*p, slot, look ? look.get() : &p->defaultLook(), {}, {}, light_count, lights, sizeof_light,
                        capacity, out_max_count);
    });
}

// ---- the fire's probe grid -----------------------------------------------------------------------

namespace {
constexpr size_t kProbeFloats = basis::kFireProbeCoefficients * 3;

fl_fire_probe_grid toCaller(const basis::FireProbeGrid& g) {
    fl_fire_probe_grid out{};
    for (int a = 0; a < 3; ++a) {
        out.counts[a] = g.counts[a];
        out.origin[a] = g.origin[a];
        out.spacing[a] = g.spacing[a];
        out.falloff_centre[a] = g.falloff_centre[a];
    }
    out.falloff_radius = g.falloff_radius;
    return out;
}

// The fire probes of a package's frame (by slot) for a look's extinction and emission coefficients
// (or for `look`, resolved here, when rbf is empty).
void writeFireProbes(const world::Package& p, int slot, const Look* look, ExtinctionParams extinction,
                     std::span<const Rgb> rbf, fl_fire_probe_grid* out_grid, float* coefficients,
                     size_t capacity, size_t* out_count) {
    const basis::FireProbeTable* table = p.fireProbes(slot);
    if (!table)
        fail(ErrorCode::NotFound, p.name() + ": frame " + std::to_string(p.frameNumber(slot)) +
                                      " has no fire probes (baked without --fire-probes)");
    if (out_grid) checkStruct(out_grid, "out_grid");
    const size_t needed = static_cast<size_t>(table->grid.probes()) * kProbeFloats;
    if (out_count) *out_count = needed;
    if (out_grid) writeOut(out_grid, toCaller(table->grid));
    if (isSizeQuery(capacity)) return;
    checkPointer(coefficients, "coefficients");
    checkCapacity(capacity, needed, "floats");
    world::ResolvedLook resolved;
    if (look) {
        resolved = world::resolveLook(*look, p.description());  // LookError
        extinction = resolved.extinction;
        rbf = resolved.rbf;
    }
    std::vector<Rgb> values(static_cast<size_t>(table->grid.probes()) * basis::kFireProbeCoefficients);
    basis::evaluateFireProbes(*table, basis::interpolationWeights(p.description().axes, extinction), rbf,
                              values.data());
    for (size_t v = 0; v < values.size(); ++v)
        for (int c = 0; c < 3; ++c) {
            // A guard, as nothing non-finite leaves: the table and the look are checked finite.
            if (!std::isfinite(values[v][c]))
                fail(ErrorCode::Internal, p.name() + ": a fire probe is not finite");
            coefficients[3 * v + c] = values[v][c];
        }
}
}  // namespace

FIRELOOK_API fl_result fl_package_get_fire_probes(fl_package ph, int32_t frame, fl_look lh,
                                                  fl_fire_probe_grid* out_grid, float* coefficients,
                                                  size_t capacity, size_t* out_count) {
    return guarded("fl_package_get_fire_probes", [&] {
        const auto p = findPackage(ph);
        const int slot = slotOrFail(*p, frame);
        const std::shared_ptr<const Look> look = lh.id ? findLook(lh) : nullptr;
        writeFireProbes(*p, slot, look ? look.get() : &p->defaultLook(), {}, {}, out_grid, coefficients,
                        capacity, out_count);
    });
}

FIRELOOK_API fl_result fl_instance_get_fire_probes(fl_world w, fl_instance i, fl_fire_probe_grid* out_grid,
                                                   float* coefficients, size_t capacity, size_t* out_count) {
    return guarded("fl_instance_get_fire_probes", [&] {
        const WorldInstance wi = findInstance(w, i);
        const world::InstanceState state = wi.world.state(wi.instance);
        if (!state.updated) fail(ErrorCode::NoData, "no fl_world_update since the instance was created");
        const world::Package& p = wi.world.package(wi.instance);
        writeFireProbes(p, slotOrFail(p, state.frame), nullptr, state.extinction, state.rbf, out_grid,
                        coefficients, capacity, out_count);
    });
}

FIRELOOK_API fl_result fl_fire_probes_sample(const fl_fire_probe_grid* grid_in, const float* coefficients,
                                             size_t count, const double point[3], const double* normal,
                                             float out_rgb[3]) {
    return guarded("fl_fire_probes_sample", [&] {
        const fl_fire_probe_grid g = readIn(grid_in, "grid");
        checkPointer(coefficients, "coefficients");
        checkPointer(point, "point");
        checkPointer(out_rgb, "out_rgb");
        basis::FireProbeGrid grid;
        for (int a = 0; a < 3; ++a) {
            if (g.counts[a] < 2 || g.counts[a] > 64)
                fail(ErrorCode::InvalidArgument, "grid counts[" + std::to_string(a) + "] is " +
                                                     std::to_string(g.counts[a]) + ", not 2 to 64");
            if (!(g.spacing[a] > 0.0) || !std::isfinite(g.spacing[a]) || !std::isfinite(g.origin[a]) ||
                !std::isfinite(g.falloff_centre[a]))
                fail(ErrorCode::InvalidArgument, "grid has a spacing that is not > 0 or a non-finite value");
            grid.counts[a] = g.counts[a];
            grid.origin[a] = g.origin[a];
            grid.spacing[a] = g.spacing[a];
            grid.falloff_centre[a] = g.falloff_centre[a];
        }
        if (!(g.falloff_radius >= 0.0) || !std::isfinite(g.falloff_radius))
            fail(ErrorCode::InvalidArgument, "grid falloff_radius is not a finite number >= 0");
        grid.falloff_radius = g.falloff_radius;
        const size_t needed = static_cast<size_t>(grid.probes()) * kProbeFloats;
        if (count != needed)
            fail(ErrorCode::InvalidArgument,
                 "count is " + std::to_string(count) + ", the grid's probes need " + std::to_string(needed));
        if (!std::isfinite(point[0]) || !std::isfinite(point[1]) || !std::isfinite(point[2]))
            fail(ErrorCode::InvalidArgument, "point is not finite");
        static_assert(sizeof(Rgb) == 3 * sizeof(float));
        std::vector<Rgb> values(static_cast<size_t>(grid.probes()) * basis::kFireProbeCoefficients);
        std::memcpy(values.data(), coefficients, needed * sizeof(float));
        Rgb sh[basis::kFireProbeCoefficients];
        const glm::dvec3 x(point[0], point[1], point[2]);
        basis::sampleFireProbes(grid, values, x, sh);
        Rgb result = basis::fluenceFromSh(sh);
        if (normal) {
            const glm::dvec3 n(normal[0], normal[1], normal[2]);
            const double length = glm::length(n);
            result =
                length > 0.0 && std::isfinite(length) ? basis::irradianceFromSh(sh, n / length) : Rgb(0.0f);
        }
        for (int c = 0; c < 3; ++c)
            out_rgb[c] = std::isfinite(result[c]) && result[c] > 0.0f ? result[c] : 0.0f;
    });
}

FIRELOOK_API fl_result fl_instance_get_fire_lights(fl_world w, fl_instance i, uint32_t light_count,
                                                   fl_fire_light* lights, uint32_t sizeof_light,
                                                   uint32_t capacity, uint32_t* out_max_count) {
    return guarded("fl_instance_get_fire_lights", [&] {
        const WorldInstance wi = findInstance(w, i);
        const world::InstanceState state = wi.world.state(wi.instance);
        if (!state.updated) fail(ErrorCode::NoData, "no fl_world_update since the instance was created");
        const world::Package& p = wi.world.package(wi.instance);
        // The extinction and emission coefficients the update interpolated: what the image shows.
        writeFireLights(p, slotOrFail(p, state.frame), nullptr, state.extinction, state.rbf, light_count, lights,
                        sizeof_light, capacity, out_max_count);
    });
}
