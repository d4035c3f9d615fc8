#include "image_format.h"

#include <algorithm>
#include <cctype>
#include <string>

#include "image/image.h"

namespace firelook::image::detail {

FileFormat formatFromExtension(const std::filesystem::path& path, bool allow_tga) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension == ".exr") return FileFormat::Exr;
    if (extension == ".png") return FileFormat::Png;
    if (allow_tga && extension == ".tga") return FileFormat::Tga;
    throw ImageError(path.string() + ": unsupported image extension '" + path.extension().string() +
                     (allow_tga ? "' (expected .exr, .png or .tga)" : "' (expected .exr or .png)"));
}

const char* oiioFormatName(FileFormat format) {
    return format == FileFormat::Exr ? "openexr" : format == FileFormat::Png ? "png" : "targa";
}

}  // namespace firelook::image::detail
