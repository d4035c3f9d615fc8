#include "bake/axis_collapse.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>

namespace firelook::bake {
namespace {

// The flame share p = (1 + f) / 2 and the smoke share q = 1 - p, each from its own logistic so
// that a share near 0 keeps its digits (1 - p would round it away).
struct Shares {
    double p = 0.0, q = 1.0;
};
Shares sharesAt(double t, double tc, double dT) {
    const double r = (t - tc) / dT;
    return {1.0 / (1.0 + std::exp(-r)), 1.0 / (1.0 + std::exp(r))};
}

double kappa(double ks, double kf, const Shares& s) { return ks * s.q + kf * s.p; }

// A relative change: 0 when nothing changes, unbounded when the extinction itself can be 0.
double relative(double change, double extinction) {
    if (change == 0.0) return 0.0;
    return extinction > 0.0 ? change / extinction : std::numeric_limits<double>::infinity();
}

const char* kAxisNames[3] = {"temperature_threshold", "smoke_extinction", "flame_extinction"};

const std::vector<double>& axisSamples(const basis::ParameterAxes& axes, int axis) {
    return axis == 0 ? axes.temperature_threshold : axis == 1 ? axes.smoke_extinction : axes.flame_extinction;
}
std::vector<double>& axisSamples(basis::ParameterAxes& axes, int axis) {
    return axis == 0 ? axes.temperature_threshold : axis == 1 ? axes.smoke_extinction : axes.flame_extinction;
}

}  // namespace

void DensityTemperatureRange::merge(const DensityTemperatureRange& other) {
    if (!other.any_density) return;
    if (!any_density) {
        *this = other;
        return;
    }
    t_min = std::min(t_min, other.t_min);
    t_max = std::max(t_max, other.t_max);
}

DensityTemperatureRange densityTemperatureRange(const render::Medium& medium) {
    DensityTemperatureRange out;
    const glm::ivec3 n = medium.brickCounts();
    for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
            for (int x = 0; x < n.x; ++x) {
                const render::BrickRange& b = medium.brick({x, y, z});
                if (!(b.max_density > 0.0f)) continue;  // temperature without density changes no image
                out.merge({true, b.min_temperature, b.max_temperature});
            }
    return out;
}

double collapseTolerance(const basis::FrameCodecSettings& storage) {
    return std::min(storage.basis_error, storage.alpha_error) / 5.0;
}

AxisAnalysis analyseAxes(const basis::ParameterAxes& axes, const TemperatureBins& bins,
                         const DensityTemperatureRange& temperatures, double tolerance) {
    basis::validateAxes(axes);
    AxisAnalysis a;
    a.temperatures = temperatures;
    a.bins = bins;
    a.tolerance = tolerance;
    const std::vector<double>& tc = axes.temperature_threshold;
    const std::vector<double>& ks = axes.smoke_extinction;
    const std::vector<double>& kf = axes.flame_extinction;
    if (temperatures.any_density) {
        // kappa clamps T into the bins; clamping is monotone, so the range's ends clamp to the ends.
        const double lo = bins.clamp(temperatures.t_min), hi = bins.clamp(temperatures.t_max), dT = bins.width();
        if (tc.size() > 1) {
            // p(T; T_c) falls with T_c, so the spread over the samples is p(T; first) - p(T; last),
            // which is largest at the samples' midpoint: take the data's temperature nearest it.
            const double first = tc.front(), last = tc.back(), mid = 0.5 * (first + last);
            const double t = std::clamp(mid, lo, hi);
            const double spread = t <= mid ? sharesAt(t, first, dT).p - sharesAt(t, last, dT).p
                                           : sharesAt(t, last, dT).q - sharesAt(t, first, dT).q;
            // Over every sample and temperature p stays within [p(lo; last), p(hi; first)]; kappa is
            // linear in p, so its smallest value is at one of those ends.
            const Shares p_lo = sharesAt(lo, last, dT), p_hi = sharesAt(hi, first, dT);
            for (double s : ks)
                for (double f : kf)
                    a.relative_change[0] = std::max(
                        a.relative_change[0],
                        relative(std::abs(f - s) * spread, std::min(kappa(s, f, p_lo), kappa(s, f, p_hi))));
        }
        // k_s weighs q and k_f weighs p: their spreads are the axis's span times the largest share.
        for (int axis : {1, 2}) {
            const std::vector<double>& samples = axisSamples(axes, axis);
            const std::vector<double>& others = axis == 1 ? kf : ks;
            if (samples.size() < 2) continue;
            for (double c : tc) {
                const Shares at_lo = sharesAt(lo, c, dT), at_hi = sharesAt(hi, c, dT);
                const double share = axis == 1 ? at_lo.q : at_hi.p;
                for (double o : others) {
                    double smallest = std::numeric_limits<double>::infinity();
                    for (double k : {samples.front(), samples.back()})
                        for (const Shares& sh : {at_lo, at_hi})
                            smallest = std::min(smallest, axis == 1 ? kappa(k, o, sh) : kappa(o, k, sh));
                    a.relative_change[axis] = std::max(
                        a.relative_change[axis], relative((samples.back() - samples.front()) * share, smallest));
                }
            }
        }
    }
    double used = 0.0;
    for (int axis : {0, 2, 1}) {
        const std::vector<double>& samples = axisSamples(axes, axis);
        if (samples.size() < 2 || !(used + a.relative_change[axis] <= tolerance)) continue;
        used += a.relative_change[axis];
        // The lowest sample: a look below the axis renders exactly as the full axes would (they
        // clamp to it too), any other look within the bound.
        a.collapsed.push_back({kAxisNames[axis], samples, samples.front(), a.relative_change[axis]});
    }
    return a;
}

void applyAxisCollapse(basis::BakeDescription& d, const AxisAnalysis& analysis) {
    for (const AxisCollapse& c : analysis.collapsed) {
        for (int axis = 0; axis < 3; ++axis)
            if (c.axis == kAxisNames[axis]) axisSamples(d.axes, axis) = {c.kept};
        if (c.axis == kAxisNames[0]) d.alpha_thresholds = {c.kept};
    }
    basis::validateAxes(d.axes);
}

std::string axisAnalysisToJson(const AxisAnalysis& a) {
    nlohmann::ordered_json j;
    j["tolerance"] = a.tolerance;
    if (a.temperatures.any_density)
        j["temperature_with_density"] = {a.temperatures.t_min, a.temperatures.t_max};
    else
        j["temperature_with_density"] = nullptr;
    // null where unbounded (an extinction of 0 on an axis).
    nlohmann::ordered_json changes;
    for (int axis = 0; axis < 3; ++axis)
        changes[kAxisNames[axis]] = std::isfinite(a.relative_change[axis]) ? nlohmann::ordered_json(a.relative_change[axis])
                                                                          : nlohmann::ordered_json(nullptr);
    j["relative_change"] = changes;
    nlohmann::ordered_json collapsed = nlohmann::ordered_json::array();
    for (const AxisCollapse& c : a.collapsed)
        collapsed.push_back({{"axis", c.axis}, {"requested", c.requested}, {"kept", c.kept},
                             {"relative_change", c.relative_change}});
    j["collapsed"] = collapsed;
    return j.dump();
}

std::string describeAxisCollapse(const AxisCollapse& c, const AxisAnalysis& a) {
    char why[256];
    const double dT = a.bins.width();
    if (!a.temperatures.any_density) {
        std::snprintf(why, sizeof why, "no frame has density");
    } else {
        const double lo = a.bins.clamp(a.temperatures.t_min), hi = a.bins.clamp(a.temperatures.t_max);
        std::snprintf(why, sizeof why, "where there is density the temperature stays within [%.3g, %.3g] (bins of %.3g)",
                      lo, hi, dT);
    }
    char line[768];
    std::snprintf(line, sizeof line,
                  "%s axis collapsed to its lowest sample %g (of %zu, %g..%g): %s, so sigma_t changes by at most "
                  "%.2g (relative) across its samples, within the tolerance %.2g; --keep-axes keeps them",
                  c.axis.c_str(), c.kept, c.requested.size(), c.requested.front(), c.requested.back(), why,
                  c.relative_change, a.tolerance);
    return line;
}

}  // namespace firelook::bake
