// solveGramNnls (runtime/fit/gram_nnls.h) against closed forms.
#include "fit/gram_nnls.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace firelook::fit {
namespace {

// G = A^T A and b = A^T t for a random tall A.
struct Problem {
    int n;
    std::vector<double> a, gram, b;
};

Problem makeProblem(int rows, int n, const std::vector<double>& t, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Problem p{n, std::vector<double>(rows * n), std::vector<double>(n * n, 0.0), std::vector<double>(n, 0.0)};
    for (double& v : p.a) v = u(rng);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int r = 0; r < rows; ++r) p.gram[i * n + j] += p.a[r * n + i] * p.a[r * n + j];
    for (int i = 0; i < n; ++i)
        for (int r = 0; r < rows; ++r) p.b[i] += p.a[r * n + i] * t[r];
    return p;
}

TEST(GramNnls, RecoversAnExactNonNegativeSolution) {
    const int rows = 40, n = 6;
    const std::vector<double> x_true = {0.5, 0.0, 2.0, 1.0, 0.0, 3.0};
    std::mt19937 rng(3);
    std::vector<double> t(rows, 0.0);
    Problem p = makeProblem(rows, n, t, 7);
    for (int r = 0; r < rows; ++r)
        for (int i = 0; i < n; ++i) t[r] += p.a[r * n + i] * x_true[i];
    p = makeProblem(rows, n, t, 7);
    const std::vector<double> x = solveGramNnls(p.gram, p.b, n);
    // A well-conditioned 40 x 6 system: the solution to ~1e-6 of its size (the ridge is 1e-12 of G).
    for (int i = 0; i < n; ++i) EXPECT_NEAR(x[i], x_true[i], 1e-6) << i;
}

TEST(GramNnls, MeetsTheOptimalityConditionsWhenTheUnconstrainedSolutionIsNegative) {
    const int rows = 30, n = 5;
    std::mt19937 rng(11);
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<double> t(rows);
    for (double& v : t) v = g(rng);  // zero-mean noise: the unconstrained fit has negative entries
    const Problem p = makeProblem(rows, n, t, 5);
    const std::vector<double> x = solveGramNnls(p.gram, p.b, n);
    // KKT: x >= 0; gradient w = b - G x is <= 0 where x = 0 and = 0 where x > 0 (to rounding).
    for (int i = 0; i < n; ++i) {
        double w = p.b[i];
        for (int j = 0; j < n; ++j) w -= p.gram[i * n + j] * x[j];
        EXPECT_GE(x[i], 0.0);
        if (x[i] > 0.0) EXPECT_NEAR(w, 0.0, 1e-8) << i;
        else EXPECT_LE(w, 1e-8) << i;
    }
}

TEST(GramNnls, ZeroColumnsAndAZeroMatrixGiveZero) {
    // Column 1 carries nothing (a bin no pixel sees): its x is 0 and the rest is solved.
    const std::vector<double> gram = {4, 0, 0, 0, 0, 0, 0, 0, 1};
    const std::vector<double> b = {8, 0, 3};
    const std::vector<double> x = solveGramNnls(gram, b, 3);
    EXPECT_NEAR(x[0], 2.0, 1e-9);
    EXPECT_EQ(x[1], 0.0);
    EXPECT_NEAR(x[2], 3.0, 1e-9);
    const std::vector<double> zero(9, 0.0);
    for (double v : solveGramNnls(zero, b, 3)) EXPECT_EQ(v, 0.0);
}

}  // namespace
}  // namespace firelook::fit
