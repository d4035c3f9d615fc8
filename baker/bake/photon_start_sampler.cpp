#include "bake/photon_start_sampler.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace firelook::bake {
namespace {
constexpr int kSize = render::Medium::kBrickSize;

std::vector<glm::ivec3> bricksWithDensity(const render::Medium& medium) {
    std::vector<glm::ivec3> bricks;
    const glm::ivec3 counts = medium.brickCounts();
    for (int z = 0; z < counts.z; ++z)
        for (int y = 0; y < counts.y; ++y)
            for (int x = 0; x < counts.x; ++x)
                if (medium.brick({x, y, z}).max_density > 0.0f) bricks.push_back({x, y, z});
    return bricks;
}
}  // namespace

std::size_t PhotonStartSampler::bytesFor(const render::Medium& medium) {
    return bricksWithDensity(medium).size() *
           (kCubes * sizeof(float) + sizeof(glm::ivec3) + 2 * sizeof(double));
}

std::size_t PhotonStartSampler::bytes() const {
    return bricks_.capacity() * sizeof(glm::ivec3) + cube_weights_.capacity() * sizeof(float) +
           (brick_totals_.capacity() + cdf_.capacity()) * sizeof(double);
}

CubeCentres::CubeCentres(const render::Medium& medium) : bricks(bricksWithDensity(medium)) {
    values.resize(bricks.size() * kCubes);
    tbb::parallel_for(std::size_t(0), bricks.size(), [&](std::size_t b) {
        const glm::ivec3 lo = medium.origin() - 1 + bricks[b] * kSize;
        glm::vec2* v = values.data() + b * kCubes;
        for (int z = 0; z < kSize; ++z)
            for (int y = 0; y < kSize; ++y)
                for (int x = 0; x < kSize; ++x, ++v) {
                    // What sampleIndex gives at the cube's centre.
                    glm::vec2 corners[8];
                    medium.cubeCorners(lo + glm::ivec3(x, y, z), corners);
                    const render::MediumSample s = render::Medium::interpolate(corners, glm::vec3(0.5f));
                    *v = glm::vec2(s.density, s.temperature);
                }
    });
}

PhotonStartSampler::PhotonStartSampler(const render::Medium& medium, const CubeCentres& centres,
                                       const Weight& weight)
    : medium_(medium) {
    bricks_ = centres.bricks;
    cube_weights_.assign(bricks_.size() * kCubes, 0.0f);
    brick_totals_.assign(bricks_.size(), 0.0);
    tbb::parallel_for(std::size_t(0), bricks_.size(), [&](std::size_t b) {
        const glm::vec2* v = centres.values.data() + b * kCubes;
        float* w = cube_weights_.data() + b * kCubes;
        double sum = 0.0;
        for (int n = 0; n < kCubes; ++n) {
            w[n] = v[n].x > 0.0f ? static_cast<float>(std::max(weight(v[n].x, v[n].y), 0.0)) : 0.0f;
            sum += w[n];  // the stored floats: the pdf is what sample() draws by
        }
        brick_totals_[b] = sum;
    });
    // Keep only bricks that can start photons; the sum runs in a fixed order (same bytes with any
    // number of threads).
    std::size_t kept = 0;
    for (std::size_t b = 0; b < bricks_.size(); ++b) {
        if (!(brick_totals_[b] > 0.0)) continue;
        bricks_[kept] = bricks_[b];
        brick_totals_[kept] = brick_totals_[b];
        std::copy_n(cube_weights_.begin() + b * kCubes, kCubes, cube_weights_.begin() + kept * kCubes);
        total_ += brick_totals_[b];
        cdf_.push_back(total_);
        ++kept;
    }
    bricks_.resize(kept);
    brick_totals_.resize(kept);
    cube_weights_.resize(kept * kCubes);
    bricks_.shrink_to_fit();
    brick_totals_.shrink_to_fit();
    cube_weights_.shrink_to_fit();
    cdf_.shrink_to_fit();
    for (double& c : cdf_) c /= total_;
    if (!cdf_.empty()) cdf_.back() = 1.0;
}

PhotonStartSampler::Start PhotonStartSampler::sample(double u, render::Pcg32& rng) const {
    std::size_t b = static_cast<std::size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin());
    b = std::min(b, bricks_.size() - 1);
    const float* w = cube_weights_.data() + b * kCubes;
    // Where u falls within the brick's interval of the cdf is uniform in [0, 1) and picks the cube.
    const double lo = b > 0 ? cdf_[b - 1] : 0.0;
    const double within = cdf_[b] > lo ? std::clamp((u - lo) / (cdf_[b] - lo), 0.0, 1.0) : 0.0;
    double pick = within * brick_totals_[b];
    int cube = 0;
    while (cube < kCubes - 1 && (pick >= w[cube] || w[cube] == 0.0f)) {
        pick -= w[cube];
        ++cube;
    }
    while (w[cube] == 0.0f && cube > 0) --cube;  // rounding at the end: never a cube without weight
    const glm::ivec3 q = medium_.origin() - 1 + bricks_[b] * kSize +
                         glm::ivec3(cube % kSize, (cube / kSize) % kSize, cube / (kSize * kSize));
    Start start;
    start.point = glm::dvec3(q) + glm::dvec3(rng.uniform(), rng.uniform(), rng.uniform());
    start.pdf = w[cube] / total_;
    return start;
}

}  // namespace firelook::bake
