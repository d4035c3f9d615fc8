// Reading a look fit's target image and mask (issue 17): what `firelook fit` and the viewer's
// "Match target" panel both compare, read one way. EXR is linear premultiplied RGBA; PNG is read
// through the display transform `render` uses for PNG, the exposure undone, each pixel weighted by
// the sRGB curve's slope at its shown value (so a fit minimises the error as displayed, to first
// order) and clipped pixels left out.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace firelook::image {

struct FitTargetRequest {
    std::string target;  // .exr or .png
    std::string mask;    // empty: no mask; else the weight per pixel is its red channel, clamped to [0, 1]
    int width = 0, height = 0;  // the package's image size the target must have
    int frame = 0;              // named in error messages
    // Linear RGB the target was composited over; its alpha is then not matched.
    std::optional<std::array<float, 3>> background;
    double exposure = 0.0;  // stops the target was exposed by (undone on the colour and background)
};

struct FitTargetImage {
    std::vector<float> rgba;    // pixels x 4, linear, premultiplied, top row first, exposure undone
    std::vector<float> weight;  // pixels, in [0, ...); at least one above 0
    // A target opaque everywhere, or any target with a background, is the effect composited over
    // that background (black by default); otherwise its alpha is matched.
    bool match_alpha = true;
    std::array<float, 3> background{0.0f, 0.0f, 0.0f};  // exposure undone
    size_t clipped_pixels = 0;  // PNG pixels with weight left out because a channel was clipped
};

bool isPngPath(const std::string& path);

// Throws ImageError naming the file (code IoError for a missing file, else BadImage): missing,
// unreadable, another size than width x height, a value that is not finite, or no pixel left to fit
// (mask 0 everywhere, or every pixel clipped).
FitTargetImage readFitTarget(const FitTargetRequest& request);

// |fit - target| per pixel in linear RGB, opaque (alpha 1): where alpha is not matched the fit is
// composited over the background first, as the fit compared it. fit_rgba: premultiplied, as rendered.
std::vector<float> fitDifference(const std::vector<float>& target_rgba, bool match_alpha,
                                 const std::array<float, 3>& background, const std::vector<float>& fit_rgba);

}  // namespace firelook::image
