#include "fire_light_markers.h"

#include <algorithm>
#include <cmath>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <vector>

namespace firelook::viewer {
namespace {

// The lights of the instance's last update, or empty with `why` set.
std::vector<fl_fire_light> currentLights(FireSession& s, int count, std::string& why) {
    uint32_t stored = 0;
    std::vector<fl_fire_light> lights;
    if (fl_instance_get_fire_lights(s.world(), s.instance(), 0, nullptr, sizeof(fl_fire_light), 0, &stored) != FL_OK) {
        why = fl_last_error();
        return lights;
    }
    if (stored == 0) {
        why = "this package has no fire lights (baked before them)";
        return lights;
    }
    const uint32_t n = static_cast<uint32_t>(std::clamp(count, 1, static_cast<int>(stored)));
    lights.resize(n);
    if (fl_instance_get_fire_lights(s.world(), s.instance(), n, lights.data(), sizeof(fl_fire_light), n, nullptr) != FL_OK) {
        why = fl_last_error();
        lights.clear();
    }
    return lights;
}

}  // namespace

void fireLightPanel(FireSession& s, FireLightView& view) {
    ImGui::Checkbox("markers", &view.show);
    ImGui::SameLine();
    for (int n : {1, 2, 4, 8}) {
        ImGui::SameLine();
        ImGui::RadioButton(std::to_string(n).c_str(), &view.count, n);
    }
    std::string why;
    const std::vector<fl_fire_light> lights = currentLights(s, view.count, why);
    if (lights.empty()) ImGui::TextWrapped("%s", why.c_str());
    for (size_t l = 0; l < lights.size(); ++l)
        ImGui::Text("%zu: I = (%.3g, %.3g, %.3g), r = %.3g", l, lights[l].intensity[0], lights[l].intensity[1],
                    lights[l].intensity[2], lights[l].radius);
}

void drawFireLightMarkers(FireSession& s, const FireLightView& view, ImVec2 image_min, ImVec2 image_max) {
    if (!view.show) return;
    fl_camera camera = fl_camera_defaults();
    if (fl_package_get_camera(s.package(), &camera) != FL_OK) return;
    std::string why;
    const std::vector<fl_fire_light> lights = currentLights(s, view.count, why);
    if (lights.empty()) return;
    glm::dmat4 world_from_camera;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) world_from_camera[c][r] = camera.world_from_camera[4 * c + r];
    const glm::dmat4 camera_from_world = glm::inverse(world_from_camera);
    const double tan_half = std::tan(0.5 * camera.yfov_radians);
    const double aspect = static_cast<double>(camera.width) / camera.height;
    const ImVec2 size(image_max.x - image_min.x, image_max.y - image_min.y);
    // Pixels of the drawn image per unit of image-plane height at distance 1.
    const double scale = 0.5 * size.y / tan_half;
    float brightest = 0.0f;
    for (const fl_fire_light& l : lights) brightest = std::max({brightest, l.intensity[0], l.intensity[1], l.intensity[2]});
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->PushClipRect(image_min, image_max, true);
    for (const fl_fire_light& l : lights) {
        const glm::dvec4 c = camera_from_world * glm::dvec4(l.position[0], l.position[1], l.position[2], 1.0);
        if (c.z >= 0.0) continue;  // behind the camera
        const double x = c.x / -c.z, y = c.y / -c.z;
        const ImVec2 centre(image_min.x + static_cast<float>((0.5 + 0.5 * x / (tan_half * aspect)) * size.x),
                            image_min.y + static_cast<float>((0.5 - 0.5 * y / tan_half) * size.y));
        const float radius = std::max(4.0f, static_cast<float>(l.radius / -c.z * scale));
        const float k = brightest > 0.0f ? 1.0f / brightest : 0.0f;
        const ImU32 fill = ImGui::GetColorU32(ImVec4(l.intensity[0] * k, l.intensity[1] * k, l.intensity[2] * k, 0.35f));
        draw->AddCircleFilled(centre, radius, fill);
        draw->AddCircle(centre, radius, IM_COL32(255, 255, 255, 220), 0, 1.5f);
        draw->AddLine(ImVec2(centre.x - 4, centre.y), ImVec2(centre.x + 4, centre.y), IM_COL32(255, 255, 255, 255));
        draw->AddLine(ImVec2(centre.x, centre.y - 4), ImVec2(centre.x, centre.y + 4), IM_COL32(255, 255, 255, 255));
    }
    draw->PopClipRect();
}

}  // namespace firelook::viewer
