// The Blender add-on (samples/blender/firelook_addon): a scene built headless as an artist's would be
// bakes through the add-on's operator and previews a frame (tests/blender/addon_bake_preview.py
// checks the package's camera, sun and size against the scene, and the preview image). Skips,
// saying why, where Blender does not run.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../support/tiny_bake_config.h"
#include "blender_support.h"
#include "image/image_io.h"

namespace {

using namespace firelook::testing;

// Runs `blender_command` with tests/blender/SCRIPT in a fresh folder holding the tiny bake's
// bake.json; the script gets the add-on's folder, the sample and that folder.
CommandResult runAddonScript(const TempDir& dir, const std::string& blender_command, const std::string& script) {
    std::ofstream(dir / "bake.json") << kTinyBakeConfig;
    const std::string source = FIRELOOK_SOURCE_DIR;
    return runIn(dir, "FIRELOOK_EXE='" FIRELOOK_EXE "' " + blender_command + " --python '" + source +
                          "/tests/blender/" + script + "' -- '" + source + "/samples/blender' '" + kSample + "' '" +
                          dir.path().string() + "'");
}

TEST(BlenderAddon, BakesAndPreviewsTheSampleHeadless) {
    if (const std::string why = whyNoBlender(); !why.empty()) GTEST_SKIP() << why;
    TempDir dir;
    const CommandResult r =
        runAddonScript(dir, "blender -b --factory-startup --python-exit-code 1", "addon_bake_preview.py");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("addon test: baked and previewed"), std::string::npos) << r.out;
    // Progress reached the log headless (report_progress), and the files are where the add-on says.
    EXPECT_NE(r.out.find("FireLook: bake: 100%"), std::string::npos) << r.out;
    EXPECT_TRUE(std::filesystem::exists(dir / "pkg" / "scene.gltf"));
    const firelook::image::ImageRGBA preview = firelook::image::readImage(dir / "pkg" / "scene_preview_3.exr");
    EXPECT_EQ(preview.width, 48);
    EXPECT_EQ(preview.height, 32);
}

// The panel's button: the bake runs as a modal operator while Blender's window stays live (under
// Xvfb), its progress reaching the status bar (tests/blender/addon_modal_bake.py records every line
// the add-on shows there), then the preview opens in an image editor.
TEST(BlenderAddon, BakesModallyWithProgressInTheStatusBar) {
    if (const std::string why = whyNoBlender(); !why.empty()) GTEST_SKIP() << why;
    TempDir dir;
    const CommandResult r =
        runAddonScript(dir, "timeout 240 xvfb-run -a blender --factory-startup", "addon_modal_bake.py");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    ASSERT_TRUE(std::filesystem::exists(dir / "modal.json")) << r.out << r.err;
    const nlohmann::json seen = nlohmann::json::parse(readFile(dir / "modal.json"));
    EXPECT_EQ(seen.at("invoked"), nlohmann::json({"RUNNING_MODAL"}));
    EXPECT_TRUE(seen.at("package").get<bool>());
    EXPECT_EQ(seen.at("preview"), nlohmann::json({"FINISHED"}));
    // The first line names the package; firelook's own lines follow, up to 100%.
    ASSERT_GE(seen.at("percent").size(), 2u) << seen.dump();
    EXPECT_EQ(seen.at("percent").front(), 0);
    EXPECT_EQ(seen.at("percent").back(), 100);
    EXPECT_NE(seen.at("status").back().get<std::string>().find("bake: 100%"), std::string::npos) << seen.dump();
    const std::vector<std::string> areas = seen.at("areas");
    EXPECT_NE(std::find(areas.begin(), areas.end(), "IMAGE_EDITOR"), areas.end()) << seen.dump();
}

// The README's install: the script copies the add-on into Blender's user add-ons (under $HOME, a
// temporary one here) and enables it in the saved preferences.
TEST(BlenderAddon, InstallScriptInstallsAndEnablesIt) {
    if (const std::string why = whyNoBlender(); !why.empty()) GTEST_SKIP() << why;
    TempDir home;
    const std::string source = FIRELOOK_SOURCE_DIR;
    const std::string env = "HOME='" + home.path().string() + "' XDG_CONFIG_HOME='" + home.path().string() + "/.config' ";
    const CommandResult install = runIn(home, env + "'" + source + "/scripts/install_blender_addon.sh'");
    ASSERT_EQ(install.exit_code, 0) << install.out << install.err;
    const CommandResult check = runIn(home, env + "blender -b --python-expr \"import bpy; print('FIRELOOK', "
                                                  "'firelook_addon' in bpy.context.preferences.addons, "
                                                  "hasattr(bpy.types.Scene, 'firelook'))\"");
    ASSERT_EQ(check.exit_code, 0) << check.err;
    EXPECT_NE(check.out.find("FIRELOOK True True"), std::string::npos) << check.out;
}

}  // namespace
