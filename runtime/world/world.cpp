#include "world/world.h"

#include <algorithm>
#include <cmath>

#include "basis/coefficients.h"
#include "basis/recombine.h"
#include "common/error.h"

namespace firelook::world {
namespace {

// Frame range of an instance, clamped to the package's baked frames.
std::pair<int, int> frameRange(const Package& p, const PlaybackSettings& pb) {
    const int first_baked = p.frameNumber(0), last_baked = p.frameNumber(p.frameCount() - 1);
    int first = std::clamp(pb.first_frame, first_baked, last_baked);
    int last = std::clamp(pb.last_frame, first_baked, last_baked);
    if (last < first) std::swap(first, last);
    return {first, last};
}

}  // namespace

World::World(WorldSettings settings)
    : settings_(settings),
      rbf_(HostAllocator<Rgb>(&settings_.memory)),
      lights_(HostAllocator<Rgb>(&settings_.memory)),
      z_(HostAllocator<float>(&settings_.memory)),
      flare_scratch_(HostAllocator<float>(&settings_.memory)) {
    if ((settings_.memory.alloc == nullptr) != (settings_.memory.free == nullptr))
        throw Error(ErrorCode::InvalidArgument, "memory hooks: set both alloc and free, or neither");
}

World::~World() = default;

int World::denseIndex(InstanceHandle h) const { return handles_.get(h); }

bool World::valid(InstanceHandle h) const { return handles_.find(h) != nullptr; }

int World::acquirePackage(std::shared_ptr<const Package> package) {
    for (size_t i = 0; i < packages_.size(); ++i)
        if (packages_[i].package == package) return static_cast<int>(i);
    for (size_t i = 0; i < packages_.size(); ++i)
        if (!packages_[i].package) {
            packages_[i].package = std::move(package);
            resetFrames(packages_[i]);
            return static_cast<int>(i);
        }
    PackageEntry e;
    e.package = std::move(package);
    resetFrames(e);
    packages_.push_back(std::move(e));
    return static_cast<int>(packages_.size()) - 1;
}

// One empty cache entry per frame; resident frames go through the host's allocator (firelook.h).
void World::resetFrames(PackageEntry& e) {
    e.frames.clear();
    e.frames.resize(static_cast<size_t>(e.package->frameCount()));
    e.depth_table.reset();
}

void World::releasePackage(int index) {
    PackageEntry& e = packages_[index];
    if (--e.users > 0) return;
    for (FrameEntry& f : e.frames) cache_bytes_ -= f.bytes;
    if (e.depth_table) cache_bytes_ -= e.depth_table->bytes();
    e.frames.clear();
    e.depth_table.reset();
    e.package.reset();
}

void World::ensureStrides(const Package& p) {
    const int bins = p.description().bins.count;
    const int lights = static_cast<int>(p.description().light_directions.size());
    const int z = p.maxRank() * 3;
    const size_t n = dense_to_handle_.size();
    auto relayout = [n](auto& v, int old_stride, int new_stride) {
        auto fresh = v;  // same allocator
        fresh.assign(n * new_stride, typename std::decay_t<decltype(v)>::value_type{});
        for (size_t i = 0; i < n; ++i)
            std::copy(v.begin() + i * old_stride, v.begin() + i * old_stride + old_stride,
                      fresh.begin() + i * new_stride);
        v.swap(fresh);
    };
    if (bins > bins_stride_) {
        relayout(rbf_, bins_stride_, bins);
        bins_stride_ = bins;
    }
    if (lights > lights_stride_) {
        relayout(lights_, lights_stride_, lights);
        lights_stride_ = lights;
    }
    if (z > z_stride_) {
        relayout(z_, z_stride_, z);
        z_stride_ = z;
    }
}

InstanceHandle World::create(std::shared_ptr<const Package> package) {
    if (!package) throw Error(ErrorCode::InvalidArgument, "create: null package");
    Keyframe key{0.0, package->resolvedDefaultLook()};  // parsed and fitted once, by Package::open
    handles_.requireRoom();  // before anything changes

    ensureStrides(*package);  // may relayout; harmless if a later step throws
    const int pkg = acquirePackage(std::move(package));
    ++packages_[pkg].users;

    const InstanceHandle handle = handles_.add(static_cast<int32_t>(dense_to_handle_.size()));
    dense_to_handle_.push_back(handle);
    package_index_.push_back(pkg);
    keys_.push_back({std::move(key)});
    playback_.push_back({});
    outputs_.push_back({});
    frame_position_.push_back(packages_[pkg].package->frameNumber(0));
    frame_slot_.push_back(0);
    extinction_.push_back(keys_.back()[0].look.extinction);
    updated_.push_back(0);
    run_time_light_.emplace_back();
    rbf_.resize(rbf_.size() + bins_stride_);
    lights_.resize(lights_.size() + lights_stride_);
    z_.resize(z_.size() + z_stride_);
    image_.emplace_back(HostAllocator<float>(&settings_.memory));
    flare_.emplace_back(HostAllocator<float>(&settings_.memory));
    shown_entry_.push_back(nullptr);
    jobs_.emplace_back();
    // Every frame of the world's packages may be shown at once.
    size_t frames = 0;
    for (const PackageEntry& p : packages_) frames += p.frames.size();
    shown_frames_.reserve(frames);
    return handle;
}

void World::destroy(InstanceHandle h) {
    const int dense = denseIndex(h);
    const int last = static_cast<int>(dense_to_handle_.size()) - 1;
    releasePackage(package_index_[dense]);
    auto move_last = [&](auto& v) {
        if (dense != last) v[dense] = std::move(v[last]);
        v.pop_back();
    };
    auto move_last_strided = [&](auto& v, int stride) {
        if (dense != last)
            std::copy(v.begin() + size_t(last) * stride, v.begin() + size_t(last + 1) * stride,
                      v.begin() + size_t(dense) * stride);
        v.resize(size_t(last) * stride);
    };
    move_last(package_index_);
    move_last(keys_);
    move_last(playback_);
    move_last(outputs_);
    move_last(frame_position_);
    move_last(frame_slot_);
    move_last(extinction_);
    move_last(updated_);
    move_last(run_time_light_);
    move_last(image_);
    move_last(flare_);
    move_last_strided(rbf_, bins_stride_);
    move_last_strided(lights_, lights_stride_);
    move_last_strided(z_, z_stride_);
    move_last(dense_to_handle_);
    shown_entry_.pop_back();  // scratch: refilled by every update
    jobs_.pop_back();
    if (dense != last) handles_.get(dense_to_handle_[dense]) = dense;
    handles_.take(h);
}

void World::setLook(InstanceHandle h, const Look& look) {
    const std::pair<double, Look> key{0.0, look};
    setKeyframes(h, std::span(&key, 1));
}

void World::setKeyframes(InstanceHandle h, std::span<const std::pair<double, Look>> keys) {
    const int dense = denseIndex(h);
    if (keys.empty()) throw Error(ErrorCode::InvalidArgument, "setKeyframes: at least one key is required");
    const basis::BakeDescription& d = packages_[package_index_[dense]].package->description();
    std::vector<Keyframe> resolved;
    resolved.reserve(keys.size());
    for (const auto& [frame, look] : keys) {
        if (!std::isfinite(frame))
            throw Error(ErrorCode::InvalidArgument, "setKeyframes: a key's frame is not finite");
        resolved.push_back({frame, resolveLook(look, d)});
    }
    std::stable_sort(resolved.begin(), resolved.end(),
                     [](const Keyframe& a, const Keyframe& b) { return a.frame < b.frame; });
    keys_[dense] = std::move(resolved);
}

void World::setPlayback(InstanceHandle h, const PlaybackSettings& pb) {
    const int dense = denseIndex(h);
    if (!std::isfinite(pb.time) || !std::isfinite(pb.rate))
        throw Error(ErrorCode::InvalidArgument, "setPlayback: time and rate must be finite");
    playback_[dense] = pb;
}

void World::setOutputs(InstanceHandle h, const OutputSettings& out) {
    const int dense = denseIndex(h);
    if (out.lens_flare && !out.image)
        throw Error(ErrorCode::InvalidArgument,
                    "setOutputs: the lens flare is computed from the image; enable the image too");
    const basis::BakeDescription& d = packages_[package_index_[dense]].package->description();
    const size_t floats = static_cast<size_t>(d.pixelCount()) * 4;
    if (out.image) image_[dense].resize(floats);
    else image_[dense] = HostVector<float>(HostAllocator<float>(&settings_.memory));
    if (out.lens_flare) {
        flare_[dense].resize(floats);
        const size_t need = lensFlareScratchFloats(d.width, d.height);
        if (flare_scratch_.size() < need) flare_scratch_.resize(need);
    } else {
        flare_[dense] = HostVector<float>(HostAllocator<float>(&settings_.memory));
    }
    outputs_[dense] = out;
    // New buffers hold nothing valid until the next update.
    updated_[dense] = 0;
}

void World::setLightDirection(InstanceHandle h, const std::optional<basis::RunTimeLight>& light) {
    const int dense = denseIndex(h);
    if (!light) {
        run_time_light_[dense].reset();
        return;
    }
    setLightDirections(h, std::span<const basis::RunTimeLight>(&*light, 1));
}

void World::setLightDirections(InstanceHandle h, std::span<const basis::RunTimeLight> lights) {
    const int dense = denseIndex(h);
    const Package& p = *packages_[package_index_[dense]].package;
    run_time_light_[dense] = basis::relightIrradiance(p.description(), lights, p.name());
}

const PlaybackSettings& World::playback(InstanceHandle h) const { return playback_[denseIndex(h)]; }
const Package& World::package(InstanceHandle h) const { return *packages_[package_index_[denseIndex(h)]].package; }

World::FrameEntry& World::residentFrame(int package_index, int slot) {
    PackageEntry& pe = packages_[package_index];
    FrameEntry& e = pe.frames[slot];
    if (!e.frame) {
        std::unique_ptr<basis::ResidentFrame> f =
            spare_ ? std::move(spare_) : std::make_unique<basis::ResidentFrame>(&frame_memory_);
        f->depth_table = pe.depth_table;  // reused when the frame's grid is the same
        pe.package->loadResidentSlot(slot, *f, read_buffers_);  // on a throw the buffers are freed
        if (f->depth_table != pe.depth_table) {  // a new depth grid (the first frame, or a repacked one)
            if (pe.depth_table) cache_bytes_ -= pe.depth_table->bytes();
            pe.depth_table = f->depth_table;
            cache_bytes_ += pe.depth_table->bytes();
        }
        e.bytes = f->bytes();
        e.frame = std::move(f);
        cache_bytes_ += e.bytes;
        ++frame_loads_;
    }
    e.last_used = update_count_;
    return e;
}

size_t World::cachedFrames() const {
    size_t n = 0;
    for (const PackageEntry& p : packages_)
        for (const FrameEntry& f : p.frames) n += f.frame ? 1 : 0;
    return n;
}

void World::trimCache() {
    while (cache_bytes_ > settings_.frame_cache_bytes) {
        FrameEntry* oldest = nullptr;
        for (PackageEntry& p : packages_)
            for (FrameEntry& f : p.frames)
                if (f.frame && f.last_used < update_count_ && (!oldest || f.last_used < oldest->last_used))
                    oldest = &f;
        if (!oldest) break;  // everything cached is in use by this update
        cache_bytes_ -= oldest->bytes;
        if (!spare_) spare_ = std::move(oldest->frame);
        *oldest = FrameEntry{};
    }
    if (spare_ && cacheBytes() > settings_.frame_cache_bytes) spare_.reset();
}

void World::update(double dt) {
    if (!std::isfinite(dt)) throw Error(ErrorCode::InvalidArgument, "update: dt must be finite");
    ++update_count_;
    const size_t n = dense_to_handle_.size();

    // 1. Playback.
    for (size_t i = 0; i < n; ++i) {
        const Package& p = *packages_[package_index_[i]].package;
        PlaybackSettings& pb = playback_[i];
        if (pb.playing) pb.time += dt;
        const auto [first, last] = frameRange(p, pb);
        const double span = static_cast<double>(last) - first + 1.0;  // frame f shows for [f, f + 1)
        double offset;
        if (pb.loop && pb.rate != 0.0) {
            // Wrap the time itself so it never grows large enough to lose precision.
            const double period = span / std::abs(pb.rate);
            pb.time = std::fmod(pb.time, period);
            if (pb.time < 0.0) pb.time += period;
            offset = pb.time * pb.rate;  // [0, span) forwards, (-span, 0] backwards
            if (offset < 0.0) offset += span;
            if (!(offset < span)) offset = 0.0;  // rounding at the wrap
        } else if (pb.loop) {
            offset = 0.0;
        } else {
            offset = std::clamp(pb.time * pb.rate, 0.0, static_cast<double>(last - first));
        }
        frame_position_[i] = first + offset;
        frame_slot_[i] = p.slotAtOrBelow(frame_position_[i]);
    }

    // 2. Keyframes, then a run-time light over the six-way or sphere lights. Each instance's keys live
    // in their own allocations, so with many instances they come from far caches: their records are
    // prefetched two strides ahead and the coefficients they point at one stride ahead.
    constexpr size_t kAhead = 8;
    for (size_t i = 0; i < n; ++i) {
        if (i + 2 * kAhead < n)
            for (const Keyframe& k : std::span(keys_[i + 2 * kAhead]).first(std::min<size_t>(2, keys_[i + 2 * kAhead].size()))) {
                __builtin_prefetch(&k.frame);
                __builtin_prefetch(&k.look.rbf);
            }
        if (i + kAhead < n)
            for (const Keyframe& k : std::span(keys_[i + kAhead]).first(std::min<size_t>(2, keys_[i + kAhead].size()))) {
                __builtin_prefetch(k.look.rbf.data());
                __builtin_prefetch(k.look.lights.data());
            }
        sampleKeyframes(keys_[i], frame_position_[i], extinction_[i], rbf_.data() + i * bins_stride_,
                        lights_.data() + i * lights_stride_);
        if (run_time_light_[i])
            std::copy(run_time_light_[i]->begin(), run_time_light_[i]->end(),
                      lights_.data() + i * lights_stride_ +
                          packages_[package_index_[i]].package->description().relightFirstLight());
    }

    // 3. Residency (a load may throw: nothing below has changed yet).
    for (size_t i = 0; i < n; ++i) {
        FrameEntry& e = residentFrame(package_index_[i], frame_slot_[i]);
        e.package_index = package_index_[i];
        shown_entry_[i] = &e;
    }

    // 4. Coefficients: the instances grouped by the frame they show (a counting sort), one batch each.
    shown_frames_.clear();
    for (size_t i = 0; i < n; ++i)
        if (shown_entry_[i]->batch_size++ == 0) shown_frames_.push_back(shown_entry_[i]);
    size_t start = 0;
    for (FrameEntry* e : shown_frames_) {
        e->batch_start = start;
        start += e->batch_size;
        e->batch_size = 0;
    }
    for (size_t i = 0; i < n; ++i) {
        FrameEntry& e = *shown_entry_[i];
        jobs_[e.batch_start + e.batch_size++] = {extinction_[i], rbf_.data() + i * bins_stride_,
                                                 lights_.data() + i * lights_stride_, z_.data() + i * z_stride_};
    }
    for (FrameEntry* e : shown_frames_) {
        basis::coefficientBatch(packages_[e->package_index].package->description(), e->frame->svt.data(),
                                e->frame->rank, std::span(jobs_.data() + e->batch_start, e->batch_size));
        e->batch_size = 0;
    }

    // 5. CPU images.
    for (size_t i = 0; i < n; ++i) {
        if (!outputs_[i].image) continue;
        const int pkg = package_index_[i];
        const FrameEntry& e = *shown_entry_[i];
        basis::reconstructImage(packages_[pkg].package->description(), *e.frame,
                                std::span<const float>(z_.data() + i * z_stride_, z_stride_), extinction_[i],
                                image_[i]);
    }

    // 6. Lens flare.
    for (size_t i = 0; i < n; ++i) {
        if (!outputs_[i].lens_flare) continue;
        const basis::BakeDescription& d = packages_[package_index_[i]].package->description();
        renderLensFlare(image_[i].data(), d.width, d.height, outputs_[i].flare, flare_scratch_.data(),
                        flare_[i].data());
    }

    std::fill(updated_.begin(), updated_.end(), uint8_t{1});
    trimCache();
    if (prefetch()) trimCache();  // the estimate may fall short: the budget still holds
}

// Decoding ahead: the first playing instance whose next frame (in its direction of play, wrapping
// when it loops) is not resident gets it decoded now, if the cache has room for it beside what it
// holds (an estimate: the size of the frame shown). One frame per update bounds the work; the
// frame counts as used one update ago, so a trim may evict it before the frames in use.
bool World::prefetch() {
    for (size_t i = 0; i < dense_to_handle_.size(); ++i) {
        const PlaybackSettings& pb = playback_[i];
        if (!pb.playing || pb.rate == 0.0) continue;
        const int pkg = package_index_[i];
        PackageEntry& pe = packages_[pkg];
        const Package& p = *pe.package;
        const auto [first, last] = frameRange(p, pb);
        const int lo = p.slotAtOrBelow(first), hi = p.slotAtOrBelow(last);
        int next = frame_slot_[i] + (pb.rate > 0.0 ? 1 : -1);
        if (next > hi) next = pb.loop ? lo : hi;
        if (next < lo) next = pb.loop ? hi : lo;
        FrameEntry& shown = pe.frames[frame_slot_[i]];
        if (pe.frames[next].frame || !shown.frame) continue;
        if (cacheBytes() + shown.bytes > settings_.frame_cache_bytes) continue;
        try {
            residentFrame(pkg, next).last_used = update_count_ - 1;
        } catch (const std::exception&) {
            // A frame that cannot be read fails when it is shown, with the error the caller sees.
            continue;
        }
        ++prefetches_;
        return true;
    }
    return false;
}

size_t World::instanceBytes() const {
    size_t bytes = (rbf_.capacity() + lights_.capacity()) * sizeof(Rgb) +
                   (z_.capacity() + flare_scratch_.capacity()) * sizeof(float) +
                   (shown_entry_.capacity() + shown_frames_.capacity()) * sizeof(FrameEntry*) +
                   jobs_.capacity() * sizeof(basis::CoefficientJob);
    for (const HostVector<float>& image : image_) bytes += image.capacity() * sizeof(float);
    for (const HostVector<float>& flare : flare_) bytes += flare.capacity() * sizeof(float);
    return bytes;
}

InstanceState World::state(InstanceHandle h) const {
    const int i = denseIndex(h);
    const PackageEntry& pe = packages_[package_index_[i]];
    const Package& p = *pe.package;
    InstanceState s;
    s.frame = p.frameNumber(frame_slot_[i]);
    s.frame_position = frame_position_[i];
    s.time = playback_[i].time;
    s.rank = p.frameRank(frame_slot_[i]);
    s.z = z_.data() + size_t(i) * z_stride_;
    s.extinction = extinction_[i];
    s.rbf = std::span<const Rgb>(rbf_.data() + size_t(i) * bins_stride_, p.description().bins.count);
    s.lights = std::span<const Rgb>(lights_.data() + size_t(i) * lights_stride_,
                                    p.description().light_directions.size());
    s.updated = updated_[i] != 0;
    s.image = s.updated && outputs_[i].image ? image_[i].data() : nullptr;
    s.flare = s.updated && outputs_[i].lens_flare ? flare_[i].data() : nullptr;
    return s;
}

}  // namespace firelook::world

namespace firelook::world {

Look World::look(InstanceHandle h) const {
    const int i = denseIndex(h);
    const basis::BakeDescription& d = packages_[package_index_[i]].package->description();
    Look look = sampledLook(keys_[i], frame_position_[i], d);
    if (run_time_light_[i])
        std::copy(run_time_light_[i]->begin(), run_time_light_[i]->end(),
                  look.light_irradiance.begin() + d.relightFirstLight());
    return look;
}

// Frames used by an update are never evicted before the next update (trimCache), so the shown
// frame is resident whenever the instance is updated.
const basis::ResidentFrame* World::shownFrame(InstanceHandle h) const {
    const int i = denseIndex(h);
    if (!updated_[i]) return nullptr;
    return packages_[package_index_[i]].frames[frame_slot_[i]].frame.get();
}

}  // namespace firelook::world
