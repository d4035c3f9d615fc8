#include "basis/six_way_lights.h"

#include <glm/geometric.hpp>

namespace firelook::basis {

glm::dvec3 sixWayCameraAxis(int light) {
    // Towards each light: right +X, top +Y, back -Z (beyond the volume), then the opposites.
    static constexpr double kAxes[kSixWayLightCount][3] = {{1, 0, 0},  {0, 1, 0},  {0, 0, -1},
                                                           {-1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
    return {kAxes[light][0], kAxes[light][1], kAxes[light][2]};
}

std::array<glm::dvec3, kSixWayLightCount> sixWayTravelDirections(const glm::dmat4& world_from_camera) {
    const glm::dvec3 x = glm::normalize(glm::dvec3(world_from_camera[0]));
    const glm::dvec3 y = glm::normalize(glm::dvec3(world_from_camera[1]));
    const glm::dvec3 z = glm::normalize(glm::dvec3(world_from_camera[2]));
    std::array<glm::dvec3, kSixWayLightCount> out;
    for (int l = 0; l < kSixWayLightCount; ++l) {
        const glm::dvec3 a = sixWayCameraAxis(l);
        out[l] = -(a.x * x + a.y * y + a.z * z);
    }
    return out;
}

}  // namespace firelook::basis
