# Run by tests/blender/blender_addon_test.cpp:
#   blender -b --factory-startup --python-exit-code 1 --python addon_bake_preview.py -- ADDON_DIR SAMPLE OUT_DIR
# Builds a scene headless as an artist's would be (a Mantaflow gas domain whose OpenVDB cache is the
# bundled sample, under <cache>/data as Mantaflow writes it; a camera; a sun), bakes it through the
# add-on's operator and previews a frame. Any failed check raises, which exits 1.
import json
import math
import os
import shutil
import subprocess
import sys

import bpy
import mathutils

addon_dir, sample, out = sys.argv[sys.argv.index("--") + 1:][:3]
sys.dont_write_bytecode = True  # no __pycache__ in the repository
sys.path.insert(0, addon_dir)
import firelook_addon  # noqa: E402

firelook_addon.register()
scene = bpy.context.scene
for obj in list(scene.collection.all_objects):
    bpy.data.objects.remove(obj)

bpy.ops.mesh.primitive_cube_add(location=(1, 1, 1))
domain = bpy.context.active_object
fluid = domain.modifiers.new("Fluid", "FLUID")
fluid.fluid_type = "DOMAIN"
fluid.domain_settings.domain_type = "GAS"
fluid.domain_settings.cache_data_format = "OPENVDB"
# The cache holds frames that no simulation made: Blender's replay cache would write over frame 1
# when the scene is evaluated (with its own grids: density, shadow, velocity), so its range is moved
# away from the frames. The files are copies, never links to the repository's: Blender manages the
# folder.
fluid.domain_settings.cache_frame_end = 1001
fluid.domain_settings.cache_frame_start = 1000
cache = os.path.join(out, "cache")
fluid.domain_settings.cache_directory = cache
os.makedirs(os.path.join(cache, "data"), exist_ok=True)
for name in sorted(os.listdir(sample)):
    shutil.copyfile(os.path.join(sample, name), os.path.join(cache, "data", name))

camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
camera.location = (1.0, -2.0, 1.2)
camera.rotation_euler = (math.radians(80), 0.0, math.radians(3))  # a slight roll and tilt: no axis-aligned luck
scene.collection.objects.link(camera)
scene.camera = camera
sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
sun.data.energy = 3.0
sun.data.color = (1.0, 0.9, 0.8)
sun.rotation_euler = (math.radians(40), math.radians(20), 0.0)
scene.collection.objects.link(sun)
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 48, 32, 100

settings = scene.firelook
settings.package = os.path.join(out, "pkg", "scene.firelook")
settings.frames = "3"
settings.config = os.path.join(out, "bake.json")
settings.preview_frame = 3
assert bpy.ops.firelook.bake() == {"FINISHED"}
assert os.path.isfile(settings.package), "no package"

# The package holds the scene's camera and sun (firelook info --json).
info = json.loads(subprocess.run([os.environ["FIRELOOK_EXE"], "info", "--json", settings.package],
                                 check=True, capture_output=True, text=True).stdout)["metadata"]
recorded = info["camera"]
assert (recorded["width"], recorded["height"]) == (48, 32), recorded
m = recorded["world_from_camera"]
world_from_camera = mathutils.Matrix([[m[c * 4 + r] for c in range(4)] for r in range(4)])
assert all(abs(a - b) < 1e-6 for row_a, row_b in zip(world_from_camera, camera.matrix_world)
           for a, b in zip(row_a, row_b)), (world_from_camera, camera.matrix_world)
# Blender's default sensor (36 mm wide, 50 mm lens, fit to the wider side) at 48x32: yfov from the height.
expected_yfov = 2 * math.atan(36 / 2 / 50 * 32 / 48)
assert abs(recorded["yfov_radians"] - expected_yfov) < 1e-6, (recorded["yfov_radians"], expected_yfov)
travel = -(sun.matrix_world.to_3x3() @ mathutils.Vector((0, 0, 1)))
directions = info["bake"]["light_directions"]
assert len(directions) == 1 and (mathutils.Vector(directions[0]) - travel).length < 1e-6, (directions, travel)
look = info["bake"]["default_look"]
assert all(abs(a - b) < 1e-6 for a, b in zip(look["light_irradiance"][0], (3.0, 2.7, 2.4))), look

assert bpy.ops.firelook.preview() == {"FINISHED"}
image = bpy.data.images[firelook_addon.PREVIEW_IMAGE]
assert tuple(image.size) == (48, 32), tuple(image.size)
pixels = list(image.pixels)
assert all(math.isfinite(p) and p >= 0.0 for p in pixels), "non-finite or negative pixels"
alpha = pixels[3::4]
# The default camera of the scene sees the fireball: some pixels are covered, some are not.
assert 0.0 < max(alpha) <= 1.0 and min(alpha) == 0.0, (min(alpha), max(alpha))
assert sum(p for i, p in enumerate(pixels) if i % 4 != 3) > 0.0, "a black preview"
print("addon test: baked and previewed; covered pixels %d of %d" % (sum(a > 0.01 for a in alpha), len(alpha)))
