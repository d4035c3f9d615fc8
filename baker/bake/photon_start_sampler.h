// Where photons start: a point drawn with probability proportional to a per-cube weight, in two
// levels: a brick of the medium by the summed weight of its unit index cubes, then one of its cubes
// by weight, then a uniform point in that cube. Each brick that can start photons keeps its cubes'
// weights (64 floats, half the medium's own bytes for that brick): drawing recomputed them from the
// medium, 64 lookups and weights a photon, which was a ninth of the photon passes of frame 12
// upsampled 4x (perf; 8.8 -> 7.6 s at 128x128, medians of 3). The weight is
// evaluated at the cube's centre and must be positive wherever the cube holds density; since
// density is trilinear and non-negative, a cube holds density exactly where its centre does, so
// every point that can emit or scatter can start a photon.
#pragma once

#include <cstddef>
#include <functional>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "render/medium.h"
#include "render/random.h"

namespace firelook::bake {

// Density and temperature at the centre of every unit index cube of the medium's bricks that hold
// density, read once: the scattered light's two samplers and its emission masses weigh the same
// cubes, and three reads of them (a trilinear lookup each) took 0.63 s of frame 12 upsampled 4x at
// 128x128.
struct CubeCentres {
    static constexpr int kCubes =
        render::Medium::kBrickSize * render::Medium::kBrickSize * render::Medium::kBrickSize;

    explicit CubeCentres(const render::Medium& medium);
    std::vector<glm::ivec3> bricks;  // bricks holding density, z slowest, x fastest
    std::vector<glm::vec2> values;   // kCubes per brick, x fastest: (density, temperature)
};

class PhotonStartSampler {
  public:
    // weight(rho, t) at a cube centre with rho > 0; must be > 0 there.
    using Weight = std::function<double(float rho, float t)>;

    PhotonStartSampler(const render::Medium& medium, const CubeCentres& centres, const Weight& weight);
    PhotonStartSampler(const render::Medium& medium, const Weight& weight)
        : PhotonStartSampler(medium, CubeCentres(medium), weight) {}

    struct Start {
        glm::dvec3 point;  // index space
        double pdf = 0.0;  // per unit index volume
    };
    // `u` in [0, 1) picks the brick and then, by where it falls within that brick's share, the
    // cube: photons given stratified u (photon_pass.cpp) start in every brick and cube in
    // proportion to its weight, not in Poisson numbers. `rng` places the point inside the cube.
    Start sample(double u, render::Pcg32& rng) const;
    bool empty() const { return bricks_.empty(); }

    // Bytes a sampler of the medium holds at most: what the bake's memory plan counts. bytes():
    // what this one holds.
    static std::size_t bytesFor(const render::Medium& medium);
    std::size_t bytes() const;

  private:
    static constexpr int kCubes = CubeCentres::kCubes;

    const render::Medium& medium_;
    std::vector<glm::ivec3> bricks_;    // bricks with positive weight
    std::vector<float> cube_weights_;   // kCubes per brick, x fastest
    std::vector<double> brick_totals_;  // the sum of each brick's cube weights
    std::vector<double> cdf_;           // normalised, cdf_.back() == 1
    double total_ = 0.0;
};

}  // namespace firelook::bake
