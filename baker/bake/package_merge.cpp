#include "bake/package_merge.h"

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

#include "bake/bake_metadata.h"
#include "common/error.h"
#include "package/container_reader.h"
#include "package/container_writer.h"

namespace firelook::bake {
namespace {

struct Part {
    std::filesystem::path path;
    package::ContainerReader reader;
    BakeMetadata meta;
    std::map<int, std::vector<package::SectionInfo>> sections;  // by frame, in file order
};

Part openPart(const std::filesystem::path& path) {
    Part part{path, package::ContainerReader::open(path), {}, {}};
    const std::optional<std::string> meta = part.reader.metadata();
    if (!meta) throw Error(ErrorCode::Corrupt, path.string() + ": package has no metadata (META) section");
    part.meta = splitMetadata(*meta, path);
    for (const package::SectionInfo& s : part.reader.sections()) {
        if (s.type == package::kMetadataType) continue;
        if (s.frame == package::kNoFrame || !part.meta.frames.contains(static_cast<int>(s.frame)))
            throw Error(ErrorCode::Corrupt,
                        path.string() + ": holds a section of no frame its metadata lists (type " +
                            std::to_string(s.type) + ", frame " + std::to_string(s.frame) + ")");
        part.sections[static_cast<int>(s.frame)].push_back(s);
    }
    for (const auto& [frame, entries] : part.meta.frames)
        if (!part.sections.contains(frame))
            throw Error(ErrorCode::Corrupt, path.string() + ": its metadata lists frame " +
                                                std::to_string(frame) + " but it holds no section of it");
    return part;
}

std::string rangesText(const std::vector<int>& frames) {
    std::string text;
    for (size_t i = 0; i < frames.size();) {
        size_t j = i;
        while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
        text += (text.empty() ? "" : ",") + std::to_string(frames[i]) +
                (j > i ? "-" + std::to_string(frames[j]) : "");
        i = j + 1;
    }
    return text;
}

}  // namespace

MergeResult mergePackages(const std::vector<std::filesystem::path>& paths, const std::filesystem::path& output,
                          const MergeOptions& options, const std::function<void(const std::string&)>& notice) {
    if (paths.empty()) throw Error(ErrorCode::InvalidArgument, "merge: no parts given");
    std::vector<Part> parts;
    parts.reserve(paths.size());
    std::map<int, size_t> owner;  // frame -> part
    for (const std::filesystem::path& path : paths) {
        parts.push_back(openPart(path));
        const Part& part = parts.back();
        const Part& first = parts.front();
        if (!(part.reader.version() == first.reader.version()))
            throw Error(ErrorCode::InvalidArgument,
                        path.string() + ": package format " + std::to_string(part.reader.version().major) +
                            "." + std::to_string(part.reader.version().minor) + ", but " +
                            first.path.string() + " has " + std::to_string(first.reader.version().major) +
                            "." + std::to_string(first.reader.version().minor));
        // The sequence first: a part of another sequence differs in many settings derived from it,
        // and the first of those would hide the cause.
        for (const char* key : {"sequence_xxh3_64", "sequence_frames"}) {
            const nlohmann::ordered_json::json_pointer pointer(std::string("/provenance/") + key);
            const auto value = [&](const Part& p) {
                return p.meta.shared.contains(pointer) ? p.meta.shared.at(pointer) : nlohmann::ordered_json();
            };
            if (value(first) != value(part))
                throw Error(ErrorCode::InvalidArgument,
                            path.string() + ": baked from another sequence than " + first.path.string() +
                                " (or from files whose content changed): provenance." +
                                firstDifference({{key, value(first)}}, {{key, value(part)}}));
        }
        if (const std::string d = firstDifference(first.meta.shared, part.meta.shared); !d.empty())
            throw Error(ErrorCode::InvalidArgument, path.string() + ": not baked like " +
                                                        first.path.string() +
                                                        " (same sequence, settings and tool needed): " + d);
        std::vector<int> frames;
        for (const auto& [frame, entries] : part.meta.frames) {
            if (const auto [it, added] = owner.emplace(frame, parts.size() - 1); !added)
                throw Error(ErrorCode::InvalidArgument, path.string() + ": frame " + std::to_string(frame) +
                                                            " is also in " + parts[it->second].path.string());
            frames.push_back(frame);
        }
        if (notice) notice(path.string() + ": frames " + rangesText(frames));
    }

    if (!options.only.empty()) {
        std::erase_if(owner, [&](const auto& entry) {
            return std::none_of(options.only.begin(), options.only.end(),
                                [&](const auto& r) { return entry.first >= r.first && entry.first <= r.second; });
        });
        if (owner.empty())
            throw Error(ErrorCode::InvalidArgument,
                        "merge: no frame of the parts is in the frames asked for");
    }
    MergeResult result;
    for (const auto& [frame, part] : owner) result.frames.push_back(frame);
    if (!options.allow_gaps) {
        const nlohmann::ordered_json::json_pointer pointer("/provenance/sequence_frames");
        const nlohmann::ordered_json& shared = parts.front().meta.shared;
        if (!shared.contains(pointer) || !shared.at(pointer).is_array())
            throw Error(ErrorCode::InvalidArgument,
                        paths.front().string() +
                            ": its metadata does not list the sequence's frames, so missing frames cannot be "
                            "found; merge with --allow-gaps");
        std::vector<int> missing;
        for (const nlohmann::ordered_json& f : shared.at(pointer)) {
            const int frame = f.get<int>();
            if (frame > result.frames.front() && frame < result.frames.back() && !owner.contains(frame))
                missing.push_back(frame);
        }
        if (!missing.empty())
            throw Error(ErrorCode::NotFound,
                        "merge: no part holds frame" + std::string(missing.size() > 1 ? "s " : " ") +
                            rangesText(missing) + " of the sequence (--allow-gaps accepts that)");
    }

    package::ContainerWriter writer(output);
    std::vector<const FrameMetadata*> entries;
    for (const auto& [frame, index] : owner) {
        const Part& part = parts[index];
        for (const package::SectionInfo& s : part.sections.at(frame)) writer.addStoredSection(s, part.reader.stored(s));
        entries.push_back(&part.meta.frames.at(frame));
    }
    writer.addMetadata(joinMetadata(parts.front().meta.shared, entries));
    writer.commit();
    result.package_bytes = std::filesystem::file_size(output);
    return result;
}

}  // namespace firelook::bake
