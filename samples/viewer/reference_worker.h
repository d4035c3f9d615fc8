// QA: the reference path tracer (firelook::render, the same renderer as `firelook reference`) on a
// background thread, refined progressively: passes of a few samples per pixel with different seeds
// are averaged, and every pass publishes the running mean so the UI shows the image as it clears.
//
// The package records what a reference needs; the UI thread reads it through the C API
// (readReferenceScene: camera, light directions, bins, RBF width, and META's "provenance" for the
// sequence path and grid mapping), so the worker only reads the sequence (firelook::vdb) and
// traces (firelook::render). No second copy of the package reader is in the process.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "firelook/firelook.h"

namespace firelook::viewer {

// What the bake used, as the C API gives it.
struct ReferenceScene {
    fl_camera camera = fl_camera_defaults();
    std::vector<std::array<double, 3>> light_directions;  // unit, the direction each light travels
    double temperature_lo = 0.0, temperature_hi = 1.0;
    int bin_count = 0;
    double rbf_width = 0.0;
    std::string metadata_json;  // META: "provenance" names the sequence and its grids
};

// Throws ViewerError with the library's message (e.g. a package that records no camera).
ReferenceScene readReferenceScene(fl_package package, const fl_package_info& info);

struct ReferenceRequest {
    ReferenceScene scene;
    std::string package_path;  // for finding a relative sequence, and messages
    std::string sequence_override;  // empty: the sequence recorded in the package
    int frame = 0;
    std::string look_json;  // a look document (what is shown at that frame)
    int spp_per_pass = 4;
    int target_spp = 256;
    int threads = 0;  // 0: all cores but one, so the UI stays responsive
};

struct ReferenceSnapshot {
    uint64_t version = 0;  // increases with every published pass
    int width = 0, height = 0;
    std::vector<float> rgba;  // running mean, premultiplied linear RGBA, top row first
    int spp = 0;
    int target_spp = 0;
    double estimated_relative_rmse = 0.0;  // of the running mean against the exact answer
    double seconds = 0.0;
    bool running = false;
    std::string status;  // "loading the sequence", "64 / 256 spp", "done", ...
    std::string error;   // non-empty when it failed
    std::string sequence_path;
};

class ReferenceWorker {
  public:
    ReferenceWorker() = default;
    ~ReferenceWorker() { stop(); }
    ReferenceWorker(const ReferenceWorker&) = delete;
    ReferenceWorker& operator=(const ReferenceWorker&) = delete;

    void start(const ReferenceRequest& request);  // stops a render in progress first
    void stop();                                   // cancels and joins
    // Copies the shared snapshot into `out` if it is newer than out.version.
    bool poll(ReferenceSnapshot& out) const;

  private:
    void run(ReferenceRequest request);
    void publish(const ReferenceSnapshot& snapshot);

    std::thread thread_;
    std::atomic<bool> cancel_{false};
    mutable std::mutex mutex_;
    ReferenceSnapshot shared_;
};

// Where the QA worker looks for the sequence: `recorded` as given, else relative to the package's
// folder. Empty if neither exists.
std::string resolveSequencePath(const std::string& recorded, const std::string& package_path);

}  // namespace firelook::viewer
