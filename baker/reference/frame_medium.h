// The tracers' medium of one loaded frame, in one place for the bake, `firelook reference`,
// `firelook bench` and the viewer's QA reference (reference_inputs.h).
#pragma once

#include "render/medium.h"
#include "vdb/volume_frame.h"

namespace firelook::reference {

// A dense copy of the frame's sparse grids (vdb::toDense); an empty medium when the density grid
// has no active voxel.
render::Medium mediumFromFrame(const vdb::VolumeFrame& frame);

}  // namespace firelook::reference
