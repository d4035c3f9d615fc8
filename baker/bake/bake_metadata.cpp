#include "bake/bake_metadata.h"

#include <stdexcept>

#include "common/error.h"

namespace firelook::bake {
namespace {

using nlohmann::ordered_json;

// Where the per-frame lists live in META, and which member of FrameMetadata each fills.
struct FrameList {
    const char* pointer;
    ordered_json FrameMetadata::*entry;
};
constexpr FrameList kFrameLists[] = {
    {"/bake/frames", &FrameMetadata::record},
    {"/provenance/sources", &FrameMetadata::source},
    {"/errors", &FrameMetadata::errors},
};

std::string shortened(const ordered_json& value) {
    std::string text = value.dump();
    if (text.size() > 80) text = text.substr(0, 77) + "...";
    return text;
}

std::string differenceAt(const ordered_json& a, const ordered_json& b, const std::string& path) {
    if (a.is_object() && b.is_object()) {
        for (const auto& [key, value] : a.items()) {
            const std::string here = path.empty() ? key : path + "." + key;
            if (!b.contains(key)) return here + ": " + shortened(value) + " vs absent";
            if (std::string d = differenceAt(value, b.at(key), here); !d.empty()) return d;
        }
        for (const auto& [key, value] : b.items())
            if (!a.contains(key)) return (path.empty() ? key : path + "." + key) + ": absent vs " + shortened(value);
        return {};
    }
    if (a.is_array() && b.is_array() && a.size() == b.size()) {
        for (size_t i = 0; i < a.size(); ++i)
            if (std::string d = differenceAt(a[i], b[i], path + "[" + std::to_string(i) + "]"); !d.empty()) return d;
        return {};
    }
    return a == b ? std::string() : path + ": " + shortened(a) + " vs " + shortened(b);
}

}  // namespace

BakeMetadata splitMetadata(const std::string& meta_json, const std::filesystem::path& file) {
    const auto fail = [&](const std::string& problem) {
        return Error(ErrorCode::Corrupt,
                     file.string() + ": " + problem + " (not a package written by firelook bake?)");
    };
    BakeMetadata m;
    m.shared = ordered_json::parse(meta_json, nullptr, false);
    if (m.shared.is_discarded() || !m.shared.is_object()) throw fail("its metadata is not a JSON object");
    if (!m.shared.contains("provenance")) throw fail("its metadata has no provenance");
    for (const FrameList& list : kFrameLists) {
        const ordered_json::json_pointer pointer(list.pointer);
        if (!m.shared.contains(pointer) || !m.shared.at(pointer).is_array())
            throw fail(std::string("its metadata has no list ") + list.pointer);
        for (const ordered_json& entry : m.shared.at(pointer)) {
            if (!entry.is_object() || !entry.contains("frame") || !entry.at("frame").is_number_integer())
                throw fail(std::string("an entry of ") + list.pointer + " names no frame");
            ordered_json& slot = m.frames[entry.at("frame").get<int>()].*list.entry;
            if (!slot.is_null())
                throw fail(std::string(list.pointer) + " names frame " + entry.at("frame").dump() + " twice");
            slot = entry;
        }
        m.shared.at(pointer) = ordered_json::array();
    }
    for (const auto& [frame, entries] : m.frames)
        for (const FrameList& list : kFrameLists)
            if ((entries.*list.entry).is_null())
                throw fail("frame " + std::to_string(frame) + " has no entry in " + list.pointer);
    return m;
}

std::string joinMetadata(const ordered_json& shared, const std::vector<const FrameMetadata*>& frames) {
    ordered_json doc = shared;
    for (const FrameList& list : kFrameLists) {
        ordered_json& target = doc.at(ordered_json::json_pointer(list.pointer));
        for (const FrameMetadata* f : frames) target.push_back(f->*list.entry);
    }
    return doc.dump(2);  // as basis::makeMetadata writes it
}

std::string firstDifference(const ordered_json& a, const ordered_json& b) { return differenceAt(a, b, ""); }

}  // namespace firelook::bake
