#include "image_export.h"

#include <cstdio>
#include <filesystem>

#include "image/image_io.h"

namespace firelook::viewer {

void exportImage(const std::string& path, const std::vector<float>& rgba, const std::vector<float>* flare, int width,
                 int height, const ExportOptions& options) {
    image::ImageRGBA out(width, height);
    out.pixels = rgba;
    if (flare && flare->size() == rgba.size())
        for (size_t i = 0; i < rgba.size(); ++i)
            if (i % 4 != 3) out.pixels[i] += (*flare)[i];
    image::WriteOptions w;
    w.exr_pixel_type = options.float_exr ? image::ExrPixelType::Float : image::ExrPixelType::Half;
    w.png_exposure_stops = options.png_exposure_stops;
    if (options.png_background) w.png_background = *options.png_background;
    // A sequence pattern like frames/fire_####.exr names a folder that may not exist yet.
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    std::error_code ignored;
    if (!parent.empty()) std::filesystem::create_directories(parent, ignored);
    image::writeImage(path, out, w);
}

std::string sequenceFramePath(const std::string& pattern, int frame) {
    const size_t first = pattern.find('#');
    if (first != std::string::npos) {
        size_t last = first;
        while (last < pattern.size() && pattern[last] == '#') ++last;
        char number[32];
        std::snprintf(number, sizeof number, "%0*d", static_cast<int>(last - first), frame);
        return pattern.substr(0, first) + number + pattern.substr(last);
    }
    const std::filesystem::path p(pattern);
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, "_%04d", frame);
    return (p.parent_path() / (p.stem().string() + suffix + p.extension().string())).string();
}

}  // namespace firelook::viewer

#include "image/srgb.h"

namespace firelook::viewer {

void writeWindowPng(const std::string& path, const std::vector<unsigned char>& rgba8, int width, int height) {
    // The image library writes linear values sRGB-encoded; decoding the 8-bit values first makes
    // the round trip return the same bytes.
    float table[256];
    for (int v = 0; v < 256; ++v) table[v] = static_cast<float>(image::srgbToLinear(v / 255.0));
    image::ImageRGBA out(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const unsigned char* p = rgba8.data() + 4 * (static_cast<size_t>(height - 1 - y) * width + x);
            const auto px = out.at(x, y);
            px[0] = table[p[0]];
            px[1] = table[p[1]];
            px[2] = table[p[2]];
            px[3] = 1.0f;
        }
    image::writeImage(path, out);
}

}  // namespace firelook::viewer
