// The struct rule of firelook.h, after OpenEXRCore: the library copies min(caller's size, its own
// sizeof) bytes in and out. What an older caller's struct lacks stays 0 (the default of every desc
// field); what a newer caller's struct adds is not read, and not written on output. The one other
// thing each struct needs is its first published size, the smallest a caller may pass.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "firelook/firelook.h"

namespace firelook::plugin {

// FirstSize<T>::value: the end of the last field T had when first published (header 100).
template <typename T>
struct FirstSize;

#define FIRELOOK_FIRST_SIZE(type, last_field)                                              \
    template <>                                                                            \
    struct FirstSize<type> {                                                               \
        static constexpr size_t value = offsetof(type, last_field) + sizeof(type::last_field); \
    }
FIRELOOK_FIRST_SIZE(fl_init_desc, reserved2);
FIRELOOK_FIRST_SIZE(fl_world_desc, frame_cache_bytes);
FIRELOOK_FIRST_SIZE(fl_instance_desc, look);
FIRELOOK_FIRST_SIZE(fl_keyframe, reserved);
FIRELOOK_FIRST_SIZE(fl_playback_desc, rate);
FIRELOOK_FIRST_SIZE(fl_outputs_desc, streaks);
FIRELOOK_FIRST_SIZE(fl_package_info, flame_extinction_max);
FIRELOOK_FIRST_SIZE(fl_instance_state, reserved);
FIRELOOK_FIRST_SIZE(fl_package_memory_desc, flags);
FIRELOOK_FIRST_SIZE(fl_camera, world_from_camera);
FIRELOOK_FIRST_SIZE(fl_fit_desc, progress_user);
FIRELOOK_FIRST_SIZE(fl_fit_report, evaluations);
FIRELOOK_FIRST_SIZE(fl_fire_light, radius);
FIRELOOK_FIRST_SIZE(fl_fire_probe_grid, falloff_radius);
FIRELOOK_FIRST_SIZE(fl_light_direction_desc, reserved2);
FIRELOOK_FIRST_SIZE(fl_look_desc, reserved);
FIRELOOK_FIRST_SIZE(fl_fit_target_desc, exposure);
FIRELOOK_FIRST_SIZE(fl_fit_target_info, clipped_pixels);
#undef FIRELOOK_FIRST_SIZE

// The caller's struct_size (the first field of every struct that has one), read without assuming
// that the caller's struct is a whole T.
inline uint32_t callerStructSize(const void* caller) {
    uint32_t size;
    std::memcpy(&size, caller, sizeof size);
    return size;
}

// The library's T from a caller's struct of caller_size bytes (caller_size >= FirstSize<T>, checked
// by the caller of this function).
template <typename T>
T copyIn(const void* caller, size_t caller_size) {
    T local{};
    std::memcpy(&local, caller, std::min(caller_size, sizeof(T)));
    return local;
}

// Writes value over the first min(caller_size, sizeof(T)) bytes of the caller's struct; the caller's
// struct_size is written back unchanged.
template <typename T>
void copyOut(void* caller, size_t caller_size, T value) {
    value.struct_size = callerStructSize(caller);
    std::memcpy(caller, &value, std::min(caller_size, sizeof(T)));
}

}  // namespace firelook::plugin
