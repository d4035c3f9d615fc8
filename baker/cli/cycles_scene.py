# The body of the script `firelook export-cycles` writes (docs/cli.md, "export-cycles"): it builds
# one frame of a package with one look in Blender's Cycles and renders it. The command puts the
# scene's numbers first, as the JSON document SCENE; everything below reads only SCENE.
#
#   blender -b --factory-startup --python scene.py -- --spp N -o OUT.exr [--seed S] [--threads T]
#
# OUT.exr: linear, premultiplied RGBA (alpha = 1 - transmittance), the package's size, written to a
# temporary beside it and renamed. The model is docs/model.md's, node for node:
#   rho = clamp(density_scale * density, 0, 1e6)            T = temperature_scale * temperature + offset
#   sigma_t = rho * ((k_f - k_s)/2 * tanh((clamp(T, T_lo, T_hi) - T_c) / (2 dT)) + (k_f + k_s)/2)
#   Volume Scatter (colour albedo, density sigma_t) + Volume Absorption (colour albedo: Cycles absorbs
#   density * (1 - colour)) give sigma_s = albedo * sigma_t and extinction sigma_t
#   emission = rho * sum_i c_i exp(-((T' - T_i) / (w dT))^2), T' = clamp(T, T_0, T_(n-1)) (or the
#   range for packages baked before the centre clamp), c_i the look's non-negative fit
# and the package's camera (pinhole, vertical field of view, box filter over the pixel) and its
# directional lights as sun lamps of angle 0 whose strength is the irradiance.
import argparse
import json
import math
import os
import sys

import bpy
import mathutils


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="scene.py", description="Render the exported FireLook frame in Cycles")
    parser.add_argument("--spp", type=int, required=True, help="samples per pixel")
    parser.add_argument("-o", "--out", required=True, help="output image (.exr)")
    parser.add_argument("--seed", type=int, default=0, help="Cycles' sampling seed")
    parser.add_argument("--threads", type=int, default=0, help="render threads (0: every core)")
    args = parser.parse_args(argv)
    if args.spp < 1:
        parser.error("--spp must be at least 1")
    return args


def fail(message):
    print("scene.py: error: " + message, file=sys.stderr)
    sys.exit(1)


def math_node(tree, operation, a, b=None, c=None):
    """A Math node; each input is a socket (linked) or a number."""
    node = tree.nodes.new("ShaderNodeMath")
    node.operation = operation
    for index, value in enumerate((a, b, c)):
        if value is None:
            continue
        if isinstance(value, bpy.types.NodeSocket):
            tree.links.new(value, node.inputs[index])
        else:
            node.inputs[index].default_value = value
    return node.outputs[0]


def clamp_node(tree, value, lo, hi):
    node = tree.nodes.new("ShaderNodeClamp")
    tree.links.new(value, node.inputs["Value"])
    node.inputs["Min"].default_value = lo
    node.inputs["Max"].default_value = hi
    return node.outputs[0]


def grid_value(tree, grid):
    node = tree.nodes.new("ShaderNodeAttribute")
    node.attribute_type = "GEOMETRY"
    node.attribute_name = grid
    return node.outputs["Fac"]


def emission_rgb(tree, t_emission):
    """sum_i c_i exp(-u_i^2), u_i = (T' - T_i) / (w dT), as a colour; bins whose c_i is 0 add nothing."""
    bins = SCENE["bins"]
    d_t = (bins["t_hi"] - bins["t_lo"]) / bins["count"]
    scale = 1.0 / (SCENE["rbf_width"] * d_t)
    total = None
    for i, c in enumerate(SCENE["emission_coefficients"]):
        if max(c) <= 0.0:
            continue
        centre = bins["t_lo"] + (i + 0.5) * d_t
        u = math_node(tree, "MULTIPLY_ADD", t_emission, scale, -centre * scale)
        weight = math_node(tree, "POWER", math.exp(-1.0), math_node(tree, "MULTIPLY", u, u))
        term = tree.nodes.new("ShaderNodeVectorMath")
        term.operation = "SCALE"
        term.inputs[0].default_value = c
        tree.links.new(weight, term.inputs["Scale"])
        if total is None:
            total = term.outputs[0]
        else:
            add = tree.nodes.new("ShaderNodeVectorMath")
            add.operation = "ADD"
            tree.links.new(total, add.inputs[0])
            tree.links.new(term.outputs[0], add.inputs[1])
            total = add.outputs[0]
    return total


def fire_material():
    material = bpy.data.materials.new("firelook_look")
    material.use_nodes = True
    material.cycles.volume_interpolation = "LINEAR"  # docs/model.md: trilinear between voxels
    material.cycles.homogeneous_volume = False
    material.cycles.volume_sampling = "MULTIPLE_IMPORTANCE"
    tree = material.node_tree
    tree.nodes.clear()
    read = SCENE["read"]
    bins = SCENE["bins"]
    d_t = (bins["t_hi"] - bins["t_lo"]) / bins["count"]

    rho = clamp_node(tree, math_node(tree, "MULTIPLY", grid_value(tree, read["density_grid"]), read["density_scale"]),
                     0.0, SCENE["max_density"])
    temperature = math_node(tree, "MULTIPLY_ADD", grid_value(tree, read["temperature_grid"]),
                            read["temperature_scale"], read["temperature_offset"])
    t_in_bins = clamp_node(tree, temperature, bins["t_lo"], bins["t_hi"])

    look = SCENE["look"]
    a = 0.5 * (look["flame_extinction"] - look["smoke_extinction"])
    b = 0.5 * (look["flame_extinction"] + look["smoke_extinction"])
    # tanh((T - T_c) / (2 dT)) = tanh(T / (2 dT) - T_c / (2 dT))
    f = math_node(tree, "TANH", math_node(tree, "MULTIPLY_ADD", t_in_bins, 1.0 / (2.0 * d_t),
                                          -look["temperature_threshold"] / (2.0 * d_t)))
    sigma_t = math_node(tree, "MULTIPLY", math_node(tree, "MULTIPLY_ADD", f, a, b), rho)

    albedo = look["albedo"]
    scatter = tree.nodes.new("ShaderNodeVolumeScatter")
    scatter.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    scatter.inputs["Anisotropy"].default_value = 0.0  # isotropic phase function
    tree.links.new(sigma_t, scatter.inputs["Density"])
    absorb = tree.nodes.new("ShaderNodeVolumeAbsorption")
    absorb.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    tree.links.new(sigma_t, absorb.inputs["Density"])
    extinction = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(scatter.outputs[0], extinction.inputs[0])
    tree.links.new(absorb.outputs[0], extinction.inputs[1])
    volume = extinction.outputs[0]

    if SCENE["emission_clamp"] == "bin_centres":
        t_emission = clamp_node(tree, t_in_bins, bins["t_lo"] + 0.5 * d_t, bins["t_hi"] - 0.5 * d_t)
    else:
        t_emission = t_in_bins
    le = emission_rgb(tree, t_emission)
    if le is not None:
        j = tree.nodes.new("ShaderNodeVectorMath")  # j = rho * L_e(T): radiance per unit length
        j.operation = "SCALE"
        tree.links.new(le, j.inputs[0])
        tree.links.new(rho, j.inputs["Scale"])
        emission = tree.nodes.new("ShaderNodeEmission")
        emission.inputs["Strength"].default_value = 1.0
        tree.links.new(j.outputs[0], emission.inputs["Color"])
        with_emission = tree.nodes.new("ShaderNodeAddShader")
        tree.links.new(volume, with_emission.inputs[0])
        tree.links.new(emission.outputs[0], with_emission.inputs[1])
        volume = with_emission.outputs[0]

    output = tree.nodes.new("ShaderNodeOutputMaterial")
    output.target = "CYCLES"
    tree.links.new(volume, output.inputs["Volume"])
    return material


def add_volume(scene):
    path = SCENE["vdb"]
    if not os.path.isfile(path):
        fail(path + ": the frame's VDB file (from the package's provenance) does not exist")
    data = bpy.data.volumes.new("firelook_frame")
    data.filepath = path
    if not data.grids.load():
        fail(path + ": Blender cannot read it: " + data.grids.error_message)
    read = SCENE["read"]
    names = [g.name for g in data.grids]
    for grid in (read["density_grid"], read["temperature_grid"]):
        if grid not in names:
            fail(path + ": has no grid '" + grid + "' (grids: " + ", ".join(names) + ")")
    matrix = data.grids[read["density_grid"]].matrix_object
    voxel = min(matrix.col[axis].to_3d().length for axis in range(3))
    # Cycles puts voxel (i,j,k)'s value at the centre of its cell, index point (i,j,k) + 1/2, where
    # OpenVDB and FireLook put it at (i,j,k) (docs/model.md): the object moves back by half a voxel
    # along each index axis, so that Cycles' trilinear interpolation is FireLook's. Measured on frame
    # 7 of the bundled sample (emission only, 64x64): without it 10.3% relative RMSE, with it 2.4%.
    # The object is otherwise unrotated and unscaled, so densities and the step are per world unit, as
    # in FireLook.
    obj_offset = -(matrix.to_3x3() @ mathutils.Vector((0.5, 0.5, 0.5)))
    data.render.space = "WORLD"
    data.render.step_size = SCENE["step_voxels"] * voxel
    data.render.clipping = 0.0  # every active voxel is volume (the default 0.001 drops thin smoke)
    data.render.precision = "FULL"  # float grids, not Cycles' default half floats
    data.materials.append(fire_material())
    obj = bpy.data.objects.new("firelook_frame", data)
    obj.location = obj_offset
    scene.collection.objects.link(obj)
    return voxel


def add_camera(scene):
    camera = SCENE["camera"]
    data = bpy.data.cameras.new("firelook_camera")
    data.type = "PERSP"
    data.sensor_fit = "VERTICAL"
    data.angle_y = camera["yfov_radians"]
    data.clip_start = 1e-4
    data.clip_end = 1e6
    obj = bpy.data.objects.new("firelook_camera", data)
    m = camera["world_from_camera"]  # column-major; the camera looks along -Z with +Y up, as Blender's
    obj.matrix_world = mathutils.Matrix([[m[c * 4 + r] for c in range(4)] for r in range(4)])
    scene.collection.objects.link(obj)
    scene.camera = obj


def add_lights(scene):
    for index, light in enumerate(SCENE["lights"]):
        irradiance = light["irradiance"]
        strength = max(irradiance)
        data = bpy.data.lights.new("firelook_light_%d" % index, type="SUN")
        data.energy = strength  # a sun's strength is its irradiance (W/m^2) on a surface facing it
        data.color = [c / strength for c in irradiance]
        data.angle = 0.0  # a directional light, not a disc
        data.cycles.cast_shadow = True
        obj = bpy.data.objects.new(data.name, data)
        # A sun shines along its local -Z: that axis is the direction of travel.
        travel = mathutils.Vector(light["direction"]).normalized()
        obj.matrix_world = (-travel).to_track_quat("Z", "Y").to_matrix().to_4x4()
        scene.collection.objects.link(obj)


def setup_render(scene, args):
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = args.spp
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = args.seed
    cycles.use_animated_seed = False
    cycles.pixel_filter_type = "BOX"  # a pixel is the mean over its square footprint
    cycles.filter_width = 1.0
    # Every order of scattering: Russian roulette ends paths without bias, the cap almost never.
    cycles.max_bounces = SCENE["volume_bounces"]
    cycles.volume_bounces = SCENE["volume_bounces"]
    cycles.diffuse_bounces = cycles.glossy_bounces = cycles.transmission_bounces = 0
    cycles.transparent_max_bounces = SCENE["volume_bounces"]  # volume boundaries are transparent hits on shadow rays too
    cycles.sample_clamp_direct = 0.0  # no clamping: it would bias bright samples
    cycles.sample_clamp_indirect = 0.0
    cycles.light_sampling_threshold = 0.0
    cycles.volume_step_rate = 1.0  # the step is the volume's own (add_volume)
    cycles.volume_max_steps = SCENE["volume_max_steps"]
    render = scene.render
    render.resolution_x = SCENE["camera"]["width"]
    render.resolution_y = SCENE["camera"]["height"]
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    render.film_transparent = True  # alpha = 1 - transmittance, nothing behind the volume
    render.threads_mode = "FIXED" if args.threads > 0 else "AUTO"
    if args.threads > 0:
        render.threads = args.threads
    render.use_compositing = False
    render.use_sequencer = False
    render.use_file_extension = False
    image = render.image_settings
    image.file_format = "OPEN_EXR"
    image.color_mode = "RGBA"
    image.color_depth = "32"
    image.exr_codec = "ZIP"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    world = bpy.data.worlds.new("firelook_black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world


def main():
    args = arguments()
    scene = bpy.context.scene
    for obj in list(scene.collection.all_objects):  # the startup file's cube, camera and lamp
        bpy.data.objects.remove(obj)
    add_volume(scene)
    add_camera(scene)
    add_lights(scene)
    setup_render(scene, args)
    out = os.path.abspath(args.out)
    temporary = os.path.join(os.path.dirname(out), "." + os.path.basename(out) + ".%d.tmp" % os.getpid())
    scene.render.filepath = temporary
    bpy.ops.render.render(write_still=True)
    if not os.path.isfile(temporary):
        fail(out + ": Cycles wrote no image")
    os.replace(temporary, out)
    print("wrote %s: %dx%d, frame %d, %d spp, seed %d" % (out, scene.render.resolution_x, scene.render.resolution_y,
                                                         SCENE["frame"], args.spp, args.seed))


main()
