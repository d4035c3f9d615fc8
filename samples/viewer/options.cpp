#include "options.h"

#include <CLI/CLI.hpp>
#include <cstdio>

namespace firelook::viewer {

int parseOptions(int argc, char** argv, Options& o) {
    CLI::App app{"firelook_viewer: design the look of a baked fire in real time and check it against the reference"};
    std::string size, path = "gpu";
    app.add_option("PACKAGE", o.package, ".firelook package to open (or use the Open field in the window)");
    app.add_option("--look", o.look, "look file (JSON) to start with")->check(CLI::ExistingFile);
    app.add_option("--keyframes", o.keyframes, "keyframe file (JSON, see README) to play")->check(CLI::ExistingFile);
    app.add_option("--frame", o.frame, "start at this package frame number");
    app.add_flag("--play", o.play, "start playing (batch mode: 1/24 s per frame)");
    app.add_option("--frames-to-run", o.frames_to_run, "batch mode: run N frames without input, then exit")
        ->check(CLI::PositiveNumber);
    app.add_option("--screenshot", o.screenshot,
                   "batch mode: write the reconstructed image (.exr: linear premultiplied float RGBA; .png)");
    app.add_option("--ui-screenshot", o.ui_screenshot, "batch mode: write the whole window with its widgets (.png)");
    app.add_option("--path", path, "reconstruction path")->check(CLI::IsMember({"gpu", "cpu"}))->capture_default_str();
    app.add_option("--size", size, "window size WxH (default 1280x800)");
    app.add_option("--export-sequence", o.export_sequence,
                   "batch mode: then export every baked frame (PATTERN: #### becomes the frame number; .exr/.png)");
    app.add_flag("--timings", o.timings, "batch mode: print the median per-stage timings");
    app.add_option("--sequence", o.sequence, "VDB sequence for the QA reference (default: recorded in the package)");
    app.add_option("--looks-dir", o.looks_dir, "folder of look files offered as presets");
    app.add_option("--qa-spp", o.qa_spp, "start the QA reference with N samples per pixel (batch: wait for it)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--match-target", o.match_target,
                   "batch mode: fit the frame shown to this target image (.exr/.png) as the Match target panel "
                   "does, wait for it and print the error");
    app.add_option("--exposure", o.exposure, "display exposure in stops (PNG screenshots too)");
    app.add_flag("--flare", o.flare, "lens flare on");
    app.add_flag("--compare", o.compare, "show the GPU-vs-CPU difference view");
    app.add_option(
           "--light-angles", o.light_angles,
           "AZ,EL: light the fire from this direction (degrees in the camera's frame: azimuth 0 on the "
           "camera's side, 90 from the right; elevation 90 from above); needs a bake with --lights six-way "
           "or sphere")
        ->expected(2)
        ->delimiter(',')
        ->check(CLI::Range(-360.0, 360.0));
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    o.frame_given = app.count("--frame") > 0;
    o.path = path == "cpu" ? ReconstructionPath::Cpu : ReconstructionPath::Gpu;
    if (!size.empty()) {
        int w = 0, h = 0;
        char x = 0;
        if (std::sscanf(size.c_str(), "%d%c%d", &w, &x, &h) != 3 || (x != 'x' && x != 'X') || w < 320 || h < 240 ||
            w > 16384 || h > 16384) {
            std::fprintf(stderr, "firelook_viewer: error: --size must be WxH with W >= 320 and H >= 240, got '%s'\n",
                         size.c_str());
            return 2;
        }
        o.width = w;
        o.height = h;
    }
    if (o.batch() && o.package.empty()) {
        std::fprintf(stderr, "firelook_viewer: error: --frames-to-run needs a PACKAGE\n");
        return 2;
    }
    if (!o.batch() && (!o.screenshot.empty() || !o.ui_screenshot.empty() || o.timings || !o.export_sequence.empty() ||
                        !o.match_target.empty())) {
        std::fprintf(stderr,
                     "firelook_viewer: error: --screenshot, --ui-screenshot, --timings, --export-sequence and --match-target need "
                     "--frames-to-run\n");
        return 2;
    }
    return -1;
}

}  // namespace firelook::viewer
