#include "cli/scene_options.h"

namespace firelook::cli {

void addSceneFlags(CLI::App& command, SceneFlags& flags) {
    command.add_option("--scene", flags.scene, "glTF 2.0 scene: first perspective camera and its directional lights")
        ->check(CLI::ExistingFile);
    command.add_option("--camera", flags.camera, "camera as PX,PY,PZ,TX,TY,TZ,FOV_DEG (position, target, vertical fov)")
        ->expected(7)
        ->delimiter(',');
    command.add_option("--size", flags.size, "image size WxH")->capture_default_str();
    command.add_option("--up", flags.up, "world up axis of the default camera: y, or z for Blender data")
        ->check(CLI::IsMember({"y", "z"}))
        ->capture_default_str();
    command.add_option("--bins", flags.bins, "number of temperature bins")->check(CLI::Range(1, 256))->capture_default_str();
    command.add_option("--config", flags.config, "bake settings JSON (docs/bake-config.md)")->check(CLI::ExistingFile);
    command
        .add_option(
            "--lights", flags.lights,
            "six-way: add six camera-relative lights (right, top, back, left, bottom, front), off in "
            "the default look (docs/cli.md, \"Six-way lights\"); sphere, sphere:12 or sphere:42: that "
            "many camera-relative lights on a geodesic sphere (42 for sphere), off in the default "
            "look, to relight from any direction (basis/sphere_lights.h)")
        ->check(CLI::IsMember({"scene", "six-way", "sphere", "sphere:12", "sphere:42"}))
        ->capture_default_str();
    addSequenceFlags(command, flags.sequence);
}

bake::BakeConfig makeBakeConfig(const CLI::App& command, const SceneFlags& flags, const std::string& quality) {
    bake::BakeConfig config;
    if (!quality.empty()) bake::applyQuality(config, quality);
    if (!flags.config.empty()) bake::applyConfigFile(config, flags.config);
    const auto given = [&](const char* name) { return command.count(name) > 0; };
    if (given("--size") || flags.config.empty())
        std::tie(config.scene.width, config.scene.height) = bake::parseSize(flags.size);
    if (given("--up") || flags.config.empty())
        config.scene.up = flags.up == "z" ? render::UpAxis::Z : render::UpAxis::Y;
    if (given("--bins") || flags.config.empty()) config.bins = flags.bins;
    if (given("--lights")) bake::applyLightsChoice(config.scene, flags.lights);
    config.scene.scene_path = flags.scene;
    if (flags.camera.size() == 7) {
        std::array<double, 7> c{};
        std::copy(flags.camera.begin(), flags.camera.end(), c.begin());
        config.scene.camera = c;
    }
    applySequenceFlags(flags.sequence, config.read);
    return config;
}

}  // namespace firelook::cli
