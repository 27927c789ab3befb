"""Blender camera -> Facet camera (issue 22), without rendering: lens shift under every sensor
fit (Blender's fractions of the fitted side -> Facet's of the larger side), orthographic scale,
depth of field as Cycles computes it (blender/camera.cpp: radius lens 1e-3 / (2 fstop), or
1 / (2 fstop) orthographic; focus object distance along the view direction; blades < 3 round),
the reports, and Facet -> Blender (importer) -> Facet giving the same camera."""
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402


def exported(scene):
    from facet_blender import sync_camera
    problems = []
    cam = sync_camera.export_camera(bpy.context.evaluated_depsgraph_get(), scene, problems)
    return cam, problems


def close(a, b, tol=1e-5):
    return abs(a - b) <= tol * max(1.0, abs(b))


def main():
    bt.enable_addon()
    from facet_blender import importer
    scene = bt.factory_scene(200, 100)
    c = scene.camera.data
    c.lens = 50.0
    # Shift: sensor fit AUTO (landscape: the fitted side is the larger), HORIZONTAL (the
    # width, the larger here), VERTICAL (the height = half the larger side).
    c.shift_x, c.shift_y = 0.1, -0.05
    for fit, factor in (('AUTO', 1.0), ('HORIZONTAL', 1.0), ('VERTICAL', 0.5)):
        c.sensor_fit = fit
        cam, problems = exported(scene)
        bt.check(close(cam["shift_x"], 0.1 * factor) and close(cam["shift_y"], -0.05 * factor),
                 "shift under sensor fit %s: %r, %r" % (fit, cam.get("shift_x"), cam.get("shift_y")))
        bt.check(not problems, "no report for a lens shift (%s)" % problems)
    c.sensor_fit = 'AUTO'
    # Orthographic: scale = Ortho Scale (sensor fit AUTO: the larger side), shift in its units.
    c.type, c.ortho_scale = 'ORTHO', 5.0
    cam, _ = exported(scene)
    bt.check(cam["type"] == "orthographic" and close(cam["scale"], 5.0) and "fov" not in cam
             and close(cam["shift_x"], 0.1), "orthographic: %r" % cam)
    # Depth of field, perspective: Cycles' radius from lens and f-stop; blades and rotation.
    c.type = 'PERSP'
    c.dof.use_dof = True
    c.dof.aperture_fstop, c.dof.focus_distance = 2.8, 6.5
    c.dof.aperture_blades, c.dof.aperture_rotation = 6, math.radians(15.0)
    cam, problems = exported(scene)
    bt.check(close(cam["fstop"], 2.8) and close(cam["focal_length"], 50.0)
             and close(cam["focus_distance"], 6.5) and cam["blades"] == 6
             and close(cam["rotation"], 15.0), "depth of field: %r" % cam)
    c.dof.aperture_blades = 2  # Cycles renders fewer than 3 blades round
    c.dof.aperture_ratio = 1.5
    cam, problems = exported(scene)
    bt.check("blades" not in cam, "2 blades export as round: %r" % cam)
    bt.check(any("anamorphic" in p for p in problems), "anamorphic reported: %s" % problems)
    c.dof.aperture_ratio = 1.0
    # Focus object: its distance along the camera's view direction.
    target = bpy.data.objects["Cube"]
    c.dof.focus_object = target
    m, t = scene.camera.matrix_world, target.matrix_world.translation
    z = m.col[2].to_3d().normalized()
    want = abs(z.dot(m.translation - t))
    cam, _ = exported(scene)
    bt.check(close(cam["focus_distance"], want), "focus object: %r vs %r"
             % (cam["focus_distance"], want))
    c.dof.focus_object = None
    # Orthographic depth of field: Cycles' radius 1 / (2 fstop).
    c.type = 'ORTHO'
    cam, _ = exported(scene)
    bt.check(close(cam["aperture_radius"], 1.0 / 5.6) and "fstop" not in cam,
             "orthographic depth of field: %r" % cam)
    # Facet -> Blender -> Facet: the importer's settings export the same camera.
    for want in ({"fov": 35.0, "shift_x": 0.12, "shift_y": -0.07, "aperture_radius": 0.02,
                  "focus_distance": 4.0, "blades": 5, "rotation": 10.0},
                 {"type": "orthographic", "scale": 3.0, "shift_y": 0.2},
                 {"fov": 50.0, "fstop": 4.0, "focal_length": 35.0, "focus_distance": 2.0}):
        for w, h in ((200, 100), (100, 200)):
            cd = bpy.data.cameras.new("imported")
            importer._camera_settings(cd, dict(want, width=w, height=h))
            scene.camera.data = cd
            scene.render.resolution_x, scene.render.resolution_y = w, h
            cam, _ = exported(scene)
            radius = lambda d: d.get("aperture_radius") or (
                d["focal_length"] * 1e-3 / (2 * d["fstop"]) if "fstop" in d else 0.0)
            for key in ("fov", "scale", "shift_x", "shift_y", "focus_distance", "rotation"):
                bt.check(close(cam.get(key, 0.0), want.get(key, 0.0)),
                         "%dx%d %s: %r vs %r" % (w, h, key, cam.get(key), want.get(key)))
            bt.check(close(radius(cam), radius(want)) and cam.get("blades", 0) == want.get("blades", 0),
                     "%dx%d aperture: %r vs %r" % (w, h, cam, want))
    # Panoramic cameras are an error that names the camera.
    scene.camera.data.type = 'PANO'
    try:
        exported(scene)
        bt.check(False, "a panoramic camera is an error")
    except Exception as e:
        bt.check("only perspective and orthographic" in str(e), "panoramic: %s" % e)


bt.run(main)
