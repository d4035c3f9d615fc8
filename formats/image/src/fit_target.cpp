#include "image/fit_target.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "common/error.h"

#include "image/image_io.h"
#include "image/srgb.h"

namespace firelook::image {
namespace {

// d(sRGB)/d(linear) at v: the weight that makes a linear error count as it shows on a display.
// Below the sRGB curve's linear toe the slope is the toe's, 12.92.
double srgbSlope(double v) {
    v = std::max(v, 0.0031308);
    return v >= 1.0 ? 0.0 : 1.055 / 2.4 * std::pow(v, 1.0 / 2.4 - 1.0);
}

std::string sizeText(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

// Coded (common/error.h) so that the C API tells a file it cannot read from a target that does not fit.
[[noreturn]] void throwUnreadable(const std::string& message) { throw Error(ErrorCode::IoError, message); }
[[noreturn]] void throwUnfit(const std::string& message) { throw Error(ErrorCode::InvalidArgument, message); }

ImageRGBA readCoded(const std::string& path) {
    try {
        return readImage(path);
    } catch (const Error& e) {
        throwUnreadable(e.what());  // names the file; any reading failure is the file's
    }
}

}  // namespace

bool isPngPath(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext == ".png";
}

FitTargetImage readFitTarget(const FitTargetRequest& request) {
    const std::string& path = request.target;
    const std::string frame = std::to_string(request.frame);
    if (!std::filesystem::exists(path)) throwUnreadable(path + ": no such target image (frame " + frame + ")");
    const ImageRGBA img = readCoded(path);
    if (img.width != request.width || img.height != request.height)
        throwUnfit(path + ": " + sizeText(img.width, img.height) + ", but the package's images are " +
                   sizeText(request.width, request.height));
    const size_t pixels = static_cast<size_t>(request.width) * static_cast<size_t>(request.height);
    FitTargetImage target;
    target.rgba = img.pixels;
    for (float v : target.rgba)
        if (!std::isfinite(v)) throwUnfit(path + ": holds a value that is not finite");
    target.weight.assign(pixels, 1.0f);
    if (!request.mask.empty()) {
        if (!std::filesystem::exists(request.mask)) throwUnreadable(request.mask + ": no such mask image");
        const ImageRGBA mask = readCoded(request.mask);
        if (mask.width != request.width || mask.height != request.height)
            throwUnfit(request.mask + ": mask is " + sizeText(mask.width, mask.height) +
                       ", but the package's images are " + sizeText(request.width, request.height));
        for (size_t p = 0; p < pixels; ++p) {
            const float m = mask.pixels[4 * p];
            target.weight[p] = std::isfinite(m) ? std::clamp(m, 0.0f, 1.0f) : 0.0f;
        }
    }
    bool opaque = true;
    for (size_t p = 0; p < pixels; ++p) opaque = opaque && target.rgba[4 * p + 3] >= 1.0f;
    target.match_alpha = !request.background && !opaque;
    if (request.background) target.background = *request.background;

    const bool png = isPngPath(path);
    if (png) {
        // 254.5 / 255 in sRGB: a channel stored as 255 may have been clipped.
        const double clip = srgbToLinear(254.5 / 255.0);
        for (size_t p = 0; p < pixels; ++p) {
            float* t = target.rgba.data() + 4 * p;
            const double alpha = t[3];
            bool clipped = false;
            for (int c = 0; c < 3; ++c) clipped = clipped || (alpha > 0.0 && t[c] / alpha >= clip);
            const double shown = 0.2126 * t[0] + 0.7152 * t[1] + 0.0722 * t[2];
            const double slope = srgbSlope(shown);
            if (clipped && target.weight[p] > 0.0f) ++target.clipped_pixels;
            target.weight[p] = clipped ? 0.0f : static_cast<float>(target.weight[p] * slope * slope);
        }
    }
    if (std::all_of(target.weight.begin(), target.weight.end(), [](float w) { return w == 0.0f; }))
        throwUnfit((request.mask.empty() ? path : request.mask) + ": leaves no pixel of frame " + frame +
                   " to fit (" + (request.mask.empty() ? "every pixel is clipped" : "the mask is 0 everywhere") +
                                 (request.mask.empty() || !png ? "" : " or clipped") + ")");
    const float unexpose = static_cast<float>(std::exp2(-request.exposure));
    for (size_t p = 0; p < pixels; ++p)
        for (int c = 0; c < 3; ++c) target.rgba[4 * p + c] *= unexpose;
    // The background was drawn exposed too.
    if (!target.match_alpha)
        for (float& b : target.background) b *= unexpose;
    return target;
}

std::vector<float> fitDifference(const std::vector<float>& target_rgba, bool match_alpha,
                                 const std::array<float, 3>& background, const std::vector<float>& fit_rgba) {
    if (target_rgba.size() != fit_rgba.size())
        throw Error(ErrorCode::InvalidArgument, "fitDifference: the target and the fit differ in size");
    std::vector<float> difference(fit_rgba.size());
    for (size_t p = 0; p < fit_rgba.size() / 4; ++p) {
        const float* i = fit_rgba.data() + 4 * p;
        const float uncovered = match_alpha ? 0.0f : 1.0f - i[3];
        for (int c = 0; c < 3; ++c)
            difference[4 * p + c] = std::abs(i[c] + uncovered * background[c] - target_rgba[4 * p + c]);
        difference[4 * p + 3] = 1.0f;
    }
    return difference;
}

}  // namespace firelook::image
