// QA: the reference path tracer (firelook::render, the same renderer as `firelook reference`) on a
// background thread, refined progressively: passes of a few samples per pixel with different seeds
// are averaged, and every pass publishes the running mean so the UI shows the image as it clears.
//
// The package records what a reference needs; the UI thread reads it through the C API
// (readReferenceScene: camera, light directions, bins, RBF width, and META's "provenance" for the
// sequence path and grid mapping), and firelook::reference turns it into the tracer's inputs
// (baker/reference/reference_inputs.h: the sequence read as the bake read it, --clamp-extreme
// included, and the look model). No second copy of the package reader is in the process.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "firelook/firelook.h"
#include "reference/reference_inputs.h"

namespace firelook::viewer {

// What the bake used, as the C API gives it. Throws ViewerError with the library's message (e.g. a
// package that records no camera).
reference::BakedScene readReferenceScene(fl_package package, const fl_package_info& info);

struct ReferenceRequest {
    reference::BakedScene scene;
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
