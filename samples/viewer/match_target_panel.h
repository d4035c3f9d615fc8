// The "Match target" panel's ImGui drawing (the logic is fit_session.h, the glue ViewerApp).
#pragma once

#include "viewer_app.h"

namespace firelook::viewer {

// Target and mask fields, Fit / Cancel with a progress bar, the fit's errors, Accept.
void matchTargetPanel(ViewerApp& app);

// The viewport's target | fit | difference row; false (nothing drawn) unless a finished fit is shown.
bool matchTargetImages(ViewerApp& app, float width, float aspect);

}  // namespace firelook::viewer
