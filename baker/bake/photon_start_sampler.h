// Where photons start: a point drawn with probability proportional to a per-cube weight, in two
// levels so that nothing is stored per voxel (the 6x sample frame has tens of millions): a brick
// of the medium by the summed weight of its unit index cubes, then one of its cubes by weight
// (recomputed from the medium when drawn), then a uniform point in that cube. The weight is
// evaluated at the cube's centre and must be positive wherever the cube holds density; since
// density is trilinear and non-negative, a cube holds density exactly where its centre does, so
// every point that can emit or scatter can start a photon.
#pragma once

#include <cstddef>
#include <functional>
#include <glm/vec3.hpp>
#include <vector>

#include "render/medium.h"
#include "render/random.h"

namespace firelook::bake {

class PhotonStartSampler {
  public:
    // weight(rho, t) at a cube centre with rho > 0; must be > 0 there.
    using Weight = std::function<double(float rho, float t)>;

    PhotonStartSampler(const render::Medium& medium, Weight weight);

    struct Start {
        glm::dvec3 point;  // index space
        double pdf = 0.0;  // per unit index volume
    };
    // `u` in [0, 1) picks the brick and then, by where it falls within that brick's share, the
    // cube: photons given stratified u (photon_pass.cpp) start in every brick and cube in
    // proportion to its weight, not in Poisson numbers. `rng` places the point inside the cube.
    Start sample(double u, render::Pcg32& rng) const;
    bool empty() const { return bricks_.empty(); }

  private:
    double cubeWeights(std::size_t brick, double* weights) const;

    const render::Medium& medium_;
    Weight weight_;
    std::vector<glm::ivec3> bricks_;  // bricks with positive weight
    std::vector<double> cdf_;         // normalised, cdf_.back() == 1
    double total_ = 0.0;
};

}  // namespace firelook::bake
