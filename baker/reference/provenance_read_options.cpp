#include "reference/provenance_read_options.h"

#include <nlohmann/json.hpp>
#include <optional>
#include <type_traits>

#include "common/error.h"

namespace firelook::reference {
namespace {

using nlohmann::json;

// provenance[key] as T (a string, a number or a boolean), or `fallback` when it is not recorded;
// without a fallback a missing entry is an error.
template <typename T>
T provenanceEntry(const json& provenance, const char* key, const std::string& package_name,
                  std::optional<T> fallback = std::nullopt) {
    const auto it = provenance.find(key);
    if (it == provenance.end()) {
        if (fallback) return *fallback;
        throw Error(ErrorCode::NotFound, package_name + ": the provenance records no " + key +
                                             " (needed to read the sequence as the bake did)");
    }
    bool right_kind = false;
    const char* kind = "";
    if constexpr (std::is_same_v<T, std::string>) {
        right_kind = it->is_string();
        kind = "a string";
    } else if constexpr (std::is_same_v<T, bool>) {
        right_kind = it->is_boolean();
        kind = "true or false";
    } else {
        right_kind = it->is_number();
        kind = "a number";
    }
    if (!right_kind)
        throw Error(ErrorCode::Corrupt,
                    package_name + ": provenance." + key + " is not " + kind + " (" + it->dump() + ")");
    return it->get<T>();
}

}  // namespace

vdb::ReadOptions provenanceReadOptions(const std::string& metadata_json, const std::string& package_name) {
    json meta;
    try {
        meta = json::parse(metadata_json);
    } catch (const json::parse_error& e) {
        throw Error(ErrorCode::Corrupt, package_name + ": its metadata is not JSON: " + e.what());
    }
    if (!meta.is_object() || !meta.contains("provenance"))
        throw Error(ErrorCode::NotFound,
                    package_name + ": its metadata has no provenance (the sequence and grids it was baked from)");
    const json& p = meta.at("provenance");
    if (!p.is_object()) throw Error(ErrorCode::Corrupt, package_name + ": its provenance is not a JSON object");
    vdb::ReadOptions read;
    read.density_grid = provenanceEntry<std::string>(p, "density_grid", package_name);
    read.temperature_grid = provenanceEntry<std::string>(p, "temperature_grid", package_name);
    read.temperature_scale = provenanceEntry<double>(p, "temperature_scale", package_name);
    read.temperature_offset = provenanceEntry<double>(p, "temperature_offset", package_name);
    read.density_scale = provenanceEntry<double>(p, "density_scale", package_name, 1.0);  // recorded only when not 1
    // A package baked with --clamp-extreme saw clamped data: its references must too.
    read.clamp_extreme = provenanceEntry<bool>(p, "clamp_extreme", package_name, false);
    return read;
}

}  // namespace firelook::reference
