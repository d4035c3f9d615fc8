// The runtime world: many fire instances, each playing a package with a
// keyframed look, updated together by one update(dt) (docs/model.md).
//
// Data-oriented: per-instance state lives in structure-of-arrays (dense, one
// entry per live instance, swap-removed on destroy); update() runs systems
// that are flat loops over them, in this order:
//   1. playback     advance time, pick the frame (see PlaybackSettings)
//   2. keyframes    interpolate the look at the frame position (look_track.h)
//   3. residency    make every frame in use resident in the frame cache
//   4. coefficients z = S V^T w per instance (rank x 3), the instances that show
//                   one frame in one batch (basis/coefficients.h)
//   5. image        optional CPU image = U z, alpha from the optical depths
//   6. lens flare   optional, from the instance's image (lens_flare.h)
// then the frame cache is trimmed to its budget, and the next frame of one
// playing instance is decoded ahead of time when the budget has room.
//
// Frames: an instance shows baked frames only. The continuous frame position
// (used for the keyframed look, which animates smoothly) selects the last baked
// frame at or below it ("hold", no blending of two frames' images), so frame f
// is shown for positions in [f, next baked frame).
//
// Shared factors and memory: all instances of one package in a world share one
// cache entry per frame, the frame in its resident form (basis/resident_frame.h:
// the codec's quantised values, about a third of the float layout, decoded in
// about the time it takes to read them). After each update, if
// the cache exceeds WorldSettings::frame_cache_bytes, the least recently used
// frames not used by this update are evicted; frames used by the current
// update are never evicted, so the bound can be exceeded by exactly the frames
// in use at once. The buffers of one evicted frame are kept (and counted) for
// the next frame to load into, while that stays within the budget, so
// streaming frames in and out needs no fresh memory. Different worlds keep
// separate caches.
//
// Allocation: update() allocates only when a frame is loaded into the cache
// (I/O, decompression); in steady state it is allocation-free. Creating
// instances and setting looks, keyframes and outputs allocate.
//
// Thread-safety: a World is not internally synchronised; use each world from
// one thread at a time. Packages may be shared between worlds on different
// threads.
//
// Errors: InvalidHandle for a stale or invalid handle, LookError for a look
// that does not fit the package, Error(Limit) past the instance limit,
// an InvalidArgument Error for other bad input.
// A call that throws leaves the world unchanged.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "basis/coefficients.h"
#include "basis/relight.h"
#include "look/look.h"
#include "world/handle_pool.h"
#include "world/host_memory.h"
#include "world/lens_flare.h"
#include "world/look_track.h"
#include "world/package.h"

namespace firelook::world {

// From the world's HandlePool (handle_pool.h): 0 is never valid, a destroyed
// instance's handle is detected (InvalidHandle).
using InstanceHandle = uint32_t;

struct WorldSettings {
    size_t frame_cache_bytes = size_t(512) << 20;
    MemoryHooks memory;  // optional host allocator (host_memory.h)
};

struct PlaybackSettings {
    static constexpr int kPackageFirst = std::numeric_limits<int>::min();
    static constexpr int kPackageLast = std::numeric_limits<int>::max();
    double time = 0.0;  // seconds since the start of the range
    double rate = 24.0;  // frames per second (0 holds; negative plays backwards)
    bool loop = true;    // wrap at the end of the range (else clamp at its ends)
    bool playing = true;  // false: update() does not advance time
    int first_frame = kPackageFirst;  // range in package frame numbers, clamped to the baked frames
    int last_frame = kPackageLast;
};

struct OutputSettings {
    bool image = false;       // CPU image (premultiplied RGBA float, width x height, top row first)
    bool lens_flare = false;  // needs image; a separate RGBA image with A = 0, added by the host
    LensFlareSettings flare;
};

// What update() produced for one instance; pointers stay valid until the next
// call that changes the world (update, create, destroy, set*).
struct InstanceState {
    int frame = 0;                // baked frame shown
    double frame_position = 0.0;  // continuous position (keyframes are evaluated here)
    double time = 0.0;            // playback time after wrapping
    int rank = 0;
    const float* z = nullptr;     // rank x 3, z[k * 3 + channel]
    ExtinctionParams extinction;  // the interpolated look's (alpha needs it)
    std::span<const Rgb> rbf;     // interpolated emission coefficients (bins)
    std::span<const Rgb> lights;  // interpolated light irradiance
    const float* image = nullptr;  // null unless enabled and updated
    const float* flare = nullptr;
    bool updated = false;         // false until the first update() after creation
};

class World {
  public:
    explicit World(WorldSettings settings = {});
    ~World();
    World(const World&) = delete;
    World& operator=(const World&) = delete;

    // A new instance showing the package's first frame with its default look,
    // default playback and no image outputs.
    InstanceHandle create(std::shared_ptr<const Package> package);
    void destroy(InstanceHandle instance);
    bool valid(InstanceHandle instance) const;
    size_t size() const { return dense_to_handle_.size(); }

    void setLook(InstanceHandle instance, const Look& look);  // one key: constant look
    // Keys (frame number, look); sorted here; must be non-empty.
    void setKeyframes(InstanceHandle instance, std::span<const std::pair<double, Look>> keys);
    void setPlayback(InstanceHandle instance, const PlaybackSettings& playback);
    void setOutputs(InstanceHandle instance, const OutputSettings& outputs);
    // A light from a direction chosen at run time (basis/relight.h): from the next update on, the
    // six-way or sphere lights' irradiance of whatever look the instance shows is replaced by the
    // weights of `light` times its irradiance; it stays across setLook/setKeyframes. nullopt: the
    // look's own six-way or sphere irradiance again. An InvalidArgument Error (nothing changes) when
    // the package has neither or the light is not finite, has a zero direction or a negative
    // irradiance.
    void setLightDirection(InstanceHandle instance, const std::optional<basis::RunTimeLight>& light);
    // The same for several lights at once: their weighted irradiances summed (none: those lights dark).
    void setLightDirections(InstanceHandle instance, std::span<const basis::RunTimeLight> lights);
    const PlaybackSettings& playback(InstanceHandle instance) const;
    const Package& package(InstanceHandle instance) const;

    void update(double dt);
    InstanceState state(InstanceHandle instance) const;
    // The look the instance shows at its frame position (the last update's, the package's first
    // frame before any): sampledLook() of its keys (look_track.h), with a run-time light's six-way or
    // sphere irradiance (setLightDirection[s]). Allocates.
    Look look(InstanceHandle instance) const;
    // The frame the last update showed, in the cache's resident form: no decode, valid until the
    // next call that changes the world. Null until the first update after creation or setOutputs
    // (InstanceState::updated).
    const basis::ResidentFrame* shownFrame(InstanceHandle instance) const;

    // The frame cache (for tests and statistics): resident frames, their depth tables and the
    // spare frame's buffers.
    size_t cacheBytes() const { return cache_bytes_ + (spare_ ? spare_->bytes() : 0); }
    // Everything the world holds for its instances besides the cache: per-instance images, flare
    // images, coefficients and looks, and the scratch buffers.
    size_t instanceBytes() const;
    size_t cachedFrames() const;
    uint64_t frameLoads() const { return frame_loads_; }  // every frame decoded, prefetches included
    uint64_t prefetches() const { return prefetches_; }

  private:
    template <typename T>
    using HostVector = std::vector<T, HostAllocator<T>>;

    struct FrameEntry {
        std::unique_ptr<basis::ResidentFrame> frame;
        uint64_t last_used = 0;
        size_t bytes = 0;
        // During update(): where the frame's instances start in jobs_ and how many there are.
        size_t batch_start = 0, batch_size = 0;
        int package_index = 0;
    };
    struct PackageEntry {
        std::shared_ptr<const Package> package;
        std::vector<FrameEntry> frames;  // by slot
        std::shared_ptr<const basis::DepthTable> depth_table;  // shared by its frames, counted once
        int users = 0;
    };
    void resetFrames(PackageEntry& entry);

    int denseIndex(InstanceHandle instance) const;  // throws InvalidHandle
    int acquirePackage(std::shared_ptr<const Package> package);
    void releasePackage(int index);
    void ensureStrides(const Package& package);
    FrameEntry& residentFrame(int package_index, int slot);
    void trimCache();
    bool prefetch();  // true when it decoded a frame

    WorldSettings settings_;
    HostMemoryResource frame_memory_{&settings_.memory};
    HandlePool<int32_t> handles_{HandleKind::Instance};  // handle -> dense index
    std::vector<InstanceHandle> dense_to_handle_;
    std::vector<PackageEntry> packages_;

    // Components (dense). Strides grow with the packages in the world.
    int z_stride_ = 0, bins_stride_ = 0, lights_stride_ = 0;
    std::vector<int> package_index_;
    std::vector<std::vector<Keyframe>> keys_;
    std::vector<PlaybackSettings> playback_;
    std::vector<OutputSettings> outputs_;
    std::vector<double> frame_position_;
    std::vector<int> frame_slot_;
    std::vector<ExtinctionParams> extinction_;
    std::vector<uint8_t> updated_;
    // The six-way or sphere lights' irradiance of run-time lights (setLightDirection[s]), else nullopt.
    std::vector<std::optional<std::vector<Rgb>>> run_time_light_;
    HostVector<Rgb> rbf_;     // dense x bins_stride_
    HostVector<Rgb> lights_;  // dense x lights_stride_
    HostVector<float> z_;     // dense x z_stride_
    std::vector<HostVector<float>> image_;  // empty unless enabled
    std::vector<HostVector<float>> flare_;
    HostVector<float> flare_scratch_;  // lens flare scratch, largest image
    // update()'s scratch: the frame each instance shows, the frames shown, and the instances'
    // coefficient jobs grouped by frame (one batch per frame: basis/coefficients.h).
    std::vector<FrameEntry*> shown_entry_;
    std::vector<FrameEntry*> shown_frames_;
    std::vector<basis::CoefficientJob> jobs_;

    basis::FrameReadBuffers read_buffers_;        // section reads, reused
    std::unique_ptr<basis::ResidentFrame> spare_;  // an evicted frame's buffers, for the next load
    uint64_t update_count_ = 0;
    size_t cache_bytes_ = 0;
    uint64_t frame_loads_ = 0;
    uint64_t prefetches_ = 0;
};

}  // namespace firelook::world
