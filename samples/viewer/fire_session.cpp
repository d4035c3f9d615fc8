#include "fire_session.h"

#include <cmath>

#include "fl_check.h"

namespace firelook::viewer {

std::unique_ptr<FireSession> FireSession::open(const std::string& path) {
    std::unique_ptr<FireSession> s(new FireSession());
    s->path_ = path;
    // fl_last_error names the file; the prefix says which step failed.
    check(fl_package_load(path.c_str(), &s->package_), "fl_package_load");
    check(fl_package_get_info(s->package_, &s->info_), "fl_package_get_info");
    uint32_t count = 0;
    check(fl_package_get_frames(s->package_, nullptr, nullptr, 0, &count), "fl_package_get_frames");
    s->frames_.resize(count);
    s->ranks_.resize(count);
    check(fl_package_get_frames(s->package_, s->frames_.data(), s->ranks_.data(), count, &count),
          "fl_package_get_frames");
    if (s->frames_.empty()) throw ViewerError(path + ": the package has no frames");

    size_t size = 0;
    check(fl_package_get_default_look_json(s->package_, nullptr, 0, &size), "fl_package_get_default_look_json");
    s->default_look_json_.assign(size, '\0');
    check(fl_package_get_default_look_json(s->package_, s->default_look_json_.data(), size, &size),
          "fl_package_get_default_look_json");
    s->default_look_json_.resize(size > 0 ? size - 1 : 0);
    s->look_ = parseLookEdit(s->default_look_json_, path + " (default look)");

    int32_t first = -1, relight_count = 0;
    if (fl_package_get_relight_lights(s->package_, &first, &relight_count) == FL_OK) {  // six-way or sphere
        s->relight_first_light_ = first;
        s->relight_count_ = relight_count;
        fl_camera camera = fl_camera_defaults();
        if (fl_package_get_camera(s->package_, &camera) == FL_OK)
            for (int c = 0; c < 3; ++c) {  // the rotation's columns, normalised (a scale does not matter)
                const double* axis = camera.world_from_camera + 4 * c;
                const double length = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
                for (int r = 0; r < 3 && length > 0.0; ++r) s->camera_rotation_[3 * c + r] = axis[r] / length;
            }
    }

    const fl_world_desc world_desc = fl_world_desc_defaults();
    check(fl_world_create(&world_desc, &s->world_), "fl_world_create");
    fl_instance_desc desc = fl_instance_desc_defaults();
    desc.package = s->package_;  // look 0: the package's default
    check(fl_instance_create(s->world_, &desc, &s->instance_), "fl_instance_create");
    s->playback_.rate = 24.0;
    s->playback_.paused = 1;
    check(fl_instance_set_playback(s->world_, s->instance_, &s->playback_), "fl_instance_set_playback");
    return s;
}

FireSession::~FireSession() {
    if (world_.id) fl_world_destroy(world_);  // destroys the instance too
    if (package_.id) fl_package_release(package_);
}

void FireSession::setLook(const LookEdit& look) {
    const LookEdit previous = look_;
    look_ = look;
    try {
        applyLooks();
    } catch (...) {
        look_ = previous;
        throw;
    }
}

void FireSession::setLightDirection(const LightDirection& light) {
    if (!light.enabled) {
        check(fl_instance_set_light_direction(world_, instance_, nullptr), "fl_instance_set_light_direction");
    } else {
        constexpr double kDegree = 3.14159265358979323846 / 180.0;
        const double az = light.azimuth_degrees * kDegree, el = light.elevation_degrees * kDegree;
        // Towards the light in the camera frame (+X right, +Y up, +Z towards the viewer); it travels the other way.
        const double towards[3] = {std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)};
        fl_light_direction_desc desc = fl_light_direction_desc_defaults();
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) desc.direction[r] -= camera_rotation_[3 * c + r] * towards[c];
        for (int c = 0; c < 3; ++c) desc.irradiance[c] = light.irradiance[static_cast<size_t>(c)];
        check(fl_instance_set_light_direction(world_, instance_, &desc), "fl_instance_set_light_direction");
    }
    light_direction_ = light;
}

void FireSession::setAnimateKeys(bool on) {
    animate_keys_ = on;
    applyLooks();
}

void FireSession::applyLooks() {
    if (animate_keys_ && !keys_.empty()) {
        std::vector<fl_keyframe> list;
        fl_result result = FL_OK;
        try {
            for (const Keyframe& k : keys_) {
                fl_keyframe key{};
                key.frame = k.frame;
                key.look = makeFlLook(k.look, "key at frame " + std::to_string(k.frame));
                list.push_back(key);
            }
            result = fl_instance_set_keyframes(world_, instance_, list.data(), static_cast<uint32_t>(list.size()));
        } catch (...) {
            for (const fl_keyframe& k : list) fl_look_release(k.look);
            throw;
        }
        for (const fl_keyframe& k : list) fl_look_release(k.look);  // the instance copied them
        check(result, "fl_instance_set_keyframes");
        return;
    }
    const fl_look handle = makeFlLook(look_, "edited look");
    const fl_result result = fl_instance_set_look(world_, instance_, handle);
    fl_look_release(handle);
    check(result, "fl_instance_set_look");
}

void FireSession::setPlaying(bool playing) {
    // Continue from where the library's clock is, so pausing never jumps.
    if (state_.updated) playback_.time = state_.time;
    playback_.paused = playing ? 0 : 1;
    check(fl_instance_set_playback(world_, instance_, &playback_), "fl_instance_set_playback");
}

void FireSession::setRate(double frames_per_second) {
    if (!(frames_per_second > 0.0)) return;
    // Keep the frame position: time * rate is the offset from the first frame.
    const double offset = state_.updated ? state_.frame_position - info_.first_frame : 0.0;
    playback_.rate = frames_per_second;
    playback_.time = offset / frames_per_second;
    check(fl_instance_set_playback(world_, instance_, &playback_), "fl_instance_set_playback");
}

void FireSession::seek(double frame_position) {
    playback_.time = (frame_position - info_.first_frame) / playback_.rate;
    check(fl_instance_set_playback(world_, instance_, &playback_), "fl_instance_set_playback");
}

void FireSession::setOutputs(bool cpu_image, const FlareSettings& flare) {
    fl_outputs_desc o = fl_outputs_desc_defaults();
    o.image = cpu_image || flare.enabled ? 1 : 0;  // the flare is computed from the CPU image
    o.lens_flare = flare.enabled ? 1 : 0;
    // 0 means "default" in the API; the settings hold the defaults explicitly. A tiny positive
    // threshold stands for 0 as documented.
    o.flare_threshold = flare.threshold > 0.0f ? flare.threshold : 1e-6f;
    o.flare_intensity = flare.intensity > 0.0f ? flare.intensity : -1.0f;
    o.ghost_count = flare.ghost_count > 0 ? flare.ghost_count : -1;
    o.ghost_spacing = flare.ghost_spacing;
    o.halo_radius = flare.halo_radius;
    o.halo_width = flare.halo_width;
    o.halo_intensity = flare.halo_intensity > 0.0f ? flare.halo_intensity : -1.0f;
    o.streak_length = flare.streak_length;
    o.streak_intensity = flare.streak_intensity > 0.0f ? flare.streak_intensity : -1.0f;
    o.streaks = flare.streaks > 0 ? flare.streaks : -1;
    check(fl_instance_set_outputs(world_, instance_, &o), "fl_instance_set_outputs");
    outputs_ = o;
}

void FireSession::update(double dt) {
    check(fl_world_update(world_, dt), "fl_world_update");
    state_ = fl_instance_state_defaults();
    check(fl_instance_get_state(world_, instance_, &state_), "fl_instance_get_state");
    z_.resize(static_cast<size_t>(state_.rank) * 3);
    int32_t rank = 0;
    check(fl_instance_get_coefficients(world_, instance_, z_.data(), z_.size(), &rank),
          "fl_instance_get_coefficients");
}

std::string FireSession::shownLookJson() const {
    fl_look look{};
    check(fl_instance_get_look(world_, instance_, &look), "fl_instance_get_look");
    size_t size = 0;
    fl_result result = fl_look_to_json(look, nullptr, 0, &size);
    std::string text(size, '\0');
    if (result == FL_OK) result = fl_look_to_json(look, text.data(), text.size(), &size);
    const std::string error = fl_last_error();  // fl_look_release would clear it
    fl_look_release(look);
    if (result != FL_OK) throw ViewerError(error + " (" + fl_result_string(result) + ")");
    text.resize(size > 0 ? size - 1 : 0);  // drop the NUL
    return text;
}

void FireSession::readImage(std::vector<float>& rgba) const {
    rgba.resize(static_cast<size_t>(info_.width) * info_.height * 4);
    check(fl_instance_get_image(world_, instance_, rgba.data(), rgba.size()), "fl_instance_get_image");
}

void FireSession::readFlare(std::vector<float>& rgba) const {
    rgba.resize(static_cast<size_t>(info_.width) * info_.height * 4);
    check(fl_instance_get_flare(world_, instance_, rgba.data(), rgba.size()), "fl_instance_get_flare");
}

}  // namespace firelook::viewer
