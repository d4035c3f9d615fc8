/* c_example PACKAGE OUT_DIR
 *
 * Engine integration in plain C99 through the FireLook C API only: loads a baked package, animates
 * three instances with different keyframed looks (look JSON written here, adapted to the package's
 * albedo and light count), updates the world at 24 updates per second and writes, per update, one
 * image with the three fires side by side over a dark background (plus the first one's lens flare),
 * then a contact sheet of all of them. Images are binary PPM (P6) written by the tiny writer below.
 *
 *   OUT_DIR/frame_0001.ppm ...   composite per update
 *   OUT_DIR/contact_sheet.ppm    every update, 4 per row (half size when wider than 256 pixels)
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "firelook/firelook.h"

#define INSTANCES 3

static void logger(int32_t level, const char* message, void* user) {
    (void)user;
    fprintf(stderr, "[firelook %s] %s\n", level >= FL_LOG_ERROR ? "error" : level >= FL_LOG_WARNING ? "warning" : "info",
            message);
}

static int fail(const char* what, fl_result r) {
    fprintf(stderr, "c_example: %s: %s: %s\n", what, fl_result_string(r), fl_last_error());
    return 1;
}

/* Linear premultiplied radiance -> 8-bit sRGB-ish (exposure, Reinhard, gamma 2.2). */
static unsigned char toByte(float v) {
    float x = v > 0.0f ? v : 0.0f;
    x = x / (1.0f + x);
    x = powf(x, 1.0f / 2.2f);
    return (unsigned char)(x * 255.0f + 0.5f);
}

static int writePpm(const char* path, const unsigned char* rgb, int width, int height) {
    FILE* f = fopen(path, "wb");
    size_t bytes = (size_t)width * (size_t)height * 3;
    if (!f) {
        fprintf(stderr, "c_example: cannot write %s: %s\n", path, strerror(errno));
        return 1;
    }
    fprintf(f, "P6\n%d %d\n255\n", width, height);
    if (fwrite(rgb, 1, bytes, f) != bytes || fclose(f) != 0) {
        fprintf(stderr, "c_example: error writing %s\n", path);
        return 1;
    }
    return 0;
}

/* One look as firelook-look JSON; light_irradiance repeated once per light of the package. */
static fl_result makeLook(const fl_package_info* info, double threshold_fraction, double smoke, double flame,
                          const char* emission, double light, fl_look* out) {
    char lights[512] = "";
    char json[2048];
    int l;
    /* The temperature threshold as a fraction of the package's T_c axis, so any package works. */
    double tc = info->temperature_threshold_min +
                threshold_fraction * (info->temperature_threshold_max - info->temperature_threshold_min);
    for (l = 0; l < info->light_count && l < 16; ++l) {
        char one[64];
        snprintf(one, sizeof one, "%s[%g, %g, %g]", l ? ", " : "", light, light * 0.95, light * 0.9);
        strcat(lights, one);
    }
    snprintf(json, sizeof json,
             "{\"format\": \"firelook-look\", \"version\": 1, \"temperature_threshold\": %.17g, "
             "\"smoke_extinction\": %g, \"flame_extinction\": %g, \"albedo\": %.17g, \"emission\": %s, "
             "\"light_irradiance\": [%s]}",
             tc, smoke, flame, info->albedo, emission, lights);
    return fl_look_from_json(json, 0, "c_example look", out);
}

int main(int argc, char** argv) {
    fl_init_desc init = fl_init_desc_defaults();
    fl_package package = {0};
    fl_package_info info = fl_package_info_defaults();
    fl_world world = {0};
    fl_instance instances[INSTANCES];
    fl_look looks[6];
    fl_result r;
    float* image = NULL;
    float* flare = NULL;
    unsigned char* composite = NULL;
    unsigned char* sheet = NULL;
    int status = 1;
    int i, k, x, y, update, updates, sheet_columns = 4, sheet_rows, tw, th, factor;
    size_t floats;
    char path[4096];
    const char* out_dir;

    if (argc != 3) {
        fprintf(stderr, "usage: c_example PACKAGE OUT_DIR\n");
        return 2;
    }
    out_dir = argv[2];
    if (mkdir(out_dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "c_example: cannot create %s: %s\n", out_dir, strerror(errno));
        return 1;
    }

    init.log = logger;
    init.log_level = FL_LOG_WARNING;
    if ((r = fl_init(&init)) != FL_OK) { fail("fl_init", r); goto done; }
    if ((r = fl_package_load(argv[1], &package)) != FL_OK) { fail("fl_package_load", r); goto done; }
    if ((r = fl_package_get_info(package, &info)) != FL_OK) { fail("fl_package_get_info", r); goto done; }
    printf("%s: %dx%d, frames %d..%d (%d baked), rank <= %d, %d bins, %d lights\n", argv[1], info.width, info.height,
           info.first_frame, info.last_frame, info.frame_count, info.max_rank, info.bin_count, info.light_count);

    /* Six looks: two keys for each of three instances. */
    {
        const char* fire = "{\"stops\": [[0.0, 0,0,0], [1.7, 2.0,0.6,0.08], [2.3, 8.0,4.0,0.9], [3.0, 14.0,11.0,6.0]]}";
        const char* inferno = "{\"stops\": [[0.0, 0,0,0], [2.0, 3.0,0.35,0.02], [2.6, 9.0,2.2,0.2], [3.0, 12.0,4.5,0.6]]}";
        const char* blackbody = "{\"preset\": \"blackbody\", \"scale\": 6.0}";
        const char* cool = "{\"preset\": \"fire\", \"scale\": 1.0}";
        struct {
            double tc, ks, kf;
            const char* emission;
            double light;
        } spec[6] = {{0.2, 4.0, 1.0, fire, 2.5},      {0.6, 8.0, 2.0, inferno, 1.5},
                     {0.5, 9.0, 2.5, inferno, 1.6},   {0.9, 16.0, 4.0, blackbody, 3.0},
                     {0.8, 14.0, 3.5, blackbody, 3.0}, {0.1, 2.0, 0.5, cool, 1.0}};
        for (i = 0; i < 6; ++i)
            if ((r = makeLook(&info, spec[i].tc, spec[i].ks, spec[i].kf, spec[i].emission, spec[i].light, &looks[i])) !=
                FL_OK)
                { fail("fl_look_from_json", r); goto done; }
    }

    if ((r = fl_world_create(NULL, &world)) != FL_OK) { fail("fl_world_create", r); goto done; }
    for (i = 0; i < INSTANCES; ++i) {
        fl_instance_desc desc = fl_instance_desc_defaults();
        fl_keyframe keys[2];
        fl_playback_desc playback = fl_playback_desc_defaults();
        fl_outputs_desc outputs = fl_outputs_desc_defaults();
        desc.package = package;
        if ((r = fl_instance_create(world, &desc, &instances[i])) != FL_OK) { fail("fl_instance_create", r); goto done; }
        memset(keys, 0, sizeof keys);
        keys[0].frame = info.first_frame;
        keys[0].look = looks[2 * i];
        keys[1].frame = info.last_frame;
        keys[1].look = looks[2 * i + 1];
        if ((r = fl_instance_set_keyframes(world, instances[i], keys, 2)) != FL_OK)
            { fail("fl_instance_set_keyframes", r); goto done; }
        playback.rate = 24.0;
        playback.time = i / 24.0; /* each instance one frame ahead of the previous */
        if ((r = fl_instance_set_playback(world, instances[i], &playback)) != FL_OK)
            { fail("fl_instance_set_playback", r); goto done; }
        outputs.image = 1;
        outputs.lens_flare = i == 0;
        if ((r = fl_instance_set_outputs(world, instances[i], &outputs)) != FL_OK)
            { fail("fl_instance_set_outputs", r); goto done; }
    }
    /* Looks are copied into the instances: release them now. */
    for (i = 0; i < 6; ++i) fl_look_release(looks[i]);

    floats = (size_t)info.width * (size_t)info.height * 4;
    updates = info.last_frame - info.first_frame + 1;
    factor = info.width > 256 ? 2 : 1;
    tw = info.width / factor > 0 ? info.width / factor : 1;
    th = info.height / factor > 0 ? info.height / factor : 1;
    sheet_rows = (updates + sheet_columns - 1) / sheet_columns;
    image = (float*)malloc(floats * sizeof(float));
    flare = (float*)malloc(floats * sizeof(float));
    composite = (unsigned char*)malloc((size_t)INSTANCES * (size_t)info.width * (size_t)info.height * 3);
    sheet = (unsigned char*)calloc((size_t)sheet_columns * sheet_rows * INSTANCES * tw * th * 3, 1);
    if (!image || !flare || !composite || !sheet) {
        fprintf(stderr, "c_example: out of memory\n");
        goto done;
    }

    for (update = 0; update < updates; ++update) {
        /* The first update shows the start; afterwards each advances one frame (1/24 s at 24 fps). */
        if ((r = fl_world_update(world, update == 0 ? 0.0 : 1.0 / 24.0)) != FL_OK) { fail("fl_world_update", r); goto done; }
        for (i = 0; i < INSTANCES; ++i) {
            fl_instance_state state = fl_instance_state_defaults();
            if ((r = fl_instance_get_image(world, instances[i], image, floats)) != FL_OK)
                { fail("fl_instance_get_image", r); goto done; }
            if (i == 0 && (r = fl_instance_get_flare(world, instances[i], flare, floats)) != FL_OK)
                { fail("fl_instance_get_flare", r); goto done; }
            if ((r = fl_instance_get_state(world, instances[i], &state)) != FL_OK)
                { fail("fl_instance_get_state", r); goto done; }
            if (update == 0 || update == updates - 1)
                printf("update %d, instance %d: frame %d, rank %d, T_c %.3f, k_s %.2f, k_f %.2f\n", update + 1, i,
                       state.frame, state.rank, state.temperature_threshold, state.smoke_extinction,
                       state.flame_extinction);
            for (y = 0; y < info.height; ++y)
                for (x = 0; x < info.width; ++x) {
                    const float* p = image + ((size_t)y * info.width + x) * 4;
                    /* Background: a dark blue gradient. final = rgb + (1 - alpha) bg (+ flare). */
                    const float bg[3] = {0.02f, 0.03f, 0.05f + 0.05f * (float)y / (float)info.height};
                    unsigned char* o = composite + (((size_t)y * INSTANCES * info.width) + (size_t)i * info.width + x) * 3;
                    for (k = 0; k < 3; ++k) {
                        float v = p[k] + (1.0f - p[3]) * bg[k];
                        if (i == 0) v += flare[((size_t)y * info.width + x) * 4 + k];
                        o[k] = toByte(v);
                    }
                }
        }
        snprintf(path, sizeof path, "%s/frame_%04d.ppm", out_dir, update + 1);
        if (writePpm(path, composite, INSTANCES * info.width, info.height)) goto done;
        /* Contact sheet tile: the composite, box-filtered down by `factor` on the bytes. */
        {
            int col = update % sheet_columns, row = update / sheet_columns;
            int sheet_width = sheet_columns * INSTANCES * tw;
            for (y = 0; y < th; ++y)
                for (x = 0; x < INSTANCES * tw; ++x)
                    for (k = 0; k < 3; ++k) {
                        int sum = 0, n = 0, dx, dy;
                        for (dy = 0; dy < factor; ++dy)
                            for (dx = 0; dx < factor; ++dx) {
                                int sx = factor * x + dx, sy = factor * y + dy;
                                if (sx < INSTANCES * info.width && sy < info.height) {
                                    sum += composite[((size_t)sy * INSTANCES * info.width + sx) * 3 + k];
                                    ++n;
                                }
                            }
                        sheet[(((size_t)row * th + y) * sheet_width + (size_t)col * INSTANCES * tw + x) * 3 + k] =
                            (unsigned char)(n ? sum / n : 0);
                    }
        }
    }
    snprintf(path, sizeof path, "%s/contact_sheet.ppm", out_dir);
    if (writePpm(path, sheet, sheet_columns * INSTANCES * tw, sheet_rows * th)) goto done;
    printf("wrote %d frames and contact_sheet.ppm to %s\n", updates, out_dir);
    status = 0;

done:
    /* fl_shutdown releases every package, look and world still alive; the buffers are ours. */
    free(image);
    free(flare);
    free(composite);
    free(sheet);
    fl_shutdown();
    return status;
}
