"""An evaluated mesh -> numpy arrays of the core's mesh shape: triangles, split normals, UVs,
tangents and the colour attribute (export.py places them; Cycles' blender_mesh.cpp)."""
import numpy as np


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
