"""Helpers for the Blender tests (tests/blender) and the Cycles comparisons built on them
(cycles_scene.py): scripts run inside `blender -b --factory-startup --python`.
A failed check raises, and --python-exit-code makes Blender exit 1. The tests check images and
reports, never Blender's exit code alone (an exception inside a render engine exits 0)."""
import os
import sys
import traceback

import addon_utils
import bpy
import numpy as np

ADDON = "facet_blender"


def args():
    """The arguments after Blender's `--`."""
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def enable_addon():
    """Enables the addon installed (from the zip) in BLENDER_USER_SCRIPTS by test_install."""
    mod = addon_utils.enable(ADDON, default_set=True, handle_error=_raise)
    if mod is None or not hasattr(bpy.types, "FacetRenderEngine") and "FACET" not in [
            e.bl_idname for e in bpy.types.RenderEngine.__subclasses__()]:
        raise RuntimeError("the Facet addon did not register")
    return mod


def _raise(e):
    traceback.print_exception(e)
    raise e


def factory_scene(width, height, spp=4, reload=True):
    """Blender's factory scene (cube, light, camera) rendered by Facet at width x height."""
    if reload:
        bpy.ops.wm.read_homefile(use_factory_startup=True)
    scene = bpy.context.scene
    scene.render.engine = 'FACET'
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.facet.spp = spp
    return scene


def new_material(name):
    """A material with nodes and an empty tree but its Material Output: (mat, tree, output)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    return mat, nt, out


def ortho_camera(scene, scale, location):
    """A new orthographic camera looking down -Z from `location`, the scene's camera."""
    cam = bpy.data.cameras.new("cam")
    cam.type = 'ORTHO'
    cam.ortho_scale = scale
    cob = bpy.data.objects.new("cam", cam)
    cob.location = location
    scene.collection.objects.link(cob)
    scene.camera = cob
    return cob


def single_shader(mat, idname, inputs=None, props=None):
    """Replaces the material's node tree by one shader node wired to the output."""
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    node = nt.nodes.new(idname)
    for k, v in (props or {}).items():
        setattr(node, k, v)
    for k, v in (inputs or {}).items():
        node.inputs[k].default_value = v
    nt.links.new(node.outputs[0], out.inputs["Surface"])
    return node


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)
    print("ok:", msg)


def render(scene=None, path=None):
    """F12 on the scene; returns (image float32 (h, w, 3) top row first, problems). Raises
    RuntimeError when the engine reported an error (Blender turns report ERROR into that)."""
    from facet_blender import hooks
    scene = scene or bpy.context.scene
    hooks.last_image = None
    if path:
        scene.render.filepath = path
        scene.render.image_settings.file_format = 'OPEN_EXR'
        scene.render.image_settings.color_depth = '32'
        scene.render.image_settings.color_mode = 'RGB'
        scene.render.image_settings.exr_codec = 'ZIP'
    bpy.ops.render.render(write_still=bool(path))
    return hooks.last_image, list(hooks.last_problems)


def load_exr(path):
    """An EXR through Blender's own loader -> float32 (h, w, 3), top row first."""
    im = bpy.data.images.load(path, check_existing=False)
    try:
        w, h = im.size
        px = np.empty(w * h * im.channels, np.float32)
        im.pixels.foreach_get(px)
        return px.reshape(h, w, im.channels)[::-1, :, :3].copy()
    finally:
        bpy.data.images.remove(im)


def run(main):
    try:
        main()
    except Exception:
        traceback.print_exc()
        sys.stdout.flush()
        os._exit(1)  # also from inside handlers; --python-exit-code covers the rest
    print("PASS")
    sys.stdout.flush()
