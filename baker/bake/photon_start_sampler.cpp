#include "bake/photon_start_sampler.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace firelook::bake {
namespace {
constexpr int kSize = render::Medium::kBrickSize;
constexpr int kCubes = kSize * kSize * kSize;
}  // namespace

PhotonStartSampler::PhotonStartSampler(const render::Medium& medium, Weight weight)
    : medium_(medium), weight_(std::move(weight)) {
    const glm::ivec3 counts = medium.brickCounts();
    for (int z = 0; z < counts.z; ++z)
        for (int y = 0; y < counts.y; ++y)
            for (int x = 0; x < counts.x; ++x)
                if (medium.brick({x, y, z}).max_density > 0.0f) bricks_.push_back({x, y, z});
    std::vector<double> brick_weight(bricks_.size());
    tbb::parallel_for(std::size_t(0), bricks_.size(), [&](std::size_t b) {
        double w[kCubes];
        brick_weight[b] = cubeWeights(b, w);
    });
    // Keep only bricks that can start photons; the sum runs in a fixed order (same bytes with any
    // number of threads).
    std::size_t kept = 0;
    for (std::size_t b = 0; b < bricks_.size(); ++b) {
        if (!(brick_weight[b] > 0.0)) continue;
        bricks_[kept] = bricks_[b];
        total_ += brick_weight[b];
        cdf_.push_back(total_);
        ++kept;
    }
    bricks_.resize(kept);
    for (double& c : cdf_) c /= total_;
    if (!cdf_.empty()) cdf_.back() = 1.0;
}

double PhotonStartSampler::cubeWeights(std::size_t brick, double* weights) const {
    const glm::ivec3 lo = medium_.origin() - 1 + bricks_[brick] * kSize;
    double sum = 0.0;
    int n = 0;
    for (int z = 0; z < kSize; ++z)
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x, ++n) {
                const render::MediumSample s = medium_.sampleIndex(glm::dvec3(lo + glm::ivec3(x, y, z)) + 0.5);
                weights[n] = s.density > 0.0f ? std::max(weight_(s.density, s.temperature), 0.0) : 0.0;
                sum += weights[n];
            }
    return sum;
}

PhotonStartSampler::Start PhotonStartSampler::sample(double u, render::Pcg32& rng) const {
    std::size_t b = static_cast<std::size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin());
    b = std::min(b, bricks_.size() - 1);
    double w[kCubes];
    const double brick_total = cubeWeights(b, w);
    // Where u falls within the brick's interval of the cdf is uniform in [0, 1) and picks the cube.
    const double lo = b > 0 ? cdf_[b - 1] : 0.0;
    const double within = cdf_[b] > lo ? std::clamp((u - lo) / (cdf_[b] - lo), 0.0, 1.0) : 0.0;
    double pick = within * brick_total;
    int cube = 0;
    while (cube < kCubes - 1 && (pick >= w[cube] || w[cube] == 0.0)) {
        pick -= w[cube];
        ++cube;
    }
    while (w[cube] == 0.0 && cube > 0) --cube;  // rounding at the end: never a cube without weight
    const glm::ivec3 q = medium_.origin() - 1 + bricks_[b] * kSize + glm::ivec3(cube % kSize, (cube / kSize) % kSize,
                                                                              cube / (kSize * kSize));
    Start start;
    start.point = glm::dvec3(q) + glm::dvec3(rng.uniform(), rng.uniform(), rng.uniform());
    start.pdf = w[cube] / total_;
    return start;
}

}  // namespace firelook::bake
