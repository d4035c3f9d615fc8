// `firelook`: the command line for baking, inspecting and checking packages.
// Exit 0 on success; otherwise one line "firelook: error: ..." on stderr, or, after SIGINT/SIGTERM,
// one line "firelook: interrupted by SIG...; no output was written" and exit 128 + the signal.
#include <cstdio>
#include <exception>

#include "cli/commands.h"
#include "cli/interrupt.h"
#include "cli/version.h"

int main(int argc, char** argv) {
    firelook::cli::installInterruptHandler();  // first: a signal at any later moment gets the one line
    CLI::App app{"FireLook: bake volumetric fire into basis-image packages and render any look"};
    app.set_version_flag("--version", std::string("firelook ") + firelook::cli::kToolVersion);
    app.require_subcommand(1);
    firelook::cli::registerInfoCommand(app);
    firelook::cli::registerReferenceCommand(app);
    firelook::cli::registerBakeCommand(app);
    firelook::cli::registerRenderCommand(app);
    firelook::cli::registerCompareCommand(app);
    firelook::cli::registerAnimateCommand(app);
    firelook::cli::registerBenchCommand(app);
    firelook::cli::registerRepackCommand(app);
    firelook::cli::registerMergeCommand(app);
    firelook::cli::registerSplitCommand(app);
    firelook::cli::registerFitCommand(app);
    firelook::cli::registerFlipbookCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const std::exception& e) {
        // After a signal, whatever unwinds (InterruptedError, or a library's "cancelled") is the
        // interruption.
        if (firelook::cli::interruptRequested()) {
            std::fprintf(stderr, "firelook: %s\n", firelook::cli::InterruptedError().what());
            return firelook::cli::interruptExitCode();
        }
        std::fprintf(stderr, "firelook: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
