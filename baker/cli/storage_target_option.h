// --target-size SIZE | --target-error E, which `bake` and `repack` share: the storage target
// (bake/storage_target.h) chosen on the command line.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "bake/bake_config.h"  // StorageTarget, checkStorageTarget, parseByteSize

namespace firelook::cli {

struct StorageTargetFlags {
    std::string size;    // e.g. "6M"; empty: not given
    double error = 0.0;  // read only when given
};

// Adds both options to `command`, each with its help text (what the target means for the command);
// they exclude each other.
void addStorageTargetFlags(CLI::App& command, StorageTargetFlags& flags, const std::string& size_help,
                           const std::string& error_help);

// The target the flags give (inactive when neither was given), checked by bake::checkStorageTarget:
// An InvalidArgument Error for a size that does not parse or an error out of range.
bake::StorageTarget storageTarget(const CLI::App& command, const StorageTargetFlags& flags);

}  // namespace firelook::cli
