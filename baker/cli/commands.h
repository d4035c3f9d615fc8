// Each `firelook` subcommand registers its options on the shared CLI11 app and
// sets the callback that runs it. Adding a subcommand = one file + one line in
// main.cpp. docs/cli.md fixes the command-line surface.
#pragma once

#include <CLI/CLI.hpp>

namespace firelook::cli {

void registerInfoCommand(CLI::App& app);
void registerReferenceCommand(CLI::App& app);
void registerBakeCommand(CLI::App& app);
void registerRenderCommand(CLI::App& app);
void registerCompareCommand(CLI::App& app);
void registerAnimateCommand(CLI::App& app);
void registerBenchCommand(CLI::App& app);
void registerRepackCommand(CLI::App& app);
void registerMergeCommand(CLI::App& app);
void registerSplitCommand(CLI::App& app);
void registerFitCommand(CLI::App& app);
void registerFlipbookCommand(CLI::App& app);
void registerExportCyclesCommand(CLI::App& app);

}  // namespace firelook::cli
