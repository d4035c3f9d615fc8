// The look model flattened into tables for the basis tracer's inner loops: the smoke/flame split
// of the extinction per sampled T_c, the transmittance of every grid point and the emission RBFs
// (docs/model.md). Shared by the photon passes and the camera pass.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <vector>

#include "bake/basis_tracer.h"

namespace firelook::bake {

// phi(u) = exp(-(u/w)^2) < 1e-7 beyond |u| > 4 w: bins further away are skipped.
inline constexpr double kRbfSupport = 4.0;
// Arrays on the stack hold one value per sampled T_c (or per axis sample): the model is checked
// against this bound before tracing.
inline constexpr int kMaxAxisSamples = 64;
// And at most this many T_c times k_s (or k_f) samples, as the transmittance's factors are held on
// the stack: the design's axes have 6 x 4, and a bake holds every grid point in every cell.
inline constexpr std::size_t kMaxAxisFactors = 512;
// Below this transmittance at the thinnest grid point a path adds nothing visible: marches stop.
inline constexpr float kNegligibleTransmittance = 1e-5f;
// The same as an optical depth, -ln(kNegligibleTransmittance): what marches that carry only depths
// compare against, without an exponential.
inline constexpr float kNegligibleDepth = 11.512925f;
// The isotropic phase function.
inline constexpr float kInv4Pi = static_cast<float>(0.25 / std::numbers::pi);

// exp(x) for x <= 0 in plain float arithmetic, so that a loop of them vectorises (a call to expf
// cannot): range reduction to 2^n e^r with |r| <= ln2 / 2 and Cephes' degree-6 polynomial for e^r,
// within 2 ulp of std::exp (tests/bake/trace_tables_test.cpp). Below -87, 0: exp(-87) = 1.6e-38,
// far below kNegligibleTransmittance. The transmittances were a fifth of a frame's bake through
// glibc's expf. Only +, -, * and conversions: the same bits on every x86-64 and under any
// vectorisation.
inline float expNonPositive(float x) {
    x = x > -87.0f ? (x < 0.0f ? x : 0.0f) : -87.0f;
    constexpr float kRound = 12582912.0f;  // 1.5 * 2^23: adding it rounds to an integer
    const float n = (x * 1.44269504088896341f + kRound) - kRound;
    const float r = (x - n * 0.693359375f) + n * 2.12194440e-4f;
    float p = 1.9875691500e-4f;
    p = p * r + 1.3981999507e-3f;
    p = p * r + 8.3334519073e-3f;
    p = p * r + 4.1665795894e-2f;
    p = p * r + 1.6666665459e-1f;
    p = p * r + 5.0000001201e-1f;
    const float e_r = p * r * r + r + 1.0f;
    const std::int32_t bits = (static_cast<std::int32_t>(n) + 127) << 23;  // 2^n, n in [-126, 0]
    return e_r * std::bit_cast<float>(bits);
}

// exp(2 (t - c_i) k) for fixed centres c_i and any t in [lo, hi], from one exponential:
// exp(2 (t - c_0) k) exp(-2 (c_i - c_0) k). The split and alpha's sigmoids need a tanh per sampled
// T_c and per alpha threshold at every march step (27 on the bundled sample), and glibc's tanhf
// (through expm1f) was 12% of a frame's bake. Double precision keeps each within rounding of
// std::tanh's; where an exponent could leave +-300 (centres far outside [lo, hi]) every value gets
// its own exponential, clamped there (tanh is then +-1 to double precision).
class TanhLadder {
  public:
    TanhLadder() = default;
    TanhLadder(const std::vector<float>& centres, float k, float lo, float hi) : k2_(2.0 * k) {
        for (float c : centres) {
            centres_.push_back(c);
            ratio_.push_back(std::exp(-k2_ * (double(c) - double(centres.front()))));
            ladder_ = ladder_ && std::fabs(k2_ * (double(lo) - c)) <= kBound &&
                      std::fabs(k2_ * (double(hi) - c)) <= kBound;
        }
    }
    void exponentials(float t, double* e) const {
        const int n = static_cast<int>(centres_.size());
        if (ladder_ && n > 0) {
            const double e0 = std::exp(k2_ * (double(t) - centres_[0]));
            for (int i = 0; i < n; ++i) e[i] = e0 * ratio_[i];
        } else {
            for (int i = 0; i < n; ++i)
                e[i] = std::exp(std::clamp(k2_ * (double(t) - centres_[i]), -kBound, kBound));
        }
    }

  private:
    static constexpr double kBound = 300.0;
    double k2_ = 0.0;
    std::vector<double> centres_, ratio_;
    bool ladder_ = true;
};

struct TraceTables {
    int n_tc = 0, n_ks = 0, n_kf = 0, points = 0, bins = 0, lights = 0, columns = 0, n_alpha = 0;
    std::vector<float> tc, ks, kf, alpha_tc, bin_centre;
    float t_lo = 0, t_hi = 0, emission_t_lo = 0, emission_t_hi = 0, inv_2dt = 0, inv_rbf_width = 0,
          rbf_reach = 0, albedo = 0;
    TanhLadder tc_ladder, alpha_ladder;

    explicit TraceTables(const BasisModel& m) {
        n_tc = static_cast<int>(m.axes.temperature_threshold.size());
        n_ks = static_cast<int>(m.axes.smoke_extinction.size());
        n_kf = static_cast<int>(m.axes.flame_extinction.size());
        points = n_tc * n_ks * n_kf;
        bins = m.bins.count;
        lights = static_cast<int>(m.light_directions.size());
        columns = bins + lights;
        n_alpha = static_cast<int>(m.alpha_thresholds.size());
        for (double v : m.axes.temperature_threshold) tc.push_back(static_cast<float>(v));
        for (double v : m.axes.smoke_extinction) ks.push_back(static_cast<float>(v));
        for (double v : m.axes.flame_extinction) kf.push_back(static_cast<float>(v));
        for (double v : m.alpha_thresholds) alpha_tc.push_back(static_cast<float>(v));
        for (int i = 0; i < bins; ++i) bin_centre.push_back(static_cast<float>(m.bins.center(i)));
        t_lo = static_cast<float>(m.bins.t_lo);
        t_hi = static_cast<float>(m.bins.t_hi);
        // Emission holds its outer bins' values beyond their centres (docs/model.md); the
        // version-1 rule clamped to the range ends instead.
        const bool centres = m.emission_clamp_to_centres;
        emission_t_lo = centres ? bin_centre.front() : t_lo;
        emission_t_hi = centres ? bin_centre.back() : t_hi;
        inv_2dt = static_cast<float>(1.0 / (2.0 * m.bins.width()));
        inv_rbf_width = static_cast<float>(1.0 / (m.rbf_width * m.bins.width()));
        rbf_reach = static_cast<float>(kRbfSupport * m.rbf_width * m.bins.width());
        albedo = static_cast<float>(m.albedo);
        tc_ladder = TanhLadder(tc, inv_2dt, t_lo, t_hi);
        alpha_ladder = TanhLadder(alpha_tc, inv_2dt, t_lo, t_hi);
        ks_doubles_ = doublingSamples(ks);
        kf_doubles_ = doublingSamples(kf);
    }

    float clampT(float t) const { return t >= t_lo ? (t <= t_hi ? t : t_hi) : t_lo; }
    float clampEmissionT(float t) const {
        return t >= emission_t_lo ? (t <= emission_t_hi ? t : emission_t_hi) : emission_t_lo;
    }

    // rho (1 -+ f(T - T_c)) / 2 for every sampled T_c, f = tanh((T - T_c) / (2 dT)): extinction is
    // k_s*smoke + k_f*flame. With E = exp(2 (T - T_c) / (2 dT)), (1 - f) / 2 = 1 / (1 + E) and
    // (1 + f) / 2 = E / (1 + E).
    void split(float rho, float t, float* smoke, float* flame) const {
        double e[kMaxAxisSamples];
        tc_ladder.exponentials(clampT(t), e);
        for (int i = 0; i < n_tc; ++i) {
            const double inv = 1.0 / (1.0 + e[i]);
            smoke[i] = static_cast<float>(rho * inv);
            flame[i] = static_cast<float>(rho * e[i] * inv);
        }
    }

    // tanh((T - alpha_tc[a]) / (2 dT)) for every alpha threshold: the flame share of the optical
    // depths alpha is stored for (docs/model.md, "alpha").
    void alphaSigmoids(float t, double* f) const {
        alpha_ladder.exponentials(clampT(t), f);
        for (int a = 0; a < n_alpha; ++a) f[a] = 1.0 - 2.0 / (1.0 + f[a]);
    }

    // tau_g = exp(-k_s D_s(T_c) - k_f D_f(T_c)) for every grid point g, factorised so that at most
    // n_tc * (n_ks + n_kf) exponentials are evaluated, and fewer where an axis doubles: the derived
    // extinction axes are a design's doubling samples times one scale (axis_derivation.h), and
    // exp(-2 k D) is exp(-k D) squared, so those axes need one exponential per T_c and squares. The
    // squares' error grows with the chain (16 ulp at the fourth sample, about 1e-6), far below the
    // march's. Each factor is held at or above kFactorFloor, so that their product, the
    // transmittance, stays a normal float (x86 may take microcode assists on denormals; a guard:
    // flushing them to zero made no measurable difference on the bundled sample). This was the
    // bake's largest single function (a fifth of a frame's samples; a tenth with these squares and
    // the photon tracks taking it once a cell).
    void transmittance(const float* d_smoke, const float* d_flame, float* tau) const {
        float es[kMaxAxisFactors], ef[kMaxAxisFactors];
        axisFactors(ks.data(), ks_doubles_.data(), n_ks, d_smoke, es);
        axisFactors(kf.data(), kf_doubles_.data(), n_kf, d_flame, ef);
        int g = 0;
        for (int a = 0; a < n_tc; ++a) {
            float flame_row[kMaxAxisSamples];
            for (int f = 0; f < n_kf; ++f) flame_row[f] = ef[f * n_tc + a];
            for (int s = 0; s < n_ks; ++s, g += n_kf) {
                const float smoke_factor = es[s * n_tc + a];
                float* __restrict to = tau + g;
#pragma omp simd
                for (int f = 0; f < n_kf; ++f) to[f] = smoke_factor * flame_row[f];
            }
        }
    }

    void advanceDepths(const float* smoke, const float* flame, float dt, float* depth_smoke,
                       float* depth_flame) const {
        for (int a = 0; a < n_tc; ++a) {
            depth_smoke[a] += smoke[a] * dt;
            depth_flame[a] += flame[a] * dt;
        }
    }

    // The smallest optical depth over the grid (smallest k_s and k_f, every T_c): the depth of the
    // largest transmittance, to compare with kNegligibleDepth.
    float minDepthOfLeastExtinction(const float* d_smoke, const float* d_flame) const {
        float least = ks[0] * d_smoke[0] + kf[0] * d_flame[0];
        for (int a = 1; a < n_tc; ++a) least = std::min(least, ks[0] * d_smoke[a] + kf[0] * d_flame[a]);
        return least;
    }
    // The largest transmittance over the grid, from the grid transmittance() wrote.
    float maxTransmittance(const float* tau) const {
        float best = 0.0f;
        for (int a = 0; a < n_tc; ++a) best = std::max(best, tau[a * n_ks * n_kf]);
        return best;
    }

    // sigma_t per grid point (per unit length, density included).
    void extinction(const float* smoke, const float* flame, float* sigma_t) const {
        int g = 0;
        for (int a = 0; a < n_tc; ++a)
            for (int s = 0; s < n_ks; ++s)
                for (int f = 0; f < n_kf; ++f) sigma_t[g++] = ks[s] * smoke[a] + kf[f] * flame[a];
    }

    // Bins whose RBF is non-negligible at temperature t: [first, last).
    void binWindow(float t, int& first, int& last) const {
        const float tcl = clampEmissionT(t);
        first = bins;
        last = 0;
        for (int i = 0; i < bins; ++i) {
            if (std::fabs(tcl - bin_centre[i]) <= rbf_reach) {
                first = std::min(first, i);
                last = i + 1;
            }
        }
        if (last <= first) first = last = 0;
    }

    float rbf(int i, float t) const {
        const float u = (clampEmissionT(t) - bin_centre[i]) * inv_rbf_width;
        return std::exp(-u * u);
    }

  private:
    // 2^-63: the product of two factors is at least 2^-126, the smallest normal float. exp(-43.7);
    // a grid point whose transmittance is that small has long stopped adding anything visible.
    static constexpr float kFactorFloor = 0x1p-63f;
    // Per sample: 1 where it is exactly twice the sample before (an exact float comparison: only
    // then is the square its exponential).
    static std::vector<unsigned char> doublingSamples(const std::vector<float>& k) {
        std::vector<unsigned char> doubles(k.size(), 0);
        for (std::size_t s = 1; s < k.size(); ++s) doubles[s] = k[s] == 2.0f * k[s - 1];
        return doubles;
    }
    // e[s * n_tc + a] = max(exp(-k[s] depth[a]), kFactorFloor) for every T_c a and sample s:
    // each loop runs over the T_c's, the longest run of independent values.
    void axisFactors(const float* k, const unsigned char* doubles, int samples, const float* depth,
                     float* e) const {
        for (int s = 0; s < samples; ++s) {
            float* __restrict to = e + s * n_tc;
            if (doubles[s]) {
                const float* __restrict half = to - n_tc;
#pragma omp simd
                for (int a = 0; a < n_tc; ++a) to[a] = std::max(half[a] * half[a], kFactorFloor);
            } else {
                const float k_s = k[s];
#pragma omp simd
                for (int a = 0; a < n_tc; ++a)
                    to[a] = std::max(expNonPositive(-k_s * depth[a]), kFactorFloor);
            }
        }
    }
    std::vector<unsigned char> ks_doubles_, kf_doubles_;
};

// One march step integrated exactly for piecewise-constant sigma_t: the transmittance drops from
// tau_start to tau_end = tau_start exp(-sigma_t dt), and integral(tau ds) over the step is
// (tau_start - tau_end) / sigma_t. So a source proportional to sigma_t (scattering) adds
// albedo * (tau_start - tau_end) and one that is not (emission) adds j (tau_start - tau_end) / sigma_t:
// an optically thick step gives j / sigma_t, the thick-emitter limit, at any step length.
inline float stepPathLength(float tau_start, float tau_end, float sigma_t, float dt) {
    const float x = sigma_t * dt;
    if (x < 1e-3f) return tau_start * dt * (1.0f - 0.5f * x + x * x * (1.0f / 6.0f));  // series: no cancellation
    return (tau_start - tau_end) / sigma_t;
}

// sigma_t * stepPathLength(...): the light the step takes out of the path, without the division
// (the scattered share of a photon's step, every grid point at every step).
inline float stepRemoved(float tau_start, float tau_end, float sigma_t, float dt) {
    const float x = sigma_t * dt;
    if (x < 1e-3f) return tau_start * x * (1.0f - 0.5f * x + x * x * (1.0f / 6.0f));
    return tau_start - tau_end;
}

}  // namespace firelook::bake
