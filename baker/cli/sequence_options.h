// How every command that reads a VDB sequence (info, reference, bake, bench) treats doubtful data,
// and the one place its findings are printed (issue 13 C):
//   --strict          any gap in the frame numbers, any cleaned value (NaN, Inf, negative density)
//                     and any clamped value is an error instead of a warning;
//   --clamp-extreme   values beyond the plausible range (vdb/read_options.h) are clamped to it and
//                     reported, instead of refused.
// Warnings are one line each on stderr, "firelook: warning: ...", each distinct line once per run
// (a bake loads every frame twice: once for the temperature range, once to trace it).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "vdb/read_options.h"

namespace firelook::cli {

struct SequenceFlags {
    bool strict = false;
    bool clamp_extreme = false;
};

// Adds --strict and --clamp-extreme to a subcommand.
void addSequenceFlags(CLI::App& command, SequenceFlags& flags);

// Sets the read options' policies from the flags, points their warnings at printWarning, and makes
// every frame load check for SIGINT/SIGTERM first (interrupt.h).
void applySequenceFlags(const SequenceFlags& flags, vdb::ReadOptions& options);

// "firelook: warning: <message>" on stderr, unless this very line was printed before. Thread-safe.
void printWarning(const std::string& message);

}  // namespace firelook::cli
