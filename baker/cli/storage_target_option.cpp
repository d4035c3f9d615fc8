#include "cli/storage_target_option.h"

namespace firelook::cli {

void addStorageTargetFlags(CLI::App& command, StorageTargetFlags& flags, const std::string& size_help,
                           const std::string& error_help) {
    command.add_option("--target-size", flags.size, size_help);
    command.add_option("--target-error", flags.error, error_help)->excludes("--target-size");
}

bake::StorageTarget storageTarget(const CLI::App& command, const StorageTargetFlags& flags) {
    bake::StorageTarget target;
    if (!flags.size.empty()) target = {.package_bytes = bake::parseByteSize(flags.size)};
    if (command.count("--target-error")) target = {.basis_error = flags.error};
    bake::checkStorageTarget(target);
    return target;
}

}  // namespace firelook::cli
