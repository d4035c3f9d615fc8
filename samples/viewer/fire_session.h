// The viewer's FireLook state, entirely through the C API: one package, one world with one
// instance, the edited look or keyframes, playback and outputs. Every frame the app calls update()
// and then reads the state, coefficients and (when enabled) the CPU image and lens flare.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "firelook/firelook.h"
#include "keyframes_file.h"
#include "look_edit.h"

namespace firelook::viewer {

// fl_outputs_desc's lens flare settings with their documented defaults spelled out (so the sliders
// show real values rather than the API's "0 = default").
struct FlareSettings {
    bool enabled = false;
    float threshold = 1.0f;
    float intensity = 0.15f;
    int ghost_count = 4;
    float ghost_spacing = 0.45f;
    float halo_radius = 0.6f;
    float halo_width = 0.08f;
    float halo_intensity = 0.5f;
    float streak_length = 0.06f;
    float streak_intensity = 0.6f;
    int streaks = 1;
    bool operator==(const FlareSettings&) const = default;
};

// A light from a direction chosen at run time (fl_instance_set_light_direction), for packages baked
// with six-way or sphere lights. The angles are in the package camera's frame, towards the light: azimuth 0
// on the camera's side, 90 from the right; elevation 90 from above, -90 from below.
struct LightDirection {
    bool enabled = false;
    float azimuth_degrees = 45.0f;
    float elevation_degrees = 30.0f;
    Rgb3 irradiance{1.0f, 1.0f, 1.0f};
    bool operator==(const LightDirection&) const = default;
};

class FireSession {
  public:
    // Loads the package and creates the world and instance with the package's default look.
    // Throws ViewerError whose message names the file (missing, not a package, corrupt...).
    static std::unique_ptr<FireSession> open(const std::string& path);
    ~FireSession();
    FireSession(const FireSession&) = delete;
    FireSession& operator=(const FireSession&) = delete;

    const std::string& path() const { return path_; }
    fl_package package() const { return package_; }
    fl_world world() const { return world_; }
    fl_instance instance() const { return instance_; }
    const fl_package_info& info() const { return info_; }
    const std::vector<int>& frames() const { return frames_; }
    const std::vector<int>& ranks() const { return ranks_; }
    const std::string& defaultLookJson() const { return default_look_json_; }

    // The edited look; applied at once unless keyframes are being played. Throws ViewerError (the
    // instance keeps its previous look).
    const LookEdit& look() const { return look_; }
    void setLook(const LookEdit& look);

    // Keyframes: edit keys() freely, then applyLooks(). With animate on (and at least one key) the
    // instance plays fl_instance_set_keyframes; otherwise it shows the edited look.
    std::vector<Keyframe>& keys() { return keys_; }
    bool animateKeys() const { return animate_keys_; }
    void setAnimateKeys(bool on);
    void applyLooks();

    // The run-time light (only with six-way or sphere lights: hasRelightLights()). Throws ViewerError.
    bool hasRelightLights() const { return relight_first_light_ >= 0; }
    int relightFirstLight() const { return relight_first_light_; }
    int relightLightCount() const { return relight_count_; }
    const LightDirection& lightDirection() const { return light_direction_; }
    void setLightDirection(const LightDirection& light);

    // Playback: the library advances the time; seek() pauses nowhere by itself.
    bool playing() const { return playback_.paused == 0; }
    void setPlaying(bool playing);
    double rate() const { return playback_.rate; }
    void setRate(double frames_per_second);
    void seek(double frame_position);  // package frame number (fractional allowed)

    // The CPU image is needed by the CPU path, the difference view and the lens flare.
    void setOutputs(bool cpu_image, const FlareSettings& flare);
    bool cpuImageEnabled() const { return outputs_.image != 0; }
    bool flareEnabled() const { return outputs_.lens_flare != 0; }

    // One fl_world_update, then the state and coefficients are read back.
    void update(double dt);
    const fl_instance_state& state() const { return state_; }
    // Look-file JSON of the look the instance shows at the last update's frame position: the edited
    // look, or while keys play the library's interpolation of them (fl_instance_get_look).
    std::string shownLookJson() const;
    const std::vector<float>& coefficients() const { return z_; }  // rank x 3
    // The CPU image / flare of the last update (width x height x 4 floats). Throws if not enabled.
    void readImage(std::vector<float>& rgba) const;
    void readFlare(std::vector<float>& rgba) const;

  private:
    FireSession() = default;

    std::string path_;
    fl_package package_{};
    fl_world world_{};
    fl_instance instance_{};
    fl_package_info info_ = fl_package_info_defaults();
    std::vector<int> frames_, ranks_;
    std::string default_look_json_;
    LookEdit look_;
    std::vector<Keyframe> keys_;
    bool animate_keys_ = false;
    fl_playback_desc playback_ = fl_playback_desc_defaults();
    fl_outputs_desc outputs_ = fl_outputs_desc_defaults();
    fl_instance_state state_ = fl_instance_state_defaults();
    std::vector<float> z_;
    int relight_first_light_ = -1;  // the first six-way or sphere light, -1 without them
    int relight_count_ = 0;         // 6, or the sphere's 12 or 42
    double camera_rotation_[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // world from camera, columns; identity without a camera
    LightDirection light_direction_;
};

}  // namespace firelook::viewer
