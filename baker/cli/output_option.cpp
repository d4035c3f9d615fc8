#include "cli/output_option.h"

namespace firelook::cli {

CLI::Option* addOutputOption(CLI::App& command, std::string& path, const std::string& description,
                             const std::vector<std::string>& old_spellings) {
    std::string names = "-o,--out";
    for (const std::string& name : old_spellings) names += "," + name;
    return command.add_option(names, path, description);
}

}  // namespace firelook::cli
