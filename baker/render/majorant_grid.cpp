#include "render/majorant_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace firelook::render {
namespace {

// Guards the majorant against float rounding in the interpolation (sigma_t must never exceed it).
constexpr double kSafetyFactor = 1.0 + 1e-5;

}  // namespace

MajorantGrid::MajorantGrid(const Medium& medium, const ExtinctionParams& extinction,
                           const TemperatureBins& bins, double minimum_rate)
    : medium_(&medium), counts_(medium.brickCounts()) {
    majorants_.resize(static_cast<std::size_t>(counts_.x) * static_cast<std::size_t>(counts_.y) *
                      static_cast<std::size_t>(counts_.z));
    std::size_t n = 0;
    for (int z = 0; z < counts_.z; ++z)
        for (int y = 0; y < counts_.y; ++y)
            for (int x = 0; x < counts_.x; ++x, ++n) {
                const BrickRange& range = medium.brick({x, y, z});
                if (range.max_density <= 0.0f) {
                    majorants_[n] = 0.0;
                    continue;
                }
                const double kappa = std::max(extinctionPerDensity(range.min_temperature, extinction, bins),
                                              extinctionPerDensity(range.max_temperature, extinction, bins));
                majorants_[n] =
                    std::max(kSafetyFactor * std::max(kappa, 0.0) * range.max_density, minimum_rate);
            }
}

MajorantTracker::MajorantTracker(const MajorantGrid& grid, const Ray& ray) : grid_(&grid), ray_(ray) {
    const Medium& medium = grid.medium();
    const glm::ivec3 counts = grid.brickCounts();
    if (counts.x == 0 || counts.y == 0 || counts.z == 0) return;
    index_origin_ = glm::dvec3(medium.worldToIndex() * glm::dvec4(ray.origin, 1.0));
    index_direction_ = glm::dvec3(medium.worldToIndex() * glm::dvec4(ray.direction, 0.0));

    // The ray in brick units: g(t) = g0 + t * dg, bricks cover [0, counts).
    const double brick = Medium::kBrickSize;
    const glm::dvec3 g0 = (index_origin_ - medium.brickGridOrigin()) / brick;
    const glm::dvec3 dg = index_direction_ / brick;
    double t_enter = 0.0, t_exit = 0.0;
    if (!intersectBox(g0, dg, glm::dvec3(0.0), glm::dvec3(counts), t_enter, t_exit)) return;

    const glm::dvec3 entry = g0 + t_enter * dg;
    for (int axis = 0; axis < 3; ++axis) {
        cell_[axis] = std::clamp(static_cast<int>(std::floor(entry[axis])), 0, counts[axis] - 1);
        if (dg[axis] > 0.0) {
            step_[axis] = 1;
            t_next_[axis] = (cell_[axis] + 1 - g0[axis]) / dg[axis];
            t_delta_[axis] = 1.0 / dg[axis];
        } else if (dg[axis] < 0.0) {
            step_[axis] = -1;
            t_next_[axis] = (cell_[axis] - g0[axis]) / dg[axis];
            t_delta_[axis] = -1.0 / dg[axis];
        } else {
            step_[axis] = 0;
            t_next_[axis] = std::numeric_limits<double>::infinity();
            t_delta_[axis] = 0.0;
        }
    }
    t_ = t_enter;
    t_exit_ = t_exit;
    done_ = false;
}

bool MajorantTracker::advance(double optical_distance, TentativeCollision& collision) {
    const glm::ivec3 counts = grid_->brickCounts();
    while (!done_) {
        const int axis =
            t_next_.x < t_next_.y ? (t_next_.x < t_next_.z ? 0 : 2) : (t_next_.y < t_next_.z ? 1 : 2);
        const double t_end = std::min(t_next_[axis], t_exit_);
        const double majorant = grid_->majorant(cell_);
        if (majorant > 0.0) {
            const double length = std::max(t_end - t_, 0.0);
            if (majorant * length > optical_distance) {
                t_ += optical_distance / majorant;
                collision.distance = t_;
                collision.majorant = majorant;
                collision.index_point = index_origin_ + t_ * index_direction_;
                return true;
            }
            optical_distance -= majorant * length;
        }
        t_ = t_end;
        if (t_end >= t_exit_) break;
        cell_[axis] += step_[axis];
        if (cell_[axis] < 0 || cell_[axis] >= counts[axis]) break;
        t_next_[axis] += t_delta_[axis];
    }
    done_ = true;
    return false;
}

}  // namespace firelook::render
