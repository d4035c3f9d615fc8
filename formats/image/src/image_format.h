// Which file format a path names, from its extension.
#pragma once

#include <filesystem>

namespace firelook::image::detail {

enum class FileFormat { Exr, Png, Tga };

// Throws ImageError naming the file when the extension is neither ".exr" nor ".png" (nor ".tga"
// when `allow_tga`: data textures only, image_io.h).
FileFormat formatFromExtension(const std::filesystem::path& path, bool allow_tga = false);

// The name OpenImageIO knows the format by, so a file can be opened whatever its own name.
const char* oiioFormatName(FileFormat format);

}  // namespace firelook::image::detail
