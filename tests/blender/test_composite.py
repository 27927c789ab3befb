"""Math, Vector Math, Mix RGB / Mix and ColorRamp nodes between textures, and the Brick Texture,
converted natively (facet_blender/textures.py -> the core's math, vector_math, mix_rgb,
color_ramp and brick kinds, FORMAT.md "Composite kinds"): evaluated per hit, no bake.

1. Exported data: each quad's emission converts to the kinds, nested as the node tree nests
   them, with no report and no bake; a ColorRamp in HSV mode becomes Cycles' 256-entry table as
   stops; a colour into a number input is its luminance (reported: Facet's weights); the Mix
   node's Vector mode is the mix of its vectors as colours (a Non-Uniform factor: one factor
   per component, mix_rgb's fac_color); a Brick's Color1 / Mortar fed by
   textures become the brick's texture inputs (its Fac output exports none); Vector Math of
   textures becomes vector_math (Vector output into a colour, Value output into a ramp's Fac),
   and a Vector Math vector into a number input stays reported.
2. Renders against Cycles, as tests/blender/test_procedural.py does: strips of emission quads
   (the Vector Math ones a second strip), one node per quad, orthographic camera, box filter
   1 px, 16 spp in both renderers.
   Criterion (issue 35): per quad, mean |Facet - Cycles| <= 1e-3 of Cycles' range over the quad.
   Controls that must fail it: the input's own constant (what the addon rendered before: the
   Emission Color's white), and the first ramp with its middle stop moved by 0.02.
"""
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

SPP = 16
PX = 96  # pixels per quad side
new_material = bt.new_material


def node(nt, idname, props=None, inputs=None):
    n = nt.nodes.new(idname)
    for k, v in (props or {}).items():
        setattr(n, k, v)
    for k, v in (inputs or {}).items():
        next(s for s in n.inputs if s.identifier == k or s.name == k).default_value = v
    return n


def noise(nt, scale=3.0, detail=2.0):
    return node(nt, "ShaderNodeTexNoise", {},
                {"Scale": scale, "Detail": detail, "Roughness": 0.5, "Distortion": 0.0})


def ramp(nt, interp, fac, stops=((0.25, (0.9, 0.1, 0.05, 1.0)), (0.5, (0.1, 0.8, 0.3, 0.6)),
                                 (0.7, (0.05, 0.2, 0.9, 0.2))), mode='RGB'):
    r = node(nt, "ShaderNodeValToRGB")
    cr = r.color_ramp
    cr.interpolation = interp
    cr.color_mode = mode
    els = cr.elements
    els[0].position, els[0].color = stops[0]
    els[1].position, els[1].color = stops[1]
    for pos, col in stops[2:]:
        e = els.new(pos)
        e.color = col
    nt.links.new(fac, r.inputs["Fac"])
    return r


def math_node(nt, op, a, b=None, c=None, clamp=False):
    m = node(nt, "ShaderNodeMath", {"operation": op, "use_clamp": clamp})
    for sock, v in zip(m.inputs, (a, b, c)):
        if v is None:
            continue
        if isinstance(v, float):
            sock.default_value = v
        else:
            nt.links.new(v, sock)
    return m


def mix_rgb(nt, blend, fac, c1, c2, clamp=False):
    m = node(nt, "ShaderNodeMixRGB", {"blend_type": blend, "use_clamp": clamp})
    for sock, v in zip(m.inputs, (fac, c1, c2)):
        if isinstance(v, (float, tuple)):
            sock.default_value = v
        else:
            nt.links.new(v, sock)
    return m


def mix_node(nt, data_type, blend, fac, a, b, clamp_factor=True, clamp_result=False):
    m = node(nt, "ShaderNodeMix", {"data_type": data_type, "blend_type": blend,
                                   "clamp_factor": clamp_factor, "clamp_result": clamp_result})
    suffix = {'RGBA': "Color", 'FLOAT': "Float", 'VECTOR': "Vector"}[data_type]
    for ident, v in (("Factor_Float", fac), ("A_" + suffix, a), ("B_" + suffix, b)):
        sock = next(s for s in m.inputs if s.identifier == ident)
        if isinstance(v, (float, tuple)):
            sock.default_value = v
        else:
            nt.links.new(v, sock)
    return next(s for s in m.outputs if s.identifier == "Result_" + suffix)


def vector_math(nt, op, a, b=None, c=None, scale=None, output="Vector"):
    m = node(nt, "ShaderNodeVectorMath", {"operation": op})
    for ident, v in (("Vector", a), ("Vector_001", b), ("Vector_002", c), ("Scale", scale)):
        if v is None:
            continue
        sock = next(x for x in m.inputs if x.identifier == ident)
        if isinstance(v, (float, tuple)):
            sock.default_value = v
        else:
            nt.links.new(v, sock)
    return m.outputs[output]


def brick(nt):
    # Turned by 0.5 rad through a Mapping (its matrix reaches the brick kind). Large bricks
    # with smooth mortar: where a value changes fast across a pixel, 16 samples of it differ
    # by Cycles' own noise (measured with Scale 2, Mortar Size 0.03, Mortar Smooth 0.3:
    # 2.8e-3 of the range at 16 spp, 3.4e-4 at 128 spp, shrinking with the samples).
    tc = nt.nodes.new("ShaderNodeTexCoord")
    m = node(nt, "ShaderNodeMapping", {}, {"Rotation": (0.0, 0.0, 0.5)})
    nt.links.new(tc.outputs["Generated"], m.inputs["Vector"])
    b = node(nt, "ShaderNodeTexBrick",
                {"offset": 0.4, "offset_frequency": 2, "squash": 1.3, "squash_frequency": 3},
                {"Scale": 0.6, "Mortar Size": 0.12, "Mortar Smooth": 1.0, "Bias": 0.1,
                 "Brick Width": 0.6, "Row Height": 0.3, "Color1": (0.8, 0.3, 0.1, 1.0),
                 "Color2": (0.3, 0.5, 0.8, 1.0), "Mortar": (0.9, 0.9, 0.85, 1.0)})
    nt.links.new(m.outputs["Vector"], b.inputs["Vector"])
    return b


def brick_textured(nt):
    # Color1 a noise's colour, Mortar a gradient's Fac (a number into a colour: grey), Color2
    # constant: the core's brick evaluates its colour inputs at the same hit.
    b = brick(nt)
    nt.links.new(noise(nt, 2.0).outputs["Color"], b.inputs["Color1"])
    nt.links.new(gradient(nt).outputs["Fac"], b.inputs["Mortar"])
    return b


def gradient(nt):
    return node(nt, "ShaderNodeTexGradient", {"gradient_type": 'LINEAR'})


def mix_non_uniform(nt):
    # The Mix node's Vector mode with a Non-Uniform factor that differs per component: a
    # noise's colour (its three channels differ) mixes a gradient-fed ramp and a constant.
    out = mix_node(nt, 'VECTOR', 'MIX', 0.5,
                   ramp(nt, 'LINEAR', gradient(nt).outputs["Fac"]).outputs["Color"],
                   (0.9, 0.2, 0.4))
    m = out.node
    m.factor_mode = 'NON_UNIFORM'
    nt.links.new(noise(nt, 3.5).outputs["Color"],
                 next(x for x in m.inputs if x.identifier == "Factor_Vector"))
    return out


# (name, builder(nt) -> output socket): one quad each.
QUADS = [
    ("ramp_linear", lambda nt: ramp(nt, 'LINEAR', noise(nt).outputs["Fac"]).outputs["Color"]),
    ("ramp_ease", lambda nt: ramp(nt, 'EASE', noise(nt).outputs["Fac"]).outputs["Color"]),
    ("ramp_cardinal",
     lambda nt: ramp(nt, 'CARDINAL', noise(nt).outputs["Fac"]).outputs["Color"]),
    ("ramp_b_spline",
     lambda nt: ramp(nt, 'B_SPLINE', noise(nt).outputs["Fac"]).outputs["Color"]),
    ("ramp_constant",
     lambda nt: ramp(nt, 'CONSTANT', noise(nt, 1.0, 0.0).outputs["Fac"]).outputs["Color"]),
    ("ramp_hsv_alpha",
     lambda nt: ramp(nt, 'LINEAR', gradient(nt).outputs["Fac"], mode='HSV').outputs["Alpha"]),
    ("ramp_hsl", lambda nt: ramp(nt, 'LINEAR', gradient(nt).outputs["Fac"],
                                 mode='HSL').outputs["Color"]),
    ("math_power_clamp",
     lambda nt: math_node(nt, 'POWER', math_node(nt, 'MULTIPLY', noise(nt).outputs["Fac"],
                                                 1.6).outputs[0], 2.5, clamp=True).outputs[0]),
    ("math_product",
     lambda nt: math_node(nt, 'MULTIPLY', noise(nt).outputs["Fac"],
                          gradient(nt).outputs["Fac"]).outputs[0]),
    ("math_sine",
     lambda nt: math_node(nt, 'MULTIPLY_ADD', math_node(nt, 'SINE', math_node(
         nt, 'MULTIPLY', noise(nt).outputs["Fac"], 12.0).outputs[0]).outputs[0], 0.5,
         0.5).outputs[0]),
    ("math_smooth_max",
     lambda nt: math_node(nt, 'SMOOTH_MAX', noise(nt).outputs["Fac"],
                          gradient(nt).outputs["Fac"], 0.3).outputs[0]),
    ("mix_overlay",
     lambda nt: mix_rgb(nt, 'OVERLAY', noise(nt, 2.0).outputs["Fac"],
                        noise(nt, 5.0).outputs["Color"], (0.2, 0.6, 0.9, 1.0)).outputs[0]),
    ("mix_hue",
     lambda nt: mix_rgb(nt, 'HUE', 0.8, noise(nt, 4.0).outputs["Color"],
                        ramp(nt, 'LINEAR', gradient(nt).outputs["Fac"]).outputs["Color"])
     .outputs[0]),
    ("mix_multiply_clamped",
     lambda nt: mix_rgb(nt, 'MULTIPLY', gradient(nt).outputs["Fac"], (1.6, 0.7, 0.4, 1.0),
                        noise(nt).outputs["Color"], clamp=True).outputs[0]),
    ("mix_node_soft_light",
     lambda nt: mix_node(nt, 'RGBA', 'SOFT_LIGHT', noise(nt, 2.5).outputs["Fac"],
                         noise(nt, 6.0).outputs["Color"], (0.9, 0.3, 0.5, 1.0))),
    ("mix_node_float",
     lambda nt: mix_node(nt, 'FLOAT', 'MIX', gradient(nt).outputs["Fac"],
                         noise(nt, 2.0).outputs["Fac"], noise(nt, 4.0).outputs["Fac"])),
    # A colour into a number input (the ramp's Fac): its luminance (reported: Facet's weights).
    ("ramp_of_mix_luminance",
     lambda nt: ramp(nt, 'LINEAR', mix_rgb(nt, 'MIX', gradient(nt).outputs["Fac"],
                                           noise(nt, 2.0).outputs["Color"],
                                           (0.9, 0.2, 0.1, 1.0)).outputs[0]).outputs["Color"]),
    ("brick_color", lambda nt: brick(nt).outputs["Color"]),
    ("brick_fac", lambda nt: brick(nt).outputs["Fac"]),
    ("brick_textured_colours", lambda nt: brick_textured(nt).outputs["Color"]),
    # The Mix node's Vector mode between a noise's colour and a constant vector, its factor a
    # gradient (a colour through vector sockets: the components unchanged).
    ("mix_node_vector",
     lambda nt: mix_node(nt, 'VECTOR', 'MIX', gradient(nt).outputs["Fac"],
                         noise(nt, 2.0).outputs["Color"], (0.9, 0.2, 0.4))),
    ("mix_node_vector_non_uniform", mix_non_uniform),
    # The Fac output reads no colour: the textures on Color1 and Mortar are not exported.
    ("brick_textured_fac", lambda nt: brick_textured(nt).outputs["Fac"]),
]

# Vector Math, rendered as a second strip (the first strip's Generated x spans its own quads:
# its quads' values are set for that strip's length).
VECTOR_QUADS = [
    # Vector Math of textures: a noise's colour scaled; |(a - 1/2) x b| of two noise colours
    # (a centred: two colours near grey are nearly parallel, their product small); a dot
    # product (Value output) into a ramp's Fac; a normalised colour; a wrapped scaled colour;
    # the length of a colour (Value output into the colour: grey).
    ("vmath_scale",
     lambda nt: vector_math(nt, 'SCALE', noise(nt, 2.0).outputs["Color"], scale=0.8)),
    ("vmath_cross_abs",
     lambda nt: vector_math(nt, 'ABSOLUTE', vector_math(
         nt, 'CROSS_PRODUCT', vector_math(nt, 'SUBTRACT', noise(nt, 2.0).outputs["Color"],
                                          (0.5, 0.5, 0.5)),
         noise(nt, 3.0).outputs["Color"]))),
    ("vmath_dot_ramp",
     lambda nt: ramp(nt, 'LINEAR', vector_math(nt, 'DOT_PRODUCT', noise(nt, 3.0).outputs["Color"],
                                               (0.5, 0.3, 0.2), output="Value"))
     .outputs["Color"]),
    ("vmath_normalize",
     lambda nt: vector_math(nt, 'NORMALIZE', noise(nt, 2.5).outputs["Color"])),
    ("vmath_wrap",
     lambda nt: vector_math(nt, 'WRAP', vector_math(
         nt, 'SCALE', noise(nt, 1.0, 0.0).outputs["Color"], scale=2.0), (0.9, 0.85, 0.8),
         (0.1, 0.15, 0.2))),
    ("vmath_length",
     lambda nt: vector_math(nt, 'LENGTH', vector_math(
         nt, 'SUBTRACT', noise(nt, 2.0).outputs["Color"], gradient(nt).outputs["Fac"]),
         output="Value")),
]


def strip_scene(builders):
    bpy.ops.wm.read_homefile(use_factory_startup=True)
    scene = bpy.context.scene
    for ob in list(scene.objects):
        bpy.data.objects.remove(ob)
    n = len(builders)
    verts, faces = [], []
    for i in range(n):
        verts += [(i, 0, 0), (i + 1, 0, 0), (i + 1, 1, 0), (i, 1, 0)]
        faces.append((4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3))
    me = bpy.data.meshes.new("strip")
    me.from_pydata(verts, [], faces)
    uv = me.uv_layers.new(name="UVMap")
    for i in range(len(me.loops)):
        uv.data[i].uv = [(0, 0), (1, 0), (1, 1), (0, 1)][i % 4]
    ob = bpy.data.objects.new("strip", me)
    scene.collection.objects.link(ob)
    # Generated coordinates over the whole strip: x in [0, 1] across it.
    bt.ortho_camera(scene, n, (n / 2.0, 0.5, 5.0))
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    for i, (name, build) in enumerate(builders):
        mat, nt, out = new_material("comp_" + name)
        e = nt.nodes.new("ShaderNodeEmission")
        nt.links.new(build(nt), e.inputs["Color"])
        nt.links.new(e.outputs[0], out.inputs["Surface"])
        me.materials.append(mat)
        me.polygons[i].material_index = i
    scene.render.resolution_x, scene.render.resolution_y = PX * n, PX
    scene.render.resolution_percentage = 100
    scene.facet.spp = SPP
    scene.facet.max_depth = 1
    cs.cycles_settings(scene, samples=SPP, seed=1, max_depth=1)
    return scene, me


def not_luminance(problems):
    """The report lines other than the luminance notes (a colour into a number input)."""
    return [p for p in problems if "luminance" not in p]


def kinds_of(t, found):
    """The texture kinds of a (nested) texture dict."""
    for k, v in t.items():
        if isinstance(v, dict) and k != "mapping":
            found.add(k)
            for x in v.values():
                if isinstance(x, dict):
                    kinds_of(x, found)
    return found


def exported():
    from facet_blender import materials
    scene, me = strip_scene(QUADS + VECTOR_QUADS)
    ob = bpy.data.objects["strip"]
    for mat in me.materials:
        c = materials.convert(mat, ob)
        em = c.emission
        bt.check(isinstance(em, dict) and not c.baked and not not_luminance(c.problems),
                 "%s converts natively: %.300s, problems %s" % (mat.name, em, c.problems))
    c = materials.convert(bpy.data.materials["comp_ramp_of_mix_luminance"], ob)
    bt.check(c.emission["color_ramp"]["fac"].get("channel") == "luminance"
             and len(c.problems) == 1 and "luminance" in c.problems[0],
             "a Mix's colour into a ramp's Fac: its luminance, reported: %s" % c.problems)
    em = materials.convert(bpy.data.materials["comp_ramp_linear"], ob).emission
    bt.check(em["color_ramp"]["interpolation"] == "linear"
             and len(em["color_ramp"]["stops"]) == 3
             and "noise" in em["color_ramp"]["fac"], "ramp of a noise: %s" % em)
    em = materials.convert(bpy.data.materials["comp_ramp_hsv_alpha"], ob).emission
    bt.check(len(em["color_ramp"]["stops"]) == 256 and em["color_ramp"]["output"] == "alpha",
             "an HSV ramp is Cycles' table: %d stops" % len(em["color_ramp"]["stops"]))
    em = materials.convert(bpy.data.materials["comp_math_sine"], ob).emission
    bt.check(kinds_of(em, set()) == {"math", "noise"} and em["math"]["operation"] ==
             "multiply_add", "nested Math chain: %s" % em)
    em = materials.convert(bpy.data.materials["comp_brick_textured_colours"], ob).emission
    bt.check("noise" in em["brick"]["color1"] and "gradient" in em["brick"]["mortar"]
             and isinstance(em["brick"]["color2"], list),
             "Brick Color1 / Mortar textures -> the brick's inputs: %.300s" % em)
    em = materials.convert(bpy.data.materials["comp_brick_textured_fac"], ob).emission
    bt.check(not any(k in em["brick"] for k in ("color1", "color2", "mortar")),
             "Brick Fac: no colours exported: %.300s" % em)
    em = materials.convert(bpy.data.materials["comp_mix_node_float"], ob).emission
    bt.check(em["mix_rgb"]["blend_type"] == "mix", "Mix (Float) -> mix_rgb: %s" % em)
    c = materials.convert(bpy.data.materials["comp_math_product"], ob)
    bt.check(c.generated, "a nested Generated input exports the texture space")
    # Reported by name: a Mix's colour into a number input (a Principled Roughness).
    mat, nt, out = new_material("comp_reported")
    p = nt.nodes.new("ShaderNodeBsdfPrincipled")
    m = mix_rgb(nt, 'MIX', 0.5, noise(nt).outputs["Color"], (0.2, 0.2, 0.2, 1.0))
    nt.links.new(m.outputs[0], p.inputs["Metallic"])
    nt.links.new(p.outputs[0], out.inputs["Surface"])
    c = materials.convert(mat)
    bt.check(c.data["metallic"]["channel"] == "luminance"
             and any("Mix" in x and "Metallic" in x and "luminance" in x for x in c.problems),
             "a Mix's colour into Metallic: its luminance, reported: %s" % c.problems)
    # Vector Math -> vector_math, nested; the Value output into a ramp's Fac.
    em = materials.convert(bpy.data.materials["comp_vmath_cross_abs"], ob).emission
    bt.check(em["vector_math"]["operation"] == "absolute"
             and em["vector_math"]["a"]["vector_math"]["operation"] == "cross_product"
             and em["vector_math"]["a"]["vector_math"]["a"]["vector_math"]["operation"]
             == "subtract"
             and kinds_of(em, set()) == {"vector_math", "noise"},
             "Vector Math Absolute of a Cross Product: %.300s" % em)
    em = materials.convert(bpy.data.materials["comp_vmath_dot_ramp"], ob).emission
    fac = em["color_ramp"]["fac"]["vector_math"]
    bt.check(fac["operation"] == "dot_product" and fac["output"] == "value"
             and all(abs(x - y) < 1e-6 for x, y in zip(fac["b"], (0.5, 0.3, 0.2))),
             "Vector Math Dot Product into a ramp's Fac: %.300s" % em)
    # Still reported: a Vector Math vector into a number input (Cycles' mean of the
    # components), and Vector Math of texture coordinates into a colour.
    mat, nt, out = new_material("comp_vmath_reported")
    p = nt.nodes.new("ShaderNodeBsdfPrincipled")
    nt.links.new(vector_math(nt, 'SCALE', noise(nt).outputs["Color"], scale=0.5),
                 p.inputs["Metallic"])
    tc = nt.nodes.new("ShaderNodeTexCoord")
    nt.links.new(vector_math(nt, 'NORMALIZE', tc.outputs["Object"]), p.inputs["Base Color"])
    nt.links.new(p.outputs[0], out.inputs["Surface"])
    c = materials.convert(mat)
    bt.check(any("Metallic" in x for x in c.problems)
             and any("Base Color" in x for x in c.problems),
             "a Vector Math vector into Metallic and of coordinates: reported: %s" % c.problems)
    # The Mix node's Vector mode -> mix_rgb's mix.
    em = materials.convert(bpy.data.materials["comp_mix_node_vector"], ob).emission
    bt.check(em["mix_rgb"]["blend_type"] == "mix" and "noise" in em["mix_rgb"]["color1"]
             and "gradient" in em["mix_rgb"]["fac"], "Mix (Vector) -> mix_rgb: %.300s" % em)
    # A Non-Uniform factor: mix_rgb's fac_color, the noise's colour.
    em = materials.convert(bpy.data.materials["comp_mix_node_vector_non_uniform"], ob).emission
    bt.check(em["mix_rgb"]["blend_type"] == "mix" and "fac" not in em["mix_rgb"]
             and "noise" in em["mix_rgb"]["fac_color"],
             "Mix (Vector, Non-Uniform) -> mix_rgb with fac_color: %.300s" % em)


def rendered(outdir, quads=QUADS, tag="composite"):
    """The strip `quads` in both renderers against the criterion; returns (scene, mesh, the
    Cycles image)."""
    scene, me = strip_scene(quads)
    a, _ = cs.render(scene, 'FACET', os.path.join(outdir, tag + "_facet.exr"), seed=1)
    from facet_blender import hooks
    problems = list(hooks.last_problems)
    bt.check(not_luminance(problems) == [],
             "the strip converts without a report (but the luminance note): %s" % problems)
    b, _ = cs.render(scene, 'CYCLES', os.path.join(outdir, tag + "_cycles.exr"), seed=1)
    # The seed-to-seed floor (Facet seed 2 against seed 1), printed for each quad.
    a2, _ = cs.render(scene, 'FACET', os.path.join(outdir, tag + "_facet2.exr"), seed=2)
    failed = []
    for i, (name, _) in enumerate(quads):
        qa, qb = a[:, PX * i:PX * (i + 1)], b[:, PX * i:PX * (i + 1)]
        rng = max(float(qb.max() - qb.min()), 1e-3)
        d = float(np.abs(qa - qb).mean())
        floor = float(np.abs(qa - a2[:, PX * i:PX * (i + 1)]).mean())
        white = float(np.abs(1.0 - qb).mean())  # the control: the input's own white
        print("%-24s mean |Facet - Cycles| %.3g = %.3g of the range %.3g (seed floor %.3g); "
              "control %.3g" % (name, d, d / rng, rng, floor / rng, white / rng))
        if not d <= 1e-3 * rng:
            failed.append("%s: %.3g > 1e-3 x range %.3g" % (name, d, rng))
        bt.check(white > 1e-3 * rng, "control %s: the constant fails (%.3g)" % (name, white))
    bt.check(not failed, "quads within 1e-3 of the range: " + "; ".join(failed))
    return scene, me, b


def moved_stop(outdir, scene, me, b):
    """Control: the first ramp's middle stop moved by 0.02 must fail the criterion."""
    nt = me.materials[0].node_tree
    r = next(x for x in nt.nodes if x.bl_idname == 'ShaderNodeValToRGB')
    r.color_ramp.elements[1].position += 0.02
    scene.render.use_border = True
    scene.render.use_crop_to_border = True
    n = len(QUADS)
    scene.render.border_min_x, scene.render.border_max_x = 0.0, 1.0 / n
    scene.render.border_min_y, scene.render.border_max_y = 0.0, 1.0
    c, _ = cs.render(scene, 'FACET', os.path.join(outdir, "composite_control.exr"), seed=1)
    bt.check(c.shape[1] == PX, "the control renders quad 0 alone (%s)" % (c.shape,))
    qb = b[:, :PX]
    d = float(np.abs(c - qb).mean())
    rng = float(qb.max() - qb.min())
    print("control stop moved by 0.02: %.3g of the range" % (d / rng))
    bt.check(d > 1e-3 * rng, "a moved stop fails the criterion (%.3g)" % (d / rng))


def main():
    bt.enable_addon()
    outdir = bt.args()[0]
    exported()
    moved_stop(outdir, *rendered(outdir))
    rendered(outdir, VECTOR_QUADS, "composite_vector_math")


bt.run(main)
