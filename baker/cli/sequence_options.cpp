#include "cli/sequence_options.h"

#include <cstdio>
#include <mutex>
#include <set>

#include "cli/interrupt.h"

namespace firelook::cli {

void addSequenceFlags(CLI::App& command, SequenceFlags& flags) {
    command.add_flag("--strict", flags.strict,
                     "refuse a sequence with gaps in its frame numbers or with values that need cleaning "
                     "(NaN, Inf, negative density) or clamping, instead of warning");
    command.add_flag("--clamp-extreme", flags.clamp_extreme,
                     "clamp densities above 1e6 and temperatures beyond +-1e6 to those bounds (and warn) "
                     "instead of refusing the frame");
}

void applySequenceFlags(const SequenceFlags& flags, vdb::ReadOptions& options) {
    options.strict = flags.strict;
    options.clamp_extreme = flags.clamp_extreme;
    options.warn = printWarning;
    options.before_load = [](const std::filesystem::path&) { throwIfInterrupted(); };
}

void printWarning(const std::string& message) {
    static std::mutex mutex;
    static std::set<std::string> printed;
    const std::lock_guard<std::mutex> lock(mutex);
    if (!printed.insert(message).second) return;
    std::fprintf(stderr, "firelook: warning: %s\n", message.c_str());
}

}  // namespace firelook::cli
