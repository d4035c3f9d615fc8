// The viewer's keyframe file: a small JSON document listing looks at package frame numbers,
// each look being exactly a look-file object (README.md, "Keyframe files"):
//   {"format": "firelook-viewer-keyframes", "version": 1,
//    "keys": [{"frame": 5, "look": {"format": "firelook-look", ...}}, ...]}
#pragma once

#include <filesystem>
#include <vector>

#include "look_edit.h"

namespace firelook::viewer {

struct Keyframe {
    double frame = 0.0;  // package frame number, fractional allowed
    LookEdit look;
};

// Keys sorted by frame; a second key at the same frame replaces the first.
void insertKey(std::vector<Keyframe>& keys, const Keyframe& key);

std::string keyframesToJson(const std::vector<Keyframe>& keys);
// Every look is validated by the library; errors name `source` and the key index. Throws ViewerError.
std::vector<Keyframe> parseKeyframes(const std::string& json, const std::string& source);

void saveKeyframes(const std::filesystem::path& path, const std::vector<Keyframe>& keys);
std::vector<Keyframe> loadKeyframes(const std::filesystem::path& path);

}  // namespace firelook::viewer
