#include "world/package.h"

#include <algorithm>
#include <new>
#include <stdexcept>
#include <utility>

#include "common/error.h"
#include "look/look.h"

namespace firelook::world {
namespace {

// The basis layer throws coded errors, which pass through, as does out-of-memory. An uncoded
// exception on the way (a third-party library's) is about what came from the file: Corrupt.
template <typename F>
auto corruptOnFailure(F&& read) {
    try {
        return read();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(ErrorCode::Corrupt, e.what());
    }
}

}  // namespace

Package::Package(basis::BasisReader package) : package_(std::move(package)), name_(package_.file().string()) {
    std::vector<basis::FrameRecord> records = package_.description().frames;
    std::sort(records.begin(), records.end(),
              [](const basis::FrameRecord& a, const basis::FrameRecord& b) { return a.frame < b.frame; });
    for (const basis::FrameRecord& r : records) {
        frame_numbers_.push_back(r.frame);
        frame_ranks_.push_back(r.rank);
        max_rank_ = std::max(max_rank_, r.rank);
    }
}

std::shared_ptr<const Package> Package::open(const std::filesystem::path& file) {
    return checked(corruptOnFailure([&] { return basis::BasisReader::open(file); }));
}

std::shared_ptr<const Package> Package::openMemory(std::span<const std::byte> bytes,
                                                   package::ContainerReader::MemoryOwnership ownership,
                                                   const std::string& name) {
    return checked(corruptOnFailure([&] { return basis::BasisReader::openMemory(bytes, ownership, name); }));
}

std::shared_ptr<const Package> Package::checked(basis::BasisReader package) {
    std::shared_ptr<Package> p(new Package(std::move(package)));
    const basis::BakeDescription& d = p->description();
    const auto corrupt = [&](const std::string& problem) { throw Error(ErrorCode::Corrupt, p->name_ + ": " + problem); };
    if (p->frame_numbers_.empty()) corrupt("the package has no baked frames");
    if (d.width <= 0 || d.height <= 0) corrupt("the package's image size is empty");
    for (size_t i = 1; i < p->frame_numbers_.size(); ++i)
        if (p->frame_numbers_[i] == p->frame_numbers_[i - 1])
            corrupt("frame " + std::to_string(p->frame_numbers_[i]) + " is listed twice");
    for (int r : p->frame_ranks_)
        if (r < 0) corrupt("a frame has a negative rank");
    // The default look must be usable as is (it is every instance's initial look): parsed and
    // fitted here, once for the package's lifetime.
    p->default_look_ = resolveLook(parseLook(d.default_look_json, p->name_ + " (default look)"), d);
    for (int frame : p->frame_numbers_) {
        p->fire_lights_.push_back(corruptOnFailure([&] { return p->package_.loadFireLights(frame); }));
        p->fire_probes_.push_back(corruptOnFailure([&] { return p->package_.loadFireProbes(frame); }));
    }
    try {
        p->camera_ = readPackageCamera(p->package_.metadataJson(), p->name_);
    } catch (const Error& e) {
        p->camera_problem_ = e.what();
    }
    return p;
}

basis::ResidentFrame Package::loadResidentSlot(int slot, std::pmr::memory_resource* memory,
                                               std::shared_ptr<const basis::DepthTable> table) const {
    return corruptOnFailure(
        [&] { return package_.loadResidentFrame(frame_numbers_[slot], memory, std::move(table)); });
}

void Package::loadResidentSlot(int slot, basis::ResidentFrame& out, basis::FrameReadBuffers& buffers) const {
    corruptOnFailure([&] {
        package_.loadResidentFrame(frame_numbers_[slot], out, buffers);
        return 0;
    });
}

int Package::slotAtOrBelow(double frame_number) const {
    if (frame_numbers_.empty()) return -1;
    if (!(frame_number >= frame_numbers_.front())) return 0;  // also NaN
    const auto it = std::upper_bound(frame_numbers_.begin(), frame_numbers_.end(), frame_number,
                                     [](double v, int f) { return v < static_cast<double>(f); });
    return static_cast<int>(it - frame_numbers_.begin()) - 1;
}

int Package::slotOf(int frame_number) const {
    const auto it = std::lower_bound(frame_numbers_.begin(), frame_numbers_.end(), frame_number);
    return it != frame_numbers_.end() && *it == frame_number ? static_cast<int>(it - frame_numbers_.begin()) : -1;
}

}  // namespace firelook::world
