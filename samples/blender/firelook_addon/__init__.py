# FireLook for Blender: bakes the active scene's Mantaflow smoke/fire cache into a .firelook package
# with `firelook bake` (the scene's camera and sun lamps go with it, as a glTF scene beside the
# package) and shows `firelook render` of a chosen frame and look in an image editor.
# Install: scripts/install_blender_addon.sh (README, "Blender"). Panel: Properties > Scene > FireLook.
import json
import math
import os
import queue
import re
import shutil
import subprocess
import threading

import bpy
import mathutils

bl_info = {
    "name": "FireLook",
    "author": "FireLook",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Scene > FireLook",
    "description": "Bake the fluid domain's cache into a FireLook package and preview a look",
    "category": "Render",
}

PREVIEW_IMAGE = "FireLook preview"
# `firelook bake` logs one progress line per 10% when its stderr is not a terminal (progress_bar.cpp).
PROGRESS_LINE = re.compile(r"^bake:\s+(\d+)%")


class FireLookError(Exception):
    pass


def firelook_executable(context):
    """The preferences' path, else $FIRELOOK_EXE, else `firelook` on the PATH."""
    prefs = context.preferences.addons[__name__].preferences if __name__ in context.preferences.addons else None
    for candidate in ((prefs.executable if prefs else ""), os.environ.get("FIRELOOK_EXE", ""), "firelook"):
        if candidate:
            found = shutil.which(bpy.path.abspath(candidate))
            if found:
                return found
    raise FireLookError("firelook not found: set its path in the add-on's preferences or put it on the PATH")


def fluid_domain(scene):
    """The first object of the scene with a Fluid modifier of type Domain."""
    for obj in scene.objects:
        for modifier in obj.modifiers:
            if modifier.type == "FLUID" and modifier.fluid_type == "DOMAIN":
                return obj, modifier.domain_settings
    raise FireLookError("the scene has no fluid domain (an object with a Fluid modifier of type Domain)")


def cache_sequence(settings):
    """The folder of the domain's OpenVDB frames: Mantaflow writes them to <cache>/data."""
    if settings.cache_data_format != "OPENVDB":
        raise FireLookError("the fluid domain's cache format is %s; FireLook reads OpenVDB" % settings.cache_data_format)
    folder = bpy.path.abspath(settings.cache_directory)
    data = os.path.join(folder, "data")
    folder = data if os.path.isdir(data) else folder
    if not os.path.isdir(folder) or not any(name.endswith(".vdb") for name in os.listdir(folder)):
        raise FireLookError("no .vdb files in the fluid cache %s (bake the simulation first)" % folder)
    return folder


def column_major(matrix):
    return [matrix[row][col] for col in range(4) for row in range(4)]


def write_scene_gltf(context, path):
    """The scene's camera and sun lamps as glTF 2.0 (KHR_lights_punctual), in Blender's own Z-up
    world, which is the cache's: FireLook places both in the VDB's world (docs/cli.md)."""
    scene = context.scene
    camera = scene.camera
    if camera is None or camera.type != "CAMERA":
        raise FireLookError("the scene has no active camera")
    if camera.data.type != "PERSP":
        raise FireLookError("the active camera is not a perspective camera")
    width, height = render_size(scene)
    yfov = vertical_fov(camera.data, width * scene.render.pixel_aspect_x, height * scene.render.pixel_aspect_y)
    location, rotation, _ = camera.matrix_world.decompose()  # no scale: a camera's frame is rigid
    nodes = [{"name": camera.name, "camera": 0,
              "matrix": column_major(rigid_matrix(location, rotation))}]
    lights = []
    for obj in scene.objects:
        if obj.type == "LIGHT" and obj.data.type == "SUN" and not obj.hide_render:
            # A sun shines along its local -Z, as a glTF directional light; its strength is an
            # irradiance, which FireLook takes as colour x intensity.
            _, sun_rotation, _ = obj.matrix_world.decompose()
            nodes.append({"name": obj.name, "matrix": column_major(rigid_matrix(mathutils.Vector(), sun_rotation)),
                          "extensions": {"KHR_lights_punctual": {"light": len(lights)}}})
            lights.append({"name": obj.data.name, "type": "directional", "color": list(obj.data.color),
                           "intensity": obj.data.energy})
    document = {
        "asset": {"version": "2.0", "generator": "FireLook Blender add-on"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": yfov, "aspectRatio": width / height, "znear": camera.data.clip_start}}],
    }
    if lights:
        document["extensionsUsed"] = ["KHR_lights_punctual"]
        document["extensions"] = {"KHR_lights_punctual": {"lights": lights}}
    write_atomically(path, json.dumps(document, indent=1))


def vertical_fov(camera, width, height):
    """The vertical field of view Blender renders with, from the lens and the sensor fit. Computed by
    hand: Camera.calc_matrix_camera wants an evaluated depsgraph, and evaluating the scene makes a
    fluid domain in replay mode write its current frame into the very cache being baked."""
    fit = camera.sensor_fit
    if fit == "AUTO":
        fit = "HORIZONTAL" if width >= height else "VERTICAL"
        sensor = camera.sensor_width  # AUTO fits the sensor width to the larger side
    else:
        sensor = camera.sensor_width if fit == "HORIZONTAL" else camera.sensor_height
    half = sensor / 2.0 / camera.lens
    return 2.0 * math.atan(half * height / width if fit == "HORIZONTAL" else half)


def rigid_matrix(location, rotation):
    return mathutils.Matrix.Translation(location) @ rotation.to_matrix().to_4x4()


def write_atomically(path, text):
    temporary = path + ".%d.tmp" % os.getpid()
    with open(temporary, "w") as out:
        out.write(text)
    os.replace(temporary, path)


def render_size(scene):
    scale = scene.render.resolution_percentage / 100.0
    return max(1, int(scene.render.resolution_x * scale)), max(1, int(scene.render.resolution_y * scale))


def package_path(settings):
    path = bpy.path.abspath(settings.package)
    if not path.endswith(".firelook"):
        raise FireLookError("the package path must end in .firelook: " + path)
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    return path


def bake_command(context):
    """The `firelook bake` command for the active scene, and the package it writes."""
    scene = context.scene
    settings = scene.firelook
    _, domain = fluid_domain(scene)
    sequence = cache_sequence(domain)
    package = package_path(settings)
    gltf = os.path.splitext(package)[0] + ".gltf"
    write_scene_gltf(context, gltf)
    width, height = render_size(scene)
    command = [firelook_executable(context), "bake", sequence, "--scene", gltf, "--size", "%dx%d" % (width, height),
               "--up", "z", "-o", package]
    if settings.frames.strip():
        command += ["--frames", settings.frames.strip()]
    if settings.config:
        command += ["--config", bpy.path.abspath(settings.config)]
    return command, package


def report_progress(context, percent, line):
    """Blender's status bar (and the window manager's progress cursor) in the UI; the log headless."""
    context.window_manager.progress_update(percent)
    if context.workspace is not None and not bpy.app.background:
        context.workspace.status_text_set("FireLook: " + line)
    else:
        print("FireLook: " + line, flush=True)


def finish_progress(context):
    context.window_manager.progress_end()
    if context.workspace is not None and not bpy.app.background:
        context.workspace.status_text_set(None)


def pump(stream, lines):
    for line in iter(stream.readline, ""):
        lines.put(line.rstrip("\n"))
    lines.put(None)


class FIRELOOK_OT_bake(bpy.types.Operator):
    """Bake the fluid domain's cache, with the scene's camera and suns, into the FireLook package"""
    bl_idname = "firelook.bake"
    bl_label = "Bake FireLook Package"
    running = False  # one bake at a time: a second would write the same package

    def start(self, context):
        if FIRELOOK_OT_bake.running:
            raise FireLookError("a FireLook bake is already running")
        command, self.package = bake_command(context)
        self.log = []
        self.process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        FIRELOOK_OT_bake.running = True
        self.lines = queue.Queue()
        threading.Thread(target=pump, args=(self.process.stdout, self.lines), daemon=True).start()
        context.window_manager.progress_begin(0, 100)
        report_progress(context, 0, "baking " + os.path.basename(self.package))

    def drain(self, context):
        """Handles the lines so far; True once the bake has ended."""
        while True:
            try:
                line = self.lines.get_nowait()
            except queue.Empty:
                return False
            if line is None:
                return True
            self.log.append(line)
            match = PROGRESS_LINE.match(line)
            if match:
                report_progress(context, int(match.group(1)), line)

    def end(self, context):
        code = self.process.wait()
        FIRELOOK_OT_bake.running = False
        finish_progress(context)
        if code != 0:
            errors = [line for line in self.log if "error" in line] or self.log[-1:]
            self.report({"ERROR"}, "firelook bake failed: " + (errors[-1] if errors else "exit %d" % code))
            return {"CANCELLED"}
        self.report({"INFO"}, "FireLook: baked " + self.package)
        return {"FINISHED"}

    def execute(self, context):
        # Headless (blender -b) there is no event loop for a modal operator: bake to the end here.
        try:
            self.start(context)
        except FireLookError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        while not self.drain(context):
            threading.Event().wait(0.1)
        return self.end(context)

    def invoke(self, context, event):
        try:
            self.start(context)
        except FireLookError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.timer = context.window_manager.event_timer_add(0.25, window=context.window)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self.process.terminate()  # firelook stops between steps and writes nothing
        if event.type not in {"TIMER", "ESC"} or not self.drain(context):
            return {"PASS_THROUGH"}
        context.window_manager.event_timer_remove(self.timer)
        return self.end(context)


def show_in_image_editor(context, image):
    """In the first image editor of the screen, or a new window's (nothing to show headless)."""
    if bpy.app.background or context.window_manager is None:
        return
    for window in context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == "IMAGE_EDITOR":
                area.spaces.active.image = image
                return
    bpy.ops.wm.window_new()
    area = context.window_manager.windows[-1].screen.areas[0]
    area.type = "IMAGE_EDITOR"
    area.spaces.active.image = image


class FIRELOOK_OT_preview(bpy.types.Operator):
    """Render the chosen frame of the package with the chosen look (firelook render) and show it"""
    bl_idname = "firelook.preview"
    bl_label = "Preview FireLook Frame"

    def execute(self, context):
        settings = context.scene.firelook
        try:
            package = package_path(settings)
            if not os.path.isfile(package):
                raise FireLookError("no package at %s: bake it first" % package)
            image_path = os.path.splitext(package)[0] + "_preview_%d.exr" % settings.preview_frame
            command = [firelook_executable(context), "render", package, "--frame", str(settings.preview_frame),
                       "-o", image_path]
            if settings.look:
                command += ["--look", bpy.path.abspath(settings.look)]
        except FireLookError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        result = subprocess.run(command, capture_output=True, text=True)
        if result.returncode != 0:
            self.report({"ERROR"}, "firelook render failed: " + (result.stderr.strip().splitlines() or ["?"])[-1])
            return {"CANCELLED"}
        image = bpy.data.images.get(PREVIEW_IMAGE)
        if image is None:
            image = bpy.data.images.load(image_path)
            image.name = PREVIEW_IMAGE
        else:
            image.filepath = image_path
            image.reload()
        show_in_image_editor(context, image)
        self.report({"INFO"}, "FireLook: frame %d in '%s'" % (settings.preview_frame, PREVIEW_IMAGE))
        return {"FINISHED"}


class FireLookSettings(bpy.types.PropertyGroup):
    package: bpy.props.StringProperty(name="Package", subtype="FILE_PATH", default="//firelook/scene.firelook",
                                      description="The .firelook package to write and preview")
    frames: bpy.props.StringProperty(name="Frames", default="",
                                     description="Frames to bake: A-B ranges and single frames (empty: all)")
    config: bpy.props.StringProperty(name="Bake settings", subtype="FILE_PATH", default="",
                                     description="Optional bake.json (docs/bake-config.md)")
    look: bpy.props.StringProperty(name="Look", subtype="FILE_PATH", default="",
                                   description="Look file for the preview (empty: the package's default look)")
    preview_frame: bpy.props.IntProperty(name="Preview frame", default=1, description="Frame number of the cache")


class FireLookPreferences(bpy.types.AddonPreferences):
    bl_idname = __name__
    executable: bpy.props.StringProperty(name="firelook", subtype="FILE_PATH", default="",
                                         description="The firelook program (empty: $FIRELOOK_EXE or the PATH)")

    def draw(self, context):
        self.layout.prop(self, "executable")


class FIRELOOK_PT_scene(bpy.types.Panel):
    bl_label = "FireLook"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "scene"

    def draw(self, context):
        settings = context.scene.firelook
        layout = self.layout
        for name in ("package", "frames", "config"):
            layout.prop(settings, name)
        layout.operator(FIRELOOK_OT_bake.bl_idname, icon="RENDER_ANIMATION")
        layout.prop(settings, "look")
        layout.prop(settings, "preview_frame")
        layout.operator(FIRELOOK_OT_preview.bl_idname, icon="RENDER_STILL")


classes = (FireLookSettings, FireLookPreferences, FIRELOOK_OT_bake, FIRELOOK_OT_preview, FIRELOOK_PT_scene)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.firelook = bpy.props.PointerProperty(type=FireLookSettings)


def unregister():
    del bpy.types.Scene.firelook
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
