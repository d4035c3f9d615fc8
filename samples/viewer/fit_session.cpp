#include "fit_session.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include "fire_session.h"
#include "fl_check.h"

namespace firelook::viewer {
namespace {

// The mask a threshold on the target makes: pixels whose luminance (linear, Rec. 709) or alpha is
// above it keep their weight, the others are left out.
void applyThreshold(const FitRequest& request, const std::vector<float>& rgba, std::vector<float>& weight) {
    for (size_t p = 0; p < weight.size(); ++p) {
        const float* t = rgba.data() + 4 * p;
        const float value = request.threshold_on_alpha ? t[3] : 0.2126f * t[0] + 0.7152f * t[1] + 0.0722f * t[2];
        if (!(value > request.threshold)) weight[p] = 0.0f;
    }
    if (std::all_of(weight.begin(), weight.end(), [](float w) { return w == 0.0f; }))
        throw ViewerError(request.target + ": no pixel's " + (request.threshold_on_alpha ? "alpha" : "luminance") +
                          " is above the threshold " + std::to_string(request.threshold) + " (nothing to fit)");
}

}  // namespace

std::vector<float> renderLookImage(fl_package package, const fl_package_info& info, fl_look look, int frame) {
    // A world of its own: the fit runs beside the viewer's world, never touching it.
    fl_world world{};
    check(fl_world_create(nullptr, &world), "fl_world_create");
    std::vector<float> rgba(static_cast<size_t>(info.width) * info.height * 4);
    try {
        fl_instance_desc desc = fl_instance_desc_defaults();
        desc.package = package;
        desc.look = look;
        fl_instance instance{};
        check(fl_instance_create(world, &desc, &instance), "fl_instance_create");
        fl_playback_desc playback = fl_playback_desc_defaults();
        playback.paused = 1;
        playback.rate = 24.0;
        playback.time = (frame - info.first_frame) / playback.rate;
        check(fl_instance_set_playback(world, instance, &playback), "fl_instance_set_playback");
        fl_outputs_desc outputs = fl_outputs_desc_defaults();
        outputs.image = 1;
        check(fl_instance_set_outputs(world, instance, &outputs), "fl_instance_set_outputs");
        check(fl_world_update(world, 0.0), "fl_world_update");
        check(fl_instance_get_image(world, instance, rgba.data(), rgba.size()), "fl_instance_get_image");
    } catch (...) {
        fl_world_destroy(world);
        throw;
    }
    fl_world_destroy(world);
    return rgba;
}

void FitSession::start(fl_package package, const fl_package_info& info, const FitRequest& request) {
    cancel();
    // The target as `firelook fit` reads it, by the library (fl_fit_target_load; errors name the file).
    fl_fit_target_desc read = fl_fit_target_desc_defaults();
    read.frame = request.frame;
    read.target_path = request.target.c_str();
    if (request.mask_kind == MaskKind::File) read.mask_path = request.mask.c_str();
    if (request.background) {
        read.flags = FL_FIT_OVER_BACKGROUND;
        for (int c = 0; c < 3; ++c) read.background[c] = (*request.background)[c];
    }
    read.exposure = request.exposure;
    const size_t pixels = static_cast<size_t>(info.width) * info.height;
    std::vector<float> rgba(4 * pixels), weight(pixels);
    fl_fit_target_info target = fl_fit_target_info_defaults();
    check(fl_fit_target_load(package, &read, rgba.data(), weight.data(), pixels, nullptr, &target),
          "fl_fit_target_load");
    if (request.mask_kind == MaskKind::Threshold) applyThreshold(request, rgba, weight);

    fl_fit_desc desc = fl_fit_desc_defaults();
    desc.frame = request.frame;
    desc.flags = target.flags;
    for (int c = 0; c < 3; ++c) desc.background[c] = target.background[c];
    desc.smoothness = request.smoothness;
    desc.progress = &FitSession::progress;
    desc.progress_user = this;

    FitSnapshot running;
    running.status = FitStatus::Running;
    running.width = info.width;
    running.height = info.height;
    running.clipped_pixels = static_cast<size_t>(target.clipped_pixels);
    publish(running);
    cancel_ = false;
    thread_ = std::thread(&FitSession::run, this, package, info, desc, std::move(rgba), std::move(weight));
}

void FitSession::cancel() {
    cancel_ = true;
    if (thread_.joinable()) thread_.join();
}

bool FitSession::poll(FitSnapshot& out) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (shared_.version == out.version) return false;
    out = shared_;
    return true;
}

void FitSession::accept(FireSession& session) const {
    std::string json;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (shared_.status != FitStatus::Done) throw ViewerError("match target: no finished fit to accept");
        json = shared_.look_json;
    }
    session.setLook(parseLookEdit(json, "fitted look"));
}

void FitSession::publish(const FitSnapshot& snapshot) {
    std::lock_guard<std::mutex> lock(mutex_);
    const uint64_t version = shared_.version + 1;
    shared_ = snapshot;
    shared_.version = version;
}

int32_t FitSession::progress(double fraction, void* user) {
    auto* self = static_cast<FitSession*>(user);
    {
        std::lock_guard<std::mutex> lock(self->mutex_);
        self->shared_.fraction = fraction;
        ++self->shared_.version;
    }
    return self->cancel_ ? 1 : 0;
}

void FitSession::run(fl_package package, fl_package_info info, fl_fit_desc desc, std::vector<float> target,
                     std::vector<float> weights) {
    FitSnapshot done;
    done.width = info.width;
    done.height = info.height;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        done.clipped_pixels = shared_.clipped_pixels;
    }
    const auto start = std::chrono::steady_clock::now();
    desc.target_rgba = target.data();
    desc.weights = weights.data();
    fl_look look{};
    const fl_result result = fl_package_fit_look(package, &desc, &look, &done.report);
    try {
        if (result == FL_ERROR_CANCELLED) {
            done.status = FitStatus::Cancelled;
            publish(done);
            return;
        }
        check(result, "fl_package_fit_look");
        done.fit_rgba = renderLookImage(package, info, look, desc.frame);
        done.look_json = lookToJsonText(look);
        fl_look_release(look);
        look = fl_look{};
        done.difference_rgba.resize(done.fit_rgba.size());
        check(fl_fit_difference(target.data(), done.fit_rgba.data(), done.fit_rgba.size() / 4,
                                desc.flags & FL_FIT_OVER_BACKGROUND, desc.background, done.difference_rgba.data()),
              "fl_fit_difference");
        done.target_rgba = std::move(target);
        done.status = FitStatus::Done;
        done.fraction = 1.0;
    } catch (const std::exception& e) {
        if (look.id) fl_look_release(look);
        done.status = FitStatus::Failed;
        done.error = e.what();
    }
    done.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    publish(done);
}

}  // namespace firelook::viewer
