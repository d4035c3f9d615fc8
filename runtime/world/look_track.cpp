#include "world/look_track.h"

#include <algorithm>
#include <cmath>

#include "look/emission_fit.h"

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
    const double t = bracket.t;
    const auto lerp = [t](double x, double y) { return (1.0 - t) * x + t * y; };
    const float s = static_cast<float>(1.0 - t), u = static_cast<float>(t);
    extinction_out.temperature_threshold = lerp(a.extinction.temperature_threshold, b.extinction.temperature_threshold);
    extinction_out.smoke_extinction = lerp(a.extinction.smoke_extinction, b.extinction.smoke_extinction);
    extinction_out.flame_extinction = lerp(a.extinction.flame_extinction, b.extinction.flame_extinction);
    for (size_t i = 0; i < a.rbf.size(); ++i) rbf_out[i] = s * a.rbf[i] + u * b.rbf[i];
    for (size_t l = 0; l < a.lights.size(); ++l) lights_out[l] = s * a.lights[l] + u * b.lights[l];
}

Look sampledLook(std::span<const Keyframe> keys, double frame, const basis::BakeDescription& d) {
    const KeyframeBracket bracket = bracketKeyframes(keys, frame);
    if (bracket.lo == bracket.hi) return keys[bracket.lo].look.source;
    // The very numbers the world uses (sampleKeyframes), then the emission they make at the centres.
    ExtinctionParams extinction;
    EmissionFunction emission;
    emission.basis.bins = d.bins;
    emission.basis.width_in_bins = d.rbf_width;
    emission.coefficients.resize(static_cast<size_t>(d.bins.count));
    std::vector<Rgb> lights(keys[bracket.lo].look.lights.size());
    sampleKeyframes(keys, frame, extinction, emission.coefficients.data(), lights.data());
    Look look;
    look.temperature_threshold = extinction.temperature_threshold;
    look.smoke_extinction = extinction.smoke_extinction;
    look.flame_extinction = extinction.flame_extinction;
    look.albedo = keys[bracket.lo].look.source.albedo;  // equal in every key (resolveLook)
    EmissionBins bins;
    for (int j = 0; j < d.bins.count; ++j) bins.emissivity.push_back(emission.evaluate(d.bins.center(j)));
    look.emission = std::move(bins);
    look.light_irradiance = std::move(lights);
    look.source_name = "the look interpolated at frame " + std::to_string(frame);
    return look;
}

}  // namespace firelook::world
