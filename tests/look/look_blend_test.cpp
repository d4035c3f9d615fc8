// The one keyed-look blend (runtime/look/look_blend.h): linear per parameter and per fitted RBF
// coefficient; per bin of emissivity only where both keys' fits are exact interpolants.
#include "look/look_blend.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "look/emission_fit.h"

namespace firelook {
namespace {

// The coefficients a look's emission fits to, at the default RBF width.
std::vector<Rgb> fittedRbf(const Look& look, const TemperatureBins& bins) {
    return fitEmissionCoefficients(EmissionBasis{bins, kDefaultRbfWidth}, resolveBinEmissivity(look, bins));
}

TEST(InterpolateLooks, IsLinearPerParameterAndPerFittedCoefficient) {
    const TemperatureBins bins{0.0, 3.0, 8};
    Look a = defaultLook();
    Look b = defaultLook();
    b.temperature_threshold = 2.0;
    b.smoke_extinction = 2.0;
    b.flame_extinction = 0.5;
    b.emission = EmissionPreset{"blackbody", 10.0};
    b.light_irradiance = {Rgb(0.0f)};
    const std::vector<Rgb> rbf_a = fittedRbf(a, bins), rbf_b = fittedRbf(b, bins);

    // At t = 0 the result renders as a: its emission fits to a's coefficients.
    const Look start = interpolateLooks(a, b, 0.0, bins, kDefaultRbfWidth);
    const std::vector<Rgb> rbf_start = fittedRbf(start, bins);
    for (int i = 0; i < bins.count; ++i)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(rbf_start[i][c], rbf_a[i][c], 1e-4 * (1.0 + std::abs(rbf_a[i][c])));
    EXPECT_EQ(start.temperature_threshold, a.temperature_threshold);

    const Look mid = interpolateLooks(a, b, 0.5, bins, kDefaultRbfWidth);
    EXPECT_DOUBLE_EQ(mid.temperature_threshold, 1.7);
    EXPECT_DOUBLE_EQ(mid.smoke_extinction, 4.0);
    EXPECT_DOUBLE_EQ(mid.flame_extinction, 1.0);
    EXPECT_EQ(mid.albedo, a.albedo);
    // The emission is the blend of the fitted coefficients, evaluated at the bin centres.
    std::vector<Rgb> rbf_mid;
    for (int i = 0; i < bins.count; ++i) rbf_mid.push_back(0.5f * rbf_a[i] + 0.5f * rbf_b[i]);
    const EmissionFunction blend{EmissionBasis{bins, kDefaultRbfWidth}, rbf_mid};
    const std::vector<Rgb> em = resolveBinEmissivity(mid, bins);
    for (int i = 0; i < bins.count; ++i)
        for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(em[i][c], blend.evaluate(bins.center(i))[c]);
    EXPECT_EQ(mid.light_irradiance[0], 0.5f * a.light_irradiance[0]);
    // t is clamped to [0, 1].
    EXPECT_EQ(interpolateLooks(a, b, 7.0, bins, kDefaultRbfWidth).smoke_extinction, 2.0);

    b.albedo = 0.5;
    EXPECT_THROW(interpolateLooks(a, b, 0.5, bins, kDefaultRbfWidth), LookError);
    b.albedo = a.albedo;
    EXPECT_THROW(interpolateLooks(a, b, std::nan(""), bins, kDefaultRbfWidth), LookError);
    EXPECT_THROW(interpolateLooks(a, b, 0.5, bins, 0.0), LookError);
}

// Where both keys' fits are exact interpolants, the blend is linear in each bin's emissivity too.
TEST(InterpolateLooks, IsLinearPerBinForExactFits) {
    const TemperatureBins bins{0.0, 3.0, 16};
    Look a = defaultLook(), b = defaultLook();
    std::vector<Rgb> ea, eb;
    for (int i = 0; i < bins.count; ++i) {
        const float x = static_cast<float>(i) / (bins.count - 1);
        ea.push_back(Rgb(1.0f + x, 0.5f + 0.5f * x * x, 0.3f));
        eb.push_back(Rgb(4.0f - 2.0f * x, 2.0f, 0.2f + x));
    }
    a.emission = EmissionBins{ea};
    b.emission = EmissionBins{eb};
    for (double t : {0.0, 0.25, 0.6, 1.0}) {
        const std::vector<Rgb> em = resolveBinEmissivity(interpolateLooks(a, b, t, bins, kDefaultRbfWidth), bins);
        for (int i = 0; i < bins.count; ++i)
            for (int c = 0; c < 3; ++c) {
                const double want = (1.0 - t) * ea[i][c] + t * eb[i][c];
                EXPECT_NEAR(em[i][c], want, 1e-4 * (1.0 + want)) << "t " << t << " bin " << i;
            }
    }
}

// A key that needs the non-negative fit (a sharp step): the blend stays non-negative everywhere and
// is the blend of the fits, not the per-bin blend of the emissivity.
TEST(InterpolateLooks, BlendsTheNonNegativeFitOfAStep) {
    const TemperatureBins bins{0.0, 3.0, 16};
    Look a = defaultLook(), b = defaultLook();
    std::vector<Rgb> ea(bins.count, Rgb(0.0f)), eb;
    for (int i = bins.count / 2; i < bins.count; ++i) ea[i] = Rgb(10.0f, 5.0f, 1.0f);
    for (int i = 0; i < bins.count; ++i) eb.push_back(Rgb(2.0f + 0.1f * i));
    a.emission = EmissionBins{ea};
    b.emission = EmissionBins{eb};
    const std::vector<Rgb> rbf_a = fittedRbf(a, bins), rbf_b = fittedRbf(b, bins);
    const float t = 0.25f;
    std::vector<Rgb> rbf;
    for (int i = 0; i < bins.count; ++i) rbf.push_back((1.0f - t) * rbf_a[i] + t * rbf_b[i]);
    const EmissionFunction blend{EmissionBasis{bins, kDefaultRbfWidth}, rbf};
    const std::vector<Rgb> em = resolveBinEmissivity(interpolateLooks(a, b, t, bins, kDefaultRbfWidth), bins);
    double per_bin_miss = 0.0;
    for (int i = 0; i < bins.count; ++i)
        for (int c = 0; c < 3; ++c) {
            EXPECT_GE(em[i][c], 0.0f);
            EXPECT_FLOAT_EQ(em[i][c], blend.evaluate(bins.center(i))[c]);
            per_bin_miss = std::max(per_bin_miss, std::abs(em[i][c] - ((1.0 - t) * ea[i][c] + t * eb[i][c])));
        }
    EXPECT_GT(per_bin_miss, 0.1);  // the step's own fit misses it by ~11% of 10 next to the step
}

}  // namespace
}  // namespace firelook
