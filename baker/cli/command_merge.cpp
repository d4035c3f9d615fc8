// firelook merge PART... -o OUT.firelook [--allow-gaps]: one package from shards of one bake.
#include <cstdio>

#include "bake/package_merge.h"
#include "cli/commands.h"
#include "cli/output_option.h"

namespace firelook::cli {

void registerMergeCommand(CLI::App& app) {
    struct Args {
        std::vector<std::string> parts;
        std::string output;
        bool allow_gaps = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand(
        "merge", "Merge packages that each hold some frames of one bake (e.g. bake --frames shards) into one package, "
                 "byte for byte the one a single bake of all their frames writes");
    cmd->add_option("PART", args->parts, "packages baked from the same sequence with the same settings")
        ->required()
        ->check(CLI::ExistingFile);
    addOutputOption(*cmd, args->output, "output package (.firelook), written atomically")->required();
    cmd->add_flag("--allow-gaps", args->allow_gaps,
                  "accept frames of the sequence missing between the parts' first and last frame (by default that is "
                  "an error, as a lost shard would be)");
    cmd->callback([args] {
        std::vector<std::filesystem::path> parts(args->parts.begin(), args->parts.end());
        const bake::MergeResult result =
            bake::mergePackages(parts, args->output, {.allow_gaps = args->allow_gaps, .only = {}},
                                [](const std::string& line) { std::printf("%s\n", line.c_str()); });
        std::printf("wrote %s: %zu frames (%d-%d), %.1f MB\n", args->output.c_str(), result.frames.size(),
                    result.frames.front(), result.frames.back(), result.package_bytes / 1e6);
    });
}

}  // namespace firelook::cli
