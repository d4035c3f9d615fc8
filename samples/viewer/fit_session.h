// "Match target" (issue 17): the logic behind the viewer's panel, without any GUI. Reads a target
// image and optional mask (fl_fit_target_load: the reader `firelook fit` uses), runs
// fl_package_fit_look on a worker thread with progress and cancel, renders the fitted look's image
// through its own world and hands target / fit / difference to the panel; accept() puts the fitted
// look into the viewer's edited look.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "firelook/firelook.h"
#include "look_edit.h"

namespace firelook::viewer {

class FireSession;

enum class MaskKind { None, File, Threshold };

struct FitRequest {
    int frame = 0;
    std::string target;  // .exr (linear premultiplied) or .png (through the display transform)
    MaskKind mask_kind = MaskKind::None;
    std::string mask;               // MaskKind::File: weight = its red channel
    float threshold = 0.0f;         // MaskKind::Threshold: pixels above it count, others are left out
    bool threshold_on_alpha = false;  // threshold the target's alpha (else its luminance, linear)
    std::optional<Rgb3> background;   // the target is opaque over this linear RGB; alpha not matched
    double exposure = 0.0;            // stops the (PNG) target was exposed by
    double smoothness = 0.0;          // fl_fit_desc.smoothness
};

enum class FitStatus { Idle, Running, Done, Cancelled, Failed };

struct FitSnapshot {
    uint64_t version = 0;  // increases with every change
    FitStatus status = FitStatus::Idle;
    double fraction = 0.0;
    std::string error;  // FitStatus::Failed
    int width = 0, height = 0;
    // Done: linear premultiplied RGBA, top row first. difference is |fit - target| (opaque), the fit
    // composited over the background where alpha is not matched.
    std::vector<float> target_rgba, fit_rgba, difference_rgba;
    fl_fit_report report = fl_fit_report_defaults();
    std::string look_json;  // Done: the fitted look (fl_look_to_json)
    double seconds = 0.0;
    size_t clipped_pixels = 0;  // PNG pixels left out as clipped
};

class FitSession {
  public:
    FitSession() = default;
    ~FitSession() { cancel(); }
    FitSession(const FitSession&) = delete;
    FitSession& operator=(const FitSession&) = delete;

    // Reads the target (and mask) here, so a bad file throws ViewerError naming it at once, then fits
    // on a worker thread. Cancels a fit in progress first. `package` must outlive the fit (cancel()
    // before releasing it).
    void start(fl_package package, const fl_package_info& info, const FitRequest& request);
    // Asks the fit to stop (its progress callback returns nonzero) and joins; no look is made.
    void cancel();
    // Copies the shared snapshot into `out` if it is newer than out.version.
    bool poll(FitSnapshot& out) const;
    // Puts the finished fit's look into the session's edited look (FireSession::setLook). Throws
    // ViewerError when no fit has finished.
    void accept(FireSession& session) const;

  private:
    void run(fl_package package, fl_package_info info, fl_fit_desc desc, std::vector<float> target,
             std::vector<float> weights);
    void publish(const FitSnapshot& snapshot);
    static int32_t progress(double fraction, void* user);

    std::thread thread_;
    std::atomic<bool> cancel_{false};
    mutable std::mutex mutex_;
    FitSnapshot shared_;
};

// The look's image of a package frame (fl_instance_get_image through a world of its own).
std::vector<float> renderLookImage(fl_package package, const fl_package_info& info, fl_look look, int frame);

}  // namespace firelook::viewer
