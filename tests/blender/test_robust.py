"""Scenes that must render or report clearly, never crash Blender: NaN vertices, zero-area
faces, no lights, no camera, an unsupported node, an empty mesh; and cancellation (Esc) in the
middle of a render: the session stops after the pass in flight, the image keeps what was
rendered."""
import math
import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402


def fresh():
    return bt.factory_scene(160, 90)


def mesh_object(name, verts, faces):
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], faces)
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def render_error():
    """Renders; returns the error message Blender raised (None when it rendered)."""
    try:
        bt.render()
    except RuntimeError as e:
        return str(e)
    return None


def case_nan_vertex():
    fresh()
    mesh_object("NaNMesh", [(0, 0, 2), (1, 0, 2), (float("nan"), 1, 2)], [(0, 1, 2)])
    err = render_error()
    bt.check(err is not None and "NaNMesh" in err, "NaN vertex: error names the object: %s" % err)


def case_zero_area():
    fresh()
    mesh_object("Degenerate", [(0, 0, 1.5), (1, 0, 1.5), (2, 0, 1.5), (0, 1, 1.5)],
                [(0, 1, 2), (0, 1, 3)])
    err = render_error()
    from facet_blender import hooks
    bt.check(err is None and hooks.last_image is not None and np.isfinite(hooks.last_image).all(),
             "zero-area face: renders (problems: %s)" % hooks.last_problems)


def case_no_lights():
    scene = fresh()
    bpy.data.objects.remove(bpy.data.objects["Light"])
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    err = render_error()
    bt.check(err is not None and "light" in err.lower(), "no lights: reported: %s" % err)


def case_no_camera():
    fresh()
    bpy.data.objects.remove(bpy.data.objects["Camera"])
    err = render_error()
    bt.check(err is not None and "camera" in err.lower(), "no camera: reported: %s" % err)


def case_unsupported_node():
    fresh()
    mat = bpy.data.materials["Material"]
    nt = mat.node_tree
    toon = nt.nodes.new("ShaderNodeBsdfToon")  # no Facet equivalent: not converted
    nt.links.new(toon.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    err = render_error()
    from facet_blender import hooks
    msgs = [p for p in hooks.last_problems if "Material" in p and "Toon BSDF" in p]
    bt.check(err is None and hooks.last_image is not None and msgs,
             "unsupported node: renders and names material and node: %s" % msgs)


def case_empty_mesh():
    fresh()
    mesh_object("Empty", [], [])
    err = render_error()
    from facet_blender import hooks
    msgs = [p for p in hooks.last_problems if "Empty" in p]
    bt.check(err is None and hooks.last_image is not None and msgs,
             "empty mesh: renders and says so: %s" % msgs)


def case_cancel():
    scene = fresh()
    scene.render.resolution_x, scene.render.resolution_y = 640, 360
    scene.facet.spp = 1 << 16  # minutes of work
    from facet_blender import hooks
    calls = []

    def hook():
        calls.append(time.perf_counter())
        return len(calls) >= 2  # Esc after the second pass
    hooks.test_break = hook
    t0 = time.perf_counter()
    try:
        err = render_error()
    finally:
        hooks.test_break = None
    dt = time.perf_counter() - t0
    img = hooks.last_image
    bt.check(err is None and hooks.last_cancelled, "cancelled without an error")
    bt.check(dt < 20.0, "stopped within a pass or so: %.2f s after the start" % dt)
    bt.check(img is not None and np.isfinite(img).all() and img.max() > 0.0,
             "the image keeps the passes rendered")


def main():
    bt.enable_addon()
    for case in (case_nan_vertex, case_zero_area, case_no_lights, case_no_camera,
                 case_unsupported_node, case_empty_mesh, case_cancel):
        print("--", case.__name__)
        case()


bt.run(main)
