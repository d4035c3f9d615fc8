#include "bake/bake_checkpoint.h"

#include <stdexcept>
#include <system_error>

#include "common/error.h"
#include "package/container_reader.h"

namespace firelook::bake {
namespace {

constexpr const char* kPartPrefix = "frame_";
constexpr const char* kPartSuffix = ".firelook";

bool isPartName(const std::string& name) {
    return name.starts_with(kPartPrefix) && name.ends_with(kPartSuffix) && name.front() != '.';
}

size_t partsIn(const std::filesystem::path& folder) {
    size_t count = 0;
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator(folder, error))
        if (isPartName(entry.path().filename().string())) ++count;
    return count;
}

}  // namespace

std::filesystem::path BakeCheckpoint::folderFor(const std::filesystem::path& output) {
    return output.parent_path() / (output.filename().string() + ".partial");
}

BakeCheckpoint::BakeCheckpoint(const std::filesystem::path& output, bool resume) : folder_(folderFor(output)) {
    std::error_code error;
    if (std::filesystem::exists(folder_, error)) {
        for (const auto& entry : std::filesystem::directory_iterator(folder_)) {
            const std::string name = entry.path().filename().string();
            // A part is kept for --resume; anything else (a killed writer's temporary file, or
            // every part when not resuming) goes.
            if (!resume || !isPartName(name)) std::filesystem::remove_all(entry.path());
        }
    }
    if (!std::filesystem::create_directory(folder_, error) && error)
        throw Error(ErrorCode::IoError,
                    folder_.string() + ": cannot create the folder for finished frames: " + error.message());
}

BakeCheckpoint::~BakeCheckpoint() {
    std::error_code error;
    if (partsIn(folder_) == 0) std::filesystem::remove_all(folder_, error);
}

std::filesystem::path BakeCheckpoint::partPath(int frame) const {
    return folder_ / (kPartPrefix + std::to_string(frame) + kPartSuffix);
}

std::optional<FrameMetadata> BakeCheckpoint::reusable(int frame, const nlohmann::ordered_json& shared,
                                                      const std::string& source_hash, std::string& why) const {
    why.clear();
    const std::filesystem::path path = partPath(frame);
    if (!std::filesystem::exists(path)) return std::nullopt;
    try {
        const package::ContainerReader reader = package::ContainerReader::open(path);
        const std::optional<std::string> meta = reader.metadata();
        if (!meta) throw Error(ErrorCode::Corrupt, "it has no metadata");
        const BakeMetadata kept = splitMetadata(*meta, path);
        if (kept.frames.size() != 1 || !kept.frames.contains(frame))
            throw Error(ErrorCode::Corrupt, "it does not hold exactly frame " + std::to_string(frame));
        const FrameMetadata& entries = kept.frames.at(frame);
        // The most specific reason first: the frame's own file, then another frame of the sequence
        // (which the sequence's identity covers), then the settings.
        if (entries.source.value("xxh3_64", std::string()) != source_hash)
            throw Error(ErrorCode::InvalidArgument, "the frame's input file has changed since");
        const nlohmann::ordered_json::json_pointer identity("/provenance/sequence_xxh3_64");
        if (kept.shared.contains(identity) && shared.contains(identity) &&
            kept.shared.at(identity) != shared.at(identity))
            throw Error(ErrorCode::InvalidArgument,
                        "another frame of the sequence has changed since (sequence xxh3 " +
                            kept.shared.at(identity).get<std::string>() + " then, " +
                            shared.at(identity).get<std::string>() + " now)");
        if (const std::string d = firstDifference(shared, kept.shared); !d.empty())
            throw Error(ErrorCode::InvalidArgument, "it was baked with other settings (" + d + ")");
        // Every section's checksum, so a part damaged on disk is baked again rather than merged.
        for (const package::SectionInfo& s : reader.sections()) (void)reader.stored(s);
        return entries;
    } catch (const std::exception& e) {
        why = "frame " + std::to_string(frame) + ": not resumed from " + path.string() + ": " + e.what();
        return std::nullopt;
    }
}

size_t BakeCheckpoint::keptFrames(const std::filesystem::path& output) { return partsIn(folderFor(output)); }

void BakeCheckpoint::remove() {
    std::error_code error;
    std::filesystem::remove_all(folder_, error);  // a leftover folder is harmless: the next bake clears it
}

}  // namespace firelook::bake
