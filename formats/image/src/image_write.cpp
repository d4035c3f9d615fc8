#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include "common/atomic_file.h"
#include "common/error.h"
#include "image/image_io.h"
#include "image_format.h"
#include "png_pixels.h"

namespace firelook::image {
namespace {

// The largest finite half; anything larger would be stored as infinity.
constexpr float kHalfMax = 65504.0f;

std::string formatValue(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", static_cast<double>(value));
    return text;
}

std::string pixelName(const ImageRGBA& image, std::size_t value_index) {
    static constexpr char kChannels[] = "RGBA";
    const std::size_t pixel = value_index / 4;
    return "pixel (" + std::to_string(pixel % static_cast<std::size_t>(image.width)) + ", " +
           std::to_string(pixel / static_cast<std::size_t>(image.width)) + ") channel " +
           kChannels[value_index % 4];
}

void checkWritable(const std::filesystem::path& path, const ImageRGBA& image, bool stored_as_half) {
    if (image.width <= 0 || image.height <= 0) {
        throw ImageError(path.string() + ": cannot write an empty image (" + std::to_string(image.width) +
                         "x" + std::to_string(image.height) + ")");
    }
    const std::size_t expected =
        4 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
    if (image.pixels.size() != expected) {
        throw ImageError(path.string() + ": image of " + std::to_string(image.width) + "x" +
                         std::to_string(image.height) + " holds " + std::to_string(image.pixels.size()) +
                         " values instead of " + std::to_string(expected));
    }
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        const float value = image.pixels[i];
        if (!std::isfinite(value)) {
            throw ImageError(path.string() + ": refusing to write non-finite value " + formatValue(value) +
                             " at " + pixelName(image, i));
        }
        if (stored_as_half && std::fabs(value) > kHalfMax) {
            throw ImageError(path.string() + ": value " + formatValue(value) + " at " + pixelName(image, i) +
                             " exceeds the half-float range (65504); write float EXR instead");
        }
    }
}

// Opens, writes and closes one OpenImageIO output at `temporary`; errors name `target`.
void writeWithOiio(const std::filesystem::path& target, const std::filesystem::path& temporary,
                   detail::FileFormat format, const OIIO::ImageSpec& spec, OIIO::TypeDesc data_type,
                   const void* data) {
    auto output = OIIO::ImageOutput::create(detail::oiioFormatName(format));
    if (!output) {
        throw ImageError(target.string() + ": OpenImageIO cannot create a writer: " + OIIO::geterror());
    }
    if (!output->open(temporary.string(), spec)) {
        throw ImageError(target.string() + ": cannot open for writing: " + output->geterror());
    }
    const bool written = output->write_image(data_type, data);
    const bool closed = output->close();
    if (!written || !closed) {
        throw ImageError(target.string() + ": cannot write: " + output->geterror());
    }
}

void writeExr(const std::filesystem::path& target, const std::filesystem::path& temporary,
              const ImageRGBA& image, ExrPixelType pixel_type) {
    OIIO::ImageSpec spec(image.width, image.height, 4,
                         pixel_type == ExrPixelType::Half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", "zip");
    spec.attribute("oiio:ColorSpace", "Linear");
    spec.attribute("Software", "FireLook");
    writeWithOiio(target, temporary, detail::FileFormat::Exr, spec, OIIO::TypeDesc::FLOAT,
                  image.pixels.data());
}

void writePng(const std::filesystem::path& target, const std::filesystem::path& temporary,
              const ImageRGBA& image, const WriteOptions& options) {
    const detail::Png8Pixels pixels =
        detail::encodePng8(image, options.png_exposure_stops, options.png_background);
    OIIO::ImageSpec spec(image.width, image.height, pixels.channels, OIIO::TypeDesc::UINT8);
    // The colour is already un-premultiplied; OpenImageIO must not divide by alpha a second time.
    spec.attribute("oiio:UnassociatedAlpha", 1);
    spec.attribute("oiio:ColorSpace", "sRGB");
    spec.attribute("Software", "FireLook");
    writeWithOiio(target, temporary, detail::FileFormat::Png, spec, OIIO::TypeDesc::UINT8,
                  pixels.values.data());
}

}  // namespace

void writeImage(const std::filesystem::path& path, const ImageRGBA& image, const WriteOptions& options) {
    const detail::FileFormat format = detail::formatFromExtension(path);
    checkWritable(path, image,
                  format == detail::FileFormat::Exr && options.exr_pixel_type == ExrPixelType::Half);
    if (format == detail::FileFormat::Png && !std::isfinite(options.png_exposure_stops)) {
        throw ImageError(path.string() + ": PNG exposure is not finite");
    }
    try {
        writeFileAtomically(path, [&](const std::filesystem::path& temporary) {
            if (format == detail::FileFormat::Exr) {
                writeExr(path, temporary, image, options.exr_pixel_type);
            } else {
                writePng(path, temporary, image, options);
            }
        });
    } catch (const firelook::Error& error) {
        throw ImageError(error.code(),
                         error.what());  // the temporary's failures (its message names the file)
    }
}

void writeDataImage(const std::filesystem::path& path, const ImageRGBA& image, const WriteOptions& options) {
    const detail::FileFormat format = detail::formatFromExtension(path, /*allow_tga=*/true);
    checkWritable(path, image,
                  format == detail::FileFormat::Exr && options.exr_pixel_type == ExrPixelType::Half);
    std::vector<std::uint8_t> bytes;
    if (format != detail::FileFormat::Exr) {
        bytes.resize(image.pixels.size());
        for (std::size_t i = 0; i < bytes.size(); ++i)
            bytes[i] = static_cast<std::uint8_t>(std::lround(std::clamp(image.pixels[i], 0.0f, 1.0f) * 255.0f));
    }
    try {
        writeFileAtomically(path, [&](const std::filesystem::path& temporary) {
            if (format == detail::FileFormat::Exr) {
                writeExr(path, temporary, image, options.exr_pixel_type);
                return;
            }
            OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::UINT8);
            // Data, not colour: no sRGB curve, and alpha is a channel like the others.
            spec.attribute("oiio:UnassociatedAlpha", 1);
            spec.attribute("oiio:ColorSpace", "Linear");
            spec.attribute("Software", "FireLook");
            writeWithOiio(path, temporary, format, spec, OIIO::TypeDesc::UINT8, bytes.data());
        });
    } catch (const firelook::Error& error) {
        throw ImageError(error.code(), error.what());
    }
}

}  // namespace firelook::image
