"""Colour attributes and the Color Attribute node (facet_blender/textures.py, export.py) in
headless Blender:

1. Export: a Color Attribute node naming a float corner attribute becomes the texture
   {"vertex_color": true} and the mesh's `colors` are the attribute's values per loop, bit for
   bit (foreach_get); an empty name reads the mesh's default colour attribute (here bytes on
   points: Blender's decoded linear `color`, one per vertex); the Alpha output is channel
   "a", the Color output into a number input (Principled Roughness) channel "luminance"
   (reported, as for images); a missing attribute exports black with alpha 0 (Cycles' value)
   and is reported; float colours outside [0, 1] are clamped and reported; a Color Attribute
   into a Bump's Height is reported, not passed to the core (which refuses it).
2. Render against Cycles: three emitting planes seen from above by an orthographic camera
   (a float corner attribute, the default byte point attribute, and the alpha of the float
   one), strongly different colours per corner. Emission only, no bounces: each pixel is the
   mean of the interpolated colour over the pixel, which both renderers estimate with the
   same 64 samples per pixel; the colour changes by ~1/20 of its range across a pixel, so
   the per-pixel noise is < 0.003. Tolerance: mean |Facet - Cycles| < 0.004 over the planes'
   pixels and every pixel within 0.03. Ability to fail: Cycles interpolates the byte colours
   after decoding each corner (linear); interpolating the encoded values and decoding after
   would differ by the amount the test computes from the corner colours (0.085 on the byte
   plane, so ~0.028 over the three planes: asserted > 3x the tolerance), and a constant colour
   per plane by far more.
"""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

SPP = 64
RES = (120, 40)
RNG = np.random.default_rng(7)


def grid_plane(name, x, n=2):
    """An n x n quad grid of side 1.8 centred at (x, 0, 0), normal +Z, flat."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=n, y_subdivisions=n, size=1.8,
                                    location=(x, 0.0, 0.0))
    ob = bpy.context.object
    ob.name = name
    return ob


def emission_material(name, layer, output="Color"):
    mat, nt, out = bt.new_material(name)
    ca = nt.nodes.new("ShaderNodeVertexColor")
    ca.layer_name = layer
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 1.0
    nt.links.new(ca.outputs[output], em.inputs["Color"])
    nt.links.new(em.outputs[0], out.inputs["Surface"])
    return mat


def srgb_to_linear(c):
    c = np.asarray(c, np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def build_scene():
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = 'FACET'
    scene.render.resolution_x, scene.render.resolution_y = RES
    scene.render.resolution_percentage = 100
    world = bpy.data.worlds.new("black")
    world.use_nodes = False
    world.color = (0.0, 0.0, 0.0)
    scene.world = world
    bt.ortho_camera(scene, 6.0, (0.0, 0.0, 5.0))
    # A: float colours per corner, by name
    a = grid_plane("corner_plane", -2.0)
    fa = a.data.color_attributes.new("corner_cols", 'FLOAT_COLOR', 'CORNER')
    cols = RNG.uniform(0.0, 1.0, (len(a.data.loops), 4)).astype(np.float32)
    fa.data.foreach_set("color", cols.ravel())
    a.data.materials.append(emission_material("corner", "corner_cols"))
    # B: bytes per point, the default colour attribute (empty layer name), strongly different
    # neighbours (0 or 1 per channel) so that decoding before or after interpolating differs
    b = grid_plane("byte_plane", 0.0)
    fb = b.data.color_attributes.new("byte_pts", 'BYTE_COLOR', 'POINT')
    bcols = np.ones((len(b.data.vertices), 4), np.float32)
    bcols[:, :3] = RNG.integers(0, 2, (len(b.data.vertices), 3))
    bcols[len(bcols) // 2, :3] = 0.5  # one encoded mid value
    fb.data.foreach_set("color_srgb", bcols.ravel())
    b.data.color_attributes.active_color = fb
    b.data.color_attributes.render_color_index = list(b.data.color_attributes).index(fb)
    b.data.materials.append(emission_material("default", ""))
    # C: the float corner attribute's alpha
    c = grid_plane("alpha_plane", 2.0)
    fc = c.data.color_attributes.new("corner_cols", 'FLOAT_COLOR', 'CORNER')
    fc.data.foreach_set("color", cols[:len(c.data.loops)].ravel())
    c.data.materials.append(emission_material("alpha", "corner_cols", "Alpha"))
    return scene, cols, bcols


def shape(data, name):
    return next(s for s in data["shapes"] if s.get("name") == name)


def check_export(scene, cols, bcols):
    from facet_blender import export
    dg = bpy.context.evaluated_depsgraph_get()
    data, problems = export.export_scene(dg, mesh_cache={})
    mats = dict(data["materials"])
    bt.check(not problems, "no report for exact colour attributes (%s)" % problems)
    sa = shape(data, "corner_plane")
    bt.check(sa["emission"] == {"vertex_color": True}, "Color output -> vertex_color texture "
             "as the emission (%s)" % sa["emission"])
    bt.check(np.array_equal(np.asarray(sa["colors"]), cols),
             "float corner colours exported per loop, bit for bit")
    sb = shape(data, "byte_plane")
    me = bpy.data.objects["byte_plane"].data
    dec = np.empty(len(me.vertices) * 4, np.float32)
    me.color_attributes["byte_pts"].data.foreach_get("color", dec)
    bt.check(len(sb["colors"]) == len(me.vertices) and
             np.array_equal(np.asarray(sb["colors"]), dec.reshape(-1, 4)),
             "default (empty name) byte point attribute: Blender's decoded colours per vertex")
    bt.check(np.allclose(dec.reshape(-1, 4)[:, :3], srgb_to_linear(bcols[:, :3]), atol=2e-3),
             "byte colours are exported decoded (linear)")
    sc = shape(data, "alpha_plane")
    bt.check(sc["emission"] == {"vertex_color": True, "channel": "a"},
             "Alpha output -> channel a (%s)" % sc["emission"])
    bt.check(mats["alpha"]["model"] == "lambert" and mats["corner"]["model"] == "lambert",
             "emission materials are black lambert")
    return data


def check_reports():
    """Missing attribute, out-of-range values, colour into a number input, into a Bump."""
    from facet_blender import export
    ob = bpy.data.objects["corner_plane"]
    # Roughness from the colour (luminance), Bump from it (reported), on a Principled BSDF.
    mat, nt, out = bt.new_material("rough")
    p = nt.nodes.new("ShaderNodeBsdfPrincipled")
    ca = nt.nodes.new("ShaderNodeVertexColor")
    ca.layer_name = "corner_cols"
    bump = nt.nodes.new("ShaderNodeBump")
    nt.links.new(ca.outputs["Color"], p.inputs["Roughness"])
    nt.links.new(ca.outputs["Color"], bump.inputs["Height"])
    nt.links.new(bump.outputs["Normal"], p.inputs["Normal"])
    nt.links.new(p.outputs[0], out.inputs["Surface"])
    ob.data.materials[0] = mat
    missing = bpy.data.objects["byte_plane"]
    mat2 = emission_material("missing", "no_such_layer")
    missing.data.materials[0] = mat2
    attr = bpy.data.objects["alpha_plane"].data.color_attributes["corner_cols"]
    vals = np.empty(len(attr.data) * 4, np.float32)
    attr.data.foreach_get("color", vals)
    vals[0], vals[5] = 1.5, -0.25
    attr.data.foreach_set("color", vals)
    bpy.data.objects["alpha_plane"].data.update()
    dg = bpy.context.evaluated_depsgraph_get()
    data, problems = export.export_scene(dg, mesh_cache={})
    mats = dict(data["materials"])
    r = mats["rough"]["roughness"]
    bt.check(r == {"vertex_color": True, "channel": "luminance"},
             "Color into Roughness -> channel luminance (%s)" % r)
    bt.check("bump" not in mats["rough"], "a Color Attribute Height is not given to the core")
    text = "\n".join(problems)
    bt.check("Bump" in text and "Color Attribute as its Height" in text,
             "the Bump of a colour attribute is reported")
    bt.check("Facet's luminance" in text, "the luminance weights are reported")
    bt.check("colour attribute 'no_such_layer', which the mesh does not have" in text,
             "a missing attribute is reported")
    sb = shape(data, "byte_plane")
    bt.check(not np.asarray(sb["colors"]).any(), "a missing attribute exports black, alpha 0")
    bt.check("2 values outside [0, 1] (-0.25 to 1.5) clamped" in text,
             "out-of-range float colours are clamped and reported (%s)" % text)
    sc = shape(data, "alpha_plane")
    c = np.asarray(sc["colors"])
    bt.check(c.min() >= 0.0 and c.max() <= 1.0, "clamped colours are in [0, 1]")
    from facet_blender import native
    native.build(data)  # the core accepts all of it
    bt.check(True, "the core builds the exported scene")


def sample_wrong_byte_difference(bcols):
    """Mean |decode(interp(encoded)) - interp(decode(encoded))| over the byte plane's
    triangles (a fine barycentric grid over Blender's quad split): what interpolating the
    encoded bytes would change."""
    ob = bpy.data.objects["byte_plane"]
    me = ob.data
    me.calc_loop_triangles()
    tri = np.empty(len(me.loop_triangles) * 3, np.int32)
    me.loop_triangles.foreach_get("vertices", tri)
    tri = tri.reshape(-1, 3)
    enc = bcols[:, :3].astype(np.float64)
    g = np.linspace(0, 1, 21)
    b1, b2 = np.meshgrid(g, g)
    keep = b1 + b2 <= 1
    b1, b2 = b1[keep], b2[keep]
    b0 = 1 - b1 - b2
    diffs = []
    for t in tri:
        e = b0[:, None] * enc[t[0]] + b1[:, None] * enc[t[1]] + b2[:, None] * enc[t[2]]
        lin = (b0[:, None] * srgb_to_linear(enc[t[0]]) + b1[:, None] * srgb_to_linear(enc[t[1]])
               + b2[:, None] * srgb_to_linear(enc[t[2]]))
        diffs.append(np.abs(srgb_to_linear(e) - lin).mean())
    return float(np.mean(diffs))


def check_render(scene, bcols, out):
    cs.cycles_settings(scene, samples=SPP, seed=1, max_depth=1)
    scene.facet.spp = SPP
    scene.facet.max_depth = 1
    f, _ = cs.render(scene, 'FACET', os.path.join(out, "vertex_colours_facet.exr"), 1)
    c, _ = cs.render(scene, 'CYCLES', os.path.join(out, "vertex_colours_cycles.exr"), 1)
    lit = (f.max(axis=2) > 0) | (c.max(axis=2) > 0)
    # The planes' pixels, their borders excluded (a pixel straddling a plane's edge is part
    # black, with sample noise of up to half its value).
    inner = lit.copy()
    for axis in (0, 1):
        for shift in (1, -1):
            inner &= np.roll(lit, shift, axis=axis)
    d = np.abs(f - c)[inner]
    mean, worst = float(d.mean()), float(d.max())
    wrong = sample_wrong_byte_difference(bcols)
    print("vertex colours vs Cycles: %d pixels, mean |diff| %.5f, max %.5f; interpolating the "
          "encoded bytes would differ by %.4f on the byte plane" % (inner.sum(), mean, worst,
                                                                    wrong))
    bt.check(inner.sum() > 0.5 * RES[0] * RES[1] * 0.2, "the planes fill the view")
    bt.check(mean < 0.004, "mean |Facet - Cycles| %.5f < 0.004" % mean)
    bt.check(worst < 0.03, "every pixel within 0.03 (max %.5f)" % worst)
    # The byte plane is a third of the measured pixels.
    bt.check(wrong / 3 > 3 * 0.004, "the wrong interpolation order would fail the test (%.4f "
             "on the byte plane, %.4f over the three)" % (wrong, wrong / 3))


def main():
    bt.enable_addon()
    out = bt.args()[0] if bt.args() else "/tmp"
    scene, cols, bcols = build_scene()
    check_export(scene, cols, bcols)
    check_render(scene, bcols, out)
    check_reports()


bt.run(main)
