// Writing and reading FireLook images as OpenEXR (linear HDR) or 8-bit PNG (display-referred).
//
// The format follows the file name's extension, case-insensitively: ".exr" or ".png"; any other
// extension is an ImageError. Writes are atomic: the image goes to a temporary file in the same
// folder, which is renamed over the target only once complete, so a failed write leaves neither a
// half-written target nor a temporary file behind. Pixels that are NaN or infinite are refused with
// an ImageError naming the file, never written.
//
// EXR: channels R, G, B, A, linear, premultiplied (EXR's own convention), ZIP compression, half
// floats by default. Half holds finite values only up to 65504: a larger value is refused rather
// than silently turned into infinity; write floats for such images.
//
// PNG: 8 bits per channel. Colour is scaled by 2^png_exposure_stops, then sRGB-encoded and clamped to
// [0, 1]. Alpha is kept and stored un-premultiplied as PNG requires (colour = rgb / alpha), so
// emission seen through almost no opacity (rgb > 0, alpha ~ 0) cannot survive: its colour clamps to
// 1 and where alpha quantises to 0 it is lost. Set png_background to composite over a solid colour
// instead (final = exposed rgb + (1 - alpha) * background) and write an opaque PNG, which keeps
// every pixel's colour up to clamping and quantisation.
#pragma once

#include <array>
#include <filesystem>
#include <optional>

#include "image/image.h"

namespace firelook::image {

enum class ExrPixelType { Half, Float };

struct WriteOptions {
    ExrPixelType exr_pixel_type = ExrPixelType::Half;
    // PNG only: exposure in stops, applied to linear colour before the sRGB encoding.
    double png_exposure_stops = 0.0;
    // PNG only: linear RGB background to composite over, after the exposure; writes alpha = 1.
    std::optional<std::array<float, 3>> png_background;
};

// Throws ImageError naming the file on a bad extension, a malformed image (size and pixel count
// disagree, or an empty image), a non-finite pixel, a half overflow, or any I/O failure.
void writeImage(const std::filesystem::path& path, const ImageRGBA& image, const WriteOptions& options = {});

// Channel-packed data textures (flipbook atlases, runtime/flipbook): the four channels exactly as
// given, with no colour encoding and no alpha convention (nothing is premultiplied or divided).
// ".exr" as writeImage (linear, half or float); ".png" and ".tga" 8 bits per channel, each value
// clamped to [0, 1] and rounded to the nearest of 255 steps (error at most 1/510). Atomic, and
// non-finite values are refused, as writeImage. Throws ImageError naming the file.
void writeDataImage(const std::filesystem::path& path, const ImageRGBA& image, const WriteOptions& options = {});
// The four channels as stored (8-bit values / 255); a file without alpha reads alpha 1.
ImageRGBA readDataImage(const std::filesystem::path& path);

// For tests and QA. EXR: linear premultiplied floats as stored. PNG: 8-bit values sRGB-decoded to
// linear, then premultiplied by alpha. A file without alpha reads as opaque; a one- or two-channel
// file reads as grey (plus alpha). Throws ImageError naming the file on any failure.
ImageRGBA readImage(const std::filesystem::path& path);

}  // namespace firelook::image
