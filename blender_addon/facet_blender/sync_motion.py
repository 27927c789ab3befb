"""Motion blur as Cycles 3.4 syncs it (blender/sync.cpp, object.cpp): the scene's Motion Blur
settings -> the render's "motion_blur" (shutter, position, shutter curve), and the camera's and
objects' matrices at the motion steps -> their "motion" (scenes/FORMAT.md, "Motion blur").

An object with motion blur (Object Properties > Motion Blur, on by default) is evaluated at
N = 2^steps + 1 uniform times over the open shutter (its Steps; Cycles' object_motion_steps),
frame + offset + shutter i / (N - 1) with offset 0, -shutter/2, -shutter for the positions
Start, Center, End; it moves when its matrices differ. The camera likewise.

Deformation (Object Properties > Motion Blur > Deformation, Cycles' use_deform_motion): an
object with Motion Blur and Deformation on that may deform (modifiers, shape keys, an armature
parent) has its evaluated mesh read again at the same steps, with the same layout as its
export (sync_mesh.mesh_arrays: the same UV layer and colour attribute); when its positions
differ between steps, its mesh shapes get "motion_positions" (and "motion_normals" with
normals). When the topology changes between steps (another vertex count or other triangles),
it renders without deformation blur, as Cycles does, and the report names the object.

Hair (sync_hair.py), as Cycles 3.4 samples its curve keys at the motion steps: a CURVES
object's shape moves by the object's matrices ("motion") and, when it may deform and Deformation
is on, gets its points at the steps ("motion_positions", object space). Particle hair is
exported in world space. On an emitter that moves, it is moved by the emitter's matrices as
Cycles 3.4 moves it (particle hair is geometry in the emitter's object space, moved by the
object's transform motion, interpolated decomposed, a rotation by slerp): its points are
carried into the emitter's object space (M_frame^-1 p), its "transform" is the emitter's
matrix at the frame and its "motion" the emitter's matrices at the steps, so that a spinning
emitter's strands sweep the arc and do not cut the chord; with Deformation on its keys are
read again at the steps and carried into the emitter's space at each step (M_i^-1 p_i), and
become "motion_positions" where they move in it (the hair's own motion). On a still emitter,
Deformation on gives the keys at the steps in world space. Strands that change in number or
key count between steps render without motion blur (reported, by object and hair).

Emitting meshes move and deform like any other (the core samples them at the path's time, as
Cycles 3.4's triangle lights are). Lamps (point, spot, area, sun) are not evaluated at the
steps: Cycles 3.4 syncs lights at the frame only (blender/object.cpp returns before a light's
motion step), so a lamp renders still at the frame in both renderers, and nothing is reported."""

import math

import numpy as np

from . import sync_hair

CURVE_CELLS = 256  # the shutter curve's cells (Cycles tabulates it as finely: RAMP_TABLE_SIZE)


def motion_on(scene, view_layer):
    return bool(scene.render.use_motion_blur and view_layer.use_motion_blur)


def _position(scene):
    cyc = getattr(scene, "cycles", None)
    pos = getattr(cyc, "motion_blur_position", "CENTER") if cyc is not None else "CENTER"
    return {"START": "start", "CENTER": "center", "END": "end"}.get(pos, "center")


def _curve(scene):
    """The shutter curve's weights on CURVE_CELLS cells of the open interval (at the cells'
    centres), or [] when it is flat."""
    cm = scene.render.motion_blur_shutter_curve
    try:
        cm.initialize()
    except (AttributeError, RuntimeError):
        pass
    curve = cm.curves[0]
    w = [max(0.0, float(cm.evaluate(curve, (i + 0.5) / CURVE_CELLS))) for i in range(CURVE_CELLS)]
    if all(abs(v - w[0]) < 1e-6 for v in w) and w[0] > 0.0:
        return []
    return w


def settings(scene, view_layer):
    """The render's "motion_blur" value, or None when Motion Blur is off."""
    if not motion_on(scene, view_layer):
        return None
    out = {"shutter": float(scene.render.motion_blur_shutter), "position": _position(scene)}
    curve = _curve(scene)
    if curve:
        if not any(v > 0.0 for v in curve):
            return out  # a zero curve: Cycles falls back to a box too
        out["curve"] = curve
    return out


def step_count(obj):
    cyc = getattr(obj, "cycles", None)
    steps = max(1, int(getattr(cyc, "motion_steps", 1))) if cyc is not None else 1
    return (2 << (steps - 1)) + 1


def object_blurs(obj):
    cyc = getattr(obj, "cycles", None)
    return cyc is None or bool(getattr(cyc, "use_motion_blur", True))


def step_frames(scene, n):
    """(frame, subframe) of n uniform steps over the open shutter."""
    shutter = float(scene.render.motion_blur_shutter)
    offset = {"start": 0.0, "center": -0.5 * shutter, "end": -shutter}[_position(scene)]
    out = []
    for i in range(n):
        t = scene.frame_current + scene.frame_subframe + offset + shutter * i / (n - 1)
        f = math.floor(t)
        out.append((int(f), t - f))
    return out


def _camera_step(m):
    pos = [m[i][3] for i in range(3)]
    fwd = [-m[i][2] for i in range(3)]
    n = math.sqrt(sum(v * v for v in fwd))
    return {"position": pos, "look_at": [p + f / n for p, f in zip(pos, fwd)],
            "up": [m[i][1] for i in range(3)]}


def deform_blurs(obj):
    """Motion Blur and its Deformation on (Cycles' use_motion_blur, use_deform_motion)."""
    cyc = getattr(obj, "cycles", None)
    return object_blurs(obj) and (cyc is None or bool(getattr(cyc, "use_deform_motion", True)))


def may_deform(obj):
    """Whether the evaluated mesh of `obj` can change with time: modifiers, shape keys, an
    armature (or lattice, curve) parent deforming it."""
    if len(getattr(obj, "modifiers", ())):
        return True
    if getattr(getattr(obj, "data", None), "shape_keys", None) is not None:
        return True
    return obj.parent is not None and obj.parent_type in ('ARMATURE', 'LATTICE', 'CURVE')


def _read_step(obj_eval, source):
    """(positions, normals or None, indices) of the evaluated object, read as its export
    was (`source`: uv layer, colours, its arrays), or None when it has no triangles."""
    from .sync_mesh import mesh_arrays
    uv_layer, colors, _ = source
    a = mesh_arrays(obj_eval, uv_layer, False, colors)
    if a is None:
        return None
    return (np.array(a.positions, np.float32).reshape(-1, 3),
            None if a.normals is None else np.array(a.normals, np.float32).reshape(-1, 3),
            np.array(a.indices).reshape(-1, 3))


def _deformation(name, steps, source, problems):
    """The per-step (positions, normals) of object `name`, or None when it does not deform
    or its topology changes (reported)."""
    arrays = source[2]
    n0 = len(arrays.positions)
    for st in steps:
        if st is None or len(st[0]) != n0 or not np.array_equal(
                st[2], np.asarray(arrays.indices).reshape(-1, 3)) or (
                (st[1] is None) != (arrays.normals is None)):
            problems.append("object '%s': its mesh changes topology over the shutter (vertex "
                            "or triangle count differs between motion steps): rendered "
                            "without deformation motion blur, as Cycles does" % name)
            return None
    if all(np.array_equal(st[0], steps[0][0]) for st in steps[1:]):
        return None
    return [st[0] for st in steps], (None if steps[0][1] is None else [st[1] for st in steps])


def add_motion(depsgraph, data, frame_set, shape_objects, problems, mesh_sources=None,
               hair_sources=None):
    """Adds "motion" to the camera and to the shapes of objects that move. `frame_set(frame,
    subframe)` evaluates the depsgraph at another time (RenderEngine.frame_set); it is called
    once per distinct step time and finally at the current frame again. `shape_objects`: per
    entry of data["shapes"], the name of the object it places (None: not an object's own
    placement, e.g. instances of a collection). `mesh_sources`: per object, how its mesh was
    read (export.py), for its deformation motion. `hair_sources`: per hair shape (by id) what
    reads its points again (export.py): ("particle", object, modifier, render) or ("curves",
    object)."""
    scene = depsgraph.scene
    mesh_sources = mesh_sources or {}
    shape_objects = list(shape_objects)
    hair = {}  # shape index -> (source, whether its points are read at every step)
    for k, shape in enumerate(data["shapes"]):
        src = (hair_sources or {}).get(id(shape))
        obj = scene.objects.get(src[1]) if src is not None else None
        if obj is None or not object_blurs(obj):
            continue
        if src[0] == "curves":
            shape_objects[k] = src[1]  # placed by the object's matrix: it moves by them
            if not (deform_blurs(obj) and may_deform(obj)):
                continue
        hair[k] = (src, src[0] == "curves" or deform_blurs(obj))
    _report_instances(scene, data, shape_objects, problems)
    wanted = {}  # object name -> number of steps
    deforming = set()  # objects whose meshes are read at every step
    for name in set(n for n in shape_objects if n is not None):
        obj = scene.objects.get(name)
        if obj is not None and object_blurs(obj):
            wanted[name] = step_count(obj)
            if (deform_blurs(obj) and may_deform(obj) and name in mesh_sources
                    and mesh_sources[name][2] is not None):
                deforming.add(name)
    for src, _ in hair.values():
        wanted[src[1]] = step_count(scene.objects[src[1]])
    cam = scene.camera
    if cam is not None and object_blurs(cam):
        wanted[cam.name] = step_count(cam)
    if not wanted:
        return
    frame0 = (scene.frame_current, scene.frame_subframe)
    times = {}
    for name, n in wanted.items():
        for i, ft in enumerate(step_frames(scene, n)):
            times.setdefault(ft, []).append((name, i))
    mats = {name: [None] * n for name, n in wanted.items()}
    meshes = {name: [None] * wanted[name] for name in deforming}
    hair_steps = {k: [None] * wanted[src[1]] for k, (src, read) in hair.items() if read}
    try:
        for ft, users in sorted(times.items()):
            frame_set(ft[0], ft[1])
            for name, i in users:
                obj = scene.objects[name].evaluated_get(depsgraph)
                mats[name][i] = [list(r) for r in obj.matrix_world]
                if name in deforming:
                    meshes[name][i] = _read_step(obj, mesh_sources[name])
                for k in hair_steps:
                    if hair[k][0][1] == name:
                        hair_steps[k][i] = _read_hair_step(obj, hair[k][0])
    finally:
        frame_set(frame0[0], frame0[1])
    for k, (src, read) in sorted(hair.items()):
        shape, steps = data["shapes"][k], hair_steps.get(k)
        if src[0] == "particle":
            _carry_hair(shape, mats[src[1]])
            if read:
                # World-space keys at the steps -> the emitter's object space at each step.
                steps = [None if st is None else (st[0], sync_hair.to_object(st[1], m))
                         for st, m in zip(steps, mats[src[1]])]
        if read:
            _add_hair_deformation(shape, src[1], steps, problems)
    for name in sorted(deforming):
        d = _deformation(name, meshes[name], mesh_sources[name], problems)
        if d is None:
            continue
        for k, owner in enumerate(shape_objects):
            shape = data["shapes"][k]
            if owner != name or shape.get("type") != "mesh":
                continue
            shape["motion_positions"] = d[0]
            if d[1] is not None and shape.get("normals") is not None:
                shape["motion_normals"] = d[1]
    for name, steps in mats.items():
        if all(m == steps[0] for m in steps):
            continue  # still over the shutter
        if cam is not None and name == cam.name:
            data["camera"]["motion"] = [_camera_step(m) for m in steps]
            continue
        obj = scene.objects[name]
        for k, owner in enumerate(shape_objects):
            if owner != name:
                continue
            data["shapes"][k]["motion"] = steps


def _read_hair_step(obj, src):
    """A hair shape's (strand counts, flat points) read from the evaluated `obj` at a step."""
    if src[0] == "curves":
        return sync_hair.curves_step_points(obj)
    return sync_hair.particle_step_points(obj, src[2], src[3])


def _carry_hair(shape, step_mats):
    """A particle hair shape (in its emitter's object space, placed by the frame's matrix)
    moved by the emitter's matrices at the steps (`step_mats`), as Cycles moves particle hair
    (by the object's motion): "motion"; True. A still emitter leaves the shape as it is
    (False)."""
    if all(m == step_mats[0] for m in step_mats[1:]):
        return False
    shape["motion"] = [[[float(v) for v in row] for row in m] for m in step_mats]
    return True


def _add_hair_deformation(shape, name, steps, problems):
    """A hair shape's "motion_positions" from its points at the steps ((strand counts, flat
    points) each), when they differ; strands that change between steps are reported."""
    counts = [c - 2 for c in shape["counts"]]
    if any(st is None or st[0] != counts for st in steps):
        problems.append("object '%s': hair '%s': its strands change over the shutter (strand "
                        "or key count differs between motion steps): rendered without "
                        "deformation motion blur, as Cycles does" % (name, shape["name"]))
        return
    # Keys that do not move (to rounding: a rigid emitter's keys carried into its space at
    # each step) need no deformation.
    first = np.asarray(steps[0][1], np.float64)
    tol = 1e-6 * max(float(np.abs(first).max(initial=0.0)), 1e-6)
    if all(np.abs(np.asarray(st[1], np.float64) - first).max(initial=0.0) <= tol
           for st in steps[1:]):
        return
    shape["motion_positions"] = [st[1] for st in steps]


def _animated(obj):
    """Whether `obj` or a parent of it is animated (an action or drivers), or its mesh may
    deform: what could move it over the shutter."""
    o = obj
    while o is not None:
        ad = getattr(o, "animation_data", None)
        if ad is not None and (ad.action is not None or len(ad.drivers)):
            return True
        o = o.parent
    return may_deform(obj)


def _report_instances(scene, data, shape_objects, problems):
    """Instances (a collection instance's, particles', geometry nodes') carry no motion: each
    instanced object with Motion Blur on that is animated or may deform is named once."""
    named = set()
    for k, owner in enumerate(shape_objects):
        name = data["shapes"][k].get("name", "")
        if owner is not None or not name.endswith(" (instance)"):
            continue
        obj = scene.objects.get(name[:-len(" (instance)")])
        if obj is None or obj.name in named or not object_blurs(obj) or not _animated(obj):
            continue
        named.add(obj.name)
        problems.append("object '%s': its instances are rendered without motion blur (the "
                        "motion of instances is not converted)" % obj.name)
