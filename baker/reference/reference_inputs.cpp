#include "reference/reference_inputs.h"

#include "look/look.h"
#include "reference/frame_medium.h"
#include "reference/provenance_read_options.h"
#include "vdb/vdb_sequence.h"

namespace firelook::reference {

ReferenceInputs referenceInputs(const BakedScene& scene, const std::string& package_name,
                                const std::string& sequence_path, int frame, std::string_view look_json) {
    const vdb::ReadOptions read = provenanceReadOptions(scene.metadata_json, package_name);
    render::Camera camera(scene.camera);  // checked before the slow part
    LookModel model = makeLookModel(parseLook(look_json, "look"), scene.bins, scene.rbf_width, scene.light_directions);
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(sequence_path, read);
    return {mediumFromFrame(sequence.load(frame)), std::move(camera), std::move(model)};
}

}  // namespace firelook::reference
