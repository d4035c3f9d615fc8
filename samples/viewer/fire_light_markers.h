// The fire's point lights (fl_instance_get_fire_lights, firelook.h) drawn over the real-time image:
// a circle per light where the package's camera sees its position, as wide as its radius, filled with
// its colour; and the panel that picks how many.
#pragma once

#include <imgui.h>

#include <string>

#include "fire_session.h"

namespace firelook::viewer {

struct FireLightView {
    bool show = true;
    int count = 8;  // a power of two up to what the package stores
};

// The panel: on/off, the count, and each light's intensity and radius (or why there are none).
void fireLightPanel(FireSession& session, FireLightView& view);

// Draws the markers into the current window's draw list over the image at [image_min, image_max].
// Nothing for a package without fire lights or camera, or before the first update.
void drawFireLightMarkers(FireSession& session, const FireLightView& view, ImVec2 image_min, ImVec2 image_max);

}  // namespace firelook::viewer
