// The fire's probe grid (fl_instance_get_fire_probes, firelook.h) drawn over the real-time image: a
// dot per probe where the package's camera sees it, coloured by the fluence rate the fire gives there
// (scaled so the brightest probe is white at most), so the irradiance volume an engine lights its
// scene with can be checked against the fire it stands for; and the panel that shows it.
#pragma once

#include <imgui.h>

#include "fire_session.h"

namespace firelook::viewer {

struct FireProbeView {
    bool show = true;  // only packages baked with --fire-probes have any
};

// The panel: on/off, the grid's size and the fluence range (or why there are none).
void fireProbePanel(FireSession& session, FireProbeView& view);

// Draws the dots into the current window's draw list over the image at [image_min, image_max].
// Nothing for a package without fire probes or camera, or before the first update.
void drawFireProbeDots(FireSession& session, const FireProbeView& view, ImVec2 image_min, ImVec2 image_max);

}  // namespace firelook::viewer
