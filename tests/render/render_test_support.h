// Small builders shared by the render tests.
#pragma once

#include <glm/vec3.hpp>

#include "look/look_model.h"

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

}  // namespace firelook::render::test
