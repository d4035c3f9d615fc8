#include "bake/order_series.h"

#include <algorithm>

namespace firelook::bake {

OrderSeries::OrderSeries(const ScatterCells& cells, int points, int columns, int counted, double albedo)
    : cells_(cells),
      points_(points),
      columns_(columns),
      counted_(counted),
      albedo_(albedo),
      total_(static_cast<std::size_t>(points) * columns, 0.0),
      last_(total_.size(), 0.0),
      previous_(total_.size(), 0.0) {}

void OrderSeries::add(const std::vector<float>& field) {
    std::vector<double> power(total_.size(), 0.0);
    for (int s = 0; s < cells_.slots; ++s)
        for (int g = 0; g < points_; ++g) {
            const double m = cells_.mass[static_cast<std::size_t>(s) * points_ + g];
            const float* v = field.data() + (static_cast<std::size_t>(s) * points_ + g) * columns_;
            double* p = power.data() + static_cast<std::size_t>(g) * columns_;
            for (int c = 0; c < columns_; ++c) p[c] += m * v[c];
        }
    previous_.swap(last_);
    last_.swap(power);
    for (std::size_t i = 0; i < total_.size(); ++i) total_[i] += last_[i];
    if (orders_ == 0) first_ = last_;
    ++orders_;
}

double OrderSeries::tailFactor(std::size_t i) const {
    if (orders_ < 2 || !(previous_[i] > 0.0) || !(last_[i] > 0.0)) return 0.0;
    const double r = std::clamp(last_[i] / previous_[i], 0.0, albedo_);
    return r < 1.0 ? r / (1.0 - r) : 0.0;
}

bool OrderSeries::counts(std::size_t i) const {
    return static_cast<int>(i % columns_) < counted_ && total_[i] > 0.0;
}

template <typename Share>
double OrderSeries::worstShare(Share share) const {
    double worst = 0.0;
    for (std::size_t i = 0; i < total_.size(); ++i)
        if (counts(i)) worst = std::max(worst, share(i) / (total_[i] + last_[i] * tailFactor(i)));
    return worst;
}

bool OrderSeries::converged(double tolerance) const {
    if (orders_ < 2) return false;
    // A column whose last order added nothing (no paths left) has nothing more to add: factor 0.
    for (std::size_t i = 0; i < total_.size(); ++i)
        if (counts(i) && last_[i] * tailFactor(i) > tolerance * total_[i]) return false;
    return true;
}

double OrderSeries::nextOrderShare() const {
    if (orders_ == 0) return 1.0;
    double share = 0.0;
    for (int c = 0; c < counted_; ++c) {
        double last = 0.0, first = 0.0;
        for (int g = 0; g < points_; ++g) {
            last += last_[static_cast<std::size_t>(g) * columns_ + c];
            first += first_[static_cast<std::size_t>(g) * columns_ + c];
        }
        if (first > 0.0) share = std::max(share, last / first);
    }
    return share;
}

std::vector<float> OrderSeries::tailFactors() const {
    std::vector<float> f(total_.size());
    for (std::size_t i = 0; i < f.size(); ++i) f[i] = static_cast<float>(tailFactor(i));
    return f;
}

double OrderSeries::lastOrderFraction() const {
    return worstShare([&](std::size_t i) { return last_[i]; });
}

double OrderSeries::tailFraction() const {
    return worstShare([&](std::size_t i) { return last_[i] * tailFactor(i); });
}

}  // namespace firelook::bake
