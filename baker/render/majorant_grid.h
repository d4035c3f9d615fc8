// Piecewise-constant extinction majorants over a medium's bricks, and a 3D DDA that samples
// tentative collisions along a ray through them (skipping empty space).
#pragma once

#include <vector>

#include "look/look_model.h"
#include "render/medium.h"
#include "render/ray.h"

namespace firelook::render {

// One majorant sigma_bar per brick, in 1 / world unit, with sigma_bar >= sigma_t = kappa(T) * rho at
// every point of the brick: rho is at most the brick's max density and kappa(T) is monotonic in T
// (it is a tanh), so its maximum over the brick's temperature range sits at one end.
// minimum_rate (1 / world unit) is a floor applied to every brick that holds density, so that
// emission is sampled even where extinction vanishes (k_s = k_f = 0).
class MajorantGrid {
  public:
    MajorantGrid(const Medium& medium, const ExtinctionParams& extinction, const TemperatureBins& bins,
                 double minimum_rate);

    const Medium& medium() const { return *medium_; }
    double majorant(const glm::ivec3& brick) const {
        return majorants_[static_cast<std::size_t>(brick.x) +
                          static_cast<std::size_t>(counts_.x) *
                              (static_cast<std::size_t>(brick.y) +
                               static_cast<std::size_t>(counts_.y) * static_cast<std::size_t>(brick.z))];
    }
    glm::ivec3 brickCounts() const { return counts_; }

  private:
    const Medium* medium_;
    glm::ivec3 counts_;
    std::vector<double> majorants_;
};

// A tentative collision: where it is and the majorant it was drawn with.
struct TentativeCollision {
    double distance = 0.0;     // along the ray, world units
    double majorant = 0.0;     // sigma_bar at that point
    glm::dvec3 index_point{};  // the point in the medium's index space
};

// Walks the bricks a ray crosses (Amanatides & Woo) and draws tentative collisions from the
// piecewise-constant majorant: a Poisson process of rate sigma_bar along the ray. Keeps its place
// between calls, so successive calls give successive collisions.
class MajorantTracker {
  public:
    MajorantTracker(const MajorantGrid& grid, const Ray& ray);

    // Advances by an optical distance (in majorant units, e.g. an Exp(1) sample) and reports the
    // collision there; false once the ray has left the bricks, after which it stays false.
    bool advance(double optical_distance, TentativeCollision& collision);

    glm::dvec3 worldPoint(double distance) const { return ray_.origin + distance * ray_.direction; }

  private:
    const MajorantGrid* grid_;
    Ray ray_;
    glm::dvec3 index_origin_{}, index_direction_{};  // the ray in index space, per world unit
    bool done_ = true;
    double t_ = 0.0, t_exit_ = 0.0;
    glm::ivec3 cell_{0}, step_{0};
    glm::dvec3 t_next_{0.0}, t_delta_{0.0};
};

}  // namespace firelook::render
