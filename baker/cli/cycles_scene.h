// What `firelook export-cycles` writes: a Python script for Blender that builds one frame of a
// package with one look in Cycles and renders it (docs/cli.md, "export-cycles"). The script is the
// scene's numbers as a JSON document followed by cycles_scene.py, which reads only them.
#pragma once

#include <string>

#include "basis/basis_package.h"
#include "look/look.h"

namespace firelook::cli {

// How Cycles marches and bounces. The step: against 0.25 voxel, 1 voxel moved a 64x64 image by at
// most 0.28% relative RMSE and 0.02% image mean (README, "Blender"); 0.5 keeps a quarter of that.
struct CyclesSettings {
    double step_voxels = 0.5;    // the volume's step in voxels of its density grid
    int volume_max_steps = 8192;  // so that the step is never stretched to fit the cap
    int volume_bounces = 1024;   // scattering orders; Russian roulette ends paths long before
};

// The script for frame `frame` of `package` with `look`: the package's camera, the lights the look
// turns on (irradiance not zero), its bins, RBF width and emission rule, the look's extinction,
// albedo and non-negative emission fit, and the frame's VDB file read as the package's provenance
// says (its grids, the temperature and density mappings). The file is found in `sequence` (a
// package knows its sequence by content, not path: docs/cli.md). Throws firelook::Error naming the package,
// the look or the file: a frame the package does not hold, a look whose albedo differs from the
// package's, a package without a camera or provenance, a frame the sequence lacks.
std::string cyclesSceneScript(const basis::BasisReader& package, const std::string& package_name, int frame,
                              const Look& look, const std::string& sequence,
                              const CyclesSettings& settings = {});

}  // namespace firelook::cli
