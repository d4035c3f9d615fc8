// A bake's META document (basis::makeMetadata's shape) seen as what every frame of a package
// shares plus what each frame adds. A package is assembled from parts (one frame each while
// baking, shards in `firelook merge`) by putting the frames' entries back into the shared
// document, so a package's bytes do not depend on how its frames were split between processes.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace firelook::bake {

// One frame's entries in the three per-frame lists of META: "bake"."frames" (number and rank),
// "provenance"."sources" (its input file and hash) and "errors" (what its bake measured).
struct FrameMetadata {
    nlohmann::ordered_json record, source, errors;
};

struct BakeMetadata {
    nlohmann::ordered_json shared;          // the document with its three per-frame lists empty
    std::map<int, FrameMetadata> frames;    // by frame number
};

// Splits a package's META text. Throws a Corrupt Error naming `file` when the text is not a
// bake's document (no provenance, a per-frame list missing, entries that do not name one frame each).
BakeMetadata splitMetadata(const std::string& meta_json, const std::filesystem::path& file);

// The META text of a package holding `frames` (in this order) of documents that share `shared`.
std::string joinMetadata(const nlohmann::ordered_json& shared, const std::vector<const FrameMetadata*>& frames);

// The first place where two shared documents differ, as "key.key: A vs B" (values shortened), or
// "" when they are equal.
std::string firstDifference(const nlohmann::ordered_json& a, const nlohmann::ordered_json& b);

}  // namespace firelook::bake
