// The viewer's state and its per-frame work, shared by the window and batch (headless) modes:
//   step(dt): update (C API) -> upload (textures) -> draw (GPU reconstruction or the CPU image,
//   then the display pass), plus the QA reference's progress and a sequence export in progress.
// The UI (ui_panels.cpp) edits the public settings and calls the actions below.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "compositor.h"
#include "cpu_path.h"
#include "fire_session.h"
#include "fit_session.h"
#include "frame_timings.h"
#include "gpu_reconstruction.h"
#include "heat_map.h"
#include "image_export.h"
#include "options.h"
#include "reference_worker.h"

namespace firelook::viewer {

struct LookPreset {
    std::string name;
    std::string path;  // a look file, read by the library when chosen (fl_look_load_file)
};

struct StatusMessage {
    std::string text;
    bool error = false;
};

// GPU-vs-CPU agreement of the last compared frame.
struct PathDifference {
    double max_rgb = 0.0;        // max |gpu - cpu| over RGB
    double max_rgb_relative = 0.0;  // max_rgb / peak RGB of the CPU image
    double max_alpha = 0.0;
};

class ViewerApp {
  public:
    // Needs a current OpenGL 3.3 context. `session` may be null (open one from the UI).
    ViewerApp(const Options& options, std::unique_ptr<FireSession> session);
    ~ViewerApp();
    ViewerApp(const ViewerApp&) = delete;
    ViewerApp& operator=(const ViewerApp&) = delete;

    FireSession* session() { return session_.get(); }
    const FireSession* session() const { return session_.get(); }
    bool openPackage(const std::string& path);  // keeps the current one on failure (status says why)

    void step(double dt);
    void recordFrameTime(double frame_ms);  // closes the frame's timings (the loop measures the period)
    const FrameTimings& timings() const { return timings_; }
    FrameTimings& timings() { return timings_; }
    const StageTimes& currentStages() const { return current_; }

    // Display settings and the reconstruction path (applied by the next step).
    ReconstructionPath path = ReconstructionPath::Gpu;
    bool compare = false;               // GPU-vs-CPU difference view
    float difference_gain_stops = 20.0f;  // x 2^20: float rounding differences become visible
    DisplaySettings display;
    FlareSettings flare;
    bool gpuAvailable() const { return gpu_ != nullptr; }
    const std::string& gpuError() const { return gpu_error_; }
    bool usingGpu() const { return path == ReconstructionPath::Gpu && gpu_; }
    const PathDifference& pathDifference() const { return difference_; }

    const gl::RenderTarget& displayTarget() const { return display_; }
    // The linear reconstruction (premultiplied RGBA, top row first, no flare) of the current path,
    // read back from its texture.
    void readResult(std::vector<float>& rgba) const;

    // Looks, keyframes and the run-time light (six-way packages); failures go to status.
    bool editLook(const LookEdit& look);
    bool editLightDirection(const LightDirection& light);
    const std::vector<LookPreset>& presets() const { return presets_; }
    bool applyPreset(const LookPreset& preset);  // albedo and light count adapted to the package
    bool loadLookFile(const std::string& path);
    bool saveLookFile(const std::string& path);
    void setKeyAtCurrentFrame();
    void deleteKey(size_t index);
    bool setAnimateKeys(bool on);
    bool loadKeyframesFile(const std::string& path);
    bool saveKeyframesFile(const std::string& path);
    void seekFrame(double frame);

    // QA reference.
    ReferenceRequest qa_settings;  // spp per pass, target, sequence override (the rest is filled in)
    float heat_scale = 1.0f;
    void startQa();
    void stopQa() { worker_.stop(); }
    const ReferenceSnapshot& qa() const { return qa_; }
    bool qaStarted() const { return qa_started_; }
    bool qaStale() const;  // the frame or look changed since the reference started
    const ErrorMeasures& qaMeasures() const { return qa_measures_; }
    const std::string& qaCompareError() const { return qa_compare_error_; }
    GLuint qaRealtimeTexture() const { return qa_realtime_display_.texture(); }
    GLuint qaReferenceTexture() const { return qa_reference_display_.texture(); }
    GLuint qaHeatTexture() const { return qa_heat_.texture(); }

    // Match target (fit_session.h): the fit of the frame shown to a target image.
    FitRequest match_request;  // target, mask, background... (the frame is filled in)
    void startMatch();
    void cancelMatch() { fit_.cancel(); }
    bool acceptMatch();  // the fitted look into the edited look; failures go to status
    const FitSnapshot& match() const { return match_; }
    bool match_shown = true;  // the viewport shows target / fit / difference while a fit is done
    GLuint matchTargetTexture() const { return match_target_display_.texture(); }
    GLuint matchFitTexture() const { return match_fit_display_.texture(); }
    GLuint matchDifferenceTexture() const { return match_difference_display_.texture(); }

    // Export.
    ExportOptions export_options;
    bool export_png_over_background = false;
    bool export_include_flare = true;
    bool exportCurrent(const std::string& path);
    void startSequenceExport(const std::string& pattern);
    bool exporting() const { return export_.active; }
    float exportProgress() const;

    StatusMessage status;
    std::string step_error;  // the last step's failure ("" if it succeeded); batch mode stops on it
    void setStatus(const std::string& text, bool error);

  private:
    struct ExportJob {
        bool active = false;
        std::vector<int> frames;
        size_t next = 0;
        std::string pattern;
        bool was_playing = false;
        double resume_position = 0.0;
    };

    void resetGpu();
    // Runs a session edit; its failure goes to status (and a success clears an error there).
    template <typename Edit>
    bool sessionEdit(Edit&& edit);
    void loadPresets(const std::string& folder);
    void applyOutputs();
    void pollQa();
    void pollMatch();
    void exportStep();
    ExportOptions effectiveExportOptions() const;

    Options options_;
    std::unique_ptr<FireSession> session_;
    std::unique_ptr<GpuReconstruction> gpu_;
    std::string gpu_error_;
    std::unique_ptr<Compositor> compositor_;
    CpuPath cpu_;
    gl::RenderTarget gpu_result_, cpu_result_, flare_target_, display_;
    std::vector<float> flare_rgba_;
    bool applied_cpu_image_ = false;
    FlareSettings applied_flare_;
    bool outputs_applied_ = false;
    PathDifference difference_;
    FrameTimings timings_;
    StageTimes current_;
    std::vector<LookPreset> presets_;

    ReferenceWorker worker_;
    ReferenceSnapshot qa_;
    bool qa_started_ = false;
    int qa_frame_ = 0;
    std::string qa_look_json_;
    std::vector<float> qa_realtime_;
    ErrorMeasures qa_measures_;
    std::string qa_compare_error_;
    float qa_heat_scale_shown_ = -1.0f;
    gl::RenderTarget qa_realtime_linear_, qa_reference_linear_, qa_realtime_display_, qa_reference_display_, qa_heat_;

    FitSession fit_;  // after session_: destroyed (its worker joined) before the package is released
    FitSnapshot match_;
    gl::RenderTarget match_target_linear_, match_fit_linear_, match_difference_linear_;
    gl::RenderTarget match_target_display_, match_fit_display_, match_difference_display_;

    ExportJob export_;
};

}  // namespace firelook::viewer
