// Packages of a chosen shape with deterministic pseudo-random factors, written through the real
// package writer (basis::writeFrameFactors + makeMetadata), so tests and the benchmark need no bake.
// Values are in plausible ranges: U in [-0.5, 0.5] (stored as half), S V^T in [-1, 1] scaled per
// column, optical depths >= 0 increasing with the threshold index.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/gtc/packing.hpp>

#include "basis/basis_package.h"
#include "look/look.h"

namespace firelook::testing {

struct SyntheticShape {
    int width = 16, height = 12;
    int bins = 16;
    int lights = 1;
    int rank = 8;
    std::vector<int> frames = {1, 2, 3};
    basis::ParameterAxes axes{{1.0, 1.2, 1.4, 1.6, 1.8, 2.0}, {2.0, 4.0, 8.0, 16.0}, {0.5, 1.5, 4.0}};
    int alpha_thresholds = 5;
    double albedo = 0.7;
    uint32_t seed = 1;
};

inline float syntheticValue(uint64_t& state) {  // splitmix64 -> [0, 1)
    state += 0x9E3779B97F4A7C15ull;
    uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<float>((z >> 40) * (1.0 / 16777216.0));
}

inline basis::BakeDescription syntheticDescription(const SyntheticShape& s) {
    basis::BakeDescription d;
    d.bins = {0.0, 3.0, s.bins};
    d.rbf_width = kDefaultRbfWidth;
    d.albedo = s.albedo;
    d.axes = s.axes;
    for (int i = 0; i < s.alpha_thresholds; ++i)
        d.alpha_thresholds.push_back(s.alpha_thresholds == 1 ? 1.5 : 1.0 + i * (1.0 / (s.alpha_thresholds - 1)));
    for (int l = 0; l < s.lights; ++l) d.light_directions.push_back({0.3 * l, -1.0, 0.2});
    d.width = s.width;
    d.height = s.height;
    Look look = defaultLook();
    look.albedo = s.albedo;
    look.light_irradiance.assign(s.lights, Rgb(2.0f, 1.9f, 1.8f));
    d.default_look_json = lookToJson(look);
    return d;
}

inline basis::FrameFactors syntheticFrame(const basis::BakeDescription& d, int frame, int rank, uint32_t seed) {
    uint64_t state = seed * 1000003ull + static_cast<uint64_t>(frame);
    basis::FrameFactors f;
    f.frame = frame;
    f.pixels = d.pixelCount();
    f.columns = d.columnCount();
    f.rank = rank;
    f.u_half.resize(static_cast<size_t>(f.pixels) * rank);
    for (auto& u : f.u_half) u = glm::packHalf1x16(syntheticValue(state) - 0.5f);
    f.svt.resize(static_cast<size_t>(f.columns) * rank);
    for (auto& v : f.svt) v = 2.0f * syntheticValue(state) - 1.0f;
    f.depth_b.resize(f.pixels);
    for (auto& v : f.depth_b) v = 2.0f * syntheticValue(state);
    const size_t t = d.alpha_thresholds.size();
    f.depth_a.resize(static_cast<size_t>(f.pixels) * t);
    for (int p = 0; p < f.pixels; ++p)
        for (size_t j = 0; j < t; ++j)  // O_a in [-O_b, O_b], decreasing in T_c like the real thing
            f.depth_a[j * f.pixels + p] = f.depth_b[p] * (1.0f - 2.0f * (j + 0.5f) / t);
    return f;
}

inline void writeSyntheticPackage(const std::filesystem::path& file, const SyntheticShape& s) {
    basis::BakeDescription d = syntheticDescription(s);
    package::ContainerWriter writer(file, package::WriterOptions{1});
    for (int frame : s.frames) {
        // Ranks differ per frame (rank, rank - 1, ...) so per-frame ranks are exercised.
        const int rank = std::max(1, s.rank - static_cast<int>(d.frames.size()));
        basis::writeFrameFactors(writer, d, syntheticFrame(d, frame, rank, s.seed));
        d.frames.push_back({frame, rank});
    }
    writer.addMetadata(basis::makeMetadata(d, R"({"provenance": {"tool": "synthetic_package"}})"));
    writer.commit();
}

}  // namespace firelook::testing
