// The look computations the editor needs beyond JSON in and out, through the C API:
//  - the emissivity at each bin centre of a preset or colour-stop emission, which the per-bin
//    editor starts from (fl_look_get_bin_emissivity);
//  - each bin's centre temperature, by the formula firelook.h documents there.
// The look an instance shows while keyframes play (for the QA reference) is FireSession's
// shownLookJson() (fl_instance_get_look).
#pragma once

#include <vector>

#include "firelook/firelook.h"
#include "look_edit.h"

namespace firelook::viewer {

// The emissivity e_i at each of `package`'s bin centres. Throws ViewerError for a bad look.
std::vector<Rgb3> resolveBins(const LookEdit& look, fl_package package);

// The temperature at the centre of bin i.
double binCentre(const fl_package_info& info, int bin);

}  // namespace firelook::viewer
