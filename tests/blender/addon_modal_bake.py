# Run by tests/blender/blender_addon_test.cpp under Xvfb (Blender with its window, not -b):
#   blender --factory-startup --python addon_modal_bake.py -- ADDON_DIR SAMPLE OUT_DIR
# Invokes the add-on's bake as the panel's button does (a modal operator: firelook runs while the
# UI stays live), records what reaches the status bar, then previews in an image editor. Writes
# OUT_DIR/modal.json with what it saw and quits; the C++ test judges it.
import json
import os
import shutil
import sys

import bpy

addon_dir, sample, out = sys.argv[sys.argv.index("--") + 1:][:3]
sys.dont_write_bytecode = True  # no __pycache__ in the repository
sys.path.insert(0, addon_dir)
import firelook_addon  # noqa: E402

firelook_addon.register()
bpy.context.preferences.filepaths.temporary_directory = out  # where quitting leaves quit.blend
scene = bpy.context.scene
for obj in list(scene.collection.all_objects):
    bpy.data.objects.remove(obj)
bpy.ops.mesh.primitive_cube_add(location=(1, 1, 1))
fluid = bpy.context.active_object.modifiers.new("Fluid", "FLUID")
fluid.fluid_type = "DOMAIN"
fluid.domain_settings.domain_type = "GAS"
fluid.domain_settings.cache_data_format = "OPENVDB"
fluid.domain_settings.cache_frame_end = 1001  # as in addon_bake_preview.py: no replay writes
fluid.domain_settings.cache_frame_start = 1000
fluid.domain_settings.cache_directory = os.path.join(out, "cache")
os.makedirs(os.path.join(out, "cache", "data"), exist_ok=True)
for name in sorted(os.listdir(sample)):
    shutil.copyfile(os.path.join(sample, name), os.path.join(out, "cache", "data", name))
camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
camera.location = (1.0, -2.0, 1.2)
camera.rotation_euler = (1.4, 0.0, 0.0)
scene.collection.objects.link(camera)
scene.camera = camera
scene.collection.objects.link(bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN")))
scene.render.resolution_x = scene.render.resolution_y = 32
settings = scene.firelook
settings.package = os.path.join(out, "pkg", "scene.firelook")
settings.frames = "3"
settings.config = os.path.join(out, "bake.json")
settings.preview_frame = 3

seen = {"status": [], "percent": []}
report = firelook_addon.report_progress


def recording(context, percent, line):
    seen["percent"].append(percent)
    seen["status"].append(line)
    report(context, percent, line)


firelook_addon.report_progress = recording
state = {"invoked": None}


def in_window(operator):
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window, area=window.screen.areas[0]):
        return sorted(operator())


def step():
    if state["invoked"] is None:
        state["invoked"] = in_window(lambda: bpy.ops.firelook.bake("INVOKE_DEFAULT"))
        return 0.25
    if firelook_addon.FIRELOOK_OT_bake.running:
        return 0.25
    seen["invoked"] = state["invoked"]
    seen["package"] = os.path.isfile(settings.package)
    seen["preview"] = in_window(bpy.ops.firelook.preview)
    seen["areas"] = [a.type for w in bpy.context.window_manager.windows for a in w.screen.areas]
    with open(os.path.join(out, "modal.json"), "w") as f:
        json.dump(seen, f)
    bpy.ops.wm.quit_blender()
    return None


bpy.app.timers.register(step, first_interval=1.0)
