// sourceBalance (runtime/basis/source_balance.h): which factor raises each light source's columns
// before the SVD and the storage grids measure error.
#include "basis/source_balance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace firelook::basis {
namespace {

TEST(SourceBalance, SourcesWithinTheRatioAreLeftAlone) {
    // 3 emission bins (one source: energy 3) and 2 lights (energies 0.5 and 0.04, norms 0.41 and
    // 0.12 of the emission's 1.73: within kMaxSourceRatio = 10).
    const std::vector<double> factor = sourceBalance(std::vector<double>{1.0, 1.0, 1.0, 0.5, 0.04}, 3);
    for (double f : factor) EXPECT_EQ(f, 1.0);
}

TEST(SourceBalance, AFaintSourceIsRaisedToTheRatioOfTheLargest) {
    // The light's energy is 1e-10 of the emission's: its norm 1e-5. Raised to 1/10 of the largest
    // norm: factor 1e5 / 10. The emission bins share one factor, 1.
    const std::vector<double> factor = sourceBalance(std::vector<double>{2.0, 0.0, 2.0, 4e-10}, 3);
    EXPECT_EQ(factor[0], 1.0);
    EXPECT_EQ(factor[1], 1.0) << "an empty bin belongs to the emission source, not a source of its own";
    EXPECT_EQ(factor[2], 1.0);
    EXPECT_NEAR(factor[3], 1e4, 1e-6 * 1e4);
}

TEST(SourceBalance, FaintEmissionIsRaisedLikeAFaintLight) {
    const std::vector<double> factor = sourceBalance(std::vector<double>{1e-8, 1e-8, 2.0}, 2);
    EXPECT_NEAR(factor[0], std::sqrt(2.0 / 2e-8) / kMaxSourceRatio, 1e-9 * factor[0]);
    EXPECT_EQ(factor[0], factor[1]) << "every bin of the emission takes the same factor";
    EXPECT_EQ(factor[2], 1.0);
}

TEST(SourceBalance, EmptyAndNonFiniteSourcesKeepOne) {
    const double inf = std::numeric_limits<double>::infinity();
    for (double f : sourceBalance(std::vector<double>{1.0, 0.0}, 1)) EXPECT_EQ(f, 1.0);
    for (double f : sourceBalance(std::vector<double>{0.0, 0.0, 0.0}, 2)) EXPECT_EQ(f, 1.0);
    for (double f : sourceBalance(std::vector<double>{inf, 1.0}, 1)) EXPECT_EQ(f, 1.0);
    EXPECT_TRUE(sourceBalance(std::vector<double>{}, 0).empty());
    // No emission bins (bins = 0): every kind is a light of its own.
    const std::vector<double> lights = sourceBalance(std::vector<double>{1.0, 1e-6}, 0);
    EXPECT_EQ(lights[0], 1.0);
    EXPECT_NEAR(lights[1], 1e3 / kMaxSourceRatio, 1e-9);
}

TEST(SourceBalance, OfAStoredSvtSumsEachColumnKindOverPointsAndRanks) {
    // 2 grid points x (1 emission bin + 1 light), rank 2: column j = point * 2 + c.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<float> svt = {3.0f, 4.0f,     // point 0, emission: energy 25
                                    1e-4f, 0.0f,    // point 0, light
                                    0.0f, nan,      // point 1, emission: NaN counts 0
                                    0.0f, 2e-4f};  // point 1, light: light energy 5e-8 in all
    const std::vector<double> factor = svtSourceBalance(svt, 2, 2, 1);
    ASSERT_EQ(factor.size(), 2u);
    EXPECT_EQ(factor[0], 1.0);
    EXPECT_NEAR(factor[1], std::sqrt(25.0 / 5e-8) / kMaxSourceRatio, 1e-4 * factor[1]);
    EXPECT_EQ(factor, sourceBalance(std::vector<double>{25.0, double(1e-4f) * 1e-4f + double(2e-4f) * 2e-4f}, 1));
}

}  // namespace
}  // namespace firelook::basis
