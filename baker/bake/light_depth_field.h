// Optical depths toward each directional light (smoke and flame parts per sampled T_c) on a
// lattice over the medium, so the single-scatter source sigma_s tau_light needs no shadow ray per
// sample. The lattice spacing is a whole number of voxels chosen so that no axis has more than a
// set number of points: shadows are resolved to the voxel on small volumes and to a fixed world
// resolution on large ones, and the memory is bounded.
#pragma once

#include <cstddef>
#include <functional>
#include <glm/vec3.hpp>
#include <vector>

#include "bake/basis_tracer.h"
#include "bake/scatter_cells.h"
#include "bake/trace_tables.h"
#include "render/medium.h"

namespace firelook::bake {

struct LightDepthField {
    glm::dvec3 origin{0.0};  // index point of lattice point (0,0,0)
    int spacing = 1;         // voxels between lattice points
    glm::ivec3 count{0};
    int n_tc = 0;
    std::vector<float> depths;  // [light][point][2 * n_tc]: smoke then flame

    // Trilinear interpolation of the depths toward one light at an index point.
    void sample(int light, const glm::dvec3& index_point, float* smoke, float* flame) const;
};

int lightLatticeSpacing(const render::Medium& medium, int max_per_axis);
glm::ivec3 lightLatticeCount(const render::Medium& medium, int spacing);

// Marches toward each light from every lattice point near density; a march stops once even the
// thinnest grid point's transmittance is negligible (so thick media cost little).
// progress(fraction done), called from the worker threads, returns false to stop: the field is then
// incomplete and the caller must not use it (it throws its cancel).
LightDepthField buildLightDepths(const render::Medium& medium, const BasisModel& model, const TraceTables& tables,
                                 const ScatterCells& cells, int spacing, double step_voxels,
                                 const std::function<bool(double)>& progress = {});

}  // namespace firelook::bake
