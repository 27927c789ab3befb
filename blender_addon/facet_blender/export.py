"""Blender scene (evaluated depsgraph) -> Facet scene data (native.py's vocabulary).

Meshes go through foreach_get into numpy (never Blender's structs by pointer): the evaluated
mesh (modifiers applied) of every visible object instance, triangulated by Blender's
loop_triangles, split by material slot (one Facet mesh shape per slot used), with split
normals when any face is smooth, in object space with the instance's world matrix as the
shape's transform; the colour attribute its materials' Color Attribute nodes read as the
mesh's vertex colours. A mesh placed several times (instances, linked duplicates) is one
prototype with an instance per placement (export_scene).

Objects imported from a Facet JSON scene carry their original description as custom
properties ("facet_shape", "facet_camera", "facet_light", "facet_environment") with a
snapshot of their Blender state ("facet_state"). While the state is unchanged the original
description is exported as it was read (exact analytic shapes, double-precision transforms,
the exact camera), so a JSON scene renders in Blender exactly as with `facet render`; once the
user moves or edits it, the Blender state is exported instead.
"""
import json
import math

import numpy as np

from . import bake, gaps, hooks, materials, nodegraph, textures, units

GEOMETRY_TYPES = {'MESH', 'CURVE', 'SURFACE', 'META', 'FONT'}
DEFAULT_MATERIAL_NAME = "facet_default"


class ExportError(Exception):
    pass


# --- state snapshots of imported objects ----------------------------------------------------

def _floats(vals):
    return ",".join(repr(float(v)) for v in vals)


def object_state(obj, matrix=None):
    m = obj.matrix_world if matrix is None else matrix
    parts = [_floats(v for row in m for v in row)]
    if obj.type == 'CAMERA':
        c = obj.data
        parts.append(_floats((c.lens, c.sensor_width, c.sensor_height, c.shift_x, c.shift_y,
                              c.ortho_scale)))
        parts.append(c.sensor_fit + c.type)
        d = c.dof
        parts.append("%s%s" % (d.use_dof, d.focus_object.name if d.focus_object else "")
                     + _floats((d.focus_distance, d.aperture_fstop, d.aperture_blades,
                                d.aperture_rotation, d.aperture_ratio)))
    elif obj.type == 'LIGHT':
        lt = obj.data
        parts.append(lt.type + _floats(list(lt.color) + [lt.energy]))
        if lt.type == 'SPOT':
            parts.append(_floats((lt.spot_size, lt.spot_blend)))
        if lt.type == 'SUN':
            parts.append(_floats((lt.angle,)))
        if lt.type == 'AREA':
            parts.append(lt.shape + _floats((lt.size, lt.size_y)))
    return ";".join(parts)


def render_state(scene):
    r = scene.render
    return "%d,%d,%d,%s,%s" % (r.resolution_x, r.resolution_y, r.resolution_percentage,
                              repr(float(r.pixel_aspect_x)), repr(float(r.pixel_aspect_y)))


def world_state(world):
    return _floats(world.color) + ";%s" % world.use_nodes


def _stored(id_block, key, state):
    """The original description stored at import, when the block is unchanged since."""
    if key in id_block and id_block.get("facet_state") == state:
        return json.loads(id_block[key])
    return None


# --- the scene -------------------------------------------------------------------------------

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


def _matrix_rows(m):
    return [list(row) for row in m]  # a mathutils Matrix's rows as floats


def _is_identity(m):
    return all(m[i][j] == (1.0 if i == j else 0.0) for i in range(4) for j in range(4))


def _placement(m):
    """A placement's transform rows, None for the identity."""
    rows = [list(row) for row in m]
    identity = all(rows[i][j] == (1.0 if i == j else 0.0) for i in range(4) for j in range(4))
    return None if identity else rows


class MeshArrays:
    """One evaluated mesh as arrays: positions (n, 3) f32, indices (m, 3) i32, normals (n, 3)
    f32 | None, material (m,) i32 (slot per triangle), uvs (n, 2) f32 | None, tangents (n, 4)
    f32 | None, colors (n, 4) f32 | None, and notes: what the colours could not give exactly
    (the caller reports them, naming the object)."""

    __slots__ = ("positions", "indices", "normals", "material", "uvs", "tangents", "colors",
                 "notes")

    def __init__(self, positions, indices, normals, material, uvs=None, tangents=None,
                 colors=None, notes=()):
        self.positions, self.indices, self.normals = positions, indices, normals
        self.material, self.uvs, self.tangents = material, uvs, tangents
        self.colors, self.notes = colors, list(notes)


def color_attribute(me, name):
    """The mesh attribute a Color Attribute node reads: by name, or for "" the mesh's default
    colour attribute (Cycles' ATTR_STD_VERTEX_COLOR); None when there is none."""
    if name:
        return me.attributes.get(name)
    ca = me.color_attributes
    default = getattr(ca, "default_color_name", "")
    if default and default in ca:
        return ca[default]
    i = ca.render_color_index
    return ca[i] if 0 <= i < len(ca) else None


_COLOR_TYPES = ('FLOAT_COLOR', 'BYTE_COLOR')
_COLOR_DOMAINS = ('POINT', 'CORNER', 'FACE')


def _color_values(me, name, what):
    """(linear RGBA values (k, 4) f32 of the attribute's domain, its domain, [notes]) of the
    colour attribute `name` ("" the default one). Byte colours are read decoded (`color`,
    linear), as Cycles decodes each corner before interpolating. A missing attribute gives
    (None, None, [note]): Cycles then reads black with alpha 0."""
    attr = color_attribute(me, name)
    label = "'%s'" % name if name else "(the default colour attribute)"
    if attr is None:
        return None, None, ["%s: its materials read colour attribute %s, which the mesh does "
                            "not have; black (alpha 0) used, as Cycles does" % (what, label)]
    if attr.data_type not in _COLOR_TYPES or attr.domain not in _COLOR_DOMAINS:
        return None, None, ["%s: attribute '%s' (%s on %s) is not a colour attribute Facet "
                            "reads (float or byte colours on points, corners or faces); black "
                            "(alpha 0) used" % (what, attr.name, attr.data_type.lower(),
                                                attr.domain.lower())]
    vals = np.empty(len(attr.data) * 4, np.float32)
    attr.data.foreach_get('color', vals)
    vals = vals.reshape(-1, 4)
    notes = []
    if not (vals.min(initial=0.0) >= 0.0 and vals.max(initial=0.0) <= 1.0):  # NaN: False too
        bad = ~np.isfinite(vals) | (vals < 0.0) | (vals > 1.0)
        lo, hi = float(np.nanmin(vals)), float(np.nanmax(vals))
        notes.append("%s: colour attribute '%s': %d values outside [0, 1] (%.4g to %.4g) "
                     "clamped: Facet's vertex colours are in [0, 1], Cycles uses them as they "
                     "are" % (what, attr.name, int(bad.sum()), lo, hi))
        vals = np.clip(np.nan_to_num(vals, nan=0.0), 0.0, 1.0)
    return vals, attr.domain, notes


def mesh_arrays(obj_eval, uv_layer=None, tangents=False, colors=None):
    """Evaluated object -> MeshArrays, or None for a mesh without triangles. `uv_layer` (a UV
    map's name, "" for the render one; None: no UVs) exports that layer's UVs, one vertex per
    face corner (loop) as UVs are per corner in Blender; a mesh without that layer gets uvs
    None. `tangents`: with the UVs, that layer's MikkTSpace tangents and bitangent signs per
    corner, Blender's own calc_tangents() (what Cycles' Normal Map node reads); None when
    Blender cannot compute them (a face of more than 4 corners: the core then computes
    MikkTSpace itself, FORMAT.md). `colors` (a colour attribute's name, "" the default one;
    None: none) exports it as linear RGBA per exported vertex: point colours as they are,
    corner and face colours one vertex per loop."""
    me, copied = _export_mesh(obj_eval, tangents)
    try:
        if me is None:
            return None
        me.calc_loop_triangles()
        nt = len(me.loop_triangles)
        if nt == 0:
            return None
        what = "object '%s'" % obj_eval.original.name
        nv = len(me.vertices)
        co = np.empty(nv * 3, np.float32)
        me.vertices.foreach_get('co', co)
        # 3.4: the material_index attribute is absent when every index is 0; loop_triangles
        # has it either way.
        mat = np.empty(nt, np.int32)
        me.loop_triangles.foreach_get('material_index', mat)
        smooth = np.empty(len(me.polygons), bool)
        me.polygons.foreach_get('use_smooth', smooth)
        layer = None
        if uv_layer is not None:
            layer = (me.uv_layers.get(uv_layer) if uv_layer else
                     next((u for u in me.uv_layers if u.active_render), None))
        uv_name = layer.name if layer is not None else None
        col_domain = None
        if colors is not None:
            attr = color_attribute(me, colors)
            col_domain = attr.domain if attr is not None else None
        if layer is None and col_domain in (None, 'POINT'):
            nrm = None
            if smooth.all() and not me.use_auto_smooth and not me.has_custom_normals:
                nrm = np.empty(nv * 3, np.float32)
                me.vertices.foreach_get('normal', nrm)
                nrm = nrm.reshape(-1, 3)
            if nrm is not None or not smooth.any():
                tri_v = np.empty(nt * 3, np.int32)
                me.loop_triangles.foreach_get('vertices', tri_v)
                out = MeshArrays(co.reshape(-1, 3), tri_v.reshape(-1, 3), nrm, mat)
                if colors is not None:
                    _set_colors(out, me, colors, what, None, nv)
                return out
        # Split normals (auto smooth, sharp edges, custom normals, flat faces among smooth
        # ones), UVs or corner colours: one vertex per loop.
        nl = len(me.loops)
        loop_v = np.empty(nl, np.int32)
        me.loops.foreach_get('vertex_index', loop_v)
        tri_l = np.empty(nt * 3, np.int32)
        me.loop_triangles.foreach_get('loops', tri_l)
        ln = None
        if smooth.all() and not me.use_auto_smooth and not me.has_custom_normals:
            # Smooth everywhere: the corners' normals are the vertex normals (as Cycles reads
            # them), without split normals' work and 3 floats per corner read through RNA.
            vn = np.empty(nv * 3, np.float32)
            me.vertices.foreach_get('normal', vn)
            ln = vn.reshape(-1, 3)[loop_v]
        elif smooth.any():
            me.calc_normals_split()
            ln = np.empty(nl * 3, np.float32)
            me.loops.foreach_get('normal', ln)
            ln = ln.reshape(-1, 3)
        uvs = tan = None
        if layer is not None:
            # calc_normals_split() reallocates the corners' layers: look the UV layer up again
            # (the old reference reads freed memory; its name came back empty).
            layer = me.uv_layers[uv_name]
            uvs = np.empty(nl * 2, np.float32)
            layer.data.foreach_get('uv', uvs)
            uvs = uvs.reshape(-1, 2)
            if tangents:
                tan = _loop_tangents(me, layer.name, nl)
        out = MeshArrays(co.reshape(-1, 3)[loop_v], tri_l.reshape(-1, 3), ln, mat, uvs, tan)
        if colors is not None:
            _set_colors(out, me, colors, what, loop_v, nl)
        return out
    finally:
        if copied:
            obj_eval.to_mesh_clear()


def _export_mesh(obj_eval, tangents):
    """(mesh, copied): the evaluated mesh itself when reading it needs no change to it, as
    Cycles reads it (blender/mesh.cpp: a copy only for auto smooth and edit mode); else
    to_mesh()'s copy, as split normals and tangents add layers to the mesh they are computed
    on. Skipping the copy saves ~0.27 s per 10^6 triangles (bench/blender_export_bench.py)."""
    d = obj_eval.data if obj_eval.type == 'MESH' else None
    if d is None or tangents or d.is_editmode or d.use_auto_smooth or d.has_custom_normals:
        return obj_eval.to_mesh(), True
    smooth = np.empty(len(d.polygons), bool)
    d.polygons.foreach_get('use_smooth', smooth)
    if smooth.any() and not smooth.all():  # flat faces among smooth: split normals
        return obj_eval.to_mesh(), True
    return d, False


def _set_colors(out, me, name, what, loop_v, n):
    """The colour attribute `name` per exported vertex into out.colors (n vertices: the
    mesh's points when loop_v is None, else one per loop, loop_v their points). Read last:
    calc_normals_split() and calc_tangents() reallocate the corners' layers."""
    vals, domain, notes = _color_values(me, name, what)
    out.notes.extend(notes)
    if vals is None:
        out.colors = np.zeros((n, 4), np.float32)
    elif domain == 'POINT':
        out.colors = vals if loop_v is None else vals[loop_v]
    elif domain == 'CORNER':
        out.colors = vals
    else:  # FACE: each loop takes its face's colour
        totals = np.empty(len(me.polygons), np.int32)
        me.polygons.foreach_get('loop_total', totals)
        starts = np.empty(len(me.polygons), np.int32)
        me.polygons.foreach_get('loop_start', starts)
        order = np.argsort(starts, kind="stable")  # the faces in the order of their loops
        face_of_loop = np.repeat(order.astype(np.int32), totals[order])
        out.colors = vals[face_of_loop]


def _loop_tangents(me, uv_name, nl):
    """(nl, 4) f32: Blender's MikkTSpace tangent and bitangent sign of every corner for UV map
    `uv_name` (calc_tangents() also computes the split normals they are relative to); None
    when Blender refuses (n-gons)."""
    try:
        me.calc_tangents(uvmap=uv_name)
    except RuntimeError:
        return None
    tan = np.empty((nl, 4), np.float32)
    t3 = np.empty(nl * 3, np.float32)
    me.loops.foreach_get('tangent', t3)
    sign = np.empty(nl, np.float32)
    me.loops.foreach_get('bitangent_sign', sign)
    tan[:, :3] = t3.reshape(-1, 3)
    tan[:, 3] = sign
    me.free_tangents()
    return tan


class _Materials:
    """Blender materials -> named Facet materials, each converted once."""

    def __init__(self, problems, users=None):
        self.problems = problems
        self.users = {} if users is None else users  # facet name -> {object names}
        self.by_name = {}  # facet name -> materials.Converted
        self.first_user = {}  # facet name -> the object it was converted for (bakes)
        self.order = []

    def get(self, mat, obj=None):
        name = DEFAULT_MATERIAL_NAME if mat is None else mat.name
        if name not in self.by_name:
            conv = materials.convert(mat, getattr(obj, "original", obj))
            self.problems.extend(conv.problems)
            self.by_name[name] = conv
            self.order.append(name)
            self.first_user[name] = obj.original.name if obj is not None else None
        conv = self.by_name[name]
        if obj is not None:
            self.users.setdefault(name, set()).add(obj.original.name)
        if conv.baked and obj is not None and obj.original.name != self.first_user[name]:
            line = ("material '%s': baked over object '%s''s UVs; object '%s' uses the same "
                    "image over its own UVs" % (name, self.first_user[name], obj.original.name))
            if line not in self.problems:
                self.problems.append(line)
        return name, conv

    def data(self):
        return [(n, self.by_name[n].data) for n in self.order]


# Blender's area lamp shapes -> Facet's "area" kind's (the importer maps them back).
AREA_SHAPES = {'SQUARE': "square", 'RECTANGLE': "rectangle", 'DISK': "disc", 'ELLIPSE': "ellipse"}


def _light_data(obj, matrix, problems):
    """A Blender lamp -> one light of the scene format (None: not supported, reported)."""
    lt = obj.data
    for label, value, what in gaps.light_gaps(lt):
        problems.append("light '%s': %s light %s = %s: %s" % (obj.name, lt.type.lower(), label,
                                                             value, what))
    m = matrix
    pos = [m[i][3] for i in range(3)]
    axis = [-m[i][2] for i in range(3)]  # Blender lights point along local -Z
    # Sizes as Cycles 3.4 defines them: a point or spot lamp's Radius is the radius of a sphere
    # of uniform radiance with the lamp's power (Facet's "radius"), the Sun's Angle its full
    # angular diameter (Facet's "angle", degrees) with the irradiance unchanged.
    size = {"radius": float(lt.shadow_soft_size)} if lt.type in ('POINT', 'SPOT') and \
        lt.shadow_soft_size > 0.0 else {}
    if lt.type == 'POINT':
        return {"type": "point", "position": pos, **size,
                 "power": units.point_power_from_blender(lt.color, lt.energy)}
    if lt.type == 'SPOT':
        # Blender's form (FORMAT.md, spot): outer = spot_size / 2, spot_blend as it is, with
        # Cycles 3.4's smoothstep fall-off; the power keeps K = P / (4 pi).
        outer = math.degrees(0.5 * lt.spot_size)
        return {"type": "spot", "position": pos, "direction": axis, "outer_angle": outer,
                 "spot_blend": float(lt.spot_blend), **size,
                 "power": units.spot_blend_power_from_blender(lt.color, lt.energy, outer,
                                                              lt.spot_blend)}
    if lt.type == 'SUN':
        sun = {"angle": math.degrees(lt.angle)} if lt.angle > 0.0 else {}
        return {"type": "directional", "direction": axis, **sun,
                 "irradiance": units.sun_irradiance_from_blender(lt.color, lt.energy)}
    if lt.type == 'AREA':
        return _area_light(obj, lt, m, pos, problems)
    problems.append("light '%s': type %s is not supported; skipped" % (obj.name, lt.type))
    return None


def _area_light(obj, lt, m, pos, problems):
    """Blender's area lamp -> the core's `area` kind (square, rectangle, disc, ellipse; power
    P as Blender's): centred on the object, emitting along its local -Z, local +Y up, the
    sizes times the object's scale along X and Y (as Cycles scales them). A shear between the
    lamp's X and Y axes is reported (the sizes along the scaled axes are used)."""
    x = [m[i][0] for i in range(3)]
    y = [m[i][1] for i in range(3)]
    z = [m[i][2] for i in range(3)]
    sx, sy, sz = (math.sqrt(sum(c * c for c in v)) for v in (x, y, z))
    if abs(sum(a * b for a, b in zip(x, y))) > 1e-6 * sx * sy:
        problems.append("light '%s': area lamp sheared by its transform; its X and Y sizes are "
                        "used along perpendicular axes" % obj.name)
    round_shape = lt.shape in ('DISK', 'ELLIPSE')
    size = float(lt.size) * sx
    size_y = (float(lt.size_y) if lt.shape in ('RECTANGLE', 'ELLIPSE') else float(lt.size)) * sy
    out = {"type": "area", "position": pos, "direction": [-c / sz for c in z],
           "up": [c / sy for c in y],
           "size": size, "power": units.area_power_from_blender(lt.color, lt.energy),
           # Blender 3.4 hides a new lamp from camera rays (Object > Visibility > Camera).
           "camera_visible": bool(obj.visible_camera)}
    if abs(size_y - size) > 1e-6 * size:  # float32 matrices: a square stays square
        out["shape"] = "ellipse" if round_shape else "rectangle"
        out["size_y"] = size_y
    else:
        out["shape"] = "disc" if round_shape else "square"
    return out


class ClipCheck:
    """Whether the scene camera's Clip Start or Clip End cuts an exported object off
    (gaps.CLIP_START, gaps.CLIP_END): add() each placement, lines() after, in one numpy pass.
    Cycles clips at two planes along the view axis, for perspective cameras too
    (kernel/camera/camera.h: the ray starts at depth clip_start and ends at depth clip_end).
    A placement's depths are d(x) = f . (M x + t - p) for x in its local bounding box (centre
    c, half extents h), so with w = M^T f they span w . c + f . (t - p) -+ |w| . h."""

    def __init__(self, cam_obj):
        from mathutils import Vector
        c = cam_obj.data
        m = cam_obj.matrix_world
        self.name = cam_obj.name
        self.fwd = Vector([-m[i][2] for i in range(3)]).normalized()
        self.base = self.fwd.dot(m.translation)
        self.start, self.end = float(c.clip_start), float(c.clip_end)
        self.boxes = {}  # geometry key -> (centre, half extents) of its local bounding box
        self.placed = []  # (geometry key, object name, w, f . t - f . p)

    def add(self, obj, matrix, key):
        """A placement of `obj`'s geometry (`key`: the same for the same geometry). A mesh
        object's box is its bound_box; other types' come from their exported arrays (points()):
        Blender 3.4 leaks the box it allocates for the bound_box of the evaluated mesh a curve,
        surface, metaball or text object becomes."""
        if key not in self.boxes and obj.original.type == 'MESH':
            corners = np.array([tuple(v) for v in obj.bound_box], np.float64)
            self._box(key, corners.min(axis=0), corners.max(axis=0))
        w = self.fwd @ matrix.to_3x3()  # the row vector f^T M = (M^T f)^T
        self.placed.append((key, obj.original.name, tuple(w),
                            self.fwd.dot(matrix.translation) - self.base))

    def points(self, key, arrays):
        """The box of the exported vertices (a MeshArrays or None) of a non-mesh geometry."""
        if key in self.boxes or arrays is None or not len(arrays.positions):
            return
        self._box(key, arrays.positions.min(axis=0), arrays.positions.max(axis=0))

    def _box(self, key, lo, hi):
        lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
        self.boxes[key] = (0.5 * (lo + hi), 0.5 * (hi - lo))

    def lines(self):
        placed = [p for p in self.placed if p[0] in self.boxes]
        if not placed:
            return []
        centre = np.array([self.boxes[p[0]][0] for p in placed])  # (n, 3)
        half = np.array([self.boxes[p[0]][1] for p in placed])
        w = np.array([p[2] for p in placed])
        mid = (w * centre).sum(axis=1) + np.array([p[3] for p in placed])
        reach = (np.abs(w) * half).sum(axis=1)
        far, near = mid + reach, np.maximum(mid - reach, 0.0)
        seen = far > 0.0  # not wholly behind the camera
        out = []
        far = np.where(seen, far, -np.inf)
        i = int(np.argmax(far))
        if far[i] > self.end:
            out.append(self._line(gaps.CLIP_END, self.end, placed[i][1], far[i]))
        near = np.where(seen, near, np.inf)
        i = int(np.argmin(near))
        if self.start > gaps.CLIP_START_FACTORY * (1.0 + 1e-6) and near[i] < self.start:
            out.append(self._line(gaps.CLIP_START, self.start, placed[i][1], near[i]))
        return out

    def _line(self, entry, value, name, reach):
        return ("camera '%s': %s = %.4g: %s (object '%s' reaches %.4g)"
                % (self.name, entry[0], value, entry[1], name, reach))


class _Placed:
    """One mesh (one evaluated geometry with one set of materials) and its placements: the
    shapes of its material slots in object space, and (transform rows, name) per placement."""

    def __init__(self, name, templates, emits):
        self.name = name
        self.templates = templates  # [(suffix, shape dict without transform and name)]
        self.emits = emits
        self.placements = []


def export_scene(depsgraph, camera=None, mesh_cache=None, users=None, instancing=True):
    """Evaluated depsgraph -> (scene data, [problem lines]). Raises ExportError when the
    scene cannot be rendered at all (no camera, ...). `camera` (scene-data camera) replaces the
    scene's camera (the viewport's view). `mesh_cache` (a dict kept by the caller) reuses the
    arrays of objects converted before (the viewport drops the entries of changed objects).
    `users` (a dict, filled when given): material name -> the names of the objects using it
    (for the grouped report, gaps.grouped).

    Instancing (`instancing`, on by default): a mesh placed more than once (collection
    instances, particles, geometry-nodes instances, linked duplicates: the same evaluated
    geometry with the same materials) is exported once, as a prototype (FORMAT.md,
    "Instances"), with an `instance` shape per placement; a mesh placed once stays a mesh
    shape. Where the core's instancing cannot take a mesh the placements are expanded into
    mesh shapes (exact, one copy each) and reported: an emitting mesh (the core's prototypes
    cannot emit) and Facet shapes imported from JSON (analytic kinds). Blender's nested
    instances arrive as one level already (the depsgraph composes their matrices)."""
    scene = depsgraph.scene
    problems = []
    bake.PENDING.clear()  # this export's bake requests (facet.bake_inputs bakes them)
    mats = _Materials(problems, users)
    data = {"description": "exported from Blender scene '%s'" % scene.name,
            "camera": camera or export_camera(depsgraph, scene, problems),
            "shapes": [], "lights": []}
    mesh_cache = {} if mesh_cache is None else mesh_cache
    order = []  # in depsgraph order: a shape dict, or a _Placed (one entry per placement)
    placed = {}  # geometry key -> _Placed
    expanded_shapes = set()
    seen = {}  # (object name, geometry, is instance) -> (_Placed, shape name)
    empty = []  # objects whose own mesh is empty (reported unless they place instances)
    instancers = set()
    # Settings and object flags that change Cycles' image and are not converted (gaps.py).
    view_layer = depsgraph.view_layer
    problems.extend(gaps.scene_lines(scene, view_layer))
    flagged = set()  # objects whose flags, type and particle hair were reported
    # The scene camera's clipping (the viewport's view has its own, and clips what it shows).
    clip = ClipCheck(scene.camera) if camera is None and scene.camera is not None and \
        scene.camera.type == 'CAMERA' else None
    for inst in depsgraph.object_instances:
        obj = inst.object
        matrix = inst.matrix_world.copy()
        if inst.is_instance and inst.parent is not None:
            instancers.add(inst.parent.original.name)
        if obj.original.name not in flagged:
            # The original's settings: an evaluated copy made before a Python property (such
            # as object.cycles') changed keeps the old value until the object is re-evaluated.
            flagged.add(obj.original.name)
            problems.extend(gaps.object_lines(obj.original, view_layer))
        if obj.type != obj.original.type and (obj.original.name, obj.type) not in flagged:
            # A component of another type in an object's evaluated geometry (geometry nodes'
            # Mesh to Points, Mesh to Volume, ...), placed as an instance of that type.
            flagged.add((obj.original.name, obj.type))
            problems.extend(gaps.component_lines(obj, view_layer))
        if obj.type == 'LIGHT':
            orig = obj.original
            stored = None if inst.is_instance else _stored(orig, "facet_light",
                                                           object_state(obj, matrix))
            if stored is not None:
                data["lights"].append(stored)
                continue
            light = _light_data(obj, matrix, problems)
            if light is not None:
                data["lights"].append(light)
            continue
        if obj.type not in GEOMETRY_TYPES:
            continue
        if not (obj.visible_camera or obj.visible_diffuse or obj.visible_glossy
                or obj.visible_shadow):
            continue
        orig = obj.original
        data_ptr = obj.data.as_pointer() if obj.type == 'MESH' and obj.data is not None else 0
        clip_key = data_ptr or (orig.name, inst.is_instance)
        if clip is not None:
            clip.add(obj, matrix, clip_key)
        again = seen.get((orig.name, data_ptr, inst.is_instance)) if data_ptr else None
        if again is not None:
            # Another placement of an object converted above (same object, same geometry:
            # the same materials and the same record): only its matrix is new.
            if again[0].templates:
                again[0].placements.append((_placement(matrix), again[1]))
                order.append(again[0])
            continue
        name = orig.name if not inst.is_instance else "%s (instance)" % orig.name
        if "facet_shape" in orig:
            shape = json.loads(orig["facet_shape"])
            if not inst.is_instance and orig.get("facet_state") == object_state(obj, matrix):
                pass  # unchanged since import: the stored (double precision) transform
            else:
                shape["transform"] = None if _is_identity(matrix) else _matrix_rows(matrix)
            if inst.is_instance and orig.name not in expanded_shapes:
                expanded_shapes.add(orig.name)
                problems.append("object '%s': a Facet %s shape (imported from JSON) placed by "
                                "instances is expanded into a shape per placement (only meshes "
                                "become prototypes)" % (orig.name, shape["type"]))
            if shape["type"] == "mesh" and "file" not in shape:
                arrays = _imported_mesh_arrays(obj)
                if arrays is None:
                    problems.append("object '%s': empty mesh (no faces); skipped" % orig.name)
                    continue
                shape["positions"], shape["indices"], shape["normals"] = arrays
            slot_mat = obj.material_slots[0].material if obj.material_slots else None
            _add_material(shape, slot_mat, mats, obj)
            order.append(shape)
            continue
        slots = [s.material for s in obj.material_slots] or [None]
        uv_layer = _uv_layer(obj, slots, mats, problems)
        tangents = uv_layer is not None and any(
            mats.get(m, obj)[1].tangents for m in slots
            if m is None or not m.get("facet_cycles_only"))
        colors = _color_attribute_read(obj, slots, mats, problems)
        # The same evaluated geometry (a pointer compared while this depsgraph lives) with the
        # same materials is one mesh however often it is placed; other kinds: per object.
        gkey = (data_ptr or orig.name, inst.is_instance if not data_ptr else None,
                tuple(m.name if m is not None else None for m in slots), uv_layer, tangents,
                colors)
        rec = placed.get(gkey)
        if rec is None:
            key = (orig.name, inst.is_instance, data_ptr if inst.is_instance else 0, uv_layer,
                   tangents, colors)
            if key not in mesh_cache:
                mesh_cache[key] = mesh_arrays(obj, uv_layer, tangents, colors)
                hooks.export_stats["meshes"] += 1
            rec = placed[gkey] = _placed_mesh(mesh_cache[key], obj, slots, uv_layer, mats,
                                               problems)
            if clip is not None and orig.type != 'MESH':
                clip.points(clip_key, mesh_cache[key])
        if data_ptr:
            seen[(orig.name, data_ptr, inst.is_instance)] = (rec, name)
        if not rec.templates:
            if orig.name not in empty:
                empty.append(orig.name)
            continue
        rec.placements.append((_placement(matrix), name))
        order.append(rec)
    if clip is not None:
        problems.extend(clip.lines())
    # An instancer's own geometry may be empty (geometry nodes outputting only instances).
    problems.extend("object '%s': empty mesh (no faces); skipped" % name for name in empty
                    if name not in instancers)
    data["shapes"], prototypes = _place(order, placed, instancing, problems)
    if prototypes:
        data["prototypes"] = prototypes
    env = export_environment(scene, problems)
    if env is not None:
        data["lights"].append(env)
    data["materials"] = mats.data()
    data["render"] = export_render_settings(scene)
    return data, problems


def _placed_mesh(arrays, obj, slots, uv_layer, mats, problems):
    """A _Placed for the arrays of `obj` (no templates: an empty mesh): one shape per
    material slot used."""
    orig = obj.original
    if arrays is None:
        return _Placed(orig.name, [], False)
    problems.extend(arrays.notes)
    uvs = arrays.uvs
    if uv_layer is not None and uvs is None:
        # Cycles reads a missing UV map as (0, 0): the textures' value at the origin.
        problems.append("object '%s': its textured materials read UV map '%s', which the "
                        "mesh does not have; UV (0, 0) used everywhere, as Cycles does"
                        % (orig.name, uv_layer or "(render)"))
        uvs = np.zeros((len(arrays.positions), 2), np.float32)
    used = np.unique(arrays.material)
    templates = []
    for mi in used:
        mi = int(mi)
        slot_mat = slots[min(mi, len(slots) - 1)] if slots else None
        tris = arrays.indices if len(used) == 1 else arrays.indices[arrays.material == mi]
        shape = {"type": "mesh", "positions": arrays.positions, "indices": tris,
                 "normals": arrays.normals}
        if uvs is not None:
            shape["uvs"] = uvs
        if arrays.tangents is not None:
            shape["tangents"] = arrays.tangents
        if arrays.colors is not None:
            shape["colors"] = arrays.colors
        _add_material(shape, slot_mat, mats, obj)
        templates.append(("" if len(used) == 1 else " [slot %d]" % mi, shape))
    emits = any(materials.is_texture(t.get("emission")) or any(t.get("emission") or [])
                for _, t in templates)
    return _Placed(orig.name, templates, emits)


def _place(order, placed, instancing, problems):
    """(shapes, prototypes) of the placements in `order`: a mesh placed more than once as a
    prototype and instances (when `instancing`), every other placement as mesh shapes with
    its transform."""
    prototypes = {}
    proto_of = {}  # id(_Placed) -> prototype name
    for rec in placed.values():
        n = len(rec.placements)
        if n < 2 or not instancing:
            continue
        if rec.emits:
            problems.append("object '%s': placed %d times and emits light: expanded into a mesh "
                            "per placement, not instanced (Facet's prototypes cannot emit)"
                            % (rec.name, n))
            continue
        pname, k = rec.name, 1
        while pname in prototypes:
            k += 1
            pname = "%s (%d)" % (rec.name, k)
        prototypes[pname] = [dict(t, name=rec.name + suffix) for suffix, t in rec.templates]
        proto_of[id(rec)] = pname
    shapes = []
    next_placement = {}
    for entry in order:
        if not isinstance(entry, _Placed):
            shapes.append(entry)
            continue
        i = next_placement.get(id(entry), 0)
        next_placement[id(entry)] = i + 1
        rows, name = entry.placements[i]
        pname = proto_of.get(id(entry))
        if pname is not None:
            shapes.append({"type": "instance", "of": pname, "transform": rows, "name": name})
            continue
        for suffix, t in entry.templates:
            shapes.append(dict(t, transform=rows, name=name + suffix))
    return shapes, prototypes


def _color_attribute_read(obj, slots, mats, problems):
    """The colour attribute the object's materials read through Color Attribute nodes: None
    (none), "" (the default colour attribute) or a name; one per object (the core has one
    set of vertex colours per mesh), the others reported."""
    wanted = []
    for m in slots:
        if m is not None and m.get("facet_cycles_only"):
            continue
        for name in sorted(mats.get(m, obj)[1].color_attributes):
            if name not in wanted:
                wanted.append(name)
    if len(wanted) > 1:
        line = ("object '%s': its materials read several colour attributes (%s); only '%s' is "
                "exported, the others read it too"
                % (obj.original.name, ", ".join("'%s'" % (w or "(default)") for w in wanted),
                   wanted[0] or "(default)"))
        if line not in problems:
            problems.append(line)
    return wanted[0] if wanted else None


def _uv_layer(obj, slots, mats, problems):
    """The UV map the object's textured materials read: None (no texture), "" (the render UV
    map) or a name; one per object, the others reported. A name that is the render UV map's
    (the glTF importer names it on its Normal Map nodes) is that map: ""."""
    layers = getattr(obj.data, "uv_layers", None) or ()
    render = next((u.name for u in layers if u.active_render), None)
    wanted = []
    for m in slots:
        if m is not None and m.get("facet_cycles_only"):
            continue
        for uv in sorted(mats.get(m, obj)[1].uv_maps):
            uv = "" if uv == render else uv
            if uv not in wanted:
                wanted.append(uv)
    if len(wanted) > 1:
        line = ("object '%s': its materials read several UV maps (%s); only '%s' is exported"
                % (obj.original.name, ", ".join("'%s'" % (w or "(render)") for w in wanted),
                   wanted[0] or "(render)"))
        if line not in problems:  # once, however many placements
            problems.append(line)
    return wanted[0] if wanted else None


def _imported_mesh_arrays(obj_eval):
    """A mesh imported from JSON: its vertices and triangles as they were read (Blender keeps
    float32 positions exactly) and the exact normals from the "facet_normal" attribute."""
    me = obj_eval.data
    nv, nt = len(me.vertices), len(me.polygons)
    if nt == 0:
        return None
    co = np.empty(nv * 3, np.float32)
    me.vertices.foreach_get('co', co)
    idx = np.empty(len(me.loops), np.int32)
    me.loops.foreach_get('vertex_index', idx)
    nrm = None
    if "facet_normal" in me.attributes:
        nrm = np.empty(nv * 3, np.float32)
        me.attributes["facet_normal"].data.foreach_get('vector', nrm)
        nrm = nrm.reshape(-1, 3)
    return co.reshape(-1, 3), idx.reshape(-1, 3), nrm


def _add_material(shape, mat, mats, obj=None):
    if mat is not None and mat.get("facet_cycles_only"):
        # an emitter's Cycles-only material (tests/support/python/facet_testsupport/cycles_scene.py)
        mat = None
    if mat is None and any(shape.get("emission") or []):
        return  # an emitter without a material reflects nothing (FORMAT.md)
    name, conv = mats.get(mat, obj)
    shape["material"] = name
    if "emission" not in shape or not any(shape.get("emission") or []):
        if conv.emits():
            shape["emission"] = (dict(conv.emission) if materials.is_texture(conv.emission)
                                 else list(conv.emission))
    if "two_sided" not in shape:
        shape["two_sided"] = conv.two_sided


def export_environment(scene, problems):
    world = scene.world
    if world is None:
        return None
    stored = _stored(world, "facet_environment", world_state(world))
    if stored is not None:
        return stored
    if world.use_nodes and world.node_tree is not None:
        env = _world_environment_map(world, problems)
        if env is not None:
            return env
        rad = _world_radiance(world, problems)
        if rad is None:
            return None
    else:
        rad = units.emission_from_blender(world.color, 1.0)
    if not any(c > 0.0 for c in rad):
        return None
    return {"type": "environment", "radiance": rad}


def _world_environment_map(world, problems):
    """A world whose output is a Background (or Emission) with its Color fed by an
    Environment Texture (equirectangular), through Mapping nodes of rotations (and a uniform
    scale) from the world's Generated coordinates (the view direction, also when unlinked),
    and a constant Strength -> the core's environment map: file, radiance = Strength, and
    rotate. Cycles looks up l = R d (Mapping Point / Vector: R = Rz Ry Rx; Texture: its
    transpose); Facet looks up l = M^T d, so M = R^T, given as the axis and angle of R^T.
    None when the world is not of this form (the generic conversion then reports it)."""
    from mathutils import Matrix
    walker = nodegraph.Walker(world.node_tree)
    out = nodegraph.active_output(world.node_tree, 'ShaderNodeOutputWorld')
    if out is None:
        return None
    bg = walker.input(out, 'Surface')
    if not isinstance(bg, nodegraph.Out) or bg.convs or bg.node.bl_idname not in (
            'ShaderNodeBackground', 'ShaderNodeEmission'):
        return None
    tex = walker.input(bg.node, 'Color', bg.path)
    strength, _ = walker.fold(walker.input(bg.node, 'Strength', bg.path))
    if not isinstance(tex, nodegraph.Out) or tex.node.bl_idname != 'ShaderNodeTexEnvironment' \
            or tex.socket.identifier != 'Color' or strength is None:
        return None
    what = "world '%s': %s" % (world.name, tex.label())
    node = tex.node
    if node.image is None or node.projection != 'EQUIRECTANGULAR':
        return None
    try:
        path, colorspace, note = textures.image_file(node.image)
    except ValueError:
        return None
    m = Matrix.Identity(4)
    cur = walker.input(node, 'Vector', tex.path)
    while isinstance(cur, nodegraph.Out):
        n = cur.node
        if n.bl_idname == 'ShaderNodeTexCoord' and cur.socket.identifier == 'Generated':
            break
        if n.bl_idname != 'ShaderNodeMapping':
            return None
        vals = [walker.fold(walker.input(n, name, cur.path))[0]
                for name in ('Location', 'Rotation', 'Scale')]
        mm = textures.mapping_matrix(n.vector_type, *vals) if None not in vals else None
        if mm is None:
            return None
        m = m @ Matrix(mm)
        cur = walker.input(n, 'Vector', cur.path)
    lin = m.to_3x3()
    scale = lin.determinant() ** (1.0 / 3.0) if lin.determinant() > 0.0 else 0.0
    if scale <= 0.0 or m.translation.length > 0.0 or \
            max(abs(v) for row in (lin @ lin.transposed() - Matrix.Identity(3) * scale ** 2)
                for v in row) > 1e-6 * scale ** 2:
        problems.append("%s: its Mapping is not a rotation (with a uniform scale); the map is "
                        "not rotated" % what)
        lin = Matrix.Identity(3)
    else:
        lin = lin * (1.0 / scale)
    if node.image.is_float:
        path, clamped = textures.nonnegative_radiance_file(node.image, path)
        if clamped:
            problems.append("%s: %s" % (what, clamped))
    env = {"type": "environment", "file": path, "radiance": float(strength)}
    axis, angle = lin.transposed().to_quaternion().to_axis_angle()
    if abs(angle) > 1e-12:
        if max(axis, key=abs) < 0.0:  # the same rotation, read with the axis' main part > 0
            axis, angle = -axis, -angle
        env["rotate"] = {"axis": [float(c) for c in axis], "angle": math.degrees(angle)}
    if note:
        problems.append("%s: %s" % (what, note))
    # The core reads float files as linear and other files sRGB-decoded (FORMAT.md).
    want = "linear" if path.lower().endswith((".exr", ".hdr")) else "srgb"
    if colorspace != want:
        problems.append("%s: colour space '%s': Facet reads this file as %s"
                        % (what, node.image.colorspace_settings.name, want))
    if colorspace == "srgb" and not node.image.is_float:
        problems.append("%s: Cycles interpolates an 8-bit sRGB image before decoding it, "
                        "Facet after" % what)
    if node.interpolation not in ('Linear',):
        problems.append("%s: interpolation %s converted as Linear" % (what, node.interpolation))
    return env


def _world_radiance(world, problems):
    """The world's node tree through the node-graph walker (materials.NodeContext): a
    Background or Emission with constant Color and Strength, a colour linked into the Surface,
    Add Shaders and Mix Shaders of them convert exactly; anything else is reported (gaps.py)
    with what Facet used."""
    ctx = materials.NodeContext("world", world.name, world.node_tree)
    out = nodegraph.active_output(world.node_tree, 'ShaderNodeOutputWorld')
    if out is None:
        return None
    ctx.ignored_input(out, 'Volume', (), "the World Output")
    _, rad = ctx.shader(ctx.walker.input(out, 'Surface'), "the World Output's Surface")
    problems.extend(ctx.finish())
    return rad


def export_render_settings(scene, frame=None):
    fs = scene.facet
    seed = fs.seed + (scene.frame_current if fs.animated_seed else 0)
    out = {"integrator": fs.integrator, "spp": fs.spp, "max_depth": fs.max_depth, "seed": seed}
    if fs.time_budget > 0.0:
        out["time_budget"] = fs.time_budget
    return out
