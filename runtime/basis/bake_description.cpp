#include "basis/bake_description.h"

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "basis/six_way_lights.h"
#include "common/error.h"

namespace firelook::basis {

using nlohmann::json;

const FrameRecord* BakeDescription::findFrame(int frame) const {
    for (const FrameRecord& record : frames)
        if (record.frame == frame) return &record;
    return nullptr;
}

int BasisModel::relightLightCount() const {
    if (six_way_first_light >= 0) return kSixWayLightCount;
    return sphere_first_light >= 0 ? sphere_light_count : 0;
}

std::string bakeDescriptionToJson(const BakeDescription& d) {
    json lights = json::array();
    for (const glm::dvec3& dir : d.light_directions) lights.push_back({dir.x, dir.y, dir.z});
    json frames = json::array();
    for (const FrameRecord& f : d.frames) frames.push_back({{"frame", f.frame}, {"rank", f.rank}});
    json j = {
        {"temperature_bins", {{"t_lo", d.bins.t_lo}, {"t_hi", d.bins.t_hi}, {"count", d.bins.count}}},
        {"rbf_width", d.rbf_width},
        {"rbf_fit", "non-negative least squares"},
        {"emission_temperature_clamp", d.emission_clamp_to_centres ? "bin_centres" : "range"},
        {"albedo", d.albedo},
        {"axes",
         {{"temperature_threshold", d.axes.temperature_threshold},
          {"smoke_extinction", d.axes.smoke_extinction},
          {"flame_extinction", d.axes.flame_extinction}}},
        {"alpha_thresholds", d.alpha_thresholds},
        {"footprint_samples", d.footprint_samples},
        {"light_directions", lights},
        {"width", d.width},
        {"height", d.height},
        {"frames", frames},
        {"default_look", json::parse(d.default_look_json.empty() ? "null" : d.default_look_json)},
    };
    // Written only by six-way bakes, so every other package keeps its bytes (a minor addition).
    if (d.six_way_first_light >= 0) {
        json names = json::array();
        for (std::string_view name : kSixWayLightNames) names.push_back(std::string(name));
        j["six_way_lights"] = {{"first", d.six_way_first_light}, {"names", names}};
    }
    // Likewise only by sphere bakes.
    if (d.sphere_first_light >= 0)
        j["sphere_lights"] = {{"first", d.sphere_first_light},
                              {"count", d.sphere_light_count},
                              {"interpolation", "spherical barycentric"},
                              {"triangles", d.sphere_triangles}};
    return j.dump(2);
}

BakeDescription parseBakeDescription(const std::string& json_text, const std::string& source) {
    try {
        const json j = json::parse(json_text);
        BakeDescription d;
        const json& bins = j.at("temperature_bins");
        d.bins.t_lo = bins.at("t_lo").get<double>();
        d.bins.t_hi = bins.at("t_hi").get<double>();
        d.bins.count = bins.at("count").get<int>();
        d.rbf_width = j.at("rbf_width").get<double>();
        // Version-1 packages predate the key and were baked with the range rule.
        const std::string clamp = j.value("emission_temperature_clamp", std::string("range"));
        if (clamp != "bin_centres" && clamp != "range")
            throw Error(
                ErrorCode::Corrupt,
                "emission_temperature_clamp must be \"bin_centres\" or \"range\", got \"" + clamp + "\"");
        d.emission_clamp_to_centres = clamp == "bin_centres";
        d.albedo = j.at("albedo").get<double>();
        const json& axes = j.at("axes");
        d.axes.temperature_threshold = axes.at("temperature_threshold").get<std::vector<double>>();
        d.axes.smoke_extinction = axes.at("smoke_extinction").get<std::vector<double>>();
        d.axes.flame_extinction = axes.at("flame_extinction").get<std::vector<double>>();
        d.alpha_thresholds = j.at("alpha_thresholds").get<std::vector<double>>();
        d.footprint_samples = j.value("footprint_samples", 1);
        for (const json& l : j.at("light_directions"))
            d.light_directions.emplace_back(l.at(0).get<double>(), l.at(1).get<double>(), l.at(2).get<double>());
        if (j.contains("six_way_lights")) {
            d.six_way_first_light = j["six_way_lights"].at("first").get<int>();
            if (d.six_way_first_light < 0 ||
                d.six_way_first_light + kSixWayLightCount > static_cast<int>(d.light_directions.size()))
                throw Error(ErrorCode::InvalidArgument,
                            "six_way_lights.first must leave six lights after it");
        }
        if (j.contains("sphere_lights")) {
            const json& sphere = j["sphere_lights"];
            d.sphere_first_light = sphere.at("first").get<int>();
            d.sphere_light_count = sphere.at("count").get<int>();
            d.sphere_triangles = sphere.at("triangles").get<std::vector<std::array<int, 3>>>();
            const std::string interpolation =
                sphere.value("interpolation", std::string("spherical barycentric"));
            if (interpolation != "spherical barycentric")
                throw Error(ErrorCode::InvalidArgument, "sphere_lights.interpolation \"" + interpolation +
                                                            "\" is not \"spherical barycentric\"");
            if (d.six_way_first_light >= 0)
                throw Error(ErrorCode::InvalidArgument, "six_way_lights and sphere_lights together");
            if (d.sphere_first_light < 0 || d.sphere_light_count < 4 ||
                d.sphere_first_light + d.sphere_light_count > static_cast<int>(d.light_directions.size()))
                throw Error(ErrorCode::InvalidArgument,
                            "sphere_lights must name 4 or more of the lights (first, count)");
            // A closed triangulation of N points on the sphere has 2N - 4 triangles (Euler).
            if (d.sphere_triangles.size() != static_cast<size_t>(2 * d.sphere_light_count - 4))
                throw Error(ErrorCode::InvalidArgument,
                            "sphere_lights.triangles must be 2 count - 4 triangles");
            for (const std::array<int, 3>& t : d.sphere_triangles)
                for (int v : t)
                    if (v < 0 || v >= d.sphere_light_count)
                        throw Error(ErrorCode::InvalidArgument,
                                    "sphere_lights.triangles names a light past count");
        }
        d.width = j.at("width").get<int>();
        d.height = j.at("height").get<int>();
        for (const json& f : j.at("frames")) d.frames.push_back({f.at("frame").get<int>(), f.at("rank").get<int>()});
        if (j.contains("default_look") && !j["default_look"].is_null()) d.default_look_json = j["default_look"].dump();

        validateAxes(d.axes);
        // Bounds keep every size product (pixels, columns, pixels * rank) far inside 64 bits
        // and the int arithmetic of the runtime well defined, whatever a file claims.
        if (d.bins.count < 1 || d.bins.count > 256 || !(d.bins.t_hi > d.bins.t_lo))
            throw Error(ErrorCode::InvalidArgument, "invalid temperature bins");
        if (d.width < 1 || d.height < 1 || d.width > 16384 || d.height > 16384)
            throw Error(ErrorCode::InvalidArgument, "image size must be 1..16384 pixels on each side");
        if (d.axes.pointCount() > 65536 || d.light_directions.size() > 64 || d.alpha_thresholds.size() > 256)
            throw Error(ErrorCode::InvalidArgument, "too many parameter samples, lights or alpha thresholds");
        for (const FrameRecord& f : d.frames)
            if (f.rank < 0 || f.rank > 4096)
                throw Error(ErrorCode::InvalidArgument, "frame rank out of range");
        if (d.alpha_thresholds.empty()) throw Error(ErrorCode::InvalidArgument, "no alpha thresholds");
        if (d.footprint_samples < 1 || d.footprint_samples > 64)
            throw Error(ErrorCode::InvalidArgument, "footprint_samples must be 1..64");
        return d;
    } catch (const std::exception& e) {
        // Ours and nlohmann-json's alike: whatever the description holds came from the file.
        throw Error(ErrorCode::Corrupt, source + ": invalid bake description: " + e.what());
    }
}

}  // namespace firelook::basis
