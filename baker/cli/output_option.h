// The one spelling of a command's output (issue 14): every command that writes a file or folder
// names it with -o or --out. A command's older spellings (bake's --output, animate's --out-dir,
// bench's --json) stay as aliases so that existing scripts keep working.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace firelook::cli {

// Adds -o/--out (plus `old_spellings`, each a long name such as "--output") to `command`, storing
// the path in `path`. Returns the option, for ->required() and the like.
CLI::Option* addOutputOption(CLI::App& command, std::string& path, const std::string& description,
                             const std::vector<std::string>& old_spellings = {});

}  // namespace firelook::cli
