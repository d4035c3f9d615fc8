#include "bake/axis_derivation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <nlohmann/json.hpp>
#include <vector>

namespace firelook::bake {
namespace {

std::string formatAxis(const std::vector<double>& axis) {
    std::string out = "{";
    for (size_t i = 0; i < axis.size(); ++i) {
        char value[32];
        std::snprintf(value, sizeof value, "%s%.4g", i ? "," : "", axis[i]);
        out += value;
    }
    return out + "}";
}

}  // namespace

void DensityDepth::merge(const DensityDepth& other) {
    if (other.any_density && (!any_density || other.depth > depth)) *this = other;
}

DensityDepth densityDepth(const render::Medium& medium) {
    DensityDepth out;
    if (medium.empty()) return out;
    std::vector<float> positive;
    const glm::ivec3 n = medium.dims();
    for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
            for (int x = 0; x < n.x; ++x)
                if (const float d = medium.voxel({x, y, z}).density; d > 0.0f) positive.push_back(d);
    if (positive.empty()) return out;
    const size_t rank = (positive.size() - 1) * 99 / 100;
    std::nth_element(positive.begin(), positive.begin() + static_cast<std::ptrdiff_t>(rank), positive.end());
    const double p99 = positive[rank];
    const float dense = static_cast<float>(p99 / 100.0);
    const double count = static_cast<double>(
        std::count_if(positive.begin(), positive.end(), [&](float d) { return d >= dense; }));
    const double edge = medium.minVoxelEdge();
    out.any_density = true;
    out.density_p99 = p99;
    out.dense_side = std::cbrt(count) * edge;
    out.depth = p99 * out.dense_side;
    return out;
}

double roundTwoDigits(double x) {
    if (!(x > 0.0) || !std::isfinite(x)) return x;
    // Scaled by an exact power of ten each way, so 1.0, 0.25 and 1000 come out exact.
    const int digits = 1 - static_cast<int>(std::floor(std::log10(x)));
    const double power = std::pow(10.0, std::abs(digits));
    return digits >= 0 ? std::round(x * power) / power : std::round(x / power) * power;
}

bool AxisDerivation::identity() const {
    return temperature_scale == 1.0 && temperature_offset == 0.0 && extinction_scale == 1.0;
}

basis::ParameterAxes designAxes() { return {{1.0, 1.2, 1.4, 1.6, 1.8, 2.0}, {2.0, 4.0, 8.0, 16.0}, {0.5, 1.0, 2.0, 4.0}}; }

BakeAxes::BakeAxes(std::vector<double> tc, std::vector<double> ks, std::vector<double> kf)
    : temperature_threshold(std::move(tc)), smoke_extinction(std::move(ks)), flame_extinction(std::move(kf)) {}

BakeAxes::BakeAxes(const basis::ParameterAxes& all)
    : BakeAxes(all.temperature_threshold, all.smoke_extinction, all.flame_extinction) {}

AxisDerivation deriveAxes(const BakeAxes& given, const TemperatureBins& bins, const DensityDepth& density) {
    AxisDerivation d;
    d.derived = {!given.temperature_threshold, !given.smoke_extinction, !given.flame_extinction};
    d.t_lo = bins.t_lo;
    d.t_hi = bins.t_hi;
    d.density = density;
    d.temperature_scale = roundTwoDigits((bins.t_hi - bins.t_lo) / (kDesignTHi - kDesignTLo));
    // The offset follows from the scale so that the design's t_lo lands on the data's exactly.
    d.temperature_offset = bins.t_lo - d.temperature_scale * kDesignTLo;
    if (density.any_density && density.depth > 0.0)
        d.extinction_scale = roundTwoDigits(kDesignDensityDepth / density.depth);
    return d;
}

basis::ParameterAxes derivedAxes(const BakeAxes& given, const AxisDerivation& d) {
    basis::ParameterAxes axes = given.design;
    if (given.temperature_threshold)
        axes.temperature_threshold = *given.temperature_threshold;
    else
        for (double& t : axes.temperature_threshold) t = d.temperature_scale * t + d.temperature_offset;
    if (given.smoke_extinction)
        axes.smoke_extinction = *given.smoke_extinction;
    else
        for (double& k : axes.smoke_extinction) k *= d.extinction_scale;
    if (given.flame_extinction)
        axes.flame_extinction = *given.flame_extinction;
    else
        for (double& k : axes.flame_extinction) k *= d.extinction_scale;
    return axes;
}

Look derivedDefaultLook(const AxisDerivation& d) {
    Look look = defaultLook();
    look.temperature_threshold = d.temperature_scale * look.temperature_threshold + d.temperature_offset;
    if (auto* stops = std::get_if<EmissionStops>(&look.emission))
        for (EmissionStop& s : stops->stops) {
            s.temperature = d.temperature_scale * s.temperature + d.temperature_offset;
            // Emission is per unit density (docs/model.md), like extinction: the same factor keeps
            // the glow of the dense core as bright.
            s.emissivity = static_cast<float>(d.extinction_scale) * s.emissivity;
        }
    look.smoke_extinction *= d.extinction_scale;
    look.flame_extinction *= d.extinction_scale;
    return look;
}

std::string axisDerivationToJson(const AxisDerivation& d) {
    nlohmann::ordered_json j;
    j["derived"] = {{"temperature_threshold", d.derived[0]},
                    {"smoke_extinction", d.derived[1]},
                    {"flame_extinction", d.derived[2]}};
    j["design"] = {{"t_lo", kDesignTLo}, {"t_hi", kDesignTHi}, {"density_depth", kDesignDensityDepth}};
    j["temperature"] = {{"t_lo", d.t_lo}, {"t_hi", d.t_hi}, {"scale", d.temperature_scale},
                        {"offset", d.temperature_offset}};
    j["extinction"] = {{"density_depth", d.density.any_density ? nlohmann::ordered_json(d.density.depth) : nullptr},
                       {"density_p99", d.density.density_p99},
                       {"dense_side", d.density.dense_side},
                       {"scale", d.extinction_scale}};
    return j.dump();
}

std::string describeAxisDerivation(const AxisDerivation& d, const basis::ParameterAxes& axes) {
    char text[512];
    std::snprintf(text, sizeof text,
                  "look axes from the data: temperatures x%g %+.4g (bins [%.4g, %.4g] against the design's [%g, %g]), "
                  "extinctions x%g (density p99 %.3g over %.3g units against the design's depth %g)",
                  d.temperature_scale, d.temperature_offset, d.t_lo, d.t_hi, kDesignTLo, kDesignTHi,
                  d.extinction_scale, d.density.density_p99, d.density.dense_side, kDesignDensityDepth);
    std::string line = text;
    const char* names[3] = {"T_c", "k_s", "k_f"};
    const std::vector<double>* values[3] = {&axes.temperature_threshold, &axes.smoke_extinction,
                                            &axes.flame_extinction};
    for (int i = 0; i < 3; ++i)
        line += std::string(i ? ", " : ": ") + names[i] + " " + formatAxis(*values[i]) + (d.derived[i] ? "" : " (given)");
    return line;
}

}  // namespace firelook::bake
