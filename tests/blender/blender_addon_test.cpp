// The Blender add-on (samples/blender/firelook_addon): a scene built headless as an artist's would be
// bakes through the add-on's operator and previews a frame (tests/blender/addon_bake_preview.py
// checks the package's camera, sun and size against the scene, and the preview image). Skips,
// saying why, where Blender does not run.
#include <gtest/gtest.h>

#include <fstream>

#include "../support/tiny_bake_config.h"
#include "blender_support.h"
#include "image/image_io.h"

namespace {

using namespace firelook::testing;

TEST(BlenderAddon, BakesAndPreviewsTheSampleHeadless) {
    if (const std::string why = whyNoBlender(); !why.empty()) GTEST_SKIP() << why;
    TempDir dir;
    std::ofstream(dir / "bake.json") << kTinyBakeConfig;
    const std::string source = FIRELOOK_SOURCE_DIR;
    const CommandResult r = runIn(dir, "FIRELOOK_EXE='" FIRELOOK_EXE "' blender -b --factory-startup --python-exit-code 1 "
                                       "--python '" + source + "/tests/blender/addon_bake_preview.py' -- '" + source +
                                       "/samples/blender' '" + kSample + "' '" + dir.path().string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("addon test: baked and previewed"), std::string::npos) << r.out;
    // Progress reached the log headless (report_progress), and the files are where the add-on says.
    EXPECT_NE(r.out.find("FireLook: bake: 100%"), std::string::npos) << r.out;
    EXPECT_TRUE(std::filesystem::exists(dir / "pkg" / "scene.gltf"));
    const firelook::image::ImageRGBA preview = firelook::image::readImage(dir / "pkg" / "scene_preview_3.exr");
    EXPECT_EQ(preview.width, 48);
    EXPECT_EQ(preview.height, 32);
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
