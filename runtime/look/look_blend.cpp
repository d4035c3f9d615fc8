#include "look/look_blend.h"

#include <algorithm>
#include <cmath>

#include "look/detail/look_error.h"
#include "look/emission_fit.h"

namespace firelook {

void blendFittedLooks(const FittedLookView& a, const FittedLookView& b, double t, ExtinctionParams& extinction_out,
                      Rgb* rbf_out, Rgb* lights_out) {
    // (1 - t) x + t y rather than x + t (y - x): never below min(x, y), so non-negative stays so.
    const auto lerp = [t](double x, double y) { return (1.0 - t) * x + t * y; };
    const float s = static_cast<float>(1.0 - t), u = static_cast<float>(t);
    extinction_out.temperature_threshold = lerp(a.extinction.temperature_threshold, b.extinction.temperature_threshold);
    extinction_out.smoke_extinction = lerp(a.extinction.smoke_extinction, b.extinction.smoke_extinction);
    extinction_out.flame_extinction = lerp(a.extinction.flame_extinction, b.extinction.flame_extinction);
    for (size_t i = 0; i < a.rbf.size(); ++i) rbf_out[i] = s * a.rbf[i] + u * b.rbf[i];
    for (size_t l = 0; l < a.lights.size(); ++l) lights_out[l] = s * a.lights[l] + u * b.lights[l];
}

Look lookOfFittedEmission(const ExtinctionParams& extinction, double albedo, const EmissionBasis& basis,
                          std::span<const Rgb> rbf, std::span<const Rgb> lights, std::string source_name) {
    Look look;
    look.temperature_threshold = extinction.temperature_threshold;
    look.smoke_extinction = extinction.smoke_extinction;
    look.flame_extinction = extinction.flame_extinction;
    look.albedo = albedo;
    const EmissionFunction emission{basis, std::vector<Rgb>(rbf.begin(), rbf.end())};
    EmissionBins bins;
    for (int j = 0; j < basis.bins.count; ++j) bins.emissivity.push_back(emission.evaluate(basis.bins.center(j)));
    look.emission = std::move(bins);
    look.light_irradiance.assign(lights.begin(), lights.end());
    look.source_name = std::move(source_name);
    return look;
}

Look interpolateLooks(const Look& a, const Look& b, double t, const TemperatureBins& bins, double rbf_width) {
    const std::string name =
        detail::lookDisplayName(a.source_name) + " -> " + detail::lookDisplayName(b.source_name);
    if (!std::isfinite(t)) detail::throwLookError(name, "", "interpolation parameter must be finite");
    if (a.albedo != b.albedo)
        detail::throwLookError(name, "albedo",
                               "differs (" + std::to_string(a.albedo) + " vs " + std::to_string(b.albedo) +
                                   "); it is fixed when a package is baked, so keyframes must share it");
    if (a.light_irradiance.size() != b.light_irradiance.size())
        detail::throwLookError(name, "light_irradiance", "keyframes must have the same number of lights");
    if (!std::isfinite(rbf_width) || !(rbf_width > 0.0))
        detail::throwLookError(name, "", "RBF width must be positive and finite, got " + std::to_string(rbf_width));
    const EmissionBasis basis{bins, rbf_width};
    // resolveBinEmissivity validates each look and the bins.
    const std::vector<Rgb> rbf_a = fitEmissionCoefficients(basis, resolveBinEmissivity(a, bins));
    const std::vector<Rgb> rbf_b = fitEmissionCoefficients(basis, resolveBinEmissivity(b, bins));

    t = std::clamp(t, 0.0, 1.0);
    ExtinctionParams extinction;
    std::vector<Rgb> rbf(rbf_a.size()), lights(a.light_irradiance.size());
    blendFittedLooks({a.extinction(), rbf_a, a.light_irradiance}, {b.extinction(), rbf_b, b.light_irradiance}, t,
                     extinction, rbf.data(), lights.data());
    return lookOfFittedEmission(extinction, a.albedo, basis, rbf, lights, name);
}

}  // namespace firelook
