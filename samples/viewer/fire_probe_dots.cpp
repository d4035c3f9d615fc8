#include "fire_probe_dots.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

namespace firelook::viewer {
namespace {

struct Probes {
    fl_fire_probe_grid grid{};
    std::vector<float> coefficients;  // 27 a probe
};

// The probes of the instance's last update, or empty coefficients with `why` set.
Probes currentProbes(FireSession& s, std::string& why) {
    Probes p;
    p.grid.struct_size = sizeof p.grid;
    size_t count = 0;
    if (fl_instance_get_fire_probes(s.world(), s.instance(), &p.grid, nullptr, 0, &count) != FL_OK) {
        why = fl_last_error();
        return p;
    }
    p.coefficients.resize(count);
    if (fl_instance_get_fire_probes(s.world(), s.instance(), nullptr, p.coefficients.data(), count,
                                    nullptr) != FL_OK) {
        why = fl_last_error();
        p.coefficients.clear();
    }
    return p;
}

// Fluence rate of probe `index`: sqrt(4 pi) L00 (firelook.h).
glm::vec3 probeFluence(const Probes& p, size_t index) {
    const float* l00 = p.coefficients.data() + 27 * index;
    return glm::max(2.0f * std::sqrt(3.14159265f) * glm::vec3(l00[0], l00[1], l00[2]), glm::vec3(0.0f));
}

}  // namespace

void fireProbePanel(FireSession& s, FireProbeView& view) {
    ImGui::Checkbox("probe dots", &view.show);
    std::string why;
    const Probes p = currentProbes(s, why);
    if (p.coefficients.empty()) {
        ImGui::TextWrapped("%s", why.c_str());
        return;
    }
    float lo = INFINITY, hi = 0.0f;
    for (size_t i = 0; i < p.coefficients.size() / 27; ++i) {
        const glm::vec3 f = probeFluence(p, i);
        const float mean = (f.r + f.g + f.b) / 3.0f;
        lo = std::min(lo, mean);
        hi = std::max(hi, mean);
    }
    ImGui::Text("%d x %d x %d probes, spacing %.3g", p.grid.counts[0], p.grid.counts[1], p.grid.counts[2],
                p.grid.spacing[0]);
    ImGui::Text("fluence (mean RGB) %.3g to %.3g", lo, hi);
}

void drawFireProbeDots(FireSession& s, const FireProbeView& view, ImVec2 image_min, ImVec2 image_max) {
    if (!view.show) return;
    fl_camera camera = fl_camera_defaults();
    if (fl_package_get_camera(s.package(), &camera) != FL_OK) return;
    std::string why;
    const Probes p = currentProbes(s, why);
    if (p.coefficients.empty()) return;
    glm::dmat4 world_from_camera;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) world_from_camera[c][r] = camera.world_from_camera[4 * c + r];
    const glm::dmat4 camera_from_world = glm::inverse(world_from_camera);
    const double tan_half = std::tan(0.5 * camera.yfov_radians);
    const double aspect = static_cast<double>(camera.width) / camera.height;
    const ImVec2 size(image_max.x - image_min.x, image_max.y - image_min.y);
    const size_t probes = p.coefficients.size() / 27;
    float brightest = 0.0f;
    for (size_t i = 0; i < probes; ++i) {
        const glm::vec3 f = probeFluence(p, i);
        brightest = std::max({brightest, f.r, f.g, f.b});
    }
    const float k = brightest > 0.0f ? 1.0f / brightest : 0.0f;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->PushClipRect(image_min, image_max, true);
    const int nx = p.grid.counts[0], ny = p.grid.counts[1];
    for (size_t i = 0; i < probes; ++i) {
        const int a = static_cast<int>(i) % nx, b = (static_cast<int>(i) / nx) % ny,
                  c = static_cast<int>(i) / (nx * ny);
        const glm::dvec4 x(p.grid.origin[0] + a * p.grid.spacing[0], p.grid.origin[1] + b * p.grid.spacing[1],
                           p.grid.origin[2] + c * p.grid.spacing[2], 1.0);
        const glm::dvec4 v = camera_from_world * x;
        if (v.z >= 0.0) continue;  // behind the camera
        const ImVec2 centre(
            image_min.x + static_cast<float>((0.5 + 0.5 * (v.x / -v.z) / (tan_half * aspect)) * size.x),
            image_min.y + static_cast<float>((0.5 - 0.5 * (v.y / -v.z) / tan_half) * size.y));
        const glm::vec3 f = probeFluence(p, i) * k;
        draw->AddCircleFilled(centre, 5.0f, ImGui::GetColorU32(ImVec4(f.r, f.g, f.b, 1.0f)));
        draw->AddCircle(centre, 5.0f, IM_COL32(255, 255, 255, 160), 0, 1.0f);
    }
    draw->PopClipRect();
}

}  // namespace firelook::viewer
