// Small builders shared by the render tests.
#pragma once

#include <glm/vec3.hpp>
#include <numbers>

#include "look/look_model.h"
#include "render/camera.h"

namespace firelook::render::test {

// A look over temperatures [0, 1] in 4 bins with every emission coefficient equal to emission
// (so L_e is smooth and positive) and no lights.
inline LookModel makeLook(double smoke_extinction, double flame_extinction, double threshold, double albedo,
                          const Rgb& emission) {
    LookModel look;
    look.bins = TemperatureBins{0.0, 1.0, 4};
    look.extinction = ExtinctionParams{threshold, smoke_extinction, flame_extinction};
    look.albedo = albedo;
    look.emission.basis.bins = look.bins;
    look.emission.coefficients.assign(4, emission);
    return look;
}

// Looks down -Z at the origin from z = 10 with a 2 degree field of view: every ray of the square
// image crosses the box [-1, 1]^3 through its z faces, nearly parallel.
inline Camera narrowCamera(int size = 8) {
    return Camera::lookAt({0.0, 0.0, 10.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 2.0 * std::numbers::pi / 180.0,
                          size, size);
}

}  // namespace firelook::render::test
