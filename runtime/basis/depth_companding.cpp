#include "basis/depth_companding.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "basis/resident_frame.h"

namespace firelook::basis {

double depthLevels(const DepthCompanding& g, double step) { return std::ceil(g.limit() / step); }

// g'(x) = max over k in [k_lo, k_hi] of k e^(-k x): k_hi e^(-k_hi x) below 1/k_hi, 1/(e x) up to
// 1/k_lo (the maximum is at k = 1/x), k_lo e^(-k_lo x) beyond. Its integral, piece by piece:
//   x <= 1/k_hi:         1 - e^(-k_hi x)
//   1/k_hi < x <= 1/k_lo: (1 - 1/e) + ln(k_hi x) / e
//   x > 1/k_lo:          (1 - 1/e) + ln(k_hi / k_lo) / e + 1/e - e^(-k_lo x)
// Why this bounds alpha: write tau = k_f O_b + (k_s - k_f) S with S = O_b - F the smoke part.
// If k_s >= k_f, tau >= k_f O_b and tau >= k_s S, so |d alpha / d O_b| <= k_f e^(-k_f O_b) <=
// g'(O_b) and |d alpha / d S| <= k_s e^(-k_s S) <= g'(S). If k_s < k_f, tau >= k_s O_b >= k_s S
// and both derivatives are at most k_f e^(-k_s x) <= (k_f / k_s) g'(x). So a change dg of
// g(O_b) and of g(S) moves a ray's alpha by at most c (|dg(O_b)| + |dg(S)|) with
// c = max(1, max k_f / min k_s), and a pixel's alpha (a mean of rays, linear in T_c between the
// threshold samples) by no more.
DepthCompanding DepthCompanding::forAxes(const ParameterAxes& axes) {
    DepthCompanding c;
    const auto [ks_lo, ks_hi] = std::minmax_element(axes.smoke_extinction.begin(), axes.smoke_extinction.end());
    const auto [kf_lo, kf_hi] = std::minmax_element(axes.flame_extinction.begin(), axes.flame_extinction.end());
    c.k_hi = std::max({*ks_hi, *kf_hi, 1e-6});
    // A zero extinction makes alpha independent of the depth it multiplies; the floor keeps the
    // companding finite, and for k below it the bound grows by at most k_lo |dO| (negligible).
    c.k_lo = std::max(std::min(*ks_lo, *kf_lo), c.k_hi * 1e-4);
    c.k_s_lo = std::max(*ks_lo, c.k_lo);
    c.k_f_hi = *kf_hi;
    return c;
}

double DepthCompanding::limit() const { return 1.0 + std::log(k_hi / k_lo) / M_E; }

double DepthCompanding::alphaFactor() const { return std::max(1.0, k_f_hi / k_s_lo); }

double DepthCompanding::forward(double x) const {
    if (!(x > 0.0)) return 0.0;
    if (x <= 1.0 / k_hi) return -std::expm1(-k_hi * x);
    const double first = 1.0 - 1.0 / M_E;
    if (x <= 1.0 / k_lo) return first + std::log(k_hi * x) / M_E;
    return first + std::log(k_hi / k_lo) / M_E + 1.0 / M_E - std::exp(-k_lo * x);
}

double DepthCompanding::inverse(double y) const {
    if (!(y > 0.0)) return 0.0;
    const double first = 1.0 - 1.0 / M_E;
    if (y <= first) return -std::log1p(-y) / k_hi;
    const double second = first + std::log(k_hi / k_lo) / M_E;
    if (y <= second) return std::exp((y - first) * M_E) / k_hi;
    const double rest = 1.0 / M_E - (y - second);
    return rest > 0.0 ? -std::log(rest) / k_lo : std::numeric_limits<double>::infinity();
}

std::shared_ptr<const DepthTable> DepthTable::build(double step, double k_lo, double k_hi) {
    auto table = std::make_shared<DepthTable>();
    table->step = step;
    table->k_lo = k_lo;
    table->k_hi = k_hi;
    DepthCompanding g;
    g.k_lo = k_lo;
    g.k_hi = k_hi;
    const int levels = static_cast<int>(depthLevels(g, step)) + 1;
    table->depth.resize(levels);
    for (int q = 0; q < levels; ++q)
        table->depth[q] = static_cast<float>(std::min(double(kLargestDepth), g.inverse(q * step)));
    return table;
}

}  // namespace firelook::basis
