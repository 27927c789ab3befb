"""Motion blur as Cycles 3.4 syncs it (blender/sync.cpp, object.cpp): the scene's Motion Blur
settings -> the render's "motion_blur" (shutter, position, shutter curve), and the camera's and
objects' matrices at the motion steps -> their "motion" (scenes/FORMAT.md, "Motion blur").

An object with motion blur (Object Properties > Motion Blur, on by default) is evaluated at
N = 2^steps + 1 uniform times over the open shutter (its Steps; Cycles' object_motion_steps),
frame + offset + shutter i / (N - 1) with offset 0, -shutter/2, -shutter for the positions
Start, Center, End; it moves when its matrices differ. The camera likewise. Deformation (vertex
positions per step) is not converted: a deforming object moves rigidly, reported."""

import math

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


def add_motion(depsgraph, data, frame_set, shape_objects, problems):
    """Adds "motion" to the camera and to the shapes of objects that move. `frame_set(frame,
    subframe)` evaluates the depsgraph at another time (RenderEngine.frame_set); it is called
    once per distinct step time and finally at the current frame again. `shape_objects`: per
    entry of data["shapes"], the name of the object it places (None: not an object's own
    placement, e.g. instances of a collection)."""
    scene = depsgraph.scene
    wanted = {}  # object name -> number of steps
    for name in set(n for n in shape_objects if n is not None):
        obj = scene.objects.get(name)
        if obj is not None and object_blurs(obj):
            wanted[name] = step_count(obj)
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
    try:
        for ft, users in sorted(times.items()):
            frame_set(ft[0], ft[1])
            for name, i in users:
                obj = scene.objects[name].evaluated_get(depsgraph)
                mats[name][i] = [list(r) for r in obj.matrix_world]
    finally:
        frame_set(frame0[0], frame0[1])
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
            shape = data["shapes"][k]
            if _emits(shape):
                problems.append("object '%s': emits light and moves: rendered still at the "
                                "frame (Facet's emitters do not move yet)" % name)
                continue
            shape["motion"] = steps
        cyc = getattr(obj, "cycles", None)
        if getattr(cyc, "use_deform_motion", False) and (
                len(obj.modifiers) or getattr(getattr(obj, "data", None), "shape_keys", None)):
            problems.append("object '%s': deformation motion is not converted: the object "
                            "moves rigidly over the shutter" % name)


def _emits(shape):
    e = shape.get("emission")
    if e is None:
        return False
    if isinstance(e, (int, float)):
        return e != 0
    if isinstance(e, (list, tuple)):
        return any(v != 0 for v in e)
    return True  # a texture
