// The one rule by which keyed looks are blended: `firelook animate`, the runtime world (and through
// the C API the viewer's keyframes and fl_instance_get_look) all blend here.
//
// The rule: blend in the form the runtime renders. Each key's emission is fitted once
// (fitEmissionCoefficients: the exact interpolant, or the non-negative fit where the interpolant
// would go negative), then T_c, k_s, k_f, every RBF coefficient and every light's irradiance are
// blended as (1 - t) x + t y. Why this and not "blend each bin's emissivity, then fit":
//  - the image is linear in the coefficients, so between keys the emission part of the image is
//    exactly the blend of the keys' emission images, and the look the blend stands for (bins form,
//    lookOfFittedEmission) renders that same image: a reference render of it shows what the world
//    shows;
//  - a convex blend of non-negative coefficients is non-negative, so no fit is needed per frame (the
//    world's update stays allocation-free);
//  - where both keys' fits are exact interpolants the two rules agree (the interpolant is linear in
//    the emissivity); where a key needed the non-negative fit they differ, and
//    tests/world/world_test.cpp measures by how much.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "look/look.h"

namespace firelook {

// A key as the blend reads it: its extinction, fitted RBF coefficients (one per bin) and lights.
struct FittedLookView {
    ExtinctionParams extinction;
    std::span<const Rgb> rbf;
    std::span<const Rgb> lights;
};

// The blend at weight t in [0, 1] (not clamped here; interpolateLooks clamps): a and b must have the
// same bin and light counts; rbf_out and lights_out hold as many. Allocation-free.
void blendFittedLooks(const FittedLookView& a, const FittedLookView& b, double t, ExtinctionParams& extinction_out,
                      Rgb* rbf_out, Rgb* lights_out);

// The look that blended (or any) coefficients stand for: T_c, k_s, k_f and the lights as given and
// the emission as "bins", the coefficients evaluated at each bin centre. For non-negative
// coefficients fitting that emissivity gives them back (the exact interpolant, up to float rounding),
// so the look renders the image the coefficients make.
Look lookOfFittedEmission(const ExtinctionParams& extinction, double albedo, const EmissionBasis& basis,
                          std::span<const Rgb> rbf, std::span<const Rgb> lights, std::string source_name);

// The blend of two looks at t (clamped to [0, 1]) against a package's bins and RBF width: each look's
// emission fitted, then blendFittedLooks and lookOfFittedEmission. At t = 0 and t = 1 the result
// renders as a and b do. The albedo and the number of lights must be equal in both (LookError), t
// finite. What `firelook animate` renders between keys.
Look interpolateLooks(const Look& a, const Look& b, double t, const TemperatureBins& bins, double rbf_width);

}  // namespace firelook
