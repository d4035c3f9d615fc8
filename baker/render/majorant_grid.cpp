#include "render/majorant_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "render/render_error.h"

namespace firelook::render {
namespace {

// Guards the majorant against float rounding in the interpolation (sigma_t must never exceed it).
constexpr double kSafetyFactor = 1.0 + 1e-5;

// Bisections of one piece's length at most. Every bisection at least halves the majorant optical
// depth (a piece's Bernstein coefficients are convex combinations of its parent's), and a finite
// majorant times a length is below 2^1024, so ~1030 always reach kPieceOpticalDepth; the cap only
// guards the loop.
constexpr int kMaxBisections = 1100;

int smallestAxis(const glm::dvec3& t) { return t.x < t.y ? (t.x < t.z ? 0 : 2) : (t.y < t.z ? 1 : 2); }

// de Casteljau: the cubic with Bernstein coefficients b over [0, 1] restricted to [0, r] and [r, 1].
void split(const double b[4], double r, double left[4], double right[4]) {
    const double s = 1.0 - r;
    const double b01 = s * b[0] + r * b[1], b12 = s * b[1] + r * b[2], b23 = s * b[2] + r * b[3];
    const double b012 = s * b01 + r * b12, b123 = s * b12 + r * b23;
    const double b0123 = s * b012 + r * b123;
    left[0] = b[0], left[1] = b01, left[2] = b012, left[3] = b0123;
    right[0] = b0123, right[1] = b123, right[2] = b23, right[3] = b[3];
}

double evaluate(const double b[4], double v) {
    const double s = 1.0 - v;
    const double b01 = s * b[0] + v * b[1], b12 = s * b[1] + v * b[2], b23 = s * b[2] + v * b[3];
    return s * (s * b01 + v * b12) + v * (s * b12 + v * b23);
}

}  // namespace

MajorantGrid::MajorantGrid(const Medium& medium, const ExtinctionParams& extinction,
                           const TemperatureBins& bins, double minimum_rate, double refine_optical_depth)
    : medium_(&medium),
      extinction_(extinction),
      bins_(bins),
      minimum_rate_(minimum_rate),
      refine_optical_depth_(refine_optical_depth),
      counts_(medium.brickCounts()) {
    majorants_.resize(static_cast<std::size_t>(counts_.x) * static_cast<std::size_t>(counts_.y) *
                      static_cast<std::size_t>(counts_.z));
    std::size_t n = 0;
    for (int z = 0; z < counts_.z; ++z)
        for (int y = 0; y < counts_.y; ++y)
            for (int x = 0; x < counts_.x; ++x, ++n) {
                const BrickRange& range = medium.brick({x, y, z});
                majorants_[n] = majorantFor(range.max_density, range.min_temperature, range.max_temperature);
                if (!std::isfinite(majorants_[n]))
                    throw RenderError("majorants: extinction times density overflows (k_s, k_f or the density "
                                      "is absurdly large)");
            }
}

double MajorantGrid::majorantFor(double max_density, double min_temperature, double max_temperature) const {
    if (!(max_density > 0.0)) return 0.0;
    const double kappa = std::max(extinctionPerDensity(min_temperature, extinction_, bins_),
                                  extinctionPerDensity(max_temperature, extinction_, bins_));
    return std::max(kSafetyFactor * std::max(kappa, 0.0) * max_density, minimum_rate_);
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
    bricks_done_ = false;
    done_ = false;
}

bool MajorantTracker::advance(double optical_distance, TentativeCollision& collision) {
    while (!done_) {
        if (in_piece_) {
            // Positions are kept relative to the piece's start, so they advance however small the
            // step is against the distance from the ray's origin.
            const double rest = piece_.majorant * (piece_.length - piece_.position);
            if (rest > optical_distance) {
                piece_.position += optical_distance / piece_.majorant;
                fill(collision);
                return true;
            }
            optical_distance = std::max(optical_distance - rest, 0.0);
            in_piece_ = false;
        }
        if (!nextPiece()) break;
        in_piece_ = true;
    }
    done_ = true;
    return false;
}

void MajorantTracker::fill(TentativeCollision& collision) const {
    collision.distance = piece_.start + piece_.position;
    collision.majorant = piece_.majorant;
    collision.index_point = index_origin_ + collision.distance * index_direction_;
    if (!piece_.refined) {
        collision.sample = grid_->medium().sampleIndex(collision.index_point);
        return;
    }
    const double v = std::clamp(piece_.position / piece_.length, 0.0, 1.0);
    collision.sample.density = static_cast<float>(std::max(evaluate(piece_.density, v), 0.0));
    collision.sample.temperature = static_cast<float>(evaluate(piece_.temperature, v));
}

bool MajorantTracker::nextPiece() {
    for (;;) {
        if (refine_.active) {
            if (nextRefinedPiece()) return true;
            refine_.active = false;
        }
        double t0 = 0.0, t1 = 0.0, majorant = 0.0;
        glm::ivec3 brick(0);
        if (!nextBrickSegment(t0, t1, brick, majorant)) return false;
        if (majorant * (t1 - t0) <= grid_->refineOpticalDepth()) {
            piece_.start = t0;
            piece_.length = t1 - t0;
            piece_.position = 0.0;
            piece_.majorant = majorant;
            piece_.refined = false;
            return true;
        }
        startRefinement(t0, t1, brick);
    }
}

bool MajorantTracker::nextBrickSegment(double& t0, double& t1, glm::ivec3& brick, double& majorant) {
    const glm::ivec3 counts = grid_->brickCounts();
    while (!bricks_done_) {
        const int axis = smallestAxis(t_next_);
        const double t_end = std::min(t_next_[axis], t_exit_);
        brick = cell_;
        majorant = grid_->majorant(cell_);
        t0 = t_;
        t1 = t_end;
        t_ = t_end;
        if (t_end >= t_exit_) {
            bricks_done_ = true;
        } else {
            cell_[axis] += step_[axis];
            if (cell_[axis] < 0 || cell_[axis] >= counts[axis]) bricks_done_ = true;
            t_next_[axis] += t_delta_[axis];
        }
        if (majorant > 0.0 && t1 > t0) return true;
    }
    return false;
}

void MajorantTracker::startRefinement(double t0, double t1, const glm::ivec3& brick) {
    // Interpolation cells, relative to the medium's origin: cell c holds the points between voxels
    // c and c + 1 on every axis. Brick b starts at relative index -1 + b * kBrickSize.
    Refinement& r = refine_;
    r = Refinement{};
    r.active = true;
    r.t = t0;
    r.t_end = t1;
    r.lo = brick * Medium::kBrickSize - 1;
    r.hi = r.lo + (Medium::kBrickSize - 1);
    const glm::dvec3 q0 = index_origin_ - glm::dvec3(grid_->medium().origin());
    const glm::dvec3 q = q0 + t0 * index_direction_;
    for (int axis = 0; axis < 3; ++axis) {
        const double d = index_direction_[axis];
        r.cell[axis] = std::clamp(static_cast<int>(std::floor(q[axis])), r.lo[axis], r.hi[axis]);
        if (d > 0.0) {
            r.step[axis] = 1;
            r.t_next[axis] = (r.cell[axis] + 1 - q0[axis]) / d;
            r.t_delta[axis] = 1.0 / d;
        } else if (d < 0.0) {
            r.step[axis] = -1;
            r.t_next[axis] = (r.cell[axis] - q0[axis]) / d;
            r.t_delta[axis] = -1.0 / d;
        } else {
            r.step[axis] = 0;
            r.t_next[axis] = std::numeric_limits<double>::infinity();
            r.t_delta[axis] = 0.0;
        }
    }
}

bool MajorantTracker::enterNextCell() {
    Refinement& r = refine_;
    const Medium& medium = grid_->medium();
    const glm::dvec3 q0 = index_origin_ - glm::dvec3(medium.origin());
    while (r.t < r.t_end) {
        const int axis = smallestAxis(r.t_next);
        const double start = r.t, end = std::min(r.t_next[axis], r.t_end);
        const glm::ivec3 cell = r.cell;
        r.t = end;
        r.cell[axis] += r.step[axis];
        r.t_next[axis] += r.t_delta[axis];
        if (r.cell[axis] < r.lo[axis] || r.cell[axis] > r.hi[axis]) r.t = r.t_end;  // left the brick
        if (!(end > start)) continue;

        // Along the ray each interpolation weight is a product of three linear functions of t, so in
        // Bernstein form over [start, end] it has the coefficients below (products of the factors'
        // end values, averaged over which factor takes the far end).
        const glm::dvec3 f0 = glm::clamp(q0 + start * index_direction_ - glm::dvec3(cell), 0.0, 1.0);
        const glm::dvec3 f1 = glm::clamp(q0 + end * index_direction_ - glm::dvec3(cell), 0.0, 1.0);
        double density[4] = {0.0, 0.0, 0.0, 0.0}, temperature[4] = {0.0, 0.0, 0.0, 0.0};
        for (int n = 0; n < 8; ++n) {
            const glm::ivec3 corner(n & 1, (n >> 1) & 1, n >> 2);
            const MediumSample v = medium.voxel(cell + corner);
            const double x0 = corner.x ? f0.x : 1.0 - f0.x, x1 = corner.x ? f1.x : 1.0 - f1.x;
            const double y0 = corner.y ? f0.y : 1.0 - f0.y, y1 = corner.y ? f1.y : 1.0 - f1.y;
            const double z0 = corner.z ? f0.z : 1.0 - f0.z, z1 = corner.z ? f1.z : 1.0 - f1.z;
            const double w[4] = {x0 * y0 * z0, (x1 * y0 * z0 + x0 * y1 * z0 + x0 * y0 * z1) / 3.0,
                                 (x1 * y1 * z0 + x1 * y0 * z1 + x0 * y1 * z1) / 3.0, x1 * y1 * z1};
            for (int k = 0; k < 4; ++k) {
                density[k] += w[k] * v.density;
                temperature[k] += w[k] * v.temperature;
            }
        }
        if (!(std::max({density[0], density[1], density[2], density[3]}) > 0.0)) continue;  // empty cell
        std::copy(density, density + 4, r.density);
        std::copy(temperature, temperature + 4, r.temperature);
        r.in_cell = true;
        r.rest_start = start;
        r.rest_length = end - start;
        r.last_piece = r.rest_length;
        return true;
    }
    return false;
}

bool MajorantTracker::nextRefinedPiece() {
    Refinement& r = refine_;
    for (;;) {
        if (!r.in_cell && !enterNextCell()) return false;
        const double rest = r.rest_length;
        if (!(rest > 0.0)) {
            r.in_cell = false;
            continue;
        }
        // The longest piece from the front of the cell's rest, starting from twice the last one,
        // whose majorant optical depth is at most kPieceOpticalDepth.
        double length = std::min(rest, 2.0 * r.last_piece);
        double density[4] = {}, temperature[4] = {}, density_rest[4] = {}, temperature_rest[4] = {};
        double majorant = 0.0;
        for (int bisections = 0;; ++bisections) {
            const double fraction = length / rest;
            if (fraction >= 1.0) {
                length = rest;
                std::copy(r.density, r.density + 4, density);
                std::copy(r.temperature, r.temperature + 4, temperature);
            } else {
                split(r.density, fraction, density, density_rest);
                split(r.temperature, fraction, temperature, temperature_rest);
            }
            majorant = grid_->majorantFor(std::max({density[0], density[1], density[2], density[3]}),
                                          std::min({temperature[0], temperature[1], temperature[2], temperature[3]}),
                                          std::max({temperature[0], temperature[1], temperature[2], temperature[3]}));
            if (!(majorant * length > kPieceOpticalDepth) || bisections >= kMaxBisections) break;
            length *= 0.5;
        }
        piece_.start = r.rest_start;
        piece_.length = length;
        piece_.position = 0.0;
        piece_.majorant = majorant;
        piece_.refined = true;
        std::copy(density, density + 4, piece_.density);
        std::copy(temperature, temperature + 4, piece_.temperature);
        if (length >= rest) {
            r.in_cell = false;
        } else {
            r.rest_start += length;
            r.rest_length = rest - length;
            std::copy(density_rest, density_rest + 4, r.density);
            std::copy(temperature_rest, temperature_rest + 4, r.temperature);
        }
        r.last_piece = length;
        if (majorant > 0.0 && length > 0.0) return true;
    }
}

}  // namespace firelook::render
