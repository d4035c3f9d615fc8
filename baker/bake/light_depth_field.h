// Optical depths toward each directional light (smoke and flame parts per sampled T_c) on a
// lattice over the medium, so the single-scatter source sigma_s tau_light needs no shadow ray per
// sample. The lattice spacing is a whole number of voxels chosen so that no axis has more than a
// set number of points: shadows are resolved to the voxel on small volumes and to a fixed world
// resolution on large ones, and the memory is bounded.
#pragma once

#include <atomic>
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

// LightStep and LightStepCandidate (one measured step) are in basis_tracer.h, whose FrameBasis
// reports them.

// One lattice point of every kLightStepCheckStride^3 block is checked.
inline constexpr int kLightStepCheckStride = 4;
// A light's coarser step is judged on at least this many checked points with density that its
// march reaches (as the camera's: kMinStepCheckPixels); fewer keep the finest step.
inline constexpr int kMinLightCheckPoints = 32;

// Each light's depths' march step, chosen per frame as the camera rays' is (camera_quadrature.h):
// from the checked points, marches at step_voxels times the spacing and at step_scales (ascending,
// each above 1) times that; the coarsest whose source_error and mean_change are within the
// allowances is taken, or the finest. Per light, so that adding a light changes no other light's
// depths. The midpoint rule's error is the field's: frame 12 of the bundled sample upsampled 4x is
// smooth at the voxel scale, the sample's own frames are not. Checked points are measured in
// parallel and summed in layer order: the same choice on any number of threads.
std::vector<LightStep> chooseLightSteps(const render::Medium& medium, const BasisModel& model,
                                        const TraceTables& tables, const ScatterCells& cells, int spacing,
                                        double step_voxels, const std::vector<int>& step_scales,
                                        double error_allowance, double mean_change_allowance,
                                        const std::atomic<bool>& stop);

// Marches toward each light from every lattice point near density, at step_voxels[light] (voxels:
// LightStep::step_voxels); a march stops once even the thinnest grid point's transmittance is
// negligible (so thick media cost little).
// progress(fraction done), called from the worker threads, returns false to stop: the field is then
// incomplete and the caller must not use it (it throws its cancel).
LightDepthField buildLightDepths(const render::Medium& medium, const BasisModel& model, const TraceTables& tables,
                                 const ScatterCells& cells, int spacing, const std::vector<double>& step_voxels,
                                 const std::function<bool(double)>& progress = {});

}  // namespace firelook::bake
