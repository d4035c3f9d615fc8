#include "vdb/vdb_sequence.h"

#include <algorithm>

#include "frame_reading.h"
#include "grid_names.h"

namespace firelook::vdb {

namespace {

// The files of a sequence, with its gaps warned about (or refused under --strict).
std::vector<FrameFile> listFrames(const std::string& folder_or_pattern, const ReadOptions& options) {
    std::vector<FrameFile> frames = findFrameFiles(folder_or_pattern);
    if (const std::vector<int> gaps = missingFrameNumbers(frames); !gaps.empty()) {
        const std::string message = folder_or_pattern + ": " + describeMissingFrames(gaps);
        if (options.strict) throw VdbError(message + " (refused by --strict)");
        if (options.warn) options.warn(message);
    }
    return frames;
}

}  // namespace

VdbSequence VdbSequence::openKnown(const std::string& folder_or_pattern, ReadOptions options,
                                   const Aabb& world_bounds) {
    if (options.density_grid.empty() || options.temperature_grid.empty())
        throw VdbError(folder_or_pattern + ": opening without reading needs both grid names");
    VdbSequence sequence;
    sequence.source_ = folder_or_pattern;
    sequence.frames_ = listFrames(folder_or_pattern, options);
    sequence.options_ = std::move(options);
    sequence.world_bounds_ = world_bounds;
    return sequence;
}

VdbSequence VdbSequence::open(const std::string& folder_or_pattern, ReadOptions options) {
    VdbSequence sequence;
    sequence.source_ = folder_or_pattern;
    sequence.frames_ = listFrames(folder_or_pattern, options);
    const std::filesystem::path& first = sequence.frames_.front().path;
    resolveGridNames(options, listGridNames(first), first);
    sequence.options_ = std::move(options);
    for (const FrameFile& frame : sequence.frames_) {
        sequence.world_bounds_.extend(readDensitySupportBounds(frame.path, sequence.options_));
    }
    return sequence;
}

bool VdbSequence::hasFrame(int frame_number) const {
    return std::any_of(frames_.begin(), frames_.end(),
                       [frame_number](const FrameFile& frame) { return frame.number == frame_number; });
}

VolumeFrame VdbSequence::load(int frame_number) const {
    const auto frame = std::find_if(frames_.begin(), frames_.end(),
                                    [frame_number](const FrameFile& f) { return f.number == frame_number; });
    if (frame == frames_.end()) {
        throw VdbError(ErrorCode::NotFound, source_ + ": no frame " + std::to_string(frame_number) +
                                                " (frames " + std::to_string(frames_.front().number) +
                                                " to " + std::to_string(frames_.back().number) +
                                                (gaps().empty() ? "" : ", with gaps") + ")");
    }
    if (options_.before_load) options_.before_load(frame->path);
    VolumeFrame loaded = loadFrame(*frame, options_);
    if (options_.warn)
        for (const std::string& line : cleaningReport(loaded)) options_.warn(line);
    return loaded;
}

}  // namespace firelook::vdb
