#include "reference/frame_medium.h"

#include "vdb/dense_volume.h"

namespace firelook::reference {

render::Medium mediumFromFrame(const vdb::VolumeFrame& frame) {
    const vdb::DenseVolume dense = vdb::toDense(frame);
    if (dense.voxelCount() == 0) return render::Medium();
    return render::Medium(dense.origin, dense.dims, dense.density, dense.temperature, dense.index_to_world, 0.0f);
}

}  // namespace firelook::reference
