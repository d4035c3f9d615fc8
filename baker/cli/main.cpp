// `firelook`: the command line for baking, inspecting and checking packages.
// Exit 0 on success; otherwise one line "firelook: error: ..." on stderr, or, after SIGINT/SIGTERM,
// one line "firelook: interrupted by SIG...; no output was written" and exit 128 + the signal.
#include <cstdio>
#include <exception>

#include "cli/commands.h"
#include "cli/interrupt.h"
#include "cli/version.h"

#if defined(__ELF__) && defined(__GLIBC__)
// The handler goes in before anything of the program runs: the loader calls the executable's
// .preinit_array right after mapping the libraries and before any of their constructors, which
// (OpenVDB, OpenImageIO and the ~150 libraries they bring) took most of the 0.3 s before main in
// which a signal used to kill `firelook` without its line.
static void installBeforeConstructors(int, char**, char**) { firelook::cli::installInterruptHandler(); }
__attribute__((section(".preinit_array"), used)) static void (*const kInstallBeforeConstructors)(int, char**, char**) =
    installBeforeConstructors;
#endif

int main(int argc, char** argv) {
    // Again (harmless) for a platform without .preinit_array: a signal from here on gets the line.
    firelook::cli::installInterruptHandler();
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
    firelook::cli::registerExportCyclesCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version print as CLI11 does; a usage error is one line, like every error.
        if (e.get_exit_code() == 0) return app.exit(e);
        std::fprintf(stderr, "firelook: error: %s (--help lists the options)\n", e.what());
        return e.get_exit_code();
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
