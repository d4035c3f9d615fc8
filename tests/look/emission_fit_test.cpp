// The emission fit: exact where possible, never negative, independent of units.
#include "look/emission_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "look/detail/dense_linear_algebra.h"
#include "look/detail/non_negative_least_squares.h"

namespace firelook {
namespace {

EmissionBasis basisOver(double t_lo, double t_hi, int count, double width = kDefaultRbfWidth) {
    EmissionBasis basis;
    basis.bins = TemperatureBins{t_lo, t_hi, count};
    basis.width_in_bins = width;
    return basis;
}

// Fine sampling: 64 points per bin plus both ends, enough to find the extremes
// of Gaussians about one bin wide.
template <typename Visit>
void sampleFinely(const TemperatureBins& bins, Visit visit) {
    const int samples = 64 * bins.count;
    for (int s = 0; s <= samples; ++s) visit(bins.t_lo + (bins.t_hi - bins.t_lo) * s / samples);
}

float maxComponent(const std::vector<Rgb>& values) {
    float largest = 0.0f;
    for (const Rgb& v : values) largest = std::max({largest, v.r, v.g, v.b});
    return largest;
}

TEST(FitEmissionCoefficients, ReproducesSmoothEmissivityAtBinCentres) {
    for (int count : {1, 8, 16, 64}) {
        const EmissionBasis basis = basisOver(0.0, 3.0, count);
        std::vector<Rgb> emissivity(count);
        for (int i = 0; i < count; ++i) {
            const float u = (i + 0.5f) / count;
            emissivity[i] = Rgb(1.0f + 4.0f * u, 0.5f + u * u, 0.2f + 0.1f * std::sin(6.0f * u));
        }
        const EmissionFunction function{basis, fitEmissionCoefficients(basis, emissivity)};
        for (int i = 0; i < count; ++i) {
            const Rgb value = function.evaluate(basis.bins.center(i));
            // Float coefficients (rel. 6e-8) times a condition number below 2 and a sum
            // of up to 64 float terms: 1e-5 of the largest value is ample.
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(value[c], emissivity[i][c], 1e-5f * maxComponent(emissivity))
                    << count << " bins, bin " << i;
        }
    }
}

TEST(FitEmissionCoefficients, NeverNegativeForRandomNonNegativeInput) {
    std::mt19937 random(12345);
    std::uniform_real_distribution<float> value(0.0f, 10.0f);
    std::bernoulli_distribution zero(0.3);  // many zeros force the non-negative fit to engage
    for (int trial = 0; trial < 40; ++trial) {
        const int count = 1 + trial % 33;
        const EmissionBasis basis = basisOver(-1.0, 2.0, count);
        std::vector<Rgb> emissivity(count);
        for (Rgb& e : emissivity)
            for (int c = 0; c < 3; ++c) e[c] = zero(random) ? 0.0f : value(random);
        const std::vector<Rgb> coefficients = fitEmissionCoefficients(basis, emissivity);
        for (const Rgb& c : coefficients) EXPECT_TRUE(c.r >= 0.0f && c.g >= 0.0f && c.b >= 0.0f);
        const EmissionFunction function{basis, coefficients};
        sampleFinely(basis.bins, [&](double t) {
            const Rgb v = function.evaluate(t);
            EXPECT_TRUE(v.r >= 0.0f && v.g >= 0.0f && v.b >= 0.0f) << "trial " << trial << " T " << t;
        });
    }
}

TEST(FitEmissionCoefficients, SharpStepStaysNonNegativeAndCloseAwayFromTheStep) {
    const EmissionBasis basis = basisOver(0.0, 1.0, 16);
    std::vector<Rgb> emissivity(16, Rgb(0.0f));
    for (int i = 8; i < 16; ++i) emissivity[i] = Rgb(5.0f, 2.0f, 1.0f);
    const EmissionFunction function{basis, fitEmissionCoefficients(basis, emissivity)};
    sampleFinely(basis.bins, [&](double t) {
        const Rgb v = function.evaluate(t);
        EXPECT_TRUE(v.r >= 0.0f && v.g >= 0.0f && v.b >= 0.0f) << t;
    });
    // Three bins from the step the Gaussians (width 0.7 dT, exp(-(3/0.7)^2) ~ 1e-8)
    // no longer feel it: there the fit is exact to float rounding.
    for (int i : {0, 1, 2, 3, 4, 12, 13, 14, 15})
        EXPECT_NEAR(function.evaluate(basis.bins.center(i)).r, emissivity[i].r, 1e-4f) << "bin " << i;
}

TEST(FitEmissionCoefficients, SameCurveInAnyTemperatureUnit) {
    std::vector<Rgb> emissivity(16);
    for (int i = 0; i < 16; ++i) emissivity[i] = Rgb(i < 5 ? 0.0f : i * 0.5f, i * 0.2f, 1.0f);
    const EmissionBasis reference = basisOver(0.0, 1.0, 16);
    const EmissionFunction expected{reference, fitEmissionCoefficients(reference, emissivity)};
    for (double unit : {1e-3, 1e4}) {
        const EmissionBasis basis = basisOver(0.0, unit, 16);
        const EmissionFunction function{basis, fitEmissionCoefficients(basis, emissivity)};
        for (double u = 0.0; u <= 1.0; u += 1.0 / 256)
            for (int c = 0; c < 3; ++c)
                // The matrix entries differ only by rounding of (T - T_i) / dT.
                EXPECT_NEAR(function.evaluate(u * unit)[c], expected.evaluate(u)[c], 1e-5f)
                    << unit << " " << u;
    }
}

TEST(FitEmissionCoefficients, NonFiniteTemperatureGivesFiniteEmission) {
    const EmissionBasis basis = basisOver(0.0, 3.0, 16);
    const EmissionFunction function{basis, fitEmissionCoefficients(basis, std::vector<Rgb>(16, Rgb(1.0f)))};
    for (double t : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()}) {
        const Rgb v = function.evaluate(t);
        EXPECT_TRUE(std::isfinite(v.r) && std::isfinite(v.g) && std::isfinite(v.b)) << t;
    }
}

TEST(FitEmissionCoefficients, RejectsBadInput) {
    const EmissionBasis basis = basisOver(0.0, 1.0, 4);
    EXPECT_THROW(fitEmissionCoefficients(basis, std::vector<Rgb>(3, Rgb(1.0f))), EmissionFitError);
    std::vector<Rgb> with_nan(4, Rgb(1.0f));
    with_nan[2].g = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(fitEmissionCoefficients(basis, with_nan), EmissionFitError);
    EXPECT_THROW(fitEmissionCoefficients(basisOver(1.0, 1.0, 4), std::vector<Rgb>(4, Rgb(1.0f))),
                 EmissionFitError);
}

TEST(AnalyzeEmissionFit, MatchesTheFiguresInTheDesignNote) {
    // docs/model.md quotes, for 16 bins: w = 0.7 condition 1.7, w = 0.9
    // condition 3.6 and 0.15% ripple, ~11% step undershoot; rounded as quoted.
    const EmissionFitReport narrow = analyzeEmissionFit(16, 0.7);
    const EmissionFitReport wide = analyzeEmissionFit(16, 0.9);
    EXPECT_NEAR(narrow.condition_number, 1.7, 0.05);
    EXPECT_NEAR(wide.condition_number, 3.6, 0.05);
    EXPECT_NEAR(wide.constant_ripple_middle, 0.0015, 0.0003);
    EXPECT_NEAR(wide.step_undershoot_exact, 0.11, 0.01);
    // Lattice ripple by Poisson summation, 2 exp(-(pi w)^2) to first order, twice
    // that peak to peak: at w = 0.7 the middle ripple is about 3%.
    EXPECT_NEAR(narrow.constant_ripple_middle, 2.0 * std::exp(-std::pow(M_PI * 0.7, 2)) * 2.0, 0.005);
    // The non-negative fit removes the undershoot entirely.
    EXPECT_EQ(narrow.step_undershoot_fitted, 0.0);
    EXPECT_EQ(wide.step_undershoot_fitted, 0.0);
}

TEST(AnalyzeEmissionFit, NonNegativeFitConvergesForSixtyFourBins) {
    // A step is a local problem: with 64 bins the fit must miss the centres next
    // to it no more than with 16. A stalled active-set iteration would miss more.
    const double sixteen = analyzeEmissionFit(16, kDefaultRbfWidth).step_center_error_fitted;
    const double sixty_four = analyzeEmissionFit(64, kDefaultRbfWidth).step_center_error_fitted;
    EXPECT_NEAR(sixty_four, sixteen, 1e-4);  // measured identical to 1e-5 (float coefficients)
}

TEST(AnalyzeEmissionFit, OneBinIsTrivial) {
    const EmissionFitReport one = analyzeEmissionFit(1, kDefaultRbfWidth);
    EXPECT_DOUBLE_EQ(one.condition_number, 1.0);
    EXPECT_DOUBLE_EQ(one.constant_ripple, 0.0);
}

TEST(DenseLinearAlgebra, EigenvaluesOfAKnownSymmetricMatrix) {
    // [[2, 1], [1, 2]] has eigenvalues 1 and 3.
    detail::DenseMatrix a(2, 2);
    a.values = {2.0, 1.0, 1.0, 2.0};
    std::vector<double> eigenvalues = detail::symmetricEigenvalues(a);
    std::sort(eigenvalues.begin(), eigenvalues.end());
    EXPECT_NEAR(eigenvalues[0], 1.0, 1e-14);  // Jacobi converges to rounding
    EXPECT_NEAR(eigenvalues[1], 3.0, 1e-14);
}

TEST(DenseLinearAlgebra, OverdeterminedLeastSquares) {
    // Fit y = 1 + 2x through three exact points.
    detail::DenseMatrix a(3, 2);
    a.values = {1, 0, 1, 1, 1, 2};
    const std::vector<double> x = detail::solveLeastSquares(a, std::vector<double>{1, 3, 5});
    EXPECT_NEAR(x[0], 1.0, 1e-14);  // exact data: only rounding
    EXPECT_NEAR(x[1], 2.0, 1e-14);
}

TEST(NonNegativeLeastSquares, SatisfiesTheOptimalityConditions) {
    std::mt19937 random(7);
    std::normal_distribution<double> normal;
    for (int trial = 0; trial < 20; ++trial) {
        const int rows = 12;
        const int cols = 8;
        detail::DenseMatrix a(rows, cols);
        for (double& v : a.values) v = normal(random);
        std::vector<double> b(rows);
        for (double& v : b) v = normal(random);
        const std::vector<double> x = detail::nonNegativeLeastSquares(a, b);
        // KKT: gradient g = A^T (A x - b) is 0 where x > 0 and >= 0 where x = 0.
        std::vector<double> residual(b);
        for (int r = 0; r < rows; ++r)
            for (int c = 0; c < cols; ++c) residual[r] -= a(r, c) * x[c];
        for (int c = 0; c < cols; ++c) {
            double g = 0.0;
            for (int r = 0; r < rows; ++r) g -= a(r, c) * residual[r];
            ASSERT_GE(x[c], 0.0);
            // Entries of size ~1 over 12 rows: 1e-9 is far above rounding, far below any real gradient.
            if (x[c] > 0.0)
                EXPECT_NEAR(g, 0.0, 1e-9) << "trial " << trial;
            else
                EXPECT_GE(g, -1e-9) << "trial " << trial;
        }
    }
}

}  // namespace
}  // namespace firelook
