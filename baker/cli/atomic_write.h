// Files the CLI writes besides packages and images (reports, bench results, cache
// entries): written to a temporary name beside the target and renamed into place,
// so an interrupted or failed write never leaves a truncated file under the real name.
#pragma once

#include <filesystem>
#include <string_view>

namespace firelook::cli {

// Throws std::runtime_error naming the file when it cannot be written; the temporary is removed.
void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes);

}  // namespace firelook::cli
