"""The scene camera -> the Facet camera: projection, resolution and border, shift, depth of
field (export.py calls it; Cycles' blender_camera.cpp does this job)."""
import math

from . import units
from .sync_state import ExportError, object_state, render_state, _stored


def resolution(scene):
    r = scene.render
    return (int(r.resolution_x * r.resolution_percentage / 100),
            int(r.resolution_y * r.resolution_percentage / 100))


def export_camera(depsgraph, scene, problems):
    cam = scene.camera
    if cam is None:
        raise ExportError("the scene has no camera (Scene properties > Camera)")
    cam_eval = cam.evaluated_get(depsgraph)
    width, height = resolution(scene)
    stored = _stored(cam, "facet_camera", object_state(cam_eval) + "|" + render_state(scene))
    if stored is not None:
        return stored
    c = cam_eval.data
    if c.type not in ('PERSP', 'ORTHO'):
        raise ExportError("camera '%s': only perspective and orthographic cameras are "
                          "supported (type is %s)" % (cam.name, c.type))
    r = scene.render
    if r.pixel_aspect_x != r.pixel_aspect_y:
        problems.append("render: non-square pixel aspect is not supported; square pixels used")
    proj = cam_eval.calc_matrix_camera(depsgraph, x=width, y=height, scale_x=1.0, scale_y=1.0)
    m = cam_eval.matrix_world
    pos = [m[i][3] for i in range(3)]
    fwd = [-m[i][2] for i in range(3)]
    up = [m[i][1] for i in range(3)]
    n = math.sqrt(sum(v * v for v in fwd))
    out = {"position": pos, "look_at": [p + f / n for p, f in zip(pos, fwd)], "up": up,
           "width": width, "height": height}
    # The projection matrix has the framing whatever the sensor fit: the window's half-extents
    # and centre (lens shift), FORMAT.md's h and c; Facet's shift is in fractions of the larger
    # side, Blender's of the fitted side, so it is converted through c.
    ortho = c.type == 'ORTHO'
    window = units.camera_window(proj, ortho)
    larger = 2.0 * max(window[0], window[1])
    if ortho:
        out["type"] = "orthographic"
        out["scale"] = larger
    else:
        out["fov"] = units.fov_from_projection(proj[1][1])
    if window[2] != 0.0:
        out["shift_x"] = window[2] / larger
    if window[3] != 0.0:
        out["shift_y"] = window[3] / larger
    out.update(export_dof(cam_eval, c, ortho, problems))
    return out


def export_dof(cam_eval, c, ortho, problems):
    """Blender's depth of field as Cycles renders it (blender/camera.cpp): the aperture radius
    lens 1e-3 / (2 fstop) (perspective; 1 / (2 fstop) orthographic), blades (fewer than 3:
    round) and rotation, the focus distance or the focus object's distance along the view
    direction."""
    dof = c.dof
    if not dof.use_dof:
        return {}
    name = cam_eval.name
    fstop = max(float(dof.aperture_fstop), 1e-5)
    out = {}
    if ortho:
        out["aperture_radius"] = 1.0 / (2.0 * fstop)
    else:
        out["fstop"] = fstop
        out["focal_length"] = float(c.lens)
    target = dof.focus_object
    if target is not None:
        if getattr(dof, "focus_subtarget", ""):
            problems.append("camera '%s': focus on a bone is not supported; the object's "
                            "origin is used" % name)
        cm, tm = cam_eval.matrix_world, target.matrix_world
        z = [cm[i][2] for i in range(3)]
        zn = math.sqrt(sum(v * v for v in z))
        out["focus_distance"] = abs(sum((cm[i][3] - tm[i][3]) * z[i] for i in range(3))) / zn
    else:
        out["focus_distance"] = float(dof.focus_distance)
    if dof.aperture_blades >= 3:
        out["blades"] = int(dof.aperture_blades)
        if dof.aperture_rotation != 0.0:
            out["rotation"] = math.degrees(dof.aperture_rotation)
    if dof.aperture_ratio != 1.0:
        problems.append("camera '%s': anamorphic aperture (ratio %g) is not supported; ratio 1 "
                        "used" % (name, dof.aperture_ratio))
    return out
