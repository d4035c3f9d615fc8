#include "viewer_app.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "fl_check.h"
#include "text_file.h"

namespace firelook::viewer {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Albedo is fixed by the package and the light count must match it: a preset written for another
// package is adapted rather than refused.
LookEdit fitToPackage(LookEdit look, const fl_package_info& info) {
    look.albedo = info.albedo;
    const Rgb3 fill = look.lights.empty() ? Rgb3{1.0f, 1.0f, 1.0f} : look.lights.back();
    look.lights.resize(static_cast<size_t>(std::max(info.light_count, 0)), fill);
    return look;
}

}  // namespace

ViewerApp::ViewerApp(const Options& options, std::unique_ptr<FireSession> session)
    : options_(options), session_(std::move(session)) {
    compositor_ = std::make_unique<Compositor>();
    path = options.path;
    compare = options.compare;
    display.exposure_stops = options.exposure;
    flare.enabled = options.flare;
    qa_settings.sequence_override = options.sequence;
    qa_settings.target_spp = options.qa_spp > 0 ? options.qa_spp : 256;
    loadPresets(options.looks_dir.empty() ? std::string(FIRELOOK_VIEWER_LOOKS_DIR) : options.looks_dir);
    if (session_) resetGpu();
}

ViewerApp::~ViewerApp() { worker_.stop(); }

void ViewerApp::setStatus(const std::string& text, bool error) { status = {text, error}; }

void ViewerApp::resetGpu() {
    gpu_.reset();
    gpu_error_.clear();
    try {
        gpu_ = std::make_unique<GpuReconstruction>(session_->world(), session_->instance(), session_->info());
    } catch (const std::exception& e) {
        gpu_error_ = e.what();
        setStatus(gpu_error_ + " - using the CPU path", true);
    }
    outputs_applied_ = false;
}

void ViewerApp::loadPresets(const std::string& folder) {
    presets_.clear();
    std::error_code error;
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(folder, error))
        if (entry.path().extension() == ".json") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const auto& file : files) presets_.push_back({file.stem().string(), file.string()});
}

bool ViewerApp::openPackage(const std::string& path_text) {
    try {
        std::unique_ptr<FireSession> next = FireSession::open(path_text);
        worker_.stop();
        fit_.cancel();  // it fits the old package
        match_ = FitSnapshot();
        qa_started_ = false;
        qa_ = ReferenceSnapshot();
        export_ = ExportJob();
        gpu_.reset();  // its textures belong to the old package
        session_ = std::move(next);
        resetGpu();
        timings_.clear();
        if (gpu_error_.empty()) setStatus("opened " + path_text, false);
        return true;
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
        return false;
    }
}

void ViewerApp::applyOutputs() {
    const bool cpu_image = !usingGpu() || (compare && gpu_);
    if (outputs_applied_ && cpu_image == applied_cpu_image_ && flare == applied_flare_) return;
    session_->setOutputs(cpu_image, flare);
    applied_cpu_image_ = cpu_image;
    applied_flare_ = flare;
    outputs_applied_ = true;
}

void ViewerApp::step(double dt) {
    if (!session_) return;
    const fl_package_info& info = session_->info();
    StageTimes t;
    step_error.clear();
    try {
        if (export_.active) {
            session_->seek(export_.frames[export_.next]);
            dt = 0.0;
        }
        applyOutputs();
        const bool gpu = usingGpu();
        const bool both = compare && gpu_ != nullptr;

        // 1. Update: the library advances playback and keyframes and computes z (and the CPU image).
        auto start = Clock::now();
        session_->update(dt);
        const fl_instance_state& state = session_->state();
        if (!gpu || both) cpu_.fetch(*session_);
        if (flare.enabled) session_->readFlare(flare_rgba_);
        t.update_ms = msSince(start);

        // 2. Upload.
        start = Clock::now();
        if (gpu || both) {
            gpu_->prepareFrame(state);
            gpu_->uploadCoefficients(session_->coefficients(), state.rank);
        }
        if (!gpu || both) cpu_.upload(*session_, cpu_result_);
        if (flare.enabled) uploadRgba(flare_rgba_, info.width, info.height, flare_target_);
        glFinish();
        t.upload_ms = msSince(start);

        // 3. Draw: reconstruction, then the display pass.
        start = Clock::now();
        if (gpu || both) gpu_->draw(state, gpu_result_);
        if (both) {
            compositor_->difference(gpu_result_, cpu_result_, std::exp2(difference_gain_stops), display_);
        } else {
            compositor_->composite(gpu ? gpu_result_ : cpu_result_, flare.enabled ? flare_target_.texture() : 0,
                                   display, display_);
        }
        glFinish();
        t.draw_ms = msSince(start);
        current_ = t;

        if (both) {  // not timed: a diagnostic read-back of both images
            std::vector<float> a;
            gpu_result_.readRgba(a);
            const std::vector<float>& b = cpu_.image();
            PathDifference d;
            double peak = 0.0;
            for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
                const double diff = std::abs(static_cast<double>(a[i]) - b[i]);
                if (i % 4 == 3) {
                    d.max_alpha = std::max(d.max_alpha, diff);
                } else {
                    d.max_rgb = std::max(d.max_rgb, diff);
                    peak = std::max(peak, static_cast<double>(b[i]));
                }
            }
            d.max_rgb_relative = peak > 0.0 ? d.max_rgb / peak : 0.0;
            difference_ = d;
        }
        if (export_.active) exportStep();
    } catch (const std::exception& e) {
        step_error = e.what();
        setStatus(e.what(), true);
        export_.active = false;
    }
    pollQa();
    pollMatch();
}

void ViewerApp::recordFrameTime(double frame_ms) {
    StageTimes t = current_;
    t.frame_ms = frame_ms;
    timings_.push(t);
}

void ViewerApp::readResult(std::vector<float>& rgba) const {
    (usingGpu() ? gpu_result_ : cpu_result_).readRgba(rgba);
}

template <typename Edit>
bool ViewerApp::sessionEdit(Edit&& edit) {
    if (!session_) return false;
    try {
        edit(*session_);
        if (status.error) status = {};
        return true;
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
        return false;
    }
}

bool ViewerApp::editLook(const LookEdit& look) {
    return sessionEdit([&](FireSession& s) { s.setLook(look); });
}

bool ViewerApp::editLightDirection(const LightDirection& light) {
    return sessionEdit([&](FireSession& s) { s.setLightDirection(light); });
}

bool ViewerApp::applyPreset(const LookPreset& preset) {
    if (!session_) return false;
    try {
        const LookEdit look = fitToPackage(loadLookEdit(preset.path), session_->info());
        session_->setLook(look);
        setStatus("look: " + preset.name, false);
        return true;
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
        return false;
    }
}

bool ViewerApp::loadLookFile(const std::string& file) {
    if (!session_) return false;
    try {
        session_->setLook(loadLookEdit(file));
        setStatus("loaded " + file, false);
        return true;
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
        return false;
    }
}

bool ViewerApp::saveLookFile(const std::string& file) {
    if (!session_) return false;
    try {
        writeTextFileAtomic(file, canonicalLookJson(session_->look()));
        setStatus("saved " + file, false);
        return true;
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
        return false;
    }
}

void ViewerApp::setKeyAtCurrentFrame() {
    if (!session_) return;
    // Keys go at the baked frame shown, so a key always lands on an image the artist has seen.
    insertKey(session_->keys(), {static_cast<double>(session_->state().frame), session_->look()});
    if (session_->animateKeys()) setAnimateKeys(true);
}

void ViewerApp::deleteKey(size_t index) {
    if (!session_ || index >= session_->keys().size()) return;
    session_->keys().erase(session_->keys().begin() + static_cast<long>(index));
    setAnimateKeys(session_->animateKeys());
}

bool ViewerApp::setAnimateKeys(bool on) {
    if (!session_) return false;
    try {
        session_->setAnimateKeys(on);
        return true;
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
        return false;
    }
}

bool ViewerApp::loadKeyframesFile(const std::string& file) {
    if (!session_) return false;
    try {
        std::vector<Keyframe> keys = loadKeyframes(file);
        const std::vector<Keyframe> previous = session_->keys();
        session_->keys() = std::move(keys);
        try {
            session_->setAnimateKeys(true);
        } catch (...) {
            session_->keys() = previous;
            throw;
        }
        setStatus("loaded " + std::to_string(session_->keys().size()) + " keys from " + file, false);
        return true;
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
        return false;
    }
}

bool ViewerApp::saveKeyframesFile(const std::string& file) {
    if (!session_) return false;
    try {
        saveKeyframes(file, session_->keys());
        setStatus("saved " + file, false);
        return true;
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
        return false;
    }
}

void ViewerApp::seekFrame(double frame) {
    if (!session_) return;
    try {
        session_->seek(frame);
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
    }
}

// ---- Match target --------------------------------------------------------------

void ViewerApp::startMatch() {
    if (!session_ || !session_->state().updated) return;
    try {
        match_request.frame = session_->state().frame;
        fit_.start(session_->package(), session_->info(), match_request);
        setStatus("fitting frame " + std::to_string(match_request.frame) + " to " + match_request.target, false);
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
    }
}

bool ViewerApp::acceptMatch() {
    if (!session_) return false;
    try {
        fit_.accept(*session_);
        setStatus("accepted the fitted look", false);
        return true;
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
        return false;
    }
}

void ViewerApp::pollMatch() {
    const FitStatus before = match_.status;
    const bool fresh = fit_.poll(match_);
    if (fresh && match_.status != before) {
        if (match_.status == FitStatus::Done) setStatus("fit done: Accept puts the look into the editor", false);
        if (match_.status == FitStatus::Cancelled) setStatus("fit cancelled", false);
        if (match_.status == FitStatus::Failed) setStatus(match_.error, true);
    }
    if (fresh && match_.status == FitStatus::Done) {
        const int w = match_.width, h = match_.height;
        uploadRgba(match_.target_rgba, w, h, match_target_linear_);
        uploadRgba(match_.fit_rgba, w, h, match_fit_linear_);
        uploadRgba(match_.difference_rgba, w, h, match_difference_linear_);
    }
    if (match_.status != FitStatus::Done) return;
    // Re-composited every frame so exposure and background changes apply to all three.
    compositor_->composite(match_target_linear_, 0, display, match_target_display_);
    compositor_->composite(match_fit_linear_, 0, display, match_fit_display_);
    compositor_->composite(match_difference_linear_, 0, display, match_difference_display_);
}

// ---- QA ----------------------------------------------------------------------

void ViewerApp::startQa() {
    if (!session_ || !session_->state().updated) return;
    try {
        const fl_instance_state& state = session_->state();
        ReferenceRequest request = qa_settings;
        request.scene = readReferenceScene(session_->package(), session_->info());
        request.package_path = session_->path();
        request.frame = state.frame;
        // The look shown at this frame: the edited one, or the library's interpolation while keys play.
        request.look_json = session_->animateKeys() && !session_->keys().empty() ? session_->shownLookJson()
                                                                                 : canonicalLookJson(session_->look());
        readResult(qa_realtime_);  // the real-time image it will be compared with
        qa_frame_ = state.frame;
        qa_look_json_ = request.look_json;
        uploadRgba(qa_realtime_, session_->info().width, session_->info().height, qa_realtime_linear_);
        qa_reference_linear_.reset();
        qa_heat_.reset();
        qa_measures_ = {};
        qa_compare_error_.clear();
        qa_heat_scale_shown_ = -1.0f;
        qa_ = ReferenceSnapshot();
        worker_.start(request);
        qa_started_ = true;
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
    }
}

bool ViewerApp::qaStale() const {
    if (!qa_started_ || !session_) return false;
    const std::string now = session_->animateKeys() && !session_->keys().empty()
                                ? qa_look_json_  // keyed: judged by the frame only
                                : canonicalLookJson(session_->look());
    return session_->state().frame != qa_frame_ || now != qa_look_json_;
}

void ViewerApp::pollQa() {
    if (!qa_started_ || !session_) return;
    const bool fresh = worker_.poll(qa_);
    const int w = session_->info().width, h = session_->info().height;
    if (fresh && !qa_.rgba.empty()) {
        if (qa_.width != w || qa_.height != h) {
            qa_compare_error_ = "the reference is " + std::to_string(qa_.width) + "x" + std::to_string(qa_.height) +
                                " but the package is " + std::to_string(w) + "x" + std::to_string(h);
        } else {
            uploadRgba(qa_.rgba, w, h, qa_reference_linear_);
            qa_measures_ = compareImages(qa_realtime_, qa_.rgba, w, h);
            qa_heat_scale_shown_ = -1.0f;
        }
    }
    if (qa_reference_linear_.texture() && qa_heat_scale_shown_ != heat_scale) {
        std::vector<unsigned char> heat;
        makeHeatMap(qa_realtime_, qa_.rgba, w, h, heat_scale, heat);
        uploadRgba8(heat, w, h, qa_heat_);
        qa_heat_scale_shown_ = heat_scale;
    }
    // Re-composited every frame so exposure and background changes apply to both.
    if (qa_realtime_linear_.texture()) compositor_->composite(qa_realtime_linear_, 0, display, qa_realtime_display_);
    if (qa_reference_linear_.texture())
        compositor_->composite(qa_reference_linear_, 0, display, qa_reference_display_);
}

// ---- export -------------------------------------------------------------------

ExportOptions ViewerApp::effectiveExportOptions() const {
    ExportOptions o = export_options;
    o.png_exposure_stops = display.exposure_stops;
    if (export_png_over_background) o.png_background = display.solid;
    return o;
}

bool ViewerApp::exportCurrent(const std::string& file) {
    if (!session_) return false;
    try {
        std::vector<float> rgba;
        readResult(rgba);
        const bool with_flare = export_include_flare && flare.enabled && !flare_rgba_.empty();
        exportImage(file, rgba, with_flare ? &flare_rgba_ : nullptr, session_->info().width, session_->info().height,
                    effectiveExportOptions());
        setStatus("wrote " + file, false);
        return true;
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
        return false;
    }
}

void ViewerApp::startSequenceExport(const std::string& pattern) {
    if (!session_ || export_.active) return;
    export_ = ExportJob();
    export_.active = true;
    export_.frames = session_->frames();
    export_.pattern = pattern;
    export_.was_playing = session_->playing();
    export_.resume_position = session_->state().frame_position;
    try {
        session_->setPlaying(false);
    } catch (const std::exception& e) {
        setStatus(e.what(), true);
        export_.active = false;
    }
}

void ViewerApp::exportStep() {
    // Called after this step rendered export_.frames[export_.next].
    const int frame = export_.frames[export_.next];
    const std::string file = sequenceFramePath(export_.pattern, frame);
    std::vector<float> rgba;
    readResult(rgba);
    const bool with_flare = export_include_flare && flare.enabled && !flare_rgba_.empty();
    exportImage(file, rgba, with_flare ? &flare_rgba_ : nullptr, session_->info().width, session_->info().height,
                effectiveExportOptions());
    if (++export_.next < export_.frames.size()) return;
    export_.active = false;
    session_->seek(export_.resume_position);
    session_->setPlaying(export_.was_playing);
    setStatus("exported " + std::to_string(export_.frames.size()) + " frames to " +
                  sequenceFramePath(export_.pattern, export_.frames.front()) + " ...",
              false);
}

float ViewerApp::exportProgress() const {
    return export_.frames.empty() ? 0.0f : static_cast<float>(export_.next) / static_cast<float>(export_.frames.size());
}

}  // namespace firelook::viewer
