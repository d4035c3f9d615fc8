// firelook split PACKAGE --frames A-B -o OUT.firelook: some frames of a package as a package of
// their own (for an engine that streams a long effect in pieces), byte for byte what a bake of
// just those frames writes.
#include <cstdio>

#include "bake/package_merge.h"
#include "bake/scene_setup.h"
#include "cli/commands.h"
#include "cli/output_option.h"

namespace firelook::cli {

void registerSplitCommand(CLI::App& app) {
    struct Args {
        std::string package, output, frames;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand(
        "split", "Write some frames of a baked package as a package of their own: byte for byte the package a bake of "
                 "just those frames writes (the reverse of merge)");
    cmd->add_option("PACKAGE", args->package, "a package written by firelook bake or merge")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--frames", args->frames, "frames to keep: A-B ranges and single frames, comma-separated")
        ->required();
    addOutputOption(*cmd, args->output, "output package (.firelook), written atomically")->required();
    cmd->callback([args] {
        bake::MergeOptions options;
        options.allow_gaps = true;  // a selection may skip frames on purpose
        options.only = bake::parseFrameRanges(args->frames);
        const bake::MergeResult result = bake::mergePackages({args->package}, args->output, options);
        std::printf("wrote %s: %zu frames (%d-%d), %.1f MB\n", args->output.c_str(), result.frames.size(),
                    result.frames.front(), result.frames.back(), result.package_bytes / 1e6);
    });
}

}  // namespace firelook::cli
