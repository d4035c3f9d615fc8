#include "world/look_track.h"

#include <algorithm>
#include <cmath>

#include "look/emission_fit.h"
#include "look/look_blend.h"

namespace firelook::world {

ResolvedLook resolveLook(const Look& look, const basis::BakeDescription& d) {
    if (std::abs(look.albedo - d.albedo) > 1e-6)
        throw LookError(look.source_name + ": key 'albedo': " + std::to_string(look.albedo) +
                        " differs from the package's baked albedo " + std::to_string(d.albedo) +
                        " (albedo is fixed at bake time)");
    // makeLookModel checks everything else (ranges, bin and light counts) and fits.
    const LookModel model = makeLookModel(look, d.bins, d.rbf_width, d.light_directions);
    ResolvedLook r;
    r.source = look;
    r.extinction = look.extinction();
    r.emissivity = resolveBinEmissivity(look, d.bins);
    r.rbf = model.emission.coefficients;
    r.lights = look.light_irradiance;
    for (int j = 0; j < d.bins.count && r.exact_interpolant; ++j) {
        const Rgb value = model.emission.evaluate(d.bins.center(j));
        for (int c = 0; c < 3; ++c) {
            const float e = r.emissivity[j][c];
            if (std::abs(value[c] - e) > 1e-4f * std::max(1.0f, std::abs(e))) r.exact_interpolant = false;
        }
    }
    return r;
}

void sampleKeyframes(std::span<const Keyframe> keys, double frame, ExtinctionParams& extinction_out, Rgb* rbf_out,
                     Rgb* lights_out) {
    const KeyframeBracket bracket = bracketKeyframes(keys, frame);
    if (bracket.lo == bracket.hi) {
        const ResolvedLook& k = keys[bracket.lo].look;
        extinction_out = k.extinction;
        std::copy(k.rbf.begin(), k.rbf.end(), rbf_out);
        std::copy(k.lights.begin(), k.lights.end(), lights_out);
        return;
    }
    const ResolvedLook& a = keys[bracket.lo].look;
    const ResolvedLook& b = keys[bracket.hi].look;
    blendFittedLooks({a.extinction, a.rbf, a.lights}, {b.extinction, b.rbf, b.lights}, bracket.t, extinction_out,
                     rbf_out, lights_out);
}

Look sampledLook(std::span<const Keyframe> keys, double frame, const basis::BakeDescription& d) {
    const KeyframeBracket bracket = bracketKeyframes(keys, frame);
    if (bracket.lo == bracket.hi) return keys[bracket.lo].look.source;
    // The very numbers the world uses (sampleKeyframes), then the look they stand for (look_blend.h).
    ExtinctionParams extinction;
    std::vector<Rgb> rbf(static_cast<size_t>(d.bins.count));
    std::vector<Rgb> lights(keys[bracket.lo].look.lights.size());
    sampleKeyframes(keys, frame, extinction, rbf.data(), lights.data());
    return lookOfFittedEmission(extinction, keys[bracket.lo].look.source.albedo,  // equal in every key (resolveLook)
                                EmissionBasis{d.bins, d.rbf_width}, rbf, lights,
                                "the look interpolated at frame " + std::to_string(frame));
}

}  // namespace firelook::world
