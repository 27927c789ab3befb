"""Particle hair and CURVES objects -> the core's `curves` shapes (FORMAT.md "Curves"), as
Cycles 3.4's blender/curves.cpp exports them to Embree.

Particle hair (a mesh's PARTICLE_SYSTEM modifiers of type HAIR rendered as paths): every strand
Blender evaluates (the children alone when the system has children, the parents otherwise, as
Cycles), 2^render_step + 1 keys each (2^display_step + 1 and Display Amount's share of the
children in the viewport's depsgraph, as Cycles) from ParticleSystem.co_hair (world space).
The radius at a key is Cycles' shaperadius(): with t the key's length along the strand over
the strand's length, r = (1 - t)^p (root - tip) + tip, p = 1 + shape (shape < 0) or
1 / (1 - shape) (shape > 0), root = radius_scale / 2 * root_radius * s, tip = radius_scale / 2 *
tip_radius * s, with s the emitter's scale: the cube root of |det| of its matrix (Cycles keeps
the keys in object space and its Hair::apply_transform scales the radius so); Close Tip makes the
last key's radius 0. The material is the system's slot (ParticleSettings.material).

CURVES objects (Blender 3.4's hair curves): the control points (the `position` attribute) and
the `radius` attribute (0.005 where there is none, Cycles' default), in object space, placed by
the object's matrix; the first material slot.

Both as Cycles 3.4 renders them: Catmull-Rom curves through the keys, each strand's first and
last key repeated (so that it reaches them), round tubes ("3D Curves") or ribbons facing the ray
("Rounded Ribbons": profile flat) by scene.cycles_curves.shape; root UVs (each strand's UV on the
emitter, or the Curves' surface_uv_coordinate attribute) when the material reads UVs.

Reported, by object and system: a radius of 0 (Close Tip, or a zero tip radius) becomes 1e-4 of
the strand's root radius (the core's radius is > 0); a CURVES curve type other than Catmull-Rom
is rendered through its control points as Catmull-Rom, as Cycles 3.4 does (Blender's viewport
evaluates it as its type); an emitting hair material (curves cannot emit); textured hair
without UVs (Cycles reads (0, 0)); particle hair on an object placed by instances (only the
object itself carries its hair); strands of fewer than 2 keys are left out (counted).
Each strand's random value (Hair Info Random) is Cycles' hash of its index in Cycles' hair
geometry: the strands of all the object's hair systems in one sequence, and every Curves curve
(also those left out); where that is not its index in the shape the shape gives strand_random.
Under motion blur the hair's motion steps are sync_motion.py's (particle_step_points,
curves_step_points read the points again at each step)."""
import numpy as np

from . import native

# A zero radius (Close Tip) as a fraction of the strand's root radius.
ZERO_RADIUS = 1e-4
# Cycles' radius of a Curves point without a `radius` attribute (blender/curves.cpp).
DEFAULT_CURVES_RADIUS = 0.005


def _profile(scene):
    shape = getattr(getattr(scene, "cycles_curves", None), "shape", 'THICK')
    return "flat" if shape == 'RIBBONS' else "round"


def shape_radius(shape, root, tip, t):
    """Cycles 3.4's shaperadius() (blender/curves.cpp): the radius at fraction t of the
    strand's length."""
    r = 1.0 - t
    if shape != 0.0:
        r = r ** (1.0 + shape) if shape < 0.0 else r ** (1.0 / (1.0 - shape))
    return r * (root - tip) + tip


def _expanded(counts):
    """Indices of the keys of strands of `counts` keys each with every strand's first and last
    key repeated (Cycles' Catmull-Rom curves reach their ends so)."""
    idx = []
    start = 0
    for c in counts:
        idx += [start] + list(range(start, start + c)) + [start + c - 1]
        start += c
    return np.array(idx, np.int64)


def _flat(points):
    return [float(v) for v in np.asarray(points, np.float64).ravel()]


def _strands_shape(points, radii, counts, profile, uvs=None, cycles_index=None):
    """A `curves` shape dict of Catmull-Rom strands through `points` (n x 3) with `radii`
    (n), `counts` keys each: every strand's first and last key repeated. `cycles_index`: each
    strand's index in Cycles' hair geometry, when it is not its index here (its random value:
    strand_random)."""
    idx = _expanded(counts)
    shape = {"type": "curves", "basis": "catmull_rom", "profile": profile,
             "points": _flat(np.asarray(points)[idx]),
             "radius": [float(v) for v in np.asarray(radii)[idx]],
             "counts": [int(c) + 2 for c in counts]}
    if uvs is not None:
        shape["root_uvs"] = [float(v) for v in np.asarray(uvs, np.float64).ravel()]
    if cycles_index is not None and not np.array_equal(cycles_index, np.arange(len(counts))):
        shape["strand_random"] = [float(v) for v in native.curve_random(cycles_index)]
    return shape


def _positive(radii, root, subject, problems):
    """Radii with zeros raised to ZERO_RADIUS of the root radius (reported once)."""
    radii = np.asarray(radii, np.float64)
    zero = radii <= 0.0
    if zero.any():
        radii = np.where(zero, ZERO_RADIUS * max(root, 1e-12), radii)
        problems.append("%s: %d keys of radius 0 (Close Tip, or a zero radius) are exported "
                        "with %g of the root radius (a curve's radius is > 0)"
                        % (subject, int(zero.sum()), ZERO_RADIUS))
    return radii


def _strand_range(ps, render):
    """The particle numbers of the strands Blender evaluates, and the keys per strand."""
    st = ps.settings
    totpart = len(ps.particles)
    totchild = len(ps.child_particles)
    if not render:
        totchild = int(totchild * st.display_percentage / 100.0)
    first = totpart if (st.child_type != 'NONE' and totchild) else 0
    steps = 2 ** (st.render_step if render else st.display_step) + 1
    return range(first, totpart + totchild), steps


def particle_step_points(obj, mod_name, render):
    """The points of the curves shape export_particle_hair made of modifier `mod_name` of the
    evaluated `obj`, read again (at another time: sync_motion's deformation steps), as a flat
    list; None when the system or its strands' key counts differ (another topology)."""
    mod = obj.modifiers.get(mod_name)
    if mod is None or mod.type != 'PARTICLE_SYSTEM':
        return None
    ps = mod.particle_system
    strands, steps = _strand_range(ps, render)
    points, counts = [], []
    for pa in strands:
        keys = np.array([ps.co_hair(obj, particle_no=pa, step=k) for k in range(steps)],
                        np.float64)
        if len(keys) < 2 or not np.isfinite(keys).all():
            continue
        points.append(keys)
        counts.append(len(keys))
    if not counts:
        return None
    return counts, _flat(np.concatenate(points)[_expanded(counts)])


def export_particle_hair(obj, scene, reads_uv, problems, render=True):
    """The evaluated mesh object's rendered hair particle systems -> [(shape dict without
    material, material or None, modifier name)], world space. `reads_uv(material)`: whether it
    reads UVs; `render`: the depsgraph is a final render's (else the viewport's: Display Steps
    and Display Amount, as Cycles' viewport render)."""
    out = []
    profile = _profile(scene)
    # The emitter's scale scales its hair's radius, as Cycles' Hair::apply_transform.
    scale = abs(obj.matrix_world.determinant()) ** (1.0 / 3.0)
    first = 0  # Cycles numbers the strands of all the object's hair systems in one sequence
    for mod in obj.modifiers:
        if mod.type != 'PARTICLE_SYSTEM' or not mod.show_render:
            continue
        ps = mod.particle_system
        st = ps.settings
        if st.type != 'HAIR' or st.render_type != 'PATH':
            continue
        subject = "object '%s': particle system '%s'" % (obj.original.name, ps.name)
        totpart = len(ps.particles)
        strands, steps = _strand_range(ps, render)
        kept = []  # each exported strand's index in Cycles' sequence
        half = st.radius_scale * 0.5 * scale
        root, tip = half * st.root_radius, half * st.tip_radius
        points, radii, counts, uvs = [], [], [], []
        skipped = 0
        uv_index = None
        mat = None
        if 1 <= st.material <= len(obj.material_slots):
            mat = obj.material_slots[st.material - 1].material
        textured = reads_uv(mat)
        if textured:
            layers = getattr(obj.data, "uv_layers", None) or ()
            uv_index = next((i for i, u in enumerate(layers) if u.active_render), None)
            if uv_index is None:
                problems.append("%s: the hair material reads UVs but the emitter has none; "
                                "UV (0, 0), as Cycles" % subject)
        for pa in strands:
            keys = np.array([ps.co_hair(obj, particle_no=pa, step=k) for k in range(steps)],
                            np.float64)
            if len(keys) < 2 or not np.isfinite(keys).all():
                skipped += 1
                continue
            kept.append(first + pa - strands.start)
            seg = np.linalg.norm(np.diff(keys, axis=0), axis=1)
            length = seg.sum()
            t = np.concatenate([[0.0], np.cumsum(seg)]) / length if length > 0.0 else \
                np.zeros(len(keys))
            r = np.array([shape_radius(st.shape, root, tip, float(x)) for x in t])
            if st.use_close_tip:
                r[-1] = 0.0
            points.append(keys)
            radii.append(r)
            counts.append(len(keys))
            if textured:
                uv = (0.0, 0.0)
                if uv_index is not None and totpart:
                    particle = ps.particles[pa] if pa < totpart else ps.particles[0]
                    uv = tuple(ps.uv_on_emitter(modifier=mod, particle=particle,
                                                particle_no=pa, uv_no=uv_index))
                uvs.append(uv)
        first += len(strands)
        if skipped:
            problems.append("%s: %d strands without keys are left out" % (subject, skipped))
        if not counts:
            continue
        rad = _positive(np.concatenate(radii), root, subject, problems)
        shape = _strands_shape(np.concatenate(points), rad, counts, profile,
                               uvs if textured else None, np.array(kept, np.int64))
        shape["name"] = "%s hair '%s'" % (obj.original.name, ps.name)
        out.append((shape, mat, mod.name))
    return out


_CURVE_TYPES = {0: "Catmull-Rom", 1: "Poly", 2: "Bezier", 3: "NURBS"}


def _curves_layout(cv):
    """(positions n x 3, first point per curve, points per curve) of Curves data `cv`."""
    n_points = len(cv.points)
    n_curves = len(cv.curves)
    pos = np.empty(n_points * 3, np.float32)
    cv.attributes["position"].data.foreach_get("vector", pos)
    offsets = np.empty(n_curves, np.int32)
    cv.curves.foreach_get("first_point_index", offsets)
    counts = np.empty(n_curves, np.int32)
    cv.curves.foreach_get("points_length", counts)
    return pos.reshape(-1, 3).astype(np.float64), offsets, counts


def _kept(offsets, counts):
    """The curves of 2 or more points, and the indices of their points."""
    keep = counts >= 2
    idx = np.concatenate([np.arange(o, o + c) for o, c, k in zip(offsets, counts, keep) if k]) \
        if keep.any() else np.zeros(0, np.int64)
    return keep, idx


def curves_step_points(obj):
    """The points (object space) of the curves shape export_curves_object made of the
    evaluated CURVES `obj`, read again (at another time: sync_motion's deformation steps):
    (strand counts, flat list), or None when it has no curves."""
    cv = obj.data
    if len(cv.curves) == 0 or len(cv.points) == 0:
        return None
    pos, offsets, counts = _curves_layout(cv)
    keep, idx = _kept(offsets, counts)
    if len(idx) == 0:
        return None
    kept = [int(c) for c in counts[keep]]
    return kept, _flat(pos[idx][_expanded(kept)])


def export_curves_object(obj, matrix, scene, reads_uv, problems):
    """An evaluated CURVES object placed by `matrix` -> (shape dict without material, its
    material or None), or None (no curves: reported). `reads_uv(material)` as above."""
    subject = "object '%s'" % obj.original.name
    mat = obj.material_slots[0].material if obj.material_slots else None
    cv = obj.data
    n_points = len(cv.points)
    n_curves = len(cv.curves)
    if n_curves == 0 or n_points == 0:
        problems.append("%s: hair curves with no curves; skipped" % subject)
        return None
    pos, offsets, counts_all = _curves_layout(cv)
    attr = cv.attributes.get("radius")
    if attr is not None and attr.domain == 'POINT' and attr.data_type == 'FLOAT':
        rad = np.empty(n_points, np.float32)
        attr.data.foreach_get("value", rad)
        rad = rad.astype(np.float64)
    else:
        rad = np.full(n_points, DEFAULT_CURVES_RADIUS)
    types = cv.attributes.get("curve_type")
    if types is not None:
        tv = np.empty(n_curves, np.int8)
        try:
            types.data.foreach_get("value", tv)
            other = sorted({_CURVE_TYPES.get(int(x), str(int(x))) for x in tv if int(x) != 0})
        except (TypeError, RuntimeError):
            other = []
        if other:
            problems.append("%s: curves of type %s are rendered through their control points "
                            "as Catmull-Rom curves, as Cycles 3.4 does"
                            % (subject, ", ".join(other)))
    keep, idx = _kept(offsets, counts_all)
    if not keep.all():
        problems.append("%s: %d curves of fewer than 2 points are left out"
                        % (subject, int((~keep).sum())))
    if len(idx) == 0:
        return None
    uvs = None
    if reads_uv(mat):
        ua = cv.attributes.get("surface_uv_coordinate")
        uvs = np.zeros((n_curves, 2), np.float32)
        if ua is not None and ua.domain == 'CURVE':
            flat = np.empty(n_curves * 2, np.float32)
            ua.data.foreach_get("vector", flat)
            uvs = flat.reshape(-1, 2)
        else:
            problems.append("%s: the hair material reads UVs but the curves have no "
                            "surface_uv_coordinate; UV (0, 0), as Cycles" % subject)
        uvs = uvs[keep]
    root = float(rad.max()) if len(rad) else 1.0
    radii = _positive(rad[idx], root, subject, problems)
    shape = _strands_shape(pos[idx], radii, [int(c) for c in counts_all[keep]], _profile(scene),
                           uvs, np.nonzero(keep)[0])
    shape["name"] = obj.original.name
    shape["transform"] = [[float(matrix[r][c]) for c in range(4)] for r in range(4)]
    return shape, mat

