// The ImGui panels: package, playback, look editor, keyframes, display, QA, export, timings, and
// the viewport with the real-time image (beside the QA reference and its error heat map).
#pragma once

#include <string>

#include "fire_light_markers.h"
#include "fire_probe_dots.h"
#include "viewer_app.h"

namespace firelook::viewer {

// Text fields the panels keep between frames.
struct UiState {
    std::string package_path;
    std::string look_path = "look.json";
    std::string keyframes_path = "keyframes.json";
    std::string export_path = "frame.exr";
    std::string export_pattern = "frames/fire_####.exr";
    FireLightView fire_lights;
    FireProbeView fire_probes;
};

// Draws every window for one frame (between ImGui::NewFrame and ImGui::Render).
void drawUi(ViewerApp& app, UiState& ui, int window_width, int window_height);

}  // namespace firelook::viewer
