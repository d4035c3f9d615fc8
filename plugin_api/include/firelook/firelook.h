/* firelook.h — the C API of the FireLook runtime (C99, also valid C++).

   FireLook recombines precomputed basis images of a volumetric fire into an
   image for any look (Dobashi et al.). This library plays baked .firelook
   packages: it keeps a world of fire instances, animates their looks and
   frames, and gives you per instance either a CPU image or the few numbers a
   shader needs to reconstruct the image on the GPU.

   MANUAL
   ------
   1. Start-up. Fill an fl_init_desc with fl_init_desc_defaults() (which
      records this header's version and struct sizes, like IMGUI_CHECKVERSION),
      optionally add an allocator and a log callback, and call fl_init(). A
      header the library cannot serve (another major, a newer minor, or a
      sizeof_* in the desc below that struct's first published size) is
      refused with FL_ERROR_VERSION_MISMATCH instead of misreading your
      structs; a desc whose own struct_size is 0 or below its first published
      size is refused with FL_ERROR_STRUCT_SIZE, as every struct is.
   2. Load a package: fl_package_load(path, &package), or from bytes the
      engine read from its own archive: fl_package_load_memory(), copied or
      borrowed (see there for how long borrowed bytes must live).
      fl_package_get_info() and friends describe it (frames, size, rank per
      frame, bins, lights, parameter ranges, default look as JSON, the camera
      it was baked with: fl_package_get_camera, fl_package_get_lights).
   3. Make looks from look-file JSON (fl_look_from_json), a look file
      (fl_look_load_file) or plain values (fl_look_create; fl_look_get_desc
      reads them back, for editors), or take the package's default
      (fl_package_default_look); fl_look_get_bin_emissivity resolves a look's
      emission to the package's bins (for curve editors) and
      fl_emission_preset_name lists the emission presets. To fit a look to a
      target image: fl_fit_target_load, fl_package_fit_look, fl_fit_difference.
   4. Create a world (fl_world_create) and instances in it
      (fl_instance_create); give them looks or keyframes, playback and
      outputs.
   5. Every frame: fl_world_update(world, dt), then read what you need:
      fl_instance_get_image() (CPU image, premultiplied linear RGBA float),
      fl_instance_get_flare(), or for GPU reconstruction
      fl_instance_get_coefficients() + fl_instance_get_state() with the
      textures from fl_instance_get_frame_u() and fl_instance_get_frame_depths()
      (the frame the world already holds; the fl_package_ variants decode it
      again; the shader that uses them: share/firelook/shaders/firelook_reconstruct.glsl,
      installed with the library). fl_instance_get_look() gives the look an instance shows.
      A package baked with six-way or sphere lights can be lit from any direction at run
      time: fl_instance_set_light_direction(), or several lights at once with
      fl_instance_set_light_directions().
   6. Release everything and call fl_shutdown().

   Conventions (after sokol_gfx, OpenEXRCore, Dear ImGui and flecs):
   - Handles are structs holding a 32-bit id made of its kind (package, look,
     world, instance), an index and a generation; id 0 is never valid. A
     released or destroyed object's handle, a handle of another kind, and an
     instance handle passed with a world that did not create it are detected
     (FL_ERROR_INVALID_HANDLE), never dereferenced. A released handle never
     becomes valid again: a slot whose 11-bit generation is spent is retired,
     so each kind makes at most 5.4e8 objects over the process's life
     (handles stay stale across fl_shutdown and fl_init; at 1,000 a second,
     six days), then creation fails with FL_ERROR_LIMIT.
   - Structs may grow; each (but fl_keyframe) starts with uint32_t
     struct_size = sizeof the caller's struct. The library copies
     min(struct_size, its own sizeof) bytes in and out: fields an older
     caller's struct lacks take their defaults (0), what a newer caller's
     struct adds is ignored on input and left untouched on output. A
     struct_size below the struct's first published size (noted at each
     struct: the end of the field named there) is refused with
     FL_ERROR_STRUCT_SIZE. fl_keyframe arrays are read with the stride given
     as sizeof_keyframe to fl_init. The *_defaults() functions are static
     inline here, so they fill in the caller's sizeof. In desc structs, 0
     means "default" for every field.
   - Every call returns an fl_result; FL_OK is 0, errors are negative.
     fl_result_string() names a code; fl_last_error() gives the message of
     the calling thread's last failed call (it names the file and the problem).
   - Memory: nothing is returned that the caller must free. Data comes out
     through buffers the caller provides (with the needed size reported, so a
     call with capacity 0 asks for the size); the only borrowed pointers are
     the strings from fl_result_string() (static) and fl_last_error() (valid
     until the calling thread's next FireLook call). The library keeps no
     pointer into the caller's memory once a call returns, but for the bytes
     of a package loaded with FL_PACKAGE_MEMORY_BORROW.
   - No C++ exception crosses this API. Non-finite inputs are refused.
   - Thread-safety: fl_init/fl_shutdown must not overlap any other call.
     Package and look calls (load, release, query, from_json) are safe from
     any thread at any time. A world and its instances must be used by one
     thread at a time (calls on different worlds may run in parallel);
     fl_world_destroy must not overlap calls on the same world.

   The image an instance produces is premultiplied linear RGBA, top row
   first, with alpha = 1 - transmittance: final = rgb + (1 - alpha) * bg.
   The lens flare is a separate RGBA image with alpha 0, added on top:
   final = rgb + (1 - alpha) * bg + flare.
*/
#ifndef FIRELOOK_H
#define FIRELOOK_H

#include <stddef.h>
#include <stdint.h>

#define FIRELOOK_VERSION_MAJOR 0
#define FIRELOOK_VERSION_MINOR 1
#define FIRELOOK_VERSION_PATCH 0
/* major * 10000 + minor * 100 + patch. fl_init() accepts a header of the same major and a minor no newer
   (any patch); the first published header is 100. */
#define FIRELOOK_HEADER_VERSION 100

#if defined(_WIN32)
#  if defined(FIRELOOK_BUILDING_PLUGIN)
#    define FIRELOOK_API __declspec(dllexport)
#  else
#    define FIRELOOK_API __declspec(dllimport)
#  endif
#elif defined(__GNUC__)
#  define FIRELOOK_API __attribute__((visibility("default")))
#else
#  define FIRELOOK_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ---- results ------------------------------------------------------------ */

/* Every result, in one list: X(name, value). fl_result_string() is generated from it too. */
#define FIRELOOK_RESULTS(X)                                                                              \
    X(FL_OK, 0)                                                                                          \
    X(FL_ERROR_INVALID_ARGUMENT, -1)  /* a null pointer, a non-finite or out-of-range value */           \
    X(FL_ERROR_INVALID_HANDLE, -2)    /* 0, stale (released/destroyed), another kind, another world's */ \
    X(FL_ERROR_STRUCT_SIZE, -3)       /* struct_size below the first published size, or 0 */             \
    X(FL_ERROR_VERSION_MISMATCH, -4)  /* header and library disagree (fl_init) */                        \
    X(FL_ERROR_NOT_INITIALIZED, -5)   /* fl_init has not succeeded */                                    \
    X(FL_ERROR_ALREADY_INITIALIZED, -6)                                                                  \
    X(FL_ERROR_IO, -7)                /* the file could not be opened or read */                         \
    X(FL_ERROR_NOT_A_PACKAGE, -8)     /* the file is not a .firelook package */                          \
    X(FL_ERROR_CORRUPT, -9)           /* truncated, checksum mismatch, inconsistent content */           \
    X(FL_ERROR_UNSUPPORTED, -10)      /* a newer package version or a required feature this build lacks */ \
    X(FL_ERROR_LOOK, -11)             /* bad look JSON, or a look that does not fit the package */       \
    X(FL_ERROR_BUFFER_TOO_SMALL, -12) /* the needed size is reported through the size output */          \
    X(FL_ERROR_OUT_OF_MEMORY, -13)                                                                       \
    X(FL_ERROR_NO_DATA, -14)          /* output not enabled, or no fl_world_update since it was */       \
    X(FL_ERROR_NOT_FOUND, -15)        /* no such frame, camera, six-way or sphere lights */              \
    X(FL_ERROR_LIMIT, -16)            /* too many objects of one kind */                                 \
    X(FL_ERROR_INTERNAL, -17)         /* a bug: please report with fl_last_error() */                     \
    X(FL_ERROR_CANCELLED, -18)        /* a progress callback asked to stop (fl_package_fit_look) */

typedef int32_t fl_result;
#define FIRELOOK_RESULT_ENUMERATOR(name, value) name = value,
enum { FIRELOOK_RESULTS(FIRELOOK_RESULT_ENUMERATOR) };
#undef FIRELOOK_RESULT_ENUMERATOR

/* A short constant name ("FL_ERROR_INVALID_HANDLE"), "FL_ERROR_UNKNOWN" for a value not in the list;
   never null; static storage. Callable any time. */
FIRELOOK_API const char* fl_result_string(fl_result result);
/* The calling thread's last error message ("" if none); valid until this thread's next FireLook call. */
FIRELOOK_API const char* fl_last_error(void);

/* ---- handles (0 is invalid) --------------------------------------------- */

typedef struct fl_package { uint32_t id; } fl_package;
typedef struct fl_look { uint32_t id; } fl_look;
typedef struct fl_world { uint32_t id; } fl_world;
typedef struct fl_instance { uint32_t id; } fl_instance;  /* valid only with the world that created it */

/* ---- start-up ----------------------------------------------------------- */

typedef struct fl_allocator {
    /* Both set or both null (null: malloc/free). Used for the worlds' large
       buffers (images, flare images, coefficients, decoded factor copies);
       package decompression and bookkeeping use the C++ heap. alloc must
       return 16-byte aligned memory or null; calls may come from any thread
       that calls into a world. */
    void* (*alloc)(size_t size, void* user);
    void (*free)(void* pointer, void* user);
    void* user;
} fl_allocator;

enum { FL_LOG_DEBUG = 0, FL_LOG_INFO = 1, FL_LOG_WARNING = 2, FL_LOG_ERROR = 3 };
/* message is valid during the call only. Called on the thread making the FireLook call. */
typedef void (*fl_log_fn)(int32_t level, const char* message, void* user);

/* First published size: through reserved2. */
typedef struct fl_init_desc {
    uint32_t struct_size;     /* sizeof(fl_init_desc) */
    uint32_t header_version;  /* FIRELOOK_HEADER_VERSION; read when struct_size covers it */
    /* sizeof of every struct below, as the caller compiled them: each at least its first published size
       (else FL_ERROR_VERSION_MISMATCH); larger is accepted. sizeof_keyframe is the stride of keyframe arrays. */
    uint32_t sizeof_world_desc;
    uint32_t sizeof_instance_desc;
    uint32_t sizeof_playback_desc;
    uint32_t sizeof_outputs_desc;
    uint32_t sizeof_package_info;
    uint32_t sizeof_instance_state;
    uint32_t sizeof_keyframe;
    uint32_t reserved;
    fl_allocator allocator;
    fl_log_fn log;            /* null: no logging */
    void* log_user;
    int32_t log_level;        /* lowest level passed to log; 0 = FL_LOG_DEBUG */
    int32_t reserved2;
} fl_init_desc;

/* ---- packages ----------------------------------------------------------- */

/* First published size: through flame_extinction_max. */
typedef struct fl_package_info {
    uint32_t struct_size;  /* in: sizeof(fl_package_info); kept */
    int32_t width, height;          /* image size in pixels */
    int32_t frame_count;            /* baked frames (see fl_package_get_frames) */
    int32_t first_frame, last_frame;
    int32_t max_rank;               /* largest rank of any frame */
    int32_t bin_count;              /* temperature bins */
    int32_t light_count;            /* directional lights */
    int32_t alpha_threshold_count;  /* T_c samples of the O_a layers (fl_package_get_frame_depths) */
    int32_t footprint_samples;      /* rays per pixel whose optical depths are stored (alpha = their mean) */
    int32_t reserved;
    double temperature_lo, temperature_hi;  /* bin range, data units */
    double rbf_width;               /* in units of the bin width */
    double albedo;                  /* fixed at bake time; looks must match */
    /* baked ranges of the look parameters (outside them the nearest baked value is used) */
    double temperature_threshold_min, temperature_threshold_max;
    double smoke_extinction_min, smoke_extinction_max;
    double flame_extinction_min, flame_extinction_max;
} fl_package_info;

/* Thread-safe. Loads the package's description (frames are read on demand). */
FIRELOOK_API fl_result fl_package_load(const char* path, fl_package* out_package);
/* Flags of fl_package_memory_desc. */
enum {
    /* Use the caller's bytes in place instead of copying them (see fl_package_load_memory). */
    FL_PACKAGE_MEMORY_BORROW = 1
};

/* How fl_package_load_memory holds the caller's bytes. First published size: through flags. */
typedef struct fl_package_memory_desc {
    uint32_t struct_size;  /* sizeof(fl_package_memory_desc) */
    uint32_t flags;        /* 0: copy the bytes (the default); FL_PACKAGE_MEMORY_BORROW; other bits are refused */
} fl_package_memory_desc;

/* Thread-safe. A package from `size` bytes at `data` (e.g. read by the engine from its own archive), with
   exactly the checks and results of fl_package_load on a file holding those bytes (garbage that does not
   start like a package: FL_ERROR_NOT_A_PACKAGE; truncated or damaged: FL_ERROR_CORRUPT; ...). source_name
   (may be null: "(memory)") stands for the file in every message (fl_last_error()). data null or
   size 0: FL_ERROR_INVALID_ARGUMENT. desc may be null (copy).
   - Copied (flags 0): the bytes are copied into the library's own 64-byte aligned buffer before the call
     returns; the caller may free or reuse its buffer as soon as the call returns, whatever the result.
   - Borrowed (FL_PACKAGE_MEMORY_BORROW): nothing is copied and frames are read from the caller's bytes on
     demand (checksums on first use), so the buffer must be 64-byte aligned (else FL_ERROR_INVALID_ARGUMENT,
     nothing loaded; use a copy for any other alignment) and must stay valid and unchanged until all of:
     fl_package_release() (or fl_shutdown()) has returned for the package, every instance created with it
     has been destroyed (fl_instance_destroy, fl_world_destroy or fl_shutdown: instances keep package data
     alive), and no call on the package from another thread is still running. A failed load keeps no
     reference to the buffer. */
FIRELOOK_API fl_result fl_package_load_memory(const void* data, size_t size, const char* source_name,
                                              const fl_package_memory_desc* desc, fl_package* out_package);
/* Thread-safe. Instances that use it keep its data alive until they are destroyed; the handle dies now. */
FIRELOOK_API fl_result fl_package_release(fl_package package);
FIRELOOK_API fl_result fl_package_get_info(fl_package package, fl_package_info* out_info);
/* Frame numbers and each frame's rank, in increasing frame order; either array may be null.
   capacity: entries available; *out_count (if not null) gets frame_count. */
FIRELOOK_API fl_result fl_package_get_frames(fl_package package, int32_t* frame_numbers, int32_t* ranks,
                                             uint32_t capacity, uint32_t* out_count);
/* The T_c of each O_a layer (alpha_threshold_count values). */
FIRELOOK_API fl_result fl_package_get_alpha_thresholds(fl_package package, double* thresholds, uint32_t capacity);
/* The default look as look-file JSON, NUL-terminated. *out_size gets the bytes needed including the NUL.
   capacity 0 (buffer may be null) only asks for the size. */
FIRELOOK_API fl_result fl_package_get_default_look_json(fl_package package, char* buffer, size_t capacity,
                                                        size_t* out_size);
/* The frame's U for GPU reconstruction, copied into the caller's buffer (reads and decompresses the frame
   each call: call once per upload; fl_instance_get_frame_u takes the frame a world already holds).
   Layout: layers = ceil(rank / 4) RGBA16F images of width x height;
   layer l, pixel (x, y), channel c holds U[pixel][4 l + c] (0 beyond the rank), IEEE half floats:
       buffer[((l * height + y) * width + x) * 4 + c]      (y = 0 is the top row)
   i.e. a 2D texture array (or a tall 2D texture of height layers * height). capacity and *out_count are
   in uint16_t elements: layers * width * height * 4. */
FIRELOOK_API fl_result fl_package_get_frame_u(fl_package package, int32_t frame, uint16_t* buffer, size_t capacity,
                                              size_t* out_count);
/* The frame's optical depths for exact alpha, float32 single-channel layers of width x height, with
   S = footprint_samples and T = alpha_threshold_count: first S layers O_b(s), then S * T layers
   O_a(s, j) (sample-major: layer S + s * T + j):
       buffer[(layer * height + y) * width + x]
   capacity and *out_count in floats: S * (1 + T) * width * height. */
FIRELOOK_API fl_result fl_package_get_frame_depths(fl_package package, int32_t frame, float* buffer,
                                                   size_t capacity, size_t* out_count);

/* The camera the package was baked with (read once when it was loaded). First published size: through
   world_from_camera. */
typedef struct fl_camera {
    uint32_t struct_size;  /* in: sizeof(fl_camera); kept */
    int32_t width, height; /* the image size it was baked at, pixels */
    int32_t reserved;
    double yfov_radians;   /* vertical field of view, radians, in (0, pi) */
    /* Column-major 4x4 (glTF order): world = world_from_camera * camera. The camera sits at its local
       origin, looks down local -Z, +Y up and +X right, in the world space of the baked volume. */
    double world_from_camera[16];
} fl_camera;

/* Thread-safe. The package's camera; every value finite. FL_ERROR_NOT_FOUND when the package records
   none; FL_ERROR_CORRUPT (the message names the file and the field) when the recorded one is malformed
   (the package still plays). */
FIRELOOK_API fl_result fl_package_get_camera(fl_package package, fl_camera* out_camera);
/* Thread-safe. The package's directional lights (fl_package_info.light_count of them), either array may
   be null: directions[3 l + i] the unit vector (world space, x y z) light l travels along;
   default_irradiance[3 l + c] its RGB irradiance in the package's default look (a look's
   light_irradiance, same units). capacity: lights available; *out_count (if not null) gets light_count.
   (A package whose light cannot be normalised does not load: its default look is refused.) */
FIRELOOK_API fl_result fl_package_get_lights(fl_package package, double* directions, float* default_irradiance,
                                             uint32_t capacity, uint32_t* out_count);
/* Thread-safe. The package's META document as JSON (docs/package-format.md: "bake", "provenance" with the
   sequence, grid names and temperature mapping, "camera", "errors"), NUL-terminated, with the size
   convention of fl_package_get_default_look_json. Its keys are the baker's: read it for provenance,
   not for anything a function above gives. */
FIRELOOK_API fl_result fl_package_get_metadata_json(fl_package package, char* buffer, size_t capacity,
                                                    size_t* out_size);

/* ---- looks -------------------------------------------------------------- */

/* Thread-safe. json: a firelook-look document (docs/model.md, "The look file"); length 0 = NUL-terminated.
   source_name (may be null) prefixes error messages. Looks are checked against a package when used. */
FIRELOOK_API fl_result fl_look_from_json(const char* json, size_t length, const char* source_name, fl_look* out_look);
FIRELOOK_API fl_result fl_package_default_look(fl_package package, fl_look* out_look);
/* Thread-safe. Instances copy looks when they are set: releasing a look never affects them. */
FIRELOOK_API fl_result fl_look_release(fl_look look);
/* The look as JSON (same size convention as fl_package_get_default_look_json). */
FIRELOOK_API fl_result fl_look_to_json(fl_look look, char* buffer, size_t capacity, size_t* out_size);
/* Thread-safe. The look's emissivity at the centre of each of the package's temperature bins, whatever
   the look's emission form (preset, stops or bins): rgb[3 i + c] for bin i, whose centre is
   temperature_lo + (i + 0.5) (temperature_hi - temperature_lo) / bin_count (fl_package_info); finite and
   >= 0. A look of that emissivity in bins form renders the same image. capacity: bins available;
   *out_count (if not null) gets bin_count; rgb null only asks for it. A bins-form look with another
   number of bins: FL_ERROR_LOOK. */
FIRELOOK_API fl_result fl_look_get_bin_emissivity(fl_look look, fl_package package, float* rgb, uint32_t capacity,
                                                  uint32_t* out_count);
/* fl_look_desc.emission_form: which of the look file's emission forms (docs/model.md, "The look file"). */
enum { FL_EMISSION_PRESET = 0, FL_EMISSION_STOPS = 1, FL_EMISSION_BINS = 2 };

/* A look's values in plain form, for editors: the keys of a look file without its JSON. In
   fl_look_create the pointers are read for their counts; fl_look_get_desc leaves them null and writes the
   arrays to buffers of its own arguments. Unlike the other desc structs, 0 is a value here, not a default:
   fill every field (fl_look_get_desc of an existing look is a good start). First published size: through
   reserved. */
typedef struct fl_look_desc {
    uint32_t struct_size;
    int32_t emission_form;      /* FL_EMISSION_PRESET, FL_EMISSION_STOPS or FL_EMISSION_BINS */
    double temperature_threshold, smoke_extinction, flame_extinction, albedo;
    char preset[32];            /* FL_EMISSION_PRESET: a name of fl_emission_preset_name, NUL-terminated */
    double preset_scale;        /* FL_EMISSION_PRESET: its scale */
    const double* stops;        /* FL_EMISSION_STOPS: stop_count x (temperature, r, g, b) */
    uint32_t stop_count;
    uint32_t bin_count;         /* FL_EMISSION_BINS: bin_count x (r, g, b) emissivity, one per bin */
    const float* bins;
    const float* lights;        /* light_count x (r, g, b) irradiance, one per directional light */
    uint32_t light_count;
    uint32_t reserved;
} fl_look_desc;

/* Thread-safe. A look from its values, checked as fl_look_from_json checks a look file's: a value out of
   range (a negative extinction or colour, albedo outside [0, 1], stops out of order, an unknown preset,
   an empty emission): FL_ERROR_LOOK, the message naming source_name (may be null) and the key; an
   unknown emission_form, a null array with a count above 0 or a preset name not NUL-terminated:
   FL_ERROR_INVALID_ARGUMENT. fl_look_to_json of the new look is the look file of these values. */
FIRELOOK_API fl_result fl_look_create(const fl_look_desc* desc, const char* source_name, fl_look* out_look);
/* Thread-safe. The look's values: *out_desc gets the form, the scalars, the preset and the counts (its
   pointers null); stops (4 doubles a stop), bins and lights (3 floats each) get the arrays, their
   capacities counted in stops, bins and lights. A capacity of 0 leaves that array unwritten (so a call
   with all three 0 asks for the counts); a capacity below the count: FL_ERROR_BUFFER_TOO_SMALL; a null
   buffer with a capacity above 0, or out_desc null: FL_ERROR_INVALID_ARGUMENT. */
FIRELOOK_API fl_result fl_look_get_desc(fl_look look, fl_look_desc* out_desc, double* stops, uint32_t stop_capacity,
                                        float* bins, uint32_t bin_capacity, float* lights, uint32_t light_capacity);
/* Thread-safe. A look file (docs/model.md, "The look file"; what firelook render --look reads): the look
   fl_look_from_json makes of its text, with path naming it in messages. A file that cannot be opened or
   read: FL_ERROR_IO; bad JSON or a bad value: FL_ERROR_LOOK; path or out_look null:
   FL_ERROR_INVALID_ARGUMENT. */
FIRELOOK_API fl_result fl_look_load_file(const char* path, fl_look* out_look);
/* The emission presets a look may name ({"preset": NAME, "scale": S}), so that an editor offers the
   library's list: *out_count gets how many there are (out_count null: FL_ERROR_INVALID_ARGUMENT).
   Callable any time. */
FIRELOOK_API fl_result fl_emission_preset_count(uint32_t* out_count);
/* The name of preset `index` (0 to count - 1), NUL-terminated, with the size convention of
   fl_package_get_default_look_json. An index past the last: FL_ERROR_NOT_FOUND. Callable any time. */
FIRELOOK_API fl_result fl_emission_preset_name(uint32_t index, char* buffer, size_t capacity, size_t* out_size);

/* ---- inverse design: the look that matches a target image ---------------- */

/* fl_fit_desc.flags. */
enum {
    FL_FIT_HOLD_TEMPERATURE_THRESHOLD = 1, /* hold T_c at fl_fit_desc.temperature_threshold */
    FL_FIT_HOLD_SMOKE_EXTINCTION = 2,      /* hold k_s at smoke_extinction */
    FL_FIT_HOLD_FLAME_EXTINCTION = 4,      /* hold k_f at flame_extinction */
    FL_FIT_OVER_BACKGROUND = 8             /* the target is opaque, composited over background: alpha not matched */
};

/* Called on the fitting thread with the fraction done (0 to 1) at least every few milliseconds of
   work; a nonzero return stops the fit (FL_ERROR_CANCELLED, no look made). */
typedef int32_t (*fl_fit_progress_fn)(double fraction, void* user);

/* One frame's target. First published size: through progress_user. */
typedef struct fl_fit_desc {
    uint32_t struct_size;
    int32_t frame;              /* the frame number the target shows */
    /* width x height x 4 floats at the package's image size (fl_package_info): linear RGBA,
       premultiplied, top row first, as fl_instance_get_image gives; every value finite. */
    const float* target_rgba;
    /* width x height weights, each finite and >= 0 (0 leaves a pixel out); null: 1 everywhere. At least
       one must be above 0. */
    const float* weights;
    uint32_t flags;             /* FL_FIT_* bits; other bits are refused */
    float background[3];        /* linear RGB, >= 0, with FL_FIT_OVER_BACKGROUND */
    /* Held values (inside the package's baked ranges), read where flags say so. */
    double temperature_threshold, smoke_extinction, flame_extinction;
    double smoothness;          /* weight of the emission's second differences across bins; 0: each bin free */
    fl_fit_progress_fn progress; /* may be null */
    void* progress_user;
} fl_fit_desc;

/* What a fit reached. First published size: through evaluations. */
typedef struct fl_fit_report {
    uint32_t struct_size;       /* in: sizeof(fl_fit_report); kept */
    double relative_rmse;       /* sqrt(sum W |rgb - t|^2 / sum W |t|^2), linear RGB, the look as rendered */
    double alpha_rmse;          /* sqrt(sum W (alpha - alpha_t)^2 / sum W); 0 when alpha is not matched */
    double alpha_max_error;     /* over pixels with W > 0; 0 when alpha is not matched */
    int32_t evaluations;        /* extinction settings tried */
} fl_fit_report;

/* Thread-safe (a fit of one 256x256 frame takes seconds: call it from a worker thread). The look inside the
   package's baked ranges whose image of the frame best matches the target (T_c, k_s, k_f, per-bin
   emission >= 0, the lights' irradiance), as firelook fit finds it (docs/cli.md, "firelook fit"); the same
   inputs give the same look. The new look goes to *out_look (release it with fl_look_release); out_report
   may be null. A target of another size, a bad weight or value, weights all 0, a held value outside its
   range, unknown flags: FL_ERROR_INVALID_ARGUMENT; no such frame: FL_ERROR_NOT_FOUND. */
FIRELOOK_API fl_result fl_package_fit_look(fl_package package, const fl_fit_desc* desc, fl_look* out_look,
                                           fl_fit_report* out_report);

/* A target image (and mask) to read for fl_package_fit_look. First published size: through exposure. */
typedef struct fl_fit_target_desc {
    uint32_t struct_size;
    int32_t frame;            /* the frame number the target shows (named in messages) */
    /* .exr: linear premultiplied RGBA, its alpha matched unless it is opaque; .png: read through the display
       transform firelook render uses for PNG, each pixel weighted by the sRGB curve's slope at its shown
       value and clipped pixels left out. Required. */
    const char* target_path;
    const char* mask_path;    /* null: no mask; else each pixel's weight is its red channel, clamped to [0, 1] */
    uint32_t flags;           /* FL_FIT_OVER_BACKGROUND: opaque over `background`, alpha not matched; other bits are refused */
    float background[3];      /* linear RGB, finite, with FL_FIT_OVER_BACKGROUND */
    double exposure;          /* stops the target was exposed by (undone on the colour and the background) */
} fl_fit_target_desc;

/* What fl_fit_target_load read, in fl_fit_desc's terms. First published size: through clipped_pixels. */
typedef struct fl_fit_target_info {
    uint32_t struct_size;     /* in: sizeof(fl_fit_target_info); kept */
    uint32_t flags;           /* FL_FIT_OVER_BACKGROUND where alpha is not matched (an opaque target, or a
                                 background given): for fl_fit_desc.flags */
    float background[3];      /* exposure undone: for fl_fit_desc.background */
    uint32_t reserved;
    uint64_t clipped_pixels;  /* PNG pixels left out because a channel was clipped */
} fl_fit_target_info;

/* Thread-safe. Reads a target as firelook fit does (docs/cli.md, "firelook fit"), at the package's image
   size: rgba gets width x height x 4 floats (linear, premultiplied, top row first, exposure undone:
   fl_fit_desc.target_rgba), weights width x height floats (fl_fit_desc.weights; at least one above 0).
   pixel_capacity: pixels each buffer holds; *out_pixel_count (if not null) gets width x height; a capacity
   of 0 only asks for it (the buffers and out_info may then be null). A missing or unreadable file:
   FL_ERROR_IO; a file of another size, a value that is not finite, no pixel left to fit (mask 0 everywhere,
   every pixel clipped), unknown flags, a null desc->target_path or buffer: FL_ERROR_INVALID_ARGUMENT. */
FIRELOOK_API fl_result fl_fit_target_load(fl_package package, const fl_fit_target_desc* desc, float* rgba,
                                          float* weights, size_t pixel_capacity, size_t* out_pixel_count,
                                          fl_fit_target_info* out_info);
/* |fit - target| per pixel in linear RGB, alpha 1 (what firelook fit --difference writes): with
   FL_FIT_OVER_BACKGROUND in flags the fit (premultiplied, as rendered) is composited over background
   first, as the fit compared it. pixel_count pixels of 4 floats in each array; background may be null
   without that flag. A null array, pixel_count 0 or unknown flags: FL_ERROR_INVALID_ARGUMENT. Callable any
   time. */
FIRELOOK_API fl_result fl_fit_difference(const float* target_rgba, const float* fit_rgba, size_t pixel_count,
                                         uint32_t flags, const float* background, float* out_rgba);

/* ---- worlds and instances ---------------------------------------------- */

/* First published size: through frame_cache_bytes. */
typedef struct fl_world_desc {
    uint32_t struct_size;
    uint32_t reserved;
    /* Bound on the frame cache (the frames in their resident form, their depth tables and one evicted
       frame's buffers kept for the next load): least recently used frames not used by the current update
       are evicted after each update; frames in use are never evicted. 0 = 512 MiB.
       fl_world_memory reports what the world holds. */
    uint64_t frame_cache_bytes;
} fl_world_desc;

/* First published size: through look. */
typedef struct fl_instance_desc {
    uint32_t struct_size;
    fl_package package;  /* required */
    fl_look look;        /* 0: the package's default look */
} fl_instance_desc;

/* No struct_size: arrays of it are read with fl_init's sizeof_keyframe as the stride. First published
   size: through reserved. */
typedef struct fl_keyframe {
    double frame;  /* package frame number, fractional allowed */
    fl_look look;
    uint32_t reserved;
} fl_keyframe;

/* First published size: through rate. */
typedef struct fl_playback_desc {
    uint32_t struct_size;
    int32_t paused;           /* non-zero: fl_world_update does not advance the time */
    int32_t no_loop;          /* non-zero: clamp at the ends of the range instead of wrapping */
    int32_t use_frame_range;  /* non-zero: play first_frame..last_frame (clamped to the baked frames) */
    int32_t first_frame, last_frame;
    double time;  /* seconds from the start of the range */
    double rate;  /* frames per second; 0 = 24; negative plays backwards */
} fl_playback_desc;

/* First published size: through streaks. */
typedef struct fl_outputs_desc {
    uint32_t struct_size;
    int32_t image;       /* non-zero: CPU image each update */
    int32_t lens_flare;  /* non-zero: lens flare each update (requires image) */
    /* Lens flare settings; 0 = default, negative = off for the intensities and counts:
       threshold (1.0): luminance above which light feeds the flare (use a tiny positive value for 0);
       intensity (0.15); ghost_count (4, max 8); ghost_spacing (0.45): ghost i is the bright image scaled by
       -(spacing (i+1)) for even i and +(spacing (i+1)) for odd i through the image centre; halo_radius (0.6)
       and halo_width (0.08) as fractions of half the image diagonal; halo_intensity (0.5); streak_length (0.06)
       decay length as a fraction of the width; streak_intensity (0.6); streaks (1: horizontal, 2: + vertical). */
    float flare_threshold;
    float flare_intensity;
    int32_t ghost_count;
    float ghost_spacing;
    float halo_radius;
    float halo_width;
    float halo_intensity;
    float streak_length;
    float streak_intensity;
    int32_t streaks;
} fl_outputs_desc;

/* What the last update produced for an instance; with the package's U and depth textures this is all a
   shader needs:  rgb(p) = max(0, sum_k U[p][k] * z[k])  (z from fl_instance_get_coefficients),
   alpha(p) = mean over the footprint samples s of 1 - exp(-(extinction_a * O_a(s, p) + extinction_b * O_b(s, p))),
   O_a(s, p) = (1 - alpha_layer_t) * O_a(s, alpha_layer_lower)(p) + alpha_layer_t * O_a(s, alpha_layer_upper)(p)
   (threshold indices j of fl_package_get_frame_depths). First published size: through reserved. */
typedef struct fl_instance_state {
    uint32_t struct_size;
    int32_t updated;  /* 0 until the first update after creation */
    int32_t frame;    /* baked frame shown */
    int32_t rank;     /* of that frame: z has rank x 3 floats */
    double frame_position;  /* continuous; keyframes are evaluated here */
    double time;            /* playback time after wrapping */
    double temperature_threshold, smoke_extinction, flame_extinction;  /* the interpolated look */
    float extinction_a, extinction_b;
    int32_t alpha_layer_lower, alpha_layer_upper;
    float alpha_layer_t;
    int32_t reserved;
} fl_instance_state;

/* Worlds: fl_world_create/destroy are thread-safe with respect to other worlds. */
FIRELOOK_API fl_result fl_world_create(const fl_world_desc* desc, fl_world* out_world);  /* desc may be null */
/* Destroys the world and every instance in it (their handles become invalid). */
FIRELOOK_API fl_result fl_world_destroy(fl_world world);
/* Runs playback -> keyframes -> coefficients -> images -> lens flare for every instance. dt in seconds. */
FIRELOOK_API fl_result fl_world_update(fl_world world, double dt);
FIRELOOK_API fl_result fl_world_instance_count(fl_world world, uint32_t* out_count);
/* What the world holds, in bytes, as of the last call that changed it: *frame_cache_bytes the frame cache
   (see fl_world_desc.frame_cache_bytes), *instance_bytes the per-instance images, flare images,
   coefficients and looks and the scratch buffers. Either pointer may be null. */
FIRELOOK_API fl_result fl_world_memory(fl_world world, uint64_t* frame_cache_bytes, uint64_t* instance_bytes);

FIRELOOK_API fl_result fl_instance_create(fl_world world, const fl_instance_desc* desc, fl_instance* out_instance);
FIRELOOK_API fl_result fl_instance_destroy(fl_world world, fl_instance instance);
/* A constant look (replaces any keyframes). */
FIRELOOK_API fl_result fl_instance_set_look(fl_world world, fl_instance instance, fl_look look);
/* Keys at package frame numbers (any order; count >= 1), held before the first and after the last; between
   keys T_c, k_s, k_f, each light's irradiance and each key's fitted emission coefficients are blended
   linearly, the rule firelook animate uses (docs/model.md, "Keyed looks"; where both keys' emission fits
   are exact that is linear in each bin's colour). All keys must fit the package (albedo, lights). */
FIRELOOK_API fl_result fl_instance_set_keyframes(fl_world world, fl_instance instance, const fl_keyframe* keys,
                                                 uint32_t count);
FIRELOOK_API fl_result fl_instance_set_playback(fl_world world, fl_instance instance, const fl_playback_desc* desc);
FIRELOOK_API fl_result fl_instance_set_outputs(fl_world world, fl_instance instance, const fl_outputs_desc* desc);
FIRELOOK_API fl_result fl_instance_get_state(fl_world world, fl_instance instance, fl_instance_state* out_state);
/* z = S V^T w of the last update, rank x 3 floats, z[k * 3 + channel]. capacity in floats; *out_rank gets the
   rank (a capacity of 0 only asks for it). */
FIRELOOK_API fl_result fl_instance_get_coefficients(fl_world world, fl_instance instance, float* z,
                                                    size_t capacity, int32_t* out_rank);
/* The CPU image of the last update: width x height x 4 floats, premultiplied linear RGBA, top row first.
   FL_ERROR_NO_DATA if the image output is off or no update ran since it was turned on. */
FIRELOOK_API fl_result fl_instance_get_image(fl_world world, fl_instance instance, float* rgba, size_t capacity);
/* The lens flare of the last update: same size, RGBA with A = 0, to be added on top. */
FIRELOOK_API fl_result fl_instance_get_flare(fl_world world, fl_instance instance, float* rgba, size_t capacity);
/* A new look handle (the caller releases it) holding the look the instance shows at its frame position
   (fl_instance_state.frame_position of the last update; the package's first frame before any): with a
   constant look or where one keyframe holds, that look exactly as it was set (its JSON is the same);
   between keys, T_c, k_s, k_f and the lights interpolated as the world does and the emission in bins form:
   the interpolated emission the image is made of, at each bin centre (so a reference render of this look
   shows what the instance shows, even where a key's emission needed the non-negative fit). With a light
   from fl_instance_set_light_direction[s], the six-way or sphere lights carry the irradiance it gives them. A world
   call (one thread at a time per world). */
FIRELOOK_API fl_result fl_instance_get_look(fl_world world, fl_instance instance, fl_look* out_look);
/* The U and optical depth layers of the frame the instance's last update showed, taken from the frame the
   world holds for it (its frame cache): no read, no decompression. Layout, sizes, the capacity-0 size query
   and the values are those of fl_package_get_frame_u / fl_package_get_frame_depths for that frame
   (fl_instance_state.frame). FL_ERROR_NO_DATA until the first update after creation or after
   fl_instance_set_outputs (the size query too). World calls (one thread at a time per world). */
FIRELOOK_API fl_result fl_instance_get_frame_u(fl_world world, fl_instance instance, uint16_t* buffer,
                                               size_t capacity, size_t* out_count);
FIRELOOK_API fl_result fl_instance_get_frame_depths(fl_world world, fl_instance instance, float* buffer,
                                                    size_t capacity, size_t* out_count);

/* ---- the fire as a light source (issue 16, item 4) ---------------------- */

/* One point light standing for part of the fire's emission after its own absorption (a bake stores, per
   frame, what these need for any look: runtime/basis/fire_lights.h; packages baked before have none).
   No struct_size: arrays of it are written with the stride sizeof_light given to the calls below.
   First published size: through radius. */
typedef struct fl_fire_light {
    /* World space (the baked volume's): the centroid of the light's escaping power. Inside the volume's
       bounds. */
    double position[3];
    /* RGB radiant intensity, isotropic: the model's radiance times world area. At distance d it gives
       the fluence rate intensity / d^2 (radiance integrated over all directions, the irradiance of a
       small sphere per unit of its cross-section), which is also the irradiance on a surface facing it
       (times cos for a tilted one): the units of a look's light_irradiance. Finite, >= 0. */
    float intensity[3];
    /* World units: the RMS distance of that power from position. Use it as the light's source radius
       (soft falloff); the inverse-square law holds beyond about two radii. Finite, >= 0. */
    float radius;
} fl_fire_light;

/* Thread-safe. The fire lights of a baked frame for a look (0: the package's default look): light_count of
   them, a power of two from 1 up to the stored count, each the merge of neighbouring stored ones. lights:
   capacity structs of sizeof_light bytes (pass sizeof(fl_fire_light)); may be null with light_count 0,
   which only asks: *out_max_count (if not null) gets the stored count, 0 for a package baked without fire
   lights (then any light_count > 0 gives FL_ERROR_NOT_FOUND). A frame not in the package: FL_ERROR_NOT_FOUND;
   light_count not a power of two or above the stored count: FL_ERROR_INVALID_ARGUMENT; capacity below it:
   FL_ERROR_BUFFER_TOO_SMALL; sizeof_light below the first published size: FL_ERROR_STRUCT_SIZE; a look that
   does not fit the package: FL_ERROR_LOOK. Costs microseconds plus the look's emission fit. */
FIRELOOK_API fl_result fl_package_get_fire_lights(fl_package package, int32_t frame, fl_look look,
                                                  uint32_t light_count, fl_fire_light* lights, uint32_t sizeof_light,
                                                  uint32_t capacity, uint32_t* out_max_count);
/* The same for what an instance showed at its last update: its frame (fl_instance_state.frame) and the
   look at its frame position (fl_instance_get_look). FL_ERROR_NO_DATA before the first update. A world
   call (one thread at a time per world). */
FIRELOOK_API fl_result fl_instance_get_fire_lights(fl_world world, fl_instance instance, uint32_t light_count,
                                                   fl_fire_light* lights, uint32_t sizeof_light, uint32_t capacity,
                                                   uint32_t* out_max_count);

/* ---- the fire's light as an irradiance volume (issue 29) ---------------- */

/* Where a frame's fire probes are (a bake with firelook bake --fire-probes N stores, per frame, what they
   need for any look: runtime/basis/fire_probes.h; other packages have none). Probe (i, j, k) sits at
   origin + spacing * (i, j, k) and is number i + counts[0] (j + counts[1] k). Between probes the values
   are blended trilinearly after weighting each probe by s(p) = |p - falloff_centre|^2 + falloff_radius^2,
   and divided by s(x) at the point x (the fire's light falls off about as 1 / s; outside the grid the
   nearest face's values so fall off with the inverse square); falloff_radius 0 means plain trilinear,
   clamped at the faces. fl_fire_probes_sample does exactly this. First published size: through
   falloff_radius. */
typedef struct fl_fire_probe_grid {
    uint32_t struct_size;     /* in: sizeof(fl_fire_probe_grid); kept */
    int32_t counts[3];        /* probes along x, y, z, each 2 to 64 */
    double origin[3];         /* world space (the baked volume's) */
    double spacing[3];        /* world units, each > 0 */
    double falloff_centre[3]; /* world space */
    double falloff_radius;    /* world units, >= 0 */
} fl_fire_probe_grid;

/* Thread-safe. A baked frame's fire probes for a look (0: the package's default look): out_grid (if not
   null) gets their placement; coefficients[27 p + 3 k + c] gets probe p's real spherical-harmonic
   coefficient k (order Y00, Y1-1, Y10, Y11, Y2-2, Y2-1, Y20, Y21, Y22 of the world direction towards where
   the light comes from) of the radiance arriving from the fire, channel c (the model's radiance, as a
   look's light_irradiance per steradian). capacity: floats available; 0 only asks: *out_count (if not
   null) gets 27 times the probe count. The fluence rate at a probe is sqrt(4 pi) L00; the irradiance on
   a surface facing a unit normal n is order-2 SH's, sum_l A_l sum_m L_lm Y_lm(n), A = (pi, 2 pi / 3,
   pi / 4), at least 0, blended per channel with a directional split where the light comes from one
   side (the exact rule: docs/package-format.md, "Fire probes"; fl_fire_probes_sample applies it).
   Every value finite. A frame not in the package, or a package baked without fire probes:
   FL_ERROR_NOT_FOUND; capacity below the count: FL_ERROR_BUFFER_TOO_SMALL; a look that does not fit the
   package: FL_ERROR_LOOK. Costs under a microsecond per probe (0.3 measured) plus the look's emission fit. */
FIRELOOK_API fl_result fl_package_get_fire_probes(fl_package package, int32_t frame, fl_look look,
                                                  fl_fire_probe_grid* out_grid, float* coefficients,
                                                  size_t capacity, size_t* out_count);
/* The same for what an instance showed at its last update: its frame (fl_instance_state.frame) and the
   look at its frame position (fl_instance_get_look). FL_ERROR_NO_DATA before the first update. A world
   call (one thread at a time per world). */
FIRELOOK_API fl_result fl_instance_get_fire_probes(fl_world world, fl_instance instance,
                                                   fl_fire_probe_grid* out_grid, float* coefficients,
                                                   size_t capacity, size_t* out_count);
/* Thread-safe, no state: the fire's light at a world point, blended from probes (grid and count
   coefficients as the calls above wrote them) by the grid's rule. normal null: *out_rgb the fluence rate
   (radiance integrated over all directions); otherwise the irradiance on a surface facing normal
   (normalised here; a zero normal gives 0). Finite and >= 0 for finite input. A null pointer, a count
   other than 27 times the grid's probes or a grid the calls above would not write (counts outside 2..64,
   a spacing not > 0, a non-finite value) or a non-finite point: FL_ERROR_INVALID_ARGUMENT. */
FIRELOOK_API fl_result fl_fire_probes_sample(const fl_fire_probe_grid* grid, const float* coefficients,
                                             size_t count, const double point[3], const double* normal,
                                             float out_rgb[3]);

/* ---- light from a direction chosen at run time -------------------------- */

/* Thread-safe. Whether the package was baked with six-way lights (firelook bake --lights six-way):
   *out_first_light gets the index, in fl_package_get_lights' list, of the first of the six (right, top,
   back, left, bottom, front, camera-relative, in that order). FL_ERROR_NOT_FOUND without them. */
FIRELOOK_API fl_result fl_package_get_six_way_lights(fl_package package, int32_t* out_first_light);

/* A directional light for fl_instance_set_light_direction[s]. First published size: through reserved2. */
typedef struct fl_light_direction_desc {
    uint32_t struct_size;  /* sizeof(fl_light_direction_desc) */
    uint32_t reserved;
    double direction[3];   /* the direction the light travels, world space (as fl_package_get_lights);
                              any finite non-zero length */
    float irradiance[3];   /* RGB irradiance it carries, finite and >= 0, in a look's light_irradiance units
                              (0 0 0: a dark light) */
    int32_t reserved2;
} fl_light_direction_desc;

/* Thread-safe. The lights a light from a direction chosen at run time is made of: the six-way lights, or
   the N lights on a geodesic sphere of firelook bake --lights sphere (N = 12 or 42, camera-relative;
   fl_package_get_lights lists their directions). *out_first_light gets the index of the first in
   fl_package_get_lights' list, *out_count their count (6 for six-way). FL_ERROR_NOT_FOUND without
   either; nothing is written on an error. */
FIRELOOK_API fl_result fl_package_get_relight_lights(fl_package package, int32_t* out_first_light,
                                                     int32_t* out_count);

/* Relights an instance of a package baked with six-way or sphere lights (firelook bake --lights six-way
   or --lights sphere) from any direction d = desc->direction: from the next fl_world_update on, those
   lights' irradiance in the look the instance shows (constant or keyframed) is replaced by
   w_i(d) * desc->irradiance. Six-way lights are weighted by
       w_i(d) = max(0, d . t_i)^2 / sum_j max(0, d . t_j)^2      (t_i: the direction six-way light i travels)
   sphere lights by spherical barycentric interpolation on the geodesic triangle that holds d (the three
   lights at its corners); both are >= 0, sum to 1 and are continuous in d, and at a baked direction the
   image is exactly that light's. The scene's own lights keep the look's irradiance. The light stays
   across fl_instance_set_look and fl_instance_set_keyframes; fl_instance_get_look reports the irradiance
   it gives. desc null: the look's own six-way or sphere irradiance again. A package with neither:
   FL_ERROR_NOT_FOUND; a zero, NaN or infinite direction, or a non-finite or negative irradiance:
   FL_ERROR_INVALID_ARGUMENT; nothing changes on an error. A world call (one thread at a time per world).
   Its error against the reference path tracer is measured in the README ("Light from any direction"). */
FIRELOOK_API fl_result fl_instance_set_light_direction(fl_world world, fl_instance instance,
                                                       const fl_light_direction_desc* desc);
/* Several lights at once, as fl_instance_set_light_direction for each, their irradiances summed (the
   image is linear in them). lights[] steps by lights[0].struct_size, which every element must share (at
   least the first published size); count 0 (lights may be null): those lights dark. Errors as
   fl_instance_set_light_direction for any light, FL_ERROR_STRUCT_SIZE for a size that differs; nothing
   changes on an error. */
FIRELOOK_API fl_result fl_instance_set_light_directions(fl_world world, fl_instance instance,
                                                        const fl_light_direction_desc* lights, uint32_t count);

/* ---- start-up and shutdown ---------------------------------------------- */

FIRELOOK_API fl_result fl_init(const fl_init_desc* desc);
/* Releases every package, look and world; all handles become invalid. */
FIRELOOK_API fl_result fl_shutdown(void);
/* The library's FIRELOOK_HEADER_VERSION. Callable any time. */
FIRELOOK_API uint32_t fl_version(void);

/* ---- defaults (inline: they record the caller's struct sizes) ---------- */

#if defined(__GNUC__)
#  define FIRELOOK_INLINE static inline __attribute__((unused))
#else
#  define FIRELOOK_INLINE static inline
#endif
#ifdef __cplusplus
#  define FIRELOOK_ZERO {}
#else
#  define FIRELOOK_ZERO {0}
#endif

FIRELOOK_INLINE fl_init_desc fl_init_desc_defaults(void) {
    fl_init_desc d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_init_desc);
    d.header_version = FIRELOOK_HEADER_VERSION;
    d.sizeof_world_desc = (uint32_t)sizeof(fl_world_desc);
    d.sizeof_instance_desc = (uint32_t)sizeof(fl_instance_desc);
    d.sizeof_playback_desc = (uint32_t)sizeof(fl_playback_desc);
    d.sizeof_outputs_desc = (uint32_t)sizeof(fl_outputs_desc);
    d.sizeof_package_info = (uint32_t)sizeof(fl_package_info);
    d.sizeof_instance_state = (uint32_t)sizeof(fl_instance_state);
    d.sizeof_keyframe = (uint32_t)sizeof(fl_keyframe);
    return d;
}
FIRELOOK_INLINE fl_world_desc fl_world_desc_defaults(void) {
    fl_world_desc d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_world_desc);
    return d;
}
FIRELOOK_INLINE fl_instance_desc fl_instance_desc_defaults(void) {
    fl_instance_desc d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_instance_desc);
    return d;
}
FIRELOOK_INLINE fl_playback_desc fl_playback_desc_defaults(void) {
    fl_playback_desc d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_playback_desc);
    return d;
}
FIRELOOK_INLINE fl_outputs_desc fl_outputs_desc_defaults(void) {
    fl_outputs_desc d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_outputs_desc);
    return d;
}
FIRELOOK_INLINE fl_package_info fl_package_info_defaults(void) {
    fl_package_info d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_package_info);
    return d;
}
FIRELOOK_INLINE fl_package_memory_desc fl_package_memory_desc_defaults(void) {
    fl_package_memory_desc d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_package_memory_desc);
    return d;
}
FIRELOOK_INLINE fl_camera fl_camera_defaults(void) {
    fl_camera d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_camera);
    return d;
}
FIRELOOK_INLINE fl_fit_desc fl_fit_desc_defaults(void) {
    fl_fit_desc d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_fit_desc);
    return d;
}
FIRELOOK_INLINE fl_fit_report fl_fit_report_defaults(void) {
    fl_fit_report d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_fit_report);
    return d;
}
FIRELOOK_INLINE fl_look_desc fl_look_desc_defaults(void) {
    fl_look_desc d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_look_desc);
    return d;
}
FIRELOOK_INLINE fl_fit_target_desc fl_fit_target_desc_defaults(void) {
    fl_fit_target_desc d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_fit_target_desc);
    return d;
}
FIRELOOK_INLINE fl_fit_target_info fl_fit_target_info_defaults(void) {
    fl_fit_target_info d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_fit_target_info);
    return d;
}
FIRELOOK_INLINE fl_light_direction_desc fl_light_direction_desc_defaults(void) {
    fl_light_direction_desc d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_light_direction_desc);
    return d;
}
FIRELOOK_INLINE fl_instance_state fl_instance_state_defaults(void) {
    fl_instance_state d = FIRELOOK_ZERO;
    d.struct_size = (uint32_t)sizeof(fl_instance_state);
    return d;
}

#ifdef __cplusplus
}  /* extern "C" */
#endif

#endif  /* FIRELOOK_H */
