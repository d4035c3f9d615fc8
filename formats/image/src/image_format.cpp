#include "image_format.h"

#include <algorithm>
#include <cctype>
#include <string>

#include "image/image.h"

namespace firelook::image::detail {

FileFormat formatFromExtension(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension == ".exr") return FileFormat::Exr;
    if (extension == ".png") return FileFormat::Png;
    throw ImageError(path.string() + ": unsupported image extension '" + path.extension().string() +
                     "' (expected .exr or .png)");
}

const char* oiioFormatName(FileFormat format) { return format == FileFormat::Exr ? "openexr" : "png"; }

}  // namespace firelook::image::detail
