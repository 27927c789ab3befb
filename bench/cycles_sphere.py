"""The scene that bench/principled_cycles.py and bench/multiscatter_cycles.py render with
Cycles 3.4 (run inside Blender): an icosphere of radius 1 (7 subdivisions, smooth shading) seen
by an orthographic camera along -z, a world whose Background node the caller sets, and Cycles
at reference settings (no clamping, Filter Glossy 0, caustics on, 64 bounces of every kind, no
adaptive sampling, no denoising, 2 fixed threads). The view spans [-SCALE/2, SCALE/2]^2 in
SIZE x SIZE pixels, so a pixel centre's distance from the sphere's centre is exact and the same
in Facet's renders of this scene (tests/render/test_principled_render.cpp and
test_multiscatter_render.cpp).
"""

import math

import bpy

SIZE = 48  # pixels per side
SCALE = 2.4  # orthographic scale: the view spans [-1.2, 1.2]^2
MASK_RADIUS = 0.9
SPHERE = "icosphere, 7 subdivisions, radius 1, smooth"

# Facet's parameter keys -> Blender's node input names.
BLENDER_NAMES = {
    "base_color": "Base Color", "roughness": "Roughness", "metallic": "Metallic",
    "specular": "Specular", "specular_tint": "Specular Tint", "sheen": "Sheen",
    "sheen_tint": "Sheen Tint", "clearcoat": "Clearcoat",
    "clearcoat_roughness": "Clearcoat Roughness", "anisotropic": "Anisotropic",
    "transmission": "Transmission", "transmission_roughness": "Transmission Roughness",
    "ior": "IOR", "color": "Color",
}


def setup_scene(spp):
    """An empty scene with the sphere, the camera and the world; returns (scene, sphere, world)."""
    scene = bpy.context.scene
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=7, radius=1.0, location=(0, 0, 0))
    sphere = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    cam_data = bpy.data.cameras.new("cam")
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = SCALE
    cam = bpy.data.objects.new("cam", cam_data)
    cam.location = (0, 0, 5)
    cam.rotation_euler = (0, 0, 0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    world = bpy.data.worlds.new("white")
    world.use_nodes = True
    scene.world = world
    scene.render.engine = "CYCLES"
    scene.render.resolution_x = scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    c = scene.cycles
    c.device = "CPU"
    c.samples = spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    for key in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                "volume_bounces", "transparent_max_bounces"):
        setattr(c, key, 64)
    scene.render.threads_mode = "FIXED"
    scene.render.threads = 2
    return scene, sphere, world


def set_background(world, value):
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (value, value, value, 1)
    bg.inputs["Strength"].default_value = 1.0


def set_inputs(node, params):
    """Node inputs from Facet keys (colours as RGB lists)."""
    for key, value in params.items():
        if isinstance(value, list):
            value = (*value, 1.0)
        node.inputs[BLENDER_NAMES[key]].default_value = value


def pixels(path):
    """An EXR's pixels as (distance of the pixel centre from the sphere's centre, RGB)."""
    img = bpy.data.images.load(path)
    px = list(img.pixels)
    bpy.data.images.remove(img)
    for j in range(SIZE):
        for i in range(SIZE):
            x = ((i + 0.5) / SIZE - 0.5) * SCALE
            y = ((j + 0.5) / SIZE - 0.5) * SCALE
            k = 4 * (j * SIZE + i)
            yield math.hypot(x, y), px[k:k + 3]
