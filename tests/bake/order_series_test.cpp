// The scattering orders as a series per column (baker/bake/order_series.h).
#include "bake/order_series.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace firelook::bake {
namespace {

// One cell of unit mass, one grid point, two columns whose orders are exact geometric series:
// column 0 bright and quickly converging (P_k = 100 * 0.1^k), column 1 a hundred times dimmer and
// slow (P_k = 1 * 0.8^k, as a sun's column in thick smoke beside a bright fire).
struct TwoColumns {
    ScatterCells cells;
    TwoColumns() {
        cells.slots = 1;
        cells.mass = {1.0f};
    }
    static std::vector<float> order(int k) {
        return {static_cast<float>(100.0 * std::pow(0.1, k)), static_cast<float>(std::pow(0.8, k))};
    }
};

TEST(OrderSeries, EveryColumnConvergesOnItsOwn) {
    TwoColumns t;
    OrderSeries series(t.cells, 1, 2, 2, 0.9);
    const double tolerance = 0.002;
    int k = 1;
    series.add(t.order(k));
    // The old rule (stop when the last order adds less than 0.2% of the sum over all columns) stopped
    // at order 16 here, with column 1 still lacking 2.9% of its light and nothing added for it.
    while (!series.converged(tolerance)) series.add(t.order(++k));
    // Column 1's tail 0.8^k * 4 within 0.2% of its total 0.8 (1 - 0.8^k) / 0.2: 0.8^k <= 0.002 * 4 / 4.
    EXPECT_EQ(k, static_cast<int>(std::ceil(std::log(0.002 / (1.0 + 0.002)) / std::log(0.8))));
    // The tail of an exact geometric series is exact: r / (1 - r).
    const std::vector<float> tail = series.tailFactors();
    EXPECT_NEAR(tail[0], 0.1 / 0.9, 1e-5);
    EXPECT_NEAR(tail[1], 0.8 / 0.2, 1e-4);
    EXPECT_LE(series.tailFraction(), tolerance);
}

// A ratio above the albedo can only be noise (an order's source is albedo times what the previous
// order had left), so the tail is bounded by albedo / (1 - albedo) times the last order.
TEST(OrderSeries, RatioIsBoundedByTheAlbedo) {
    TwoColumns t;
    OrderSeries series(t.cells, 1, 2, 2, 0.5);
    series.add({1.0f, 1.0f});
    series.add({2.0f, 0.25f});
    const std::vector<float> tail = series.tailFactors();
    EXPECT_FLOAT_EQ(tail[0], 1.0f);   // r clamped to 0.5
    EXPECT_FLOAT_EQ(tail[1], 1.0f / 3.0f);
}

// Columns past `counted` (six-way lights) get a tail but never keep the series going.
TEST(OrderSeries, UncountedColumnsDoNotDecideTheStop) {
    TwoColumns t;
    OrderSeries series(t.cells, 1, 2, 1, 0.9);
    series.add(t.order(1));
    series.add(t.order(2));
    series.add(t.order(3));
    EXPECT_TRUE(series.converged(0.002));
    EXPECT_GT(series.tailFactors()[1], 3.9f);
}

// Photons for the next order: the largest counted column's last order over its first (1 before any
// order), the columns summed over their grid points.
TEST(OrderSeries, NextOrderShareIsTheLastOrderOverTheFirst) {
    TwoColumns t;
    OrderSeries series(t.cells, 1, 2, 2, 0.9);
    EXPECT_DOUBLE_EQ(series.nextOrderShare(), 1.0);
    series.add(t.order(1));
    EXPECT_DOUBLE_EQ(series.nextOrderShare(), 1.0);
    series.add(t.order(2));
    EXPECT_NEAR(series.nextOrderShare(), 0.8, 1e-6);  // column 1's; column 0's is 0.1
    series.add(t.order(3));
    EXPECT_NEAR(series.nextOrderShare(), 0.64, 1e-6);
    // Counting column 0 only: its 0.01.
    OrderSeries bright(t.cells, 1, 2, 1, 0.9);
    for (int k = 1; k <= 3; ++k) bright.add(t.order(k));
    EXPECT_NEAR(bright.nextOrderShare(), 0.01, 1e-6);
}

}  // namespace
}  // namespace firelook::bake
