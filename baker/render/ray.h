// A ray in world space.
#pragma once

#include <glm/vec3.hpp>

namespace firelook::render {

// origin + t * direction; direction has unit length so t is a distance in world units.
struct Ray {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};
};

}  // namespace firelook::render
