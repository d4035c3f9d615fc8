// Command line of firelook_viewer (README.md): interactive by default; with --frames-to-run it runs
// that many frames without user input, writes the requested screenshots and exits.
#pragma once

#include <string>
#include <vector>

namespace firelook::viewer {

enum class ReconstructionPath { Gpu, Cpu };

struct Options {
    std::string package;
    std::string look;        // look file applied at start
    std::string keyframes;   // keyframe file, played at start
    std::string sequence;    // VDB sequence for QA (default: the one recorded in the package)
    std::string looks_dir;   // presets shown in the look menu
    double frame = 0.0;      // start frame (package frame number); NaN-free, checked against the package
    bool frame_given = false;
    bool play = false;
    int frames_to_run = 0;   // > 0: batch mode
    std::string screenshot;     // linear reconstruction (EXR float, or PNG via the image library)
    std::string ui_screenshot;  // the whole window with widgets (PNG)
    std::string export_sequence;  // after the frames: every baked frame to this pattern
    ReconstructionPath path = ReconstructionPath::Gpu;
    int width = 1280, height = 800;
    bool timings = false;
    std::string match_target;  // batch: fit the frame shown to this target image (waits for it)
    int qa_spp = 0;          // > 0: start the QA reference at start with this many samples per pixel
    float exposure = 0.0f;
    bool flare = false;
    bool compare = false;    // GPU-vs-CPU difference view at start
    std::vector<float> light_angles;  // azimuth, elevation (degrees): the run-time light on at start

    bool batch() const { return frames_to_run > 0; }
};

// Parses argv. Returns an exit code >= 0 if the program should exit now (--help: 0, bad usage: 2);
// -1 to go on.
int parseOptions(int argc, char** argv, Options& options);

}  // namespace firelook::viewer
