// Whole-file text I/O for looks and keyframe files. Writes are atomic (common/atomic_file.h) so a
// crash never leaves a half-written look behind.
#pragma once

#include <filesystem>
#include <string>

namespace firelook::viewer {

// Throws ViewerError naming the file.
std::string readTextFile(const std::filesystem::path& path);
void writeTextFileAtomic(const std::filesystem::path& path, const std::string& text);

}  // namespace firelook::viewer
