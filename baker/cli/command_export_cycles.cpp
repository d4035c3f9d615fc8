// firelook export-cycles PACKAGE --frame F --sequence SEQ [--look L.json] -o scene.py
// A Python script that, run as `blender -b --python scene.py -- --spp N -o OUT.exr`, renders the
// frame with the look in Cycles: the exact model as a volume shader (cycles_scene.h).
#include <cstdio>

#include "basis/basis_package.h"
#include "cli/commands.h"
#include "cli/cycles_scene.h"
#include "cli/output_option.h"
#include "common/atomic_file.h"
#include "look/look.h"

namespace firelook::cli {

void registerExportCyclesCommand(CLI::App& app) {
    struct Args {
        std::string package, look, sequence, out;
        int frame = 0;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand(
        "export-cycles", "Write a Blender script that renders a frame and look of a package in Cycles (the exact model)");
    cmd->add_option("PACKAGE", args->package, ".firelook package")->required()->check(CLI::ExistingFile);
    cmd->add_option("--frame", args->frame, "frame number")->required();
    cmd->add_option("--look", args->look, "look file (default: the look recorded in the package)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--sequence", args->sequence,
                    "the sequence the package was baked from (a package knows its frames by content, not path)")
        ->required();
    addOutputOption(*cmd, args->out, "output script (.py)")->required();
    cmd->callback([args] {
        const basis::BasisReader package = basis::BasisReader::open(args->package);
        const Look look = args->look.empty()
                              ? parseLook(package.description().default_look_json, args->package + " (default look)")
                              : loadLook(args->look);
        writeFileAtomically(args->out, cyclesSceneScript(package, args->package, args->frame, look, args->sequence));
        std::printf("wrote %s: frame %d; run: blender -b --factory-startup --python %s -- --spp N -o OUT.exr\n",
                    args->out.c_str(), args->frame, args->out.c_str());
    });
}

}  // namespace firelook::cli
