#include "keyframes_file.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "fl_check.h"
#include "text_file.h"

namespace firelook::viewer {
namespace {

using Json = nlohmann::ordered_json;
constexpr const char* kFormat = "firelook-viewer-keyframes";

}  // namespace

void insertKey(std::vector<Keyframe>& keys, const Keyframe& key) {
    const auto same = std::find_if(keys.begin(), keys.end(), [&](const Keyframe& k) { return k.frame == key.frame; });
    if (same != keys.end()) {
        same->look = key.look;
        return;
    }
    keys.push_back(key);
    std::stable_sort(keys.begin(), keys.end(), [](const Keyframe& a, const Keyframe& b) { return a.frame < b.frame; });
}

std::string keyframesToJson(const std::vector<Keyframe>& keys) {
    Json root;
    root["format"] = kFormat;
    root["version"] = 1;
    Json list = Json::array();
    for (const Keyframe& k : keys)
        list.push_back(Json{{"frame", k.frame}, {"look", Json::parse(canonicalLookJson(k.look))}});
    root["keys"] = list;
    return root.dump(2) + "\n";
}

std::vector<Keyframe> parseKeyframes(const std::string& json, const std::string& source) {
    const Json root = Json::parse(json, nullptr, /*allow_exceptions=*/false);
    if (root.is_discarded() || !root.is_object()) throw ViewerError(source + ": not a JSON object");
    if (root.value("format", std::string()) != kFormat)
        throw ViewerError(source + ": \"format\" must be \"" + kFormat + "\" (is this a keyframe file?)");
    if (!root.contains("version") || !root["version"].is_number_integer() || root["version"].get<int>() != 1)
        throw ViewerError(source + ": \"version\" must be 1");
    if (!root.contains("keys") || !root["keys"].is_array()) throw ViewerError(source + ": \"keys\" must be an array");
    std::vector<Keyframe> keys;
    const Json& list = root["keys"];
    for (size_t i = 0; i < list.size(); ++i) {
        const std::string where = source + ": keys[" + std::to_string(i) + "]";
        const Json& k = list[i];
        if (!k.is_object() || !k.contains("frame") || !k["frame"].is_number() || !k.contains("look"))
            throw ViewerError(where + " must be {\"frame\": number, \"look\": {...}}");
        const double frame = k["frame"].get<double>();
        if (!std::isfinite(frame)) throw ViewerError(where + ".frame must be finite");
        insertKey(keys, {frame, parseLookEdit(k["look"].dump(), where + ".look")});
    }
    return keys;
}

void saveKeyframes(const std::filesystem::path& path, const std::vector<Keyframe>& keys) {
    writeTextFileAtomic(path, keyframesToJson(keys));
}

std::vector<Keyframe> loadKeyframes(const std::filesystem::path& path) {
    return parseKeyframes(readTextFile(path), path.string());
}

}  // namespace firelook::viewer
