// The scattering orders of the basis tracer as a series per column (issue 27): when to stop adding
// orders, and the geometric tail that stands in for the orders not traced.
//
// Each order's Lbar field carries, per grid point g and column c, the scattered power
//   P_k(g, c) = sum over cells of M(cell, g) Lbar_k(cell, g, c)   (= integral of sigma_s Lbar_k dV),
// which is what the next order's source and the camera's in-scattered light are made of. Successive
// orders of an isotropic medium shrink by a ratio that tends to the scattering operator's largest
// eigenvalue (bounded by the albedo, since each order's source is albedo times what the previous
// order had left to interact), so once the ratio r_k = P_k / P_{k-1} has settled the untraced rest
// is P_k r / (1 - r): the tail of a geometric series. The tracer adds that tail to every column
// (scaled copies of the last order's field, whose shape is the eigenfunction's by then) and stops when,
// for every column it counts, the tail is at most `tolerance` of the column's own total so far:
// each column's truncation is bounded against itself, not against a total other columns dominate
// (a bright emission used to stop the orders while a sun's column still lacked 1-2% of its light).
#pragma once

#include <cstddef>
#include <vector>

#include "bake/scatter_cells.h"

namespace firelook::bake {

class OrderSeries {
  public:
    // `counted`: the columns (0..counted-1 of each grid point's `columns`) whose convergence decides
    // when to stop; the others get their tail too but never change how many orders are traced.
    OrderSeries(const ScatterCells& cells, int points, int columns, int counted, double albedo);

    // Adds the scattered power of one more order's Lbar field (slots x points x columns).
    void add(const std::vector<float>& order_field);

    // True when every counted column with power has a tail within `tolerance` of its total.
    bool converged(double tolerance) const;

    // Per grid point and column: the factor r / (1 - r) by which the last order's field is added
    // once more as the tail (0 before two orders are known, or where the power vanished).
    std::vector<float> tailFactors() const;

    // Largest share of its column's total (tail included) that the last order added / the tail adds,
    // over the counted columns with power: for the bake report.
    double lastOrderFraction() const;
    double tailFraction() const;

    // The photons the next order is worth, as a share of the first further order's (TraceSettings::
    // min_order_photon_share): the largest, over the counted columns with power, of the column's last
    // order's power over its first order's (grid points summed). An order's image noise is about its
    // power over the square root of its photons, so at a fixed photon cost the summed variance is
    // least with photons in proportion to the power (the Lagrange condition), and as the orders
    // shrink geometrically the last order's power over the first is the next's over the second.
    // 1 before an order is known.
    double nextOrderShare() const;

    int orders() const { return orders_; }

  private:
    // Entry i = g * columns + c: r / (1 - r) with r = P_k / P_(k-1) clamped into [0, albedo] (0
    // before two orders, where the power vanished, or at r = 1); its tail is last_[i] times that.
    double tailFactor(std::size_t i) const;
    bool counts(std::size_t i) const;  // a counted column with power
    // Largest share(i) / (total + tail) over the entries that count.
    template <typename Share>
    double worstShare(Share share) const;

    const ScatterCells& cells_;
    int points_, columns_, counted_;
    double albedo_;
    int orders_ = 0;
    std::vector<double> total_, last_, previous_, first_;  // per g * columns + c
};

}  // namespace firelook::bake
