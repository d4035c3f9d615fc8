#include "world/package_camera.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "common/error.h"

namespace firelook::world {

std::optional<PackageCamera> readPackageCamera(const std::string& metadata_json, const std::string& name) {
    const auto corrupt = [&](const std::string& problem) {
        return Error(ErrorCode::Corrupt, name + ": the camera in the package's META " + problem);
    };
    const nlohmann::json meta = nlohmann::json::parse(metadata_json, nullptr, /*allow_exceptions=*/false);
    if (!meta.is_object() || !meta.contains("camera")) return std::nullopt;
    const nlohmann::json& c = meta["camera"];
    if (!c.is_object()) throw corrupt("is not an object");
    PackageCamera camera;
    const nlohmann::json* m = c.contains("world_from_camera") ? &c["world_from_camera"] : nullptr;
    if (!m || !m->is_array() || m->size() != 16) throw corrupt("needs \"world_from_camera\": 16 numbers");
    for (size_t i = 0; i < 16; ++i) {
        const nlohmann::json& v = (*m)[i];
        if (!v.is_number() || !std::isfinite(v.get<double>()))
            throw corrupt("has a world_from_camera entry that is not a finite number (index " + std::to_string(i) + ")");
        camera.world_from_camera[i] = v.get<double>();
    }
    const auto number = [&](const char* key) {
        if (!c.contains(key) || !c[key].is_number()) throw corrupt(std::string("needs \"") + key + "\": a number");
        return c[key].get<double>();
    };
    camera.yfov_radians = number("yfov_radians");
    if (!(camera.yfov_radians > 0.0 && camera.yfov_radians < M_PI))
        throw corrupt("has yfov_radians " + std::to_string(camera.yfov_radians) + ", outside (0, pi)");
    const double width = number("width"), height = number("height");
    if (!(width >= 1.0 && height >= 1.0 && width <= 1 << 20 && height <= 1 << 20) || width != std::floor(width) ||
        height != std::floor(height))
        throw corrupt("has a size that is not a positive whole number of pixels");
    camera.width = static_cast<int>(width);
    camera.height = static_cast<int>(height);
    return camera;
}

}  // namespace firelook::world
