// What the benchmark tools (tests/world/bench_frame_decode, tests/plugin_api/bench_frame_layers)
// time with: milliseconds since a moment, and the median of repeated runs (these machines are
// noisy, so a figure is a median). Shared by every test suite (included as "../support/bench_timing.h").
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>

namespace firelook::testing {

using Clock = std::chrono::steady_clock;

inline double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace firelook::testing
