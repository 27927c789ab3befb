"""The bake fallback: a subgraph feeding a BSDF colour input that Facet cannot express
(a procedural texture with a linked parameter, a colour output into a number input through a
Mix or ColorRamp, a Vector Math vector into a number input, a vector that is no affine chain,
...; textures.py converts Noise, Voronoi, Wave, Magic, Gradient, White Noise, Brick and ridged
Musgrave, and Math, Vector Math, Mix RGB / Mix and ColorRamp nodes between textures, natively)
is baked by Blender itself into an
image over the object's UV map, and the material renders with that image.

- What: the output socket feeding the input (materials.NodeContext.param, after the folding and
  textures.py both fail; for a Roughness, through clamp(v, 0, 1)^2 Math nodes: Facet's alpha,
  which no texture can square), wired into an Emission shader on a temporary copy of the material,
  on a temporary mesh of the object's evaluated geometry (modifiers applied) holding only the
  faces of that material, with the object's render UV map active; Cycles' Emit bake (1 sample:
  a procedural is deterministic; Emission Strength 1 gives the colour as it is) into a float
  image of `scene.facet.bake_resolution` pixels square, its pixels written as a linear EXR in
  the cache directory (textures.CACHE_DIR) by the core's writer (Image.save() of a float image
  wrote view-transformed values in 3.4.1, measured: a mean of 0.73 for 0.50). The Emit pass
  equals the value Cycles feeds the input at the texel's centre; between texels Facet
  interpolates bilinearly (the approximation: detail finer than a texel is lost), and outside
  the UV islands the margin (16 px) extends the edge.
- Cache: the file is named by a hash of the material's node tree (every node, its properties,
  input values and links, node groups included), the input, the object's name, its mesh's UVs
  and positions, and the resolution: an unchanged material bakes once.
- When: the operator facet.bake_inputs (Render Properties > Facet > Bake Procedural Inputs)
  bakes every input an export needs, with progress; a render that meets an input not baked
  yet reports it (and uses the input's own value). Baking needs bpy.ops, which a render
  engine's render() cannot call.
- Reports: every baked input is listed (an approximation); an object without a UV map, an
  input fed from inside a node group, a subgraph depending on the view or the lighting
  (Fresnel, Layer Weight, Light Path, Geometry Incoming, ...: VIEW_DEPENDENT), a material used by several objects (baked over the
  first one's UVs) are reported naming the object and the material.
"""
import hashlib
import os

import bpy

from . import textures

# Nodes whose value depends on the view, the ray or the lighting: a subgraph with one of them
# is not baked (reported). Geometry's Incoming and Backfacing outputs too (request()).
VIEW_DEPENDENT = {'ShaderNodeFresnel', 'ShaderNodeLayerWeight', 'ShaderNodeLightPath',
                  'ShaderNodeCameraData', 'ShaderNodeAmbientOcclusion', 'ShaderNodeBevel',
                  'ShaderNodeLightFalloff', 'ShaderNodeShaderToRGB', 'ShaderNodeHairInfo',
                  'ShaderNodeParticleInfo', 'ShaderNodeVolumeInfo', 'ShaderNodePointInfo'}

# Requests of the current export: [Request]; export_scene clears it, facet.bake_inputs bakes.
PENDING = []
MARGIN = 16


class Request:
    def __init__(self, key, path, mat, node, input_id, obj, src, resolution, square=False):
        self.key = key
        self.path = path
        self.mat = mat
        self.node = node
        self.input_id = input_id
        self.obj = obj
        self.src = src
        self.resolution = resolution
        self.square = square

    def describe(self):
        return "%s feeding %s '%s' input '%s'%s of material '%s' over object '%s' (%d px)" % (
            self.src.label(), self.node.bl_label, self.node.name,
            _input(self.node, self.input_id).name, " (squared: alpha)" if self.square else "",
            self.mat.name, self.obj.name, self.resolution)


def _input(node, ident):
    return next(s for s in node.inputs if s.identifier == ident)


def _value_repr(v):
    if isinstance(v, (str, bytes, int, float, bool)) or v is None:
        return repr(v)
    try:
        return repr(tuple(round(float(x), 7) for x in v))
    except (TypeError, ValueError):
        return repr(v)


def tree_signature(tree, h, seen=None):
    """Feeds `h` with everything of a node tree that can change what it computes."""
    seen = set() if seen is None else seen
    if tree is None or tree.name in seen:
        return
    seen.add(tree.name)
    for n in sorted(tree.nodes, key=lambda n: n.name):
        h.update(("%s|%s|%s|" % (n.bl_idname, n.name, n.mute)).encode())
        for p in n.bl_rna.properties:
            if p.is_readonly or p.identifier in ('location', 'width', 'height', 'select',
                                                 'name', 'label', 'color', 'hide',
                                                 'show_options', 'show_preview', 'show_texture',
                                                 'use_custom_color', 'width_hidden', 'parent'):
                continue
            v = getattr(n, p.identifier, None)
            if isinstance(v, bpy.types.ID):
                v = v.name
            elif p.type == 'POINTER':
                continue
            h.update(("%s=%s|" % (p.identifier, _value_repr(v))).encode())
        for s in n.inputs:
            h.update(("%s:%s|" % (s.identifier, _value_repr(getattr(s, "default_value", None))))
                     .encode())
        if getattr(n, "node_tree", None) is not None:
            tree_signature(n.node_tree, h, seen)
        ramp = getattr(n, "color_ramp", None)
        if ramp is not None:
            h.update(repr([(e.position, tuple(e.color)) for e in ramp.elements]).encode())
    for l in tree.links:
        h.update(("%s.%s>%s.%s|%s" % (l.from_node.name, l.from_socket.identifier,
                                      l.to_node.name, l.to_socket.identifier, l.is_muted))
                 .encode())


def _mesh_signature(obj, h):
    import numpy as np
    me = obj.data
    if not hasattr(me, "vertices"):
        return
    co = np.empty(len(me.vertices) * 3, np.float32)
    me.vertices.foreach_get('co', co)
    h.update(co.tobytes())
    layer = next((u for u in me.uv_layers if u.active_render), None)
    if layer is not None:
        uv = np.empty(len(me.loops) * 2, np.float32)
        layer.data.foreach_get('uv', uv)
        h.update(uv.tobytes())


def request(ctx, node, sock, src, square=False):
    """The baked texture for `src` feeding `sock` of `node` in the material of `ctx` (with
    `square`: of clamp(value, 0, 1)^2, a roughness's alpha), None (not a material: the caller
    reports) or False (reported here). Registers the bake in PENDING when it is not cached."""
    mat, obj = ctx.material, ctx.obj
    feeds = "%s '%s' input '%s'" % (node.bl_label, node.name, sock.name)
    if mat is None or obj is None:
        return None
    scene = bpy.context.scene
    if not scene.facet.bake:
        ctx.gap(src, "not convertible; baking is off (Render Properties > Facet > Bake)",
                "feeds %s; using the input's value" % feeds)
        return False
    me = getattr(obj, "data", None)
    if me is None or not hasattr(me, "uv_layers") or len(me.uv_layers) == 0:
        ctx.problems.append("%s: %s feeds %s and cannot be baked: object '%s' has no UV map "
                            "(add one: UV > Unwrap); using the input's value"
                            % (ctx.what, src.label(), feeds, obj.name))
        return False
    if src.path:
        ctx.gap(src, "not convertible, and it is inside a node group, which the bake does not "
                "reach", "feeds %s; using the input's value" % feeds)
        return False
    for o in ctx.walker.subgraph(src):
        if o.node.bl_idname in VIEW_DEPENDENT or (
                o.node.bl_idname == 'ShaderNodeNewGeometry'
                and o.socket.identifier in ('Incoming', 'Backfacing')):
            ctx.gap(o, "it depends on the view or the lighting, which a bake over the UVs "
                    "cannot keep", "feeds %s; using the input's value" % feeds)
            return False
    res = int(scene.facet.bake_resolution)
    h = hashlib.sha1()
    tree_signature(mat.node_tree, h)
    h.update(("%s|%s|%s|%s|%s|%d|%s" % (mat.name, node.name, sock.identifier, src.node.name,
                                         src.socket.identifier, res, square)).encode())
    h.update(obj.name.encode())
    _mesh_signature(obj, h)
    key = h.hexdigest()[:20]
    path = os.path.join(textures.CACHE_DIR, "bake_%s.exr" % key)
    req = Request(key, path, mat, node, sock.identifier, obj, src, res, square)
    if os.path.isfile(path):
        ctx.problems.append("%s: baked: %s" % (ctx.what, req.describe()))
        return {"texture": path, "colorspace": "linear"}
    if all(r.key != key for r in PENDING):
        PENDING.append(req)
    ctx.gap(src, "not convertible; not baked yet: run Render Properties > Facet > Bake "
            "Procedural Inputs", "feeds %s; using the input's value" % feeds)
    return False


# --- the bake itself (bpy.ops: an operator, never a render) ----------------------------------

def bake_all(context, requests, progress=None):
    """Bakes each request; returns [(request, error or None)]."""
    out = []
    scene = context.scene
    c = scene.cycles
    saved = (scene.render.engine, c.samples, c.bake_type, c.use_adaptive_sampling,
             c.use_denoising, context.view_layer.objects.active,
             [o for o in context.selected_objects])
    try:
        scene.render.engine = 'CYCLES'
        # Adaptive sampling and denoising on (Blender's defaults) leave an Emit bake black in
        # Blender 3.4.1 (measured); a procedural needs 1 sample per texel centre.
        c.samples, c.use_adaptive_sampling, c.use_denoising = 1, False, False
        for i, req in enumerate(requests):
            if progress:
                progress(i, len(requests))
            try:
                _bake_one(context, req)
                out.append((req, None))
            except Exception as e:  # reported by the operator, the rest still bakes
                out.append((req, str(e)))
    finally:
        scene.render.engine = saved[0]
        c.samples, c.bake_type, c.use_adaptive_sampling, c.use_denoising = saved[1:5]
        for o in context.selected_objects:
            o.select_set(False)
        for o in saved[6]:
            o.select_set(True)
        context.view_layer.objects.active = saved[5]
    return out


def _bake_one(context, req):
    import bmesh
    scene = context.scene
    depsgraph = context.evaluated_depsgraph_get()
    obj = req.obj
    mat = req.mat
    tmp_mat = mat.copy()
    tmp_mat.name = "facet_bake_tmp"
    img = bpy.data.images.new("facet_bake_tmp", req.resolution, req.resolution,
                              alpha=False, float_buffer=True)
    me = bpy.data.meshes.new_from_object(obj.evaluated_get(depsgraph))
    tmp = bpy.data.objects.new("facet_bake_tmp", me)
    try:
        slots = [i for i, s in enumerate(obj.material_slots) if s.material == mat]
        bm = bmesh.new()
        bm.from_mesh(me)
        drop = [f for f in bm.faces if f.material_index not in slots] if slots else []
        bmesh.ops.delete(bm, geom=drop, context='FACES')
        for f in bm.faces:
            f.material_index = 0
        bm.to_mesh(me)
        bm.free()
        render_uv = next((u for u in me.uv_layers if u.active_render), None)
        if render_uv is not None:
            me.uv_layers.active = render_uv
        me.materials.clear()
        me.materials.append(tmp_mat)
        tmp.matrix_world = obj.matrix_world
        scene.collection.objects.link(tmp)
        nt = tmp_mat.node_tree
        out = next(n for n in nt.nodes if n.bl_idname == 'ShaderNodeOutputMaterial'
                   and n.name == _output_name(mat))
        em = nt.nodes.new("ShaderNodeEmission")
        em.inputs["Strength"].default_value = 1.0
        value = nt.nodes[req.src.node.name].outputs[req.src.socket.identifier]
        if req.square:  # clamp(v, 0, 1)^2: Cycles' alpha of a roughness
            clamp = nt.nodes.new("ShaderNodeMath")
            clamp.operation, clamp.use_clamp = 'ADD', True
            clamp.inputs[1].default_value = 0.0
            nt.links.new(value, clamp.inputs[0])
            sq = nt.nodes.new("ShaderNodeMath")
            sq.operation = 'MULTIPLY'
            nt.links.new(clamp.outputs[0], sq.inputs[0])
            nt.links.new(clamp.outputs[0], sq.inputs[1])
            value = sq.outputs[0]
        nt.links.new(value, em.inputs["Color"])
        nt.links.new(em.outputs[0], out.inputs["Surface"])
        tex = nt.nodes.new("ShaderNodeTexImage")
        tex.image = img
        for n in nt.nodes:
            n.select = False
        tex.select = True
        nt.nodes.active = tex
        for o in context.selected_objects:
            o.select_set(False)
        tmp.select_set(True)
        context.view_layer.objects.active = tmp
        scene.cycles.bake_type = 'EMIT'
        bpy.ops.object.bake(type='EMIT', margin=MARGIN, use_clear=True)
        import numpy as np
        from . import native
        px = np.empty(req.resolution * req.resolution * 4, np.float32)
        img.pixels.foreach_get(px)
        os.makedirs(textures.CACHE_DIR, exist_ok=True)
        # Blender's rows run bottom-up; the file's top row first.
        native.facet.write_image(px.reshape(req.resolution, req.resolution, 4)[::-1, :, :3]
                                 .copy(), req.path)
    finally:
        bpy.data.objects.remove(tmp)
        bpy.data.meshes.remove(me)
        bpy.data.materials.remove(tmp_mat)
        bpy.data.images.remove(img)


def _output_name(mat):
    from . import nodegraph
    return nodegraph.active_output(mat.node_tree, 'ShaderNodeOutputMaterial').name
