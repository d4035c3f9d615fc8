// firelook_viewer [PACKAGE] [options]: the look-design and QA viewer (README.md).
//   Interactive: a window with the image and the panels until it is closed.
//   Batch (--frames-to-run N): N frames without user input, then the screenshots, timings and
//   exit 0; any failure prints one line "firelook_viewer: error: ..." and exits 1.
// The package is opened before any window, so a missing or corrupt package is reported (naming
// the file) even where no display exists.
#include <imgui.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "fl_check.h"
#include "image_export.h"
#include "options.h"
#include "text_file.h"
#include "ui_panels.h"
#include "viewer_app.h"
#include "window.h"

namespace firelook::viewer {
namespace {

using Clock = std::chrono::steady_clock;

// Warnings only: errors come back through fl_last_error() and are reported once, by the caller.
void logToStderr(int32_t level, const char* message, void*) {
    if (level == FL_LOG_WARNING) std::fprintf(stderr, "firelook_viewer: warning: %s\n", message);
}

// --look, --keyframes, --light-angles, --frame and --play; errors are fatal (the command line asked for them).
void applyStartOptions(ViewerApp& app, const Options& o) {
    FireSession& s = *app.session();
    if (!o.look.empty()) s.setLook(loadLookEdit(o.look));
    if (!o.keyframes.empty()) {
        s.keys() = loadKeyframes(o.keyframes);
        s.setAnimateKeys(true);
    }
    if (o.light_angles.size() == 2) {
        LightDirection light = s.lightDirection();
        light.enabled = true;
        light.azimuth_degrees = o.light_angles[0];
        light.elevation_degrees = o.light_angles[1];
        s.setLightDirection(
            light);  // a package without six-way or sphere lights: the library's error, naming it
    }
    const fl_package_info& info = s.info();
    if (o.frame_given) {
        if (!(o.frame >= info.first_frame && o.frame <= info.last_frame))
            throw ViewerError("--frame " + std::to_string(o.frame) + " is outside the package's frames " +
                              std::to_string(info.first_frame) + "-" + std::to_string(info.last_frame));
        s.seek(o.frame);
    }
    if (o.play) s.setPlaying(true);
}

void printTimings(const ViewerApp& app, const Options& o, const std::string& renderer) {
    const StageTimes m = app.timings().median();
    const fl_package_info& info = app.session()->info();
    std::printf("timings: median of %zu frames, path %s, %dx%d, rank %d, %s\n", app.timings().size(),
                o.path == ReconstructionPath::Gpu ? "gpu" : "cpu", info.width, info.height,
                app.session()->state().rank, renderer.c_str());
    std::printf("  update %.3f ms  upload %.3f ms  draw %.3f ms  frame %.3f ms (%.1f fps)\n", m.update_ms, m.upload_ms,
                m.draw_ms, m.frame_ms, m.frame_ms > 0 ? 1000.0 / m.frame_ms : 0.0);
}

int runBatch(ViewerApp& app, Window& window, const Options& o, bool ui) {
    UiState ui_state;
    ui_state.package_path = o.package;
    const double dt = o.play ? 1.0 / 24.0 : 0.0;  // fixed, so a batch run is reproducible
    if (o.timings) app.timings().setCapacity(static_cast<size_t>(o.frames_to_run));
    std::vector<unsigned char> capture;
    int capture_w = 0, capture_h = 0;
    auto previous = Clock::now();
    // The match-target fit started at the first frame is still running (a poll may not have seen it yet).
    const auto fitting = [&] {
        return !o.match_target.empty() &&
               (app.match().status == FitStatus::Running || app.match().status == FitStatus::Idle);
    };
    for (int i = 0;; ++i) {
        const bool waiting_for_qa = o.qa_spp > 0 && app.qaStarted() && (app.qa().running || app.qa().version == 0);
        if (i >= o.frames_to_run && !waiting_for_qa && !fitting()) break;
        // While only the QA reference is left, give it the cores.
        if (i >= o.frames_to_run) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        window.pollEvents();
        app.step(i >= o.frames_to_run ? 0.0 : dt);
        if (!app.step_error.empty()) throw ViewerError(app.step_error);
        if (i == 0 && o.qa_spp > 0) app.startQa();
        if (i == 0 && !o.match_target.empty()) {
            app.match_request.target = o.match_target;
            app.startMatch();
            if (app.match().status == FitStatus::Idle && app.status.error) throw ViewerError(app.status.text);
        }
        const bool last = i + 1 >= o.frames_to_run && !(o.qa_spp > 0 && (app.qa().running || app.qa().version == 0)) &&
                          !fitting();
        if (ui) {
            int w = 0, h = 0;
            window.framebufferSize(w, h);
            window.beginUi();
            drawUi(app, ui_state, w, h);
        }
        window.present(last && !o.ui_screenshot.empty() ? &capture : nullptr, &capture_w, &capture_h);
        const auto now = Clock::now();
        // Iterations that only wait for the QA reference (and sleep) are not frames.
        if (i < o.frames_to_run) app.recordFrameTime(std::chrono::duration<double, std::milli>(now - previous).count());
        previous = now;
    }
    if (o.qa_spp > 0) {
        const ReferenceSnapshot& r = app.qa();
        if (!r.error.empty()) throw ViewerError("QA reference: " + r.error);
        std::printf("qa: frame %d, %d spp, relative RMSE %.6f, max alpha error %.6f, reference noise %.6f\n",
                    app.session()->state().frame, r.spp, app.qaMeasures().relative_rmse,
                    app.qaMeasures().max_alpha_error, r.estimated_relative_rmse);
    }
    if (!o.match_target.empty()) {
        const FitSnapshot& m = app.match();
        if (m.status == FitStatus::Failed) throw ViewerError("match target: " + m.error);
        std::printf("match: frame %d, relative RMSE %.6f, alpha RMSE %.6f, %d extinction settings, %.2f s\n",
                    app.match_request.frame, m.report.relative_rmse, m.report.alpha_rmse, m.report.evaluations,
                    m.seconds);
    }
    if (!o.screenshot.empty()) {
        std::vector<float> rgba;
        app.readResult(rgba);
        ExportOptions e;
        e.float_exr = true;  // the exact values, for comparisons
        e.png_exposure_stops = o.exposure;
        exportImage(o.screenshot, rgba, nullptr, app.session()->info().width, app.session()->info().height, e);
        std::printf("wrote %s (frame %d, %s path)\n", o.screenshot.c_str(), app.session()->state().frame,
                    app.usingGpu() ? "gpu" : "cpu");
    }
    if (!o.ui_screenshot.empty()) {
        writeWindowPng(o.ui_screenshot, capture, capture_w, capture_h);
        std::printf("wrote %s (%dx%d window)\n", o.ui_screenshot.c_str(), capture_w, capture_h);
    }
    if (!o.export_sequence.empty()) {
        app.startSequenceExport(o.export_sequence);
        while (app.exporting()) {
            app.step(0.0);
            if (!app.step_error.empty()) throw ViewerError(app.step_error);
        }
        std::printf("%s\n", app.status.text.c_str());
    }
    if (o.timings) printTimings(app, o, window.renderer());
    return 0;
}

int runInteractive(ViewerApp& app, Window& window, const Options& o) {
    UiState ui;
    ui.package_path = o.package;
    auto previous = Clock::now();
    double dt = 0.0;
    while (!window.shouldClose()) {
        window.pollEvents();
        app.step(dt);
        int w = 0, h = 0;
        window.framebufferSize(w, h);
        window.beginUi();
        drawUi(app, ui, w, h);
        window.present(nullptr, nullptr, nullptr);
        const auto now = Clock::now();
        dt = std::chrono::duration<double>(now - previous).count();
        app.recordFrameTime(dt * 1000.0);
        previous = now;
    }
    return 0;
}

int run(const Options& o) {
    // Open the package first: its errors need no display.
    std::unique_ptr<FireSession> session;
    if (!o.package.empty()) session = FireSession::open(o.package);
    const bool ui = !o.batch() || !o.ui_screenshot.empty();
    Window window(o.width, o.height, /*visible=*/ui, /*with_imgui=*/ui, /*vsync=*/!o.batch());
    int code = 0;
    {
        ViewerApp app(o, std::move(session));  // GL objects die before the window
        if (app.session()) {
            applyStartOptions(app, o);
            if (o.batch() && o.path == ReconstructionPath::Gpu && !app.gpuAvailable())
                throw ViewerError("--path gpu: " + app.gpuError());
        }
        code = o.batch() ? runBatch(app, window, o, ui) : runInteractive(app, window, o);
    }
    return code;
}

}  // namespace
}  // namespace firelook::viewer

int main(int argc, char** argv) {
    using namespace firelook::viewer;
    Options options;
    const int parsed = parseOptions(argc, argv, options);
    if (parsed >= 0) return parsed;
    fl_init_desc desc = fl_init_desc_defaults();
    desc.log = logToStderr;
    desc.log_level = FL_LOG_WARNING;
    if (fl_init(&desc) != FL_OK) {
        std::fprintf(stderr, "firelook_viewer: error: fl_init failed: %s\n", fl_last_error());
        return 1;
    }
    int code = 1;
    try {
        code = run(options);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "firelook_viewer: error: %s\n", e.what());
        code = 1;
    }
    fl_shutdown();
    return code;
}
