#include "basis/source_balance.h"

#include <algorithm>
#include <cmath>

namespace firelook::basis {

std::vector<double> sourceBalance(std::span<const double> energy, int bins) {
    const int kinds = static_cast<int>(energy.size());
    const int emission_end = std::clamp(bins, 0, kinds);
    // Source 0 is the emission (kinds 0 .. bins-1), source 1 + l is light l.
    std::vector<double> source(1 + (kinds - emission_end), 0.0);
    for (int c = 0; c < kinds; ++c) source[c < emission_end ? 0 : 1 + c - emission_end] += energy[c];
    const double largest = *std::max_element(source.begin(), source.end());
    std::vector<double> factor(kinds, 1.0);
    for (int c = 0; c < kinds; ++c) {
        const double e = source[c < emission_end ? 0 : 1 + c - emission_end];
        if (e > 0.0 && std::isfinite(e) && std::isfinite(largest))
            factor[c] = std::max(1.0, std::sqrt(largest / e) / kMaxSourceRatio);
    }
    return factor;
}

std::vector<double> svtSourceBalance(std::span<const float> svt, int rank, int columns_per_point, int bins) {
    std::vector<double> energy(static_cast<size_t>(std::max(columns_per_point, 0)), 0.0);
    if (rank <= 0 || energy.empty()) return sourceBalance(energy, bins);
    const size_t columns = svt.size() / static_cast<size_t>(rank);
    for (size_t j = 0; j < columns; ++j)
        for (int k = 0; k < rank; ++k) {
            const float v = svt[j * rank + k];
            if (std::isfinite(v)) energy[j % energy.size()] += double(v) * v;
        }
    return sourceBalance(energy, bins);
}

}  // namespace firelook::basis
