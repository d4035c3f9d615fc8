// Keyframed looks, resolved once against a package so that the per-update
// interpolation is a handful of lerps (no JSON, no fit, no allocation).
//
// Each key's emission is fitted once, when the key is set (fitEmissionCoefficients), and keys are
// blended by the one keyed-look rule of look/look_blend.h (the fitted coefficients blended linearly:
// non-negative, continuous in time, equal to the keys at the keys), which `firelook animate` renders
// too.
#pragma once

#include <span>
#include <vector>

#include "basis/bake_description.h"
#include "look/look.h"
#include "world/keyframe_bracket.h"

namespace firelook::world {

struct ResolvedLook {
    Look source;  // the look as given (what an instance held at this key reports: World::look)
    ExtinctionParams extinction;
    std::vector<Rgb> emissivity;  // e_i at the bin centres
    std::vector<Rgb> rbf;         // fitted c_i, >= 0
    std::vector<Rgb> lights;      // E_l per baked light
    // True when every channel's fit reproduces e_i at the bin centres (the
    // exact interpolant was non-negative), so blends of this key are exact.
    bool exact_interpolant = true;
};

// Throws LookError (naming look.source_name) when the look does not fit the
// package: albedo differs from the baked one, wrong number of lights or bins,
// or a value out of range.
ResolvedLook resolveLook(const Look& look, const basis::BakeDescription& description);

struct Keyframe {
    double frame = 0.0;  // in the package's frame numbers (fractional allowed)
    ResolvedLook look;
};

// The interpolated look at `frame`: the keys and weight t of bracketKeyframes()
// (keyframe_bracket.h: before the first key the first, from the last on the
// last, between keys t = (frame - f0) / (f1 - f0)), blended by blendFittedLooks() (look_blend.h).
// Keys must be sorted by frame and
// non-empty. rbf_out has bins entries, lights_out one per light.
// Allocation-free.
void sampleKeyframes(std::span<const Keyframe> keys, double frame, ExtinctionParams& extinction_out,
                     Rgb* rbf_out, Rgb* lights_out);

// The look sampleKeyframes() produces at `frame`, as a Look: where one key holds, that key's own
// look (its source, emission form included); between keys, lookOfFittedEmission() of the blend
// (look_blend.h): the Look describes the image the instance shows even where a key needed the
// non-negative fit, and equals interpolateLooks() of the two keys. Allocates.
Look sampledLook(std::span<const Keyframe> keys, double frame, const basis::BakeDescription& description);

}  // namespace firelook::world
