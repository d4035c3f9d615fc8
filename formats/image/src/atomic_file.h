// Writing a file so that readers see either the old file or the complete new one, never a part.
#pragma once

#include <filesystem>
#include <functional>

namespace firelook::image::detail {

// Calls write_to(temporary) for a fresh temporary path in the target's folder, then renames the
// temporary over the target. If write_to or the rename throws, the temporary is removed and the
// exception propagates; the target is left as it was.
void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path& temporary)>& write_to);

}  // namespace firelook::image::detail
