#pragma once

#include <openvdb/openvdb.h>

#include "vdb/volume_frame.h"

namespace firelook::vdb {

// The sparse grids of a VolumeFrame (see volume_frame.h for the conventions they follow). Both
// share one linear transform; they are read-only once loaded.
struct FrameGrids {
    openvdb::FloatGrid::ConstPtr density;
    openvdb::FloatGrid::ConstPtr temperature;
};

}  // namespace firelook::vdb
