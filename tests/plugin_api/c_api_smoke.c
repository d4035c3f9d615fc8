/* A plain-C translation unit that includes the public header (compiled as C99 with -Wall -Wextra
   -Werror -pedantic) and drives a whole cycle through the API. Called from plugin_api_test.cpp. */
#include "firelook/firelook.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define CHECK(call)                                                                          \
    do {                                                                                     \
        fl_result r_ = (call);                                                               \
        if (r_ != FL_OK) {                                                                   \
            fprintf(stderr, "%s: %s (%s)\n", #call, fl_result_string(r_), fl_last_error()); \
            return 1;                                                                        \
        }                                                                                    \
    } while (0)

int firelook_c_smoke(const char* package_path);

/* What a look editor and a GPU host read besides images: lights, the camera (the synthetic package
   records none), a look's emissivity per bin, the look an instance shows and the shown frame's U
   from the world's cache (the same size as the package's). */
static int smoke_scene_and_frames(fl_package package, const fl_package_info* info, fl_world world,
                                  fl_instance instance, fl_look look) {
    double directions[3 * 64];
    float irradiance[3 * 64], emissivity[3 * 256];
    uint32_t count = 0, l;
    size_t from_cache = 0, from_package = 0;
    fl_camera camera = fl_camera_defaults();
    fl_instance_state state = fl_instance_state_defaults();
    fl_look shown = {0};
    if (info->light_count > 64 || info->bin_count > 256) return 1;
    CHECK(fl_package_get_lights(package, directions, irradiance, 64, &count));
    if (count != (uint32_t)info->light_count) return 1;
    for (l = 0; l < count; ++l) {
        const double length = sqrt(directions[3 * l] * directions[3 * l] + directions[3 * l + 1] * directions[3 * l + 1] +
                                   directions[3 * l + 2] * directions[3 * l + 2]);
        if (!(fabs(length - 1.0) < 1e-12) || !isfinite(irradiance[3 * l])) return 1;
    }
    if (fl_package_get_camera(package, &camera) != FL_ERROR_NOT_FOUND) return 1;
    CHECK(fl_look_get_bin_emissivity(look, package, emissivity, 256, &count));
    if (count != (uint32_t)info->bin_count) return 1;
    for (l = 0; l < 3 * count; ++l)
        if (!(emissivity[l] >= 0.0f) || !isfinite(emissivity[l])) return 1;
    CHECK(fl_instance_get_look(world, instance, &shown));
    CHECK(fl_look_release(shown));
    CHECK(fl_instance_get_state(world, instance, &state));
    CHECK(fl_instance_get_frame_u(world, instance, NULL, 0, &from_cache));
    CHECK(fl_package_get_frame_u(package, state.frame, NULL, 0, &from_package));
    return from_cache == from_package && from_cache > 0 ? 0 : 1;
}

/* The same package read into memory, as an engine reads its archive, and loaded from there (copied,
   so the buffer is freed at once): it must describe the same package. */
static int smoke_memory_load(const char* package_path, const fl_package_info* from_file) {
    fl_package package = {0};
    fl_package_memory_desc desc = fl_package_memory_desc_defaults();
    fl_package_info info = fl_package_info_defaults();
    FILE* file = fopen(package_path, "rb");
    char* bytes;
    long size;
    size_t got;
    if (!file) return 1;
    if (fseek(file, 0, SEEK_END) != 0 || (size = ftell(file)) <= 0 || fseek(file, 0, SEEK_SET) != 0) {
        fclose(file);
        return 1;
    }
    bytes = (char*)malloc((size_t)size);
    got = bytes ? fread(bytes, 1, (size_t)size, file) : 0;
    fclose(file);
    if (got != (size_t)size) {
        free(bytes);
        return 1;
    }
    desc.flags = 0; /* copy: any alignment, the buffer is ours again when the call returns */
    if (fl_package_load_memory(bytes, got, "smoke.pak:package", &desc, &package) != FL_OK) {
        free(bytes);
        return 1;
    }
    free(bytes);
    CHECK(fl_package_get_info(package, &info));
    CHECK(fl_package_release(package));
    return info.width == from_file->width && info.height == from_file->height &&
                   info.frame_count == from_file->frame_count
               ? 0
               : 1;
}

int firelook_c_smoke(const char* package_path) {
    fl_package package = {0};
    fl_package_info info = fl_package_info_defaults();
    fl_world world = {0};
    fl_world_desc world_desc = fl_world_desc_defaults();
    fl_instance_desc instance_desc = fl_instance_desc_defaults();
    fl_instance instance = {0};
    fl_outputs_desc outputs = fl_outputs_desc_defaults();
    fl_playback_desc playback = fl_playback_desc_defaults();
    fl_instance_state state = fl_instance_state_defaults();
    fl_look look = {0};
    fl_keyframe keys[2];
    float* image;
    float z[3 * 256];
    int32_t rank = 0;
    size_t floats, i;

    CHECK(fl_package_load(package_path, &package));
    CHECK(fl_package_get_info(package, &info));
    CHECK(fl_world_create(&world_desc, &world));
    instance_desc.package = package;
    CHECK(fl_instance_create(world, &instance_desc, &instance));
    CHECK(fl_package_default_look(package, &look));
    keys[0].frame = info.first_frame;
    keys[0].look = look;
    keys[0].reserved = 0;
    keys[1] = keys[0];
    keys[1].frame = info.last_frame;
    CHECK(fl_instance_set_keyframes(world, instance, keys, 2));
    outputs.image = 1;
    outputs.lens_flare = 1;
    CHECK(fl_instance_set_outputs(world, instance, &outputs));
    playback.rate = 12.0;
    CHECK(fl_instance_set_playback(world, instance, &playback));
    CHECK(fl_world_update(world, 1.0 / 60.0));
    CHECK(fl_instance_get_state(world, instance, &state));
    if (!state.updated) return 2;
    CHECK(fl_instance_get_coefficients(world, instance, z, sizeof z / sizeof z[0], &rank));
    if (rank != state.rank) return 3;
    floats = (size_t)info.width * (size_t)info.height * 4;
    image = (float*)malloc(floats * sizeof(float));
    if (!image) return 4;
    CHECK(fl_instance_get_image(world, instance, image, floats));
    for (i = 0; i < floats; ++i)
        if (!(image[i] >= 0.0f) || !isfinite(image[i])) {
            free(image);
            return 5;
        }
    CHECK(fl_instance_get_flare(world, instance, image, floats));
    free(image);
    if (smoke_scene_and_frames(package, &info, world, instance, look) != 0) return 8;
    if (smoke_memory_load(package_path, &info) != 0) return 7;
    CHECK(fl_instance_destroy(world, instance));
    if (fl_instance_destroy(world, instance) != FL_ERROR_INVALID_HANDLE) return 6;
    CHECK(fl_look_release(look));
    CHECK(fl_world_destroy(world));
    CHECK(fl_package_release(package));
    return 0;
}
