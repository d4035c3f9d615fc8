// Export of the reconstructed image with the project's image library (firelook::image): EXR holds
// linear premultiplied RGBA exactly as `firelook render` writes it; PNG is 8-bit sRGB after the
// viewer's exposure, optionally composited over the solid background. Writes are atomic.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "look_edit.h"

namespace firelook::viewer {

struct ExportOptions {
    bool float_exr = false;   // EXR 32-bit floats instead of half (exact values)
    float png_exposure_stops = 0.0f;
    std::optional<Rgb3> png_background;  // composite PNGs over this linear colour (opaque PNG)
};

// rgba: width x height x 4, top row first; flare (may be null) is added to RGB first. The file's
// folder is created if missing.
// Throws (image::ImageError / ViewerError) naming the file.
void exportImage(const std::string& path, const std::vector<float>& rgba, const std::vector<float>* flare, int width,
                 int height, const ExportOptions& options);

// The file for one frame of a sequence export: a run of '#' in `pattern` becomes the zero-padded
// frame number ("fire_####.exr" -> "fire_0012.exr"); without '#', "_NNNN" goes before the extension.
std::string sequenceFramePath(const std::string& pattern, int frame);

}  // namespace firelook::viewer

namespace firelook::viewer {

// The window's pixels (RGBA8, sRGB-encoded, bottom row first as glReadPixels gives them) as an
// opaque PNG, for --ui-screenshot.
void writeWindowPng(const std::string& path, const std::vector<unsigned char>& rgba8_bottom_up, int width,
                    int height);

}  // namespace firelook::viewer
