// What the reference path tracer (render::renderReference) takes to render one frame of a package
// as its bake saw it: the frame's medium read from the sequence with the package's provenance
// (provenance_read_options.h), the package's camera, and the look model of a look file over the
// package's bins and lights. The viewer's QA reference (samples/viewer/reference_worker.cpp) gets
// everything through this header, which names no vdb or OpenVDB type.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "look/look_model.h"
#include "render/camera.h"
#include "render/medium.h"

namespace firelook::reference {

// What a package records about its bake, as its reader gets it (the C API:
// fl_package_get_metadata_json, fl_package_get_camera, fl_package_get_lights, fl_package_info).
struct BakedScene {
    std::string metadata_json;  // its "provenance" names the grids and their mapping
    render::CameraParameters camera;
    std::vector<glm::dvec3> light_directions;  // the direction each light travels
    TemperatureBins bins;
    double rbf_width = 0.0;
};

struct ReferenceInputs {
    render::Medium medium;
    render::Camera camera;
    LookModel model;
};

// Reads frame `frame` of the sequence at sequence_path as the package's provenance says and makes
// the look model of look_json (a look file's text). Throws firelook::Error naming the source and
// the problem: package_name for its provenance or camera, the frame's file for the volume, "look"
// for the look.
ReferenceInputs referenceInputs(const BakedScene& scene, const std::string& package_name,
                                const std::string& sequence_path, int frame, std::string_view look_json);

}  // namespace firelook::reference
