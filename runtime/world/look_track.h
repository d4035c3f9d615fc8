// Keyframed looks, resolved once against a package so that the per-update
// interpolation is a handful of lerps (no JSON, no fit, no allocation).
//
// Emission: each keyframe's RBF coefficients are fitted once, when the key is
// set (fitEmissionCoefficients: exact interpolant, or the non-negative fit when
// the interpolant would go negative). Between keys the runtime interpolates
// the *coefficients* linearly with the same weights interpolateLooks() uses for
// the bin emissivities. Where both keys' fits are the exact interpolant (the
// common case: smooth ramps, presets), this equals fitting the blended
// emissivity exactly (up to float rounding): the interpolant is linear in the
// emissivity and a convex blend of non-negative coefficients is non-negative,
// so the fit of the blend is the unconstrained solution. Where a key needed the
// non-negative fit (a sharp step), the blend of fits differs from the fit of
// the blend; tests/world measure by how much. Either way the result is
// non-negative (no negative emission), continuous in time and equal to the
// keys at the keys.
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
// last, between keys t = (frame - f0) / (f1 - f0)), blended in the form
// (1 - t) x + t y, as interpolateLooks(). Keys must be sorted by frame and
// non-empty. rbf_out has bins entries, lights_out one per light.
// Allocation-free.
void sampleKeyframes(std::span<const Keyframe> keys, double frame, ExtinctionParams& extinction_out,
                     Rgb* rbf_out, Rgb* lights_out);

// The look sampleKeyframes() produces at `frame`, as a Look: where one key holds, that key's own
// look (its source, emission form included); between keys, T_c, k_s, k_f and the lights as
// sampleKeyframes() blends them and the emission as "bins": the blended RBF coefficients evaluated
// at each bin centre. Those coefficients are non-negative, so fitting that emissivity gives them
// back (the exact interpolant, up to float rounding): the Look describes the image the instance
// shows even where a key needed the non-negative fit. Allocates.
Look sampledLook(std::span<const Keyframe> keys, double frame, const basis::BakeDescription& description);

}  // namespace firelook::world
