// The coarse cells that hold the scattered light of every grid point and column.
//
// Each cell stores the sigma_s-weighted mean of the mean radiance Lbar = (1/4pi) integral L dw,
//   Lbar_c = integral_c sigma_s Lbar dV / M_c,   M_c = integral_c sigma_s dV,
// because what the camera rays and the next scattering order need is the scattered source
// sigma_s Lbar. A plain volume mean would average Lbar over the empty part of a cell and over the
// interior the camera does not see, which biased thick or small media low (an 8^3 box: 0.92 of
// the reference); weighted by sigma_s, the scattered power of every cell is exact whatever its
// size, so cells can be sized by the world extent instead of the voxel count.
//
// Cells are a whole number of voxels wide, aligned with the index lattice from the influence
// box's low corner, so every unit index cube [q, q+1]^3 lies in exactly one cell. Only cells
// with density get storage ("slots"): elsewhere sigma_s = 0 and Lbar is never used.
#pragma once

#include <cstddef>
#include <functional>
#include <glm/vec3.hpp>
#include <vector>

#include "bake/trace_tables.h"
#include "render/medium.h"

namespace firelook::bake {

struct ScatterCells {
    glm::dvec3 origin{0.0};  // index point of the corner of cell (0,0,0)
    int edge = 2;            // voxels
    glm::ivec3 count{0};
    std::vector<int> slot;  // per cell, -1 where there is no density
    int slots = 0;
    // Per slot and grid point: M = integral of sigma_s over the cell, in world volume.
    std::vector<float> mass;
    // Unit cubes with density that were integrated, those whose temperatures were smooth enough
    // for 2 Gauss points along every axis, and those that took 3 along some axis and 4 along none
    // (each axis takes 2, 3 or 4 by its own temperature change: scatter_cells.cpp); the Gauss
    // points of all of them.
    std::size_t cubes = 0, smooth_cubes = 0, varied_cubes = 0, gauss_points = 0;

    std::size_t cellIndex(const glm::ivec3& c) const {
        return static_cast<std::size_t>(c.x) +
               static_cast<std::size_t>(count.x) * (static_cast<std::size_t>(c.y) +
                                                    static_cast<std::size_t>(count.y) * static_cast<std::size_t>(c.z));
    }
    // The slot of the cell holding an index point, -1 outside or where there is no density.
    int slotAt(const glm::dvec3& index_point) const;
    // Trilinear interpolation between cell centres, clamped at the grid's faces, over the corners
    // that have density only (their weights renormalised): returns how many corners were written.
    int corners(const glm::dvec3& index_point, int* slots_out, float* weights_out) const;
    // 1 / M of a slot's grid points (0 where M is 0): what turns the integral of sigma_s Lbar over
    // the cell into Lbar.
    void inverseMasses(int slot, int points, float* inverse) const {
        for (int g = 0; g < points; ++g) {
            const float m = mass[static_cast<std::size_t>(slot) * points + g];
            inverse[g] = m > 0.0f ? 1.0f / m : 0.0f;
        }
    }
};

// Cell edge in voxels: at least `min_voxels`, and coarse enough that no axis of the influence box
// has more than `max_per_axis` cells (the scattered light is smooth; its memory and photon noise
// then follow the world extent, not the resolution).
int scatterCellEdge(const render::Medium& medium, int min_voxels, int max_per_axis);
// Cells of that edge along each axis of the medium's influence box, and all of them.
glm::ivec3 scatterCellCounts(const render::Medium& medium, int edge);
std::size_t scatterCellCount(const render::Medium& medium, int edge);
// Cells touched by the medium's non-empty bricks: an upper bound on the slots buildScatterCells
// gives, from brick data only (no sampling), for the memory plan.
std::size_t scatterSlotUpperBound(const render::Medium& medium, int edge);

// progress(fraction done), called from the worker threads, returns false to stop: the cells are
// then left partly summed and the caller must not use them (it throws its cancel).
ScatterCells buildScatterCells(const render::Medium& medium, const TraceTables& tables, int edge,
                               const std::function<bool(double)>& progress = {});

// Calls visit(cube_lower_corner, corners, rho, t) for every unit index cube of the medium's bricks
// that holds density, with its eight voxels (Medium::cubeCorners) and the values at its centre,
// z-slab by z-slab: slabs [z0, z1) of cube layers (relative to the influence box's low corner) may
// run in parallel; within a slab the order is fixed.
template <typename Visit>
void forEachCubeInSlab(const render::Medium& medium, int z0, int z1, Visit&& visit) {
    const glm::ivec3 bricks = medium.brickCounts();
    const glm::ivec3 lo = medium.origin() - 1;
    const int size = render::Medium::kBrickSize;
    for (int z = z0; z < z1; ++z) {
        const int bz = z / size;
        if (bz >= bricks.z) return;
        for (int by = 0; by < bricks.y; ++by)
            for (int bx = 0; bx < bricks.x; ++bx) {
                if (!(medium.brick({bx, by, bz}).max_density > 0.0f)) continue;
                for (int y = by * size; y < (by + 1) * size; ++y)
                    for (int x = bx * size; x < (bx + 1) * size; ++x) {
                        const glm::ivec3 q = lo + glm::ivec3(x, y, z);
                        glm::vec2 corners[8];
                        medium.cubeCorners(q, corners);
                        const render::MediumSample s = render::Medium::interpolate(corners, glm::vec3(0.5f));
                        if (s.density > 0.0f) visit(q, corners, s.density, s.temperature);
                    }
            }
    }
}

}  // namespace firelook::bake
