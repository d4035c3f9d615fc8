#include <OpenImageIO/imageio.h>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "image/image_io.h"
#include "image_format.h"
#include "png_pixels.h"

namespace firelook::image {
namespace {

// Straight (colour, alpha) RGBA from a file's channels: three or more colour channels give R, G, B
// from the first three; fewer give grey from the first. Alpha comes from the alpha channel if there
// is one, else the image is opaque.
ImageRGBA toRgba(const OIIO::ImageSpec& spec, const std::vector<float>& values) {
    std::vector<int> colour_channels;
    for (int c = 0; c < spec.nchannels; ++c) {
        if (c != spec.alpha_channel) colour_channels.push_back(c);
    }
    std::array<int, 3> source{-1, -1, -1};  // file channel feeding R, G, B; -1: none, reads as 0
    for (std::size_t c = 0; c < 3 && !colour_channels.empty(); ++c) {
        source[c] = colour_channels.size() >= 3 ? colour_channels[c] : colour_channels[0];
    }

    ImageRGBA image(spec.width, spec.height);
    const std::size_t stride = static_cast<std::size_t>(spec.nchannels);
    for (std::size_t p = 0; p < image.pixels.size() / 4; ++p) {
        const float* in = &values[p * stride];
        float* out = &image.pixels[4 * p];
        for (std::size_t c = 0; c < 3; ++c) out[c] = source[c] >= 0 ? in[source[c]] : 0.0f;
        out[3] = spec.alpha_channel >= 0 ? in[spec.alpha_channel] : 1.0f;
    }
    return image;
}

}  // namespace

namespace {

// The file's channels as straight floats (8-bit values / 255), checked.
ImageRGBA readChannels(const std::filesystem::path& path, detail::FileFormat format) {
    if (!std::filesystem::exists(path))
        throw ImageError(ErrorCode::IoError, path.string() + ": no such file");

    auto input = OIIO::ImageInput::create(detail::oiioFormatName(format));
    if (!input) throw ImageError(path.string() + ": OpenImageIO cannot create a reader: " + OIIO::geterror());
    OIIO::ImageSpec config;
    // Keep PNG colour as stored (straight); premultiplying is done below, after sRGB decoding.
    config.attribute("oiio:UnassociatedAlpha", 1);
    OIIO::ImageSpec spec;
    if (!input->open(path.string(), spec, config)) {
        throw ImageError(path.string() + ": cannot open as " + detail::oiioFormatName(format) + ": " +
                         input->geterror());
    }
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth != 1) {
        throw ImageError(path.string() + ": not a flat 2D image with channels");
    }
    std::vector<float> values(static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height) *
                              static_cast<std::size_t>(spec.nchannels));
    const bool read = input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, values.data());
    input->close();
    if (!read) throw ImageError(path.string() + ": cannot read pixels: " + input->geterror());

    return toRgba(spec, values);
}

}  // namespace

ImageRGBA readImage(const std::filesystem::path& path) {
    const detail::FileFormat format = detail::formatFromExtension(path);
    ImageRGBA image = readChannels(path, format);
    if (format == detail::FileFormat::Png) detail::decodeSrgbStraightAlpha(image);
    return image;
}

ImageRGBA readDataImage(const std::filesystem::path& path) {
    return readChannels(path, detail::formatFromExtension(path, /*allow_tga=*/true));
}

}  // namespace firelook::image
