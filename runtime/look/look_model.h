// The look model every FireLook module shares (docs/model.md).
//
// This header is the single definition of what a voxel's temperature and
// density mean for extinction and emission. It is deliberately small and
// header-only so the baker's tracers, the reference path tracer and the runtime
// evaluate exactly the same formulas.
#pragma once

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

namespace firelook {

using Rgb = glm::vec3;

// n bins over [t_lo, t_hi]; bin i is centred at t_lo + (i + 0.5) dT.
struct TemperatureBins {
    double t_lo = 0.0;
    double t_hi = 1.0;
    int count = 16;

    double width() const { return (t_hi - t_lo) / count; }  // dT
    double center(int i) const { return t_lo + (i + 0.5) * width(); }
    // Temperatures outside [t_lo, t_hi] are clamped before kappa and L_e.
    // A NaN maps to t_lo so it can never propagate into an image.
    double clamp(double t) const {
        if (!(t >= t_lo)) return t_lo;
        return t > t_hi ? t_hi : t;
    }
};

// f(r) = 2/(1+exp(-r/dT)) - 1 written as tanh(r/(2 dT)): the same function,
// but tanh saturates to +-1 instead of overflowing exp() for large |r|.
inline double smokeFlameSigmoid(double r, double dT) { return std::tanh(r / (2.0 * dT)); }

// Extinction parameters theta = (T_c, k_s, k_f), per unit density per world unit.
struct ExtinctionParams {
    double temperature_threshold = 0.0;  // T_c
    double smoke_extinction = 1.0;       // k_s
    double flame_extinction = 1.0;       // k_f

    // Optical depth along a path is a * o_a(T_c) + b * o_b (docs/model.md).
    double a() const { return 0.5 * (flame_extinction - smoke_extinction); }
    double b() const { return 0.5 * (flame_extinction + smoke_extinction); }
};

// kappa(T; T_c): extinction per unit density at temperature t (clamped into the bins).
inline double extinctionPerDensity(double t, const ExtinctionParams& p, const TemperatureBins& bins) {
    const double f = smokeFlameSigmoid(bins.clamp(t) - p.temperature_threshold, bins.width());
    return p.a() * f + p.b();
}

// Default RBF width w, in units of dT. Chosen by measurement (tests/look/
// look_fit_report, the same for 8, 16 and 32 bins): w = 0.7 gives the smallest
// worst-case deviation when interpolating a constant anywhere between the outer
// bin centres (4.0%, vs 7.3% at w = 0.9, where the lattice ripple in the middle
// is only 0.14% but the coefficients ring next to the ends), a linear ramp
// within 4.4% of its maximum (7.5% at 0.9), condition number 1.7 (3.6), and
// a sharp step undershoots by 6.6% (10.8%) before the non-negative fit, which
// then misses the centres next to the step by 11% of its height (22%).
// Its costs: 3.1% lattice ripple mid-range, and the half bins outside the outer
// centres roll off by up to 45% at T_lo/T_hi (35% at 0.9) — inherent to the model.
inline constexpr double kDefaultRbfWidth = 0.7;

// Gaussian radial basis functions phi((T - T_i)/dT) with phi(u) = exp(-(u/w)^2),
// the width w measured in units of dT (emission_fit.h measures the trade-offs).
struct EmissionBasis {
    TemperatureBins bins;
    double width_in_bins = kDefaultRbfWidth;
    // docs/model.md: emission holds the outer bins' values beyond their centres,
    // L_e(T) = L_e(clamp(T, T_0, T_{n-1})), so the hottest flame keeps its colour. false is the
    // version-1 rule (clamp into [T_lo, T_hi]: up to 45% roll-off in the outer half bins), which
    // packages baked before it record.
    bool clamp_to_centres = true;

    double emissionTemperature(double t) const {
        const double in_range = bins.clamp(t);  // NaN -> T_lo
        return clamp_to_centres ? std::clamp(in_range, bins.center(0), bins.center(bins.count - 1)) : in_range;
    }
    double evaluate(int i, double t) const {
        const double u = (emissionTemperature(t) - bins.center(i)) / (bins.width() * width_in_bins);
        return std::exp(-u * u);
    }
};

// L_e(T) = sum_i c_i phi_i(T), per RGB channel. Coefficients come from
// fitEmissionCoefficients() (emission_fit.h), which keeps them non-negative.
struct EmissionFunction {
    EmissionBasis basis;
    std::vector<Rgb> coefficients;  // one per bin

    Rgb evaluate(double t) const {
        Rgb sum(0.0f);
        for (int i = 0; i < static_cast<int>(coefficients.size()); ++i)
            sum += coefficients[i] * static_cast<float>(basis.evaluate(i, t));
        return sum;
    }
};

// A directional light: direction the light travels (world space, unit length)
// and its RGB irradiance on a surface facing it.
struct DirectionalLight {
    glm::dvec3 direction{0.0, -1.0, 0.0};
    Rgb irradiance{1.0f};
};

// Everything a renderer needs to evaluate the model, resolved against the bins.
struct LookModel {
    TemperatureBins bins;
    ExtinctionParams extinction;
    double albedo = 0.8;               // sigma_s = albedo * sigma_t, isotropic phase
    EmissionFunction emission;         // j = rho * L_e(T)
    std::vector<DirectionalLight> lights;

    double sigmaT(double rho, double t) const { return rho * extinctionPerDensity(t, extinction, bins); }
};

}  // namespace firelook
