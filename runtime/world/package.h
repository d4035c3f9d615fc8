// A loaded .firelook package as the runtime world shares it between instances
// (and between worlds): the bake description plus read access to each baked
// frame's factors. Immutable after open(); the const members are safe to call
// from several threads at once (the package reader's const members are).
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "basis/basis_package.h"
#include "look/look.h"
#include "world/look_track.h"
#include "world/package_camera.h"

namespace firelook::world {

class Package {
  public:
    // Throws firelook::Error naming the file: package::PackageError from the
    // reader, LookError for a default look that does not fit, and Corrupt for
    // anything else wrong with the content (the basis layer's checks, and what
    // the runtime relies on: at least one frame, a non-empty image).
    static std::shared_ptr<const Package> open(const std::filesystem::path& file);
    // The same checks and errors for a package held in memory; `name` stands for the file in every
    // message and in name(). Borrow uses the bytes in place: they must be 64-byte aligned and stay
    // valid and unchanged while the Package lives (instances and worlds share it through
    // shared_ptr, and frames are read from it on demand). Copy takes its own aligned copy now.
    static std::shared_ptr<const Package> openMemory(std::span<const std::byte> bytes,
                                                     package::ContainerReader::MemoryOwnership ownership,
                                                     const std::string& name);

    const basis::BakeDescription& description() const { return package_.description(); }
    const basis::BasisReader& basis() const { return package_; }
    const std::filesystem::path& file() const { return package_.file(); }  // or openMemory's name
    const std::string& name() const { return name_; }  // the path (or memory name) as text, for messages

    // Baked frames in increasing frame number; frame slots index this list.
    int frameCount() const { return static_cast<int>(frame_numbers_.size()); }
    int frameNumber(int slot) const { return frame_numbers_[slot]; }
    int frameRank(int slot) const { return frame_ranks_[slot]; }
    int maxRank() const { return max_rank_; }

    // The default look, parsed and fitted once here: every instance starts from resolvedDefaultLook()
    // (World::create) and fl_package_default_look copies defaultLook().
    const Look& defaultLook() const { return default_look_.source; }
    const ResolvedLook& resolvedDefaultLook() const { return default_look_; }
    // The camera recorded in META, read at open: null when the package records none; a malformed
    // one does not stop the package from playing, cameraProblem() then says what is wrong.
    const PackageCamera* camera() const { return camera_ ? &*camera_ : nullptr; }
    const std::string& cameraProblem() const { return camera_problem_; }
    // Slot of the last baked frame whose number is <= frame_number (the first
    // slot if none); -1 only for an empty package (open() refuses those).
    int slotAtOrBelow(double frame_number) const;
    // Slot of exactly this frame number, or -1.
    int slotOf(int frame_number) const;

    // The frame's fire lights (basis/fire_lights.h), read and checked at open; null for a package
    // baked without them.
    const basis::FireLightTable* fireLights(int slot) const {
        return fire_lights_[slot] ? &*fire_lights_[slot] : nullptr;
    }

    // The frame's fire probes (basis/fire_probes.h), read and checked at open; null for a package
    // baked without them.
    const basis::FireProbeTable* fireProbes(int slot) const {
        return fire_probes_[slot] ? &*fire_probes_[slot] : nullptr;
    }

    // The frame (by slot) in the resident form the world keeps (basis/resident_frame.h), its memory
    // from `memory`, reusing `table` when the frame's depth grid is the same. Throws firelook::Error
    // (a section of the wrong shape is Corrupt).
    basis::ResidentFrame loadResidentSlot(int slot, std::pmr::memory_resource* memory,
                                          std::shared_ptr<const basis::DepthTable> table) const;
    // The same into `out`, reusing its buffers and `buffers` (one per thread).
    void loadResidentSlot(int slot, basis::ResidentFrame& out, basis::FrameReadBuffers& buffers) const;

  private:
    explicit Package(basis::BasisReader package);
    // What open() and openMemory() share: the runtime's checks of the content.
    static std::shared_ptr<const Package> checked(basis::BasisReader package);
    basis::BasisReader package_;
    std::string name_;
    std::vector<int> frame_numbers_;
    std::vector<int> frame_ranks_;
    int max_rank_ = 0;
    ResolvedLook default_look_;
    std::optional<PackageCamera> camera_;
    std::string camera_problem_;
    std::vector<std::optional<basis::FireLightTable>> fire_lights_;  // by slot
    std::vector<std::optional<basis::FireProbeTable>> fire_probes_;  // by slot
};

}  // namespace firelook::world
