// The look axes and the default look fitted to a sequence's own units (docs/bake-config.md,
// "Axes derived from the data").
//
// BakeConfig's axes and defaultLook() are designed for the bundled sample: temperatures 0..3 (1000 K
// above ambient), density peaking near 1 in a volume about 2 world units across. Another simulation
// in Kelvin, Celsius or another solver's scale, with density peaking at 0.2 or 50, or a volume 200
// units across, would sample T_c outside its data and extinctions orders of magnitude off. So the
// axes a bake is not given explicitly are mapped from that design to the data:
// - temperatures (T_c samples, the default look's T_c and emission stops) by the affine map that
//   takes the design's temperature range [kDesignTLo, kDesignTHi] onto the bake's bins [t_lo, t_hi];
// - extinctions (k_s, k_f samples, the default look's k_s and k_f) by one factor that gives the data
//   the design's optical depths: kDesignDensityDepth over the sequence's densityDepth().
// Both factors are rounded to two significant digits, so that data close to the design's scale (the
// bundled sample itself) gets exactly 1 and bakes the bytes it baked before the derivation.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "basis/parameter_grid.h"
#include "look/look.h"
#include "look/look_model.h"
#include "render/medium.h"

namespace firelook::bake {

// The bundled sample's (samples/data/explosion) temperature range over its 12 frames, and its
// densityDepth() over them, rounded: the scale the fixed axes and defaultLook() were designed for.
inline constexpr double kDesignTLo = 0.0;
inline constexpr double kDesignTHi = 3.0;
inline constexpr double kDesignDensityDepth = 0.62;  // measured 0.6168: d99 0.885, L 0.697

// The statistic the extinction factor matches, per frame and then the largest over the sequence
// (the axes must cover the densest frame): d99 * L, where d99 is the 99th percentile of the positive
// voxel densities and L the side of a cube with the volume of the voxels at d99 / 100 or more. A
// ray through the dense part of the volume crosses about L of density about d99, so k d99 L is the
// optical depth a look's k gives there. Percentile and threshold make it robust: a few extreme
// voxels move neither, and a thin haze of near-zero density (simulations leave plenty) neither
// lowers d99 much nor widens L, unlike a mean density or a bounding box would.
struct DensityDepth {
    bool any_density = false;
    double depth = 0.0;             // d99 * L, in density x world units
    double density_p99 = 0.0;       // d99 of the frame that gave `depth`
    double dense_side = 0.0;        // L of that frame, world units
    void merge(const DensityDepth& other);  // keeps the larger depth
};
DensityDepth densityDepth(const render::Medium& medium);

// The look axes the design samples (for the bundled sample's units): T_c, k_s, k_f. k_f doubles
// like k_s over its four samples: with three (0.5, 1.5, 4) the parabola between them put up to
// +0.47% on the image mean of sunlit smoke (scripts/bench/accuracy.sh, 2026-12-04), where the
// cubic through four is within 0.3%.
basis::ParameterAxes designAxes();

// The look axes of a bake: those it is given, in code or by bake.json's "axes" keys, and the design
// that stands in for the others. An axis left unset is the design's mapped to the data's units; one
// that is set is baked as it is (one value collapses it). Setting an axis is all it takes to keep
// it: there is no separate "given" flag to forget.
struct BakeAxes {
    std::optional<std::vector<double>> temperature_threshold, smoke_extinction, flame_extinction;
    // What the unset axes are derived from; tests shrink it to bake fewer points.
    basis::ParameterAxes design = designAxes();
    BakeAxes() = default;
    // All three given, as config.axes = {{1.0, 2.0}, {4.0}, {1.5}}.
    BakeAxes(std::vector<double> tc, std::vector<double> ks, std::vector<double> kf);
    BakeAxes(const basis::ParameterAxes& all);  // NOLINT(google-explicit-constructor): all three given
    bool allGiven() const { return temperature_threshold && smoke_extinction && flame_extinction; }
};

// x rounded to two significant digits (x > 0): 0.25, 1.0, 1000.0, 1.3e-3.
double roundTwoDigits(double x);

struct AxisDerivation {
    // Which of T_c, k_s, k_f (ParameterAxes order) were mapped from the design; the others were given.
    std::array<bool, 3> derived{};
    // T = temperature_scale * T_design + temperature_offset; k = extinction_scale * k_design.
    double temperature_scale = 1.0, temperature_offset = 0.0;
    double extinction_scale = 1.0;
    // What they were derived from: the bins' range and the sequence's density statistic (any_density
    // false: none measured, the factor stays 1).
    double t_lo = kDesignTLo, t_hi = kDesignTHi;
    DensityDepth density;
    // True when the map changes nothing (the bundled sample): the package records no derivation.
    bool identity() const;
};

// The derivation for a bake whose bins span `bins` and whose sequence measured `density`; the
// factors always (the default look uses them), derived[i] for the axes `given` leaves unset.
AxisDerivation deriveAxes(const BakeAxes& given, const TemperatureBins& bins, const DensityDepth& density);

// The axes a bake samples: the given ones as they are, the others given.design's mapped by
// `derivation`'s factors (AxisDerivation{} is the identity: the design's as they are).
basis::ParameterAxes derivedAxes(const BakeAxes& given, const AxisDerivation& derivation);

// defaultLook() in the data's units: T_c and the emission stops' temperatures by the affine map,
// k_s, k_f and the emissivities (emission is per unit density too) by the extinction factor (always, whether or not the axes were given: the look is
// the data's, the axes clamp it afterwards).
Look derivedDefaultLook(const AxisDerivation& derivation);

// The derivation as JSON (the package's META key "axis_derivation", the bake report).
std::string axisDerivationToJson(const AxisDerivation& derivation);

// One line for the terminal: the derived axes and what they were derived from.
std::string describeAxisDerivation(const AxisDerivation& derivation, const basis::ParameterAxes& axes);

}  // namespace firelook::bake
