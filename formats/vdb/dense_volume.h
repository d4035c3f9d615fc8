#pragma once

#include <cstddef>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "vdb/volume_frame.h"

namespace firelook::vdb {

// A frame resampled onto a dense box of voxels for tracers. Element (i,j,k) of the arrays, x
// fastest (index = i + dims.x * (j + dims.y * k)), is the voxel at index point origin + (i,j,k),
// which sits at world point index_to_world * (origin + (i,j,k), 1) (OpenVDB's convention: no
// half-voxel offset).
struct DenseVolume {
    glm::ivec3 origin{0};
    glm::ivec3 dims{0};
    glm::dmat4 index_to_world{1.0};
    std::vector<float> density;
    std::vector<float> temperature;  // mapped temperatures, like the frame's temperature grid

    std::size_t voxelCount() const {
        return static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) *
               static_cast<std::size_t>(dims.z);
    }
    std::size_t linearIndex(int i, int j, int k) const {
        return static_cast<std::size_t>(i) +
               static_cast<std::size_t>(dims.x) *
                   (static_cast<std::size_t>(j) +
                    static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(k));
    }
};

// Copies the frame's grids onto the index box of the active voxels of BOTH grids, grown by
// padding_voxels on every side (1 by default, so trilinear interpolation reaches the background at
// the border). Voxels outside the active ones read each grid's background. A frame whose density
// grid has no active voxel gives dims (0,0,0) and empty arrays. Throws VdbError if padding_voxels
// is negative or the box would exceed 2^31 voxels.
DenseVolume toDense(const VolumeFrame& frame, int padding_voxels = 1);

}  // namespace firelook::vdb
