"""The node-graph walker (facet_blender/nodegraph.py), constant folding (nodevalues.py) and
the report of what is not converted (gaps.py), in headless Blender:

1. Structure: a Principled BSDF reached through reroutes and a node group, its inputs fed
   through reroutes, a nested node group (Group Input/Output mapped through), a muted node and
   constant Math / Mix RGB chains -> the converted parameters equal the expected values
   exactly (inputs chosen exactly representable, so double and float32 agree).
2. Reports: a Geometry normal into Clearcoat Normal and an Image Texture without an image
   each give one line naming the material, the node and the input it feeds, and the rest (a
   Mix Shader, a Normal Map of the default colour) still converts; lamp settings the exporter
   ignores and a world texture are reported.
3. Against Cycles' own evaluation: a row of emission quads, each driven by one node chain
   (Math operations, Mix RGB / Mix blend modes, Invert, Gamma, Hue/Saturation/Value,
   Separate/Combine, Map Range, Bright/Contrast, Vector Math, link conversions colour -> float
   and vector -> float, a muted node with an unlinked input, an unconnected reroute, a muted
   group), rendered by Cycles at 1 spp with a
   1-px box filter: each pixel is the chain's value as Cycles evaluates it, and must equal the
   addon's folded value to 1e-6 relative (float32 evaluation; see the check).
"""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402


new_material = bt.new_material


def value_node(nt, v):
    n = nt.nodes.new("ShaderNodeValue")
    n.outputs[0].default_value = v
    return n.outputs[0]


def rgb_node(nt, c):
    n = nt.nodes.new("ShaderNodeRGB")
    n.outputs[0].default_value = tuple(c) + (1.0,)
    return n.outputs[0]


def math_node(nt, op, a, b=None, c=None, clamp=False):
    """Math node; a, b, c: a number (the input's value) or an output socket (linked)."""
    n = nt.nodes.new("ShaderNodeMath")
    n.operation = op
    n.use_clamp = clamp
    for i, x in enumerate((a, b, c)):
        if x is None:
            continue
        if isinstance(x, (int, float)):
            n.inputs[i].default_value = x
        else:
            nt.links.new(x, n.inputs[i])
    return n.outputs[0]


def mixrgb_node(nt, blend, fac, c1, c2, clamp=False):
    n = nt.nodes.new("ShaderNodeMixRGB")
    n.blend_type = blend
    n.use_clamp = clamp
    n.inputs["Fac"].default_value = fac
    for sock, c in ((n.inputs["Color1"], c1), (n.inputs["Color2"], c2)):
        if isinstance(c, tuple):
            sock.default_value = c + (1.0,)
        else:
            nt.links.new(c, sock)
    return n.outputs[0]


def reroute(nt, src):
    r = nt.nodes.new("NodeReroute")
    nt.links.new(src, r.inputs[0])
    return r.outputs[0]


def group_tree(name, in_type, out_type):
    g = bpy.data.node_groups.new(name, "ShaderNodeTree")
    g.inputs.new(in_type, "In")
    g.outputs.new(out_type, "Out")
    gi = g.nodes.new("NodeGroupInput")
    go = g.nodes.new("NodeGroupOutput")
    return g, gi, go


def group_node(nt, tree, src=None):
    n = nt.nodes.new("ShaderNodeGroup")
    n.node_tree = tree
    if src is not None:
        nt.links.new(src, n.inputs[0])
    return n


def structure():
    from facet_blender import materials
    mat, nt, out = new_material("walk")
    # Inner group: Out = In x (0.5, 0.25, 1) (Mix RGB Multiply, Fac 1).
    inner, gi, go = group_tree("inner", "NodeSocketColor", "NodeSocketColor")
    mul = mixrgb_node(inner, 'MULTIPLY', 1.0, (0.5, 0.25, 1.0), gi.outputs[0])
    inner.links.new(reroute(inner, mul), go.inputs[0])
    # Outer group: In -> reroute -> inner group -> reroute -> Out.
    outer, gi2, go2 = group_tree("outer", "NodeSocketColor", "NodeSocketColor")
    g_in = group_node(outer, inner, reroute(outer, gi2.outputs[0]))
    outer.links.new(reroute(outer, g_in.outputs[0]), go2.inputs[0])
    # Base Color = outer(RGB (0.5, 0.75, 0.5)) = (0.25, 0.1875, 0.5).
    base = group_node(nt, outer, rgb_node(nt, (0.5, 0.75, 0.5))).outputs[0]
    # Roughness = (0.25 + 0.25) via two reroutes -> alpha 0.25.
    rough = reroute(nt, reroute(nt, math_node(nt, 'ADD', value_node(nt, 0.25), 0.25)))
    # Metallic = a muted Multiply(0.5, 0) -> its first input passes: 0.5.
    muted = math_node(nt, 'MULTIPLY', value_node(nt, 0.5), 0.0)
    muted.node.mute = True
    # Specular = clamp(0.75 x 2) = 1 -> f0 dielectric part 0.08.
    spec = math_node(nt, 'MULTIPLY', 0.75, value_node(nt, 2.0), clamp=True)
    # Emission = Mix RGB Screen(0.5, (0.5, 0, 1), (0.5, 1, 0)) with Strength 2^2 = 4.
    emis = mixrgb_node(nt, 'SCREEN', 0.5, (0.5, 0.0, 1.0), (0.5, 1.0, 0.0))
    strength = math_node(nt, 'POWER', 2.0, 2.0)
    # The Principled BSDF inside a group of its own, reached through a reroute.
    shader_tree = bpy.data.node_groups.new("shader", "ShaderNodeTree")
    for t, name in (("NodeSocketColor", "Base"), ("NodeSocketFloat", "Rough"),
                    ("NodeSocketFloat", "Metal"), ("NodeSocketFloat", "Spec"),
                    ("NodeSocketColor", "Emis"), ("NodeSocketFloat", "Str")):
        shader_tree.inputs.new(t, name)
    shader_tree.outputs.new("NodeSocketShader", "BSDF")
    sgi = shader_tree.nodes.new("NodeGroupInput")
    sgo = shader_tree.nodes.new("NodeGroupOutput")
    p = shader_tree.nodes.new("ShaderNodeBsdfPrincipled")
    p.inputs["Specular Tint"].default_value = 0.0
    for i, name in enumerate(("Base Color", "Roughness", "Metallic", "Specular", "Emission",
                              "Emission Strength")):
        shader_tree.links.new(sgi.outputs[i], p.inputs[name])
    shader_tree.links.new(p.outputs[0], sgo.inputs[0])
    sg = nt.nodes.new("ShaderNodeGroup")
    sg.node_tree = shader_tree
    for i, src in enumerate((base, rough, muted, spec, emis, strength)):
        nt.links.new(src, sg.inputs[i])
    nt.links.new(reroute(nt, sg.outputs[0]), out.inputs["Surface"])
    bpy.context.view_layer.update()

    c = materials.convert(mat)
    want_base = [0.25, 0.1875, 0.5]
    want = {"base_color": want_base, "roughness": 0.5, "metallic": 0.5, "specular": 1.0,
            "specular_tint": 0.0}
    bt.check(c.data["model"] == "principled"
             and all(c.data[k] == v for k, v in want.items()),
             "through reroutes, nested groups, a muted node and constant "
             "chains: %s has %s" % (c.data, want))
    # Screen: 1 - (1 - t + t(1 - b))(1 - a), t = 0.5: (1 - 0.75 * 0.5, 1 - 0.5, 1) =
    # (0.625, 0.5, 1), x Strength 4.
    bt.check(c.emission == [2.5, 2.0, 4.0], "Mix RGB Screen x Math Power emission: %s"
             % c.emission)
    bt.check(c.problems == [], "nothing reported: %s" % c.problems)

    # The walker's view of the Principled BSDF's inputs: Base Color is the Mix RGB inside the
    # inner group (reached through the outer group and three reroutes), whose subgraph is the
    # Mix RGB and the RGB node outside both groups (the walk leaves the shader's group through
    # its Group Input); Specular Tint is a constant.
    from facet_blender import nodegraph
    w = nodegraph.Walker(nt)
    ins = w.inputs(p, (sg,))
    b = ins["Base Color"]
    bt.check(isinstance(b, nodegraph.Out) and b.node.bl_idname == 'ShaderNodeMixRGB'
             and [g.node_tree.name for g in b.path] == ["outer", "inner"]
             and isinstance(ins["Specular Tint"], nodegraph.Const)
             and ins["Specular Tint"].value == 0.0,
             "Walker.inputs: Base Color fed from %r, Specular Tint %r" % (b, ins["Specular Tint"]))
    sub = w.subgraph(b)
    bt.check(b.label() == "Mix (Legacy) 'Mix (Legacy)' in node group 'outer' > 'inner'",
             "a node's label names its groups: %s" % b.label())
    bt.check(sorted(o.node.bl_idname for o in sub) == ['ShaderNodeMixRGB', 'ShaderNodeRGB']
             and next(o for o in sub if o.node.bl_idname == 'ShaderNodeRGB').path == (),
             "Walker.subgraph: %s" % sub)
    return c


def reports():
    from facet_blender import materials
    mat, nt, out = new_material("reported")
    p = nt.nodes.new("ShaderNodeBsdfPrincipled")
    p.inputs["Roughness"].default_value = 0.5
    nm = nt.nodes.new("ShaderNodeNormalMap")
    nt.links.new(nm.outputs[0], p.inputs["Normal"])
    # A Geometry normal into Clearcoat Normal (with a clearcoat lobe to shade; at Clearcoat 0
    # the input changes nothing and is not reported): not converted.
    p.inputs["Clearcoat"].default_value = 0.5
    geo = nt.nodes.new("ShaderNodeNewGeometry")
    nt.links.new(geo.outputs["Normal"], p.inputs["Clearcoat Normal"])
    img = nt.nodes.new("ShaderNodeTexImage")
    nt.links.new(img.outputs[0], p.inputs["Base Color"])
    diff = nt.nodes.new("ShaderNodeBsdfDiffuse")
    mix = nt.nodes.new("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = 0.25
    nt.links.new(p.outputs[0], mix.inputs[1])
    nt.links.new(diff.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], out.inputs["Surface"])
    bpy.context.view_layer.update()
    c = materials.convert(mat)
    lines = c.problems
    for node, feeds in (("Geometry", "input 'Clearcoat Normal'"),
                        ("Image Texture", "input 'Base Color'")):
        hits = [x for x in lines if "'reported'" in x and "%s '%s'" % (node, node) in x]
        bt.check(len(hits) == 1 and feeds in hits[0],
                 "%s: one report line naming material, node and %s: %s" % (node, feeds, hits))
    # The rest converts: the Mix Shader (Fac 0.25) to the core's mix of the Principled BSDF
    # (Roughness 0.5, Base Color the input's own value (0.8, 0.8, 0.8), named in the Image
    # Texture's line) and the Diffuse; the Normal Map with its default Color (0.5, 0.5, 1) is
    # no map (exact: the normal unchanged), so nothing is said about it.
    p0 = c.data["materials"][0] if c.data["model"] == "mix" else {}
    bt.check(c.data.get("weight") == 0.25 and p0.get("model") == "principled"
             and p0["roughness"] == 0.5 and "normal_map" not in p0
             and all(abs(x - 0.8) < 1e-6 for x in p0["base_color"]),
             "the rest still converts: %s" % c.data)
    bt.check(len(lines) == 2, "exactly two lines: %s" % lines)

    # Mix Shader with a constant Fac of 1 (through Math) is its second shader exactly;
    # Add Shader of an Emission and a BSDF is exact.
    mat2, nt2, out2 = new_material("exact_mix")
    d = nt2.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (0.5, 0.25, 0.125, 1.0)
    e = nt2.nodes.new("ShaderNodeEmission")
    e.inputs["Strength"].default_value = 2.0
    add = nt2.nodes.new("ShaderNodeAddShader")
    nt2.links.new(e.outputs[0], add.inputs[0])
    nt2.links.new(d.outputs[0], add.inputs[1])
    m2 = nt2.nodes.new("ShaderNodeMixShader")
    nt2.links.new(math_node(nt2, 'ADD', 0.5, 0.5), m2.inputs["Fac"])
    nt2.links.new(nt2.nodes.new("ShaderNodeBsdfGlossy").outputs[0], m2.inputs[1])
    nt2.links.new(add.outputs[0], m2.inputs[2])
    nt2.links.new(m2.outputs[0], out2.inputs["Surface"])
    c = materials.convert(mat2)
    bt.check(c.data == {"model": "lambert", "reflectance": [0.5, 0.25, 0.125]}
             and c.emission == [2.0, 2.0, 2.0] and c.problems == [],
             "Mix Shader Fac 1 + Add Shader(Emission, Diffuse): exact, nothing reported: "
             "%s %s %s" % (c.data, c.emission, c.problems))

    # Linear combinations: Mix(Diffuse a, Diffuse b, 0.25) + Emission and Mix(Glossy,
    # nothing, 0.5) are exact; Add of two Diffuse summing above 1 is not (reported).
    mat5, nt5, out5 = new_material("linear_mix")
    d1 = nt5.nodes.new("ShaderNodeBsdfDiffuse")
    d1.inputs["Color"].default_value = (0.5, 0.25, 1.0, 1.0)
    d2 = nt5.nodes.new("ShaderNodeBsdfDiffuse")
    d2.inputs["Color"].default_value = (1.0, 0.5, 0.0, 1.0)
    m5 = nt5.nodes.new("ShaderNodeMixShader")
    m5.inputs["Fac"].default_value = 0.25
    nt5.links.new(d1.outputs[0], m5.inputs[1])
    nt5.links.new(d2.outputs[0], m5.inputs[2])
    e5 = nt5.nodes.new("ShaderNodeEmission")
    e5.inputs["Strength"].default_value = 0.5
    a5 = nt5.nodes.new("ShaderNodeAddShader")
    nt5.links.new(m5.outputs[0], a5.inputs[0])
    nt5.links.new(e5.outputs[0], a5.inputs[1])
    nt5.links.new(a5.outputs[0], out5.inputs["Surface"])
    c = materials.convert(mat5)
    bt.check(c.data == {"model": "lambert", "reflectance": [0.625, 0.3125, 0.75]}
             and c.emission == [0.5, 0.5, 0.5] and c.problems == [],
             "Mix of two Diffuse + Emission: exact: %s %s %s" % (c.data, c.emission,
                                                                 c.problems))
    g5 = nt5.nodes.new("ShaderNodeBsdfGlossy")
    g5.inputs["Roughness"].default_value = 0.5
    g5.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
    nt5.links.new(g5.outputs[0], m5.inputs[1])
    nt5.links.remove(m5.inputs[2].links[0])
    m5.inputs["Fac"].default_value = 0.5
    c = materials.convert(mat5)
    bt.check(c.data == {"model": "ggx", "reflectance": [0.25, 0.25, 0.25], "fresnel": "none",
                        "alpha": 0.25} and c.problems == [],
             "Mix of a Glossy and nothing at 0.5: reflectance halved: %s %s" % (c.data,
                                                                                c.problems))
    nt5.links.new(d1.outputs[0], a5.inputs[0])
    nt5.links.new(d2.outputs[0], a5.inputs[1])
    c = materials.convert(mat5)
    bt.check(c.data == {"model": "add", "materials": [
        {"model": "lambert", "reflectance": [0.5, 0.25, 1.0]},
        {"model": "lambert", "reflectance": [1.0, 0.5, 0.0]}]} and c.problems == [],
        "Add of two Diffuse above 1: the core's add (its build warns of the gain): %s %s"
        % (c.data, c.problems))

    # The output Cycles renders: target Cycles before All (even when All is active: measured,
    # a Cycles render of Emission red on an active All output and green on an inactive Cycles
    # output is green), never Eevee.
    mat4, nt4, out_all = new_material("outputs")
    for target, color, active in (('ALL', (0.25, 0.0, 0.0, 1.0), True),
                                  ('CYCLES', (0.0, 0.5, 0.0, 1.0), False),
                                  ('EEVEE', (0.0, 0.0, 0.75, 1.0), False)):
        o = out_all if target == 'ALL' else nt4.nodes.new("ShaderNodeOutputMaterial")
        o.target = target
        d = nt4.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = color
        nt4.links.new(d.outputs[0], o.inputs["Surface"])
    nt4.nodes.active = out_all
    out_all.is_active_output = True
    c = materials.convert(mat4)
    bt.check(c.data["reflectance"] == [0.0, 0.5, 0.0] and out_all.is_active_output,
             "the Cycles-target output wins over an active All one: %s" % c.data)

    # Diffuse roughness > 0: the core's oren_nayar, sigma = Roughness (Cycles' Diffuse BSDF).
    mat3, nt3, out3 = new_material("oren")
    d = nt3.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Roughness"].default_value = 0.5
    nt3.links.new(d.outputs[0], out3.inputs["Surface"])
    c = materials.convert(mat3)
    bt.check(c.data["model"] == "oren_nayar" and abs(c.data["sigma"] - 0.5) < 1e-6
             and not c.problems, "Diffuse Roughness 0.5 -> oren_nayar: %s %s"
             % (c.data, c.problems))

    # Translucent and Velvet: the core's model units, Color (and Sigma) by Cycles' names.
    mat6, nt6, out6 = new_material("translucent")
    t = nt6.nodes.new("ShaderNodeBsdfTranslucent")
    t.inputs["Color"].default_value = (0.5, 0.25, 1.0, 1.0)
    nt6.links.new(t.outputs[0], out6.inputs["Surface"])
    c = materials.convert(mat6)
    bt.check(c.data == {"model": "translucent", "transmittance": [0.5, 0.25, 1.0]}
             and not c.problems, "Translucent -> translucent: %s %s" % (c.data, c.problems))
    mat7, nt7, out7 = new_material("velvet")
    v = nt7.nodes.new("ShaderNodeBsdfVelvet")
    v.inputs["Color"].default_value = (0.5, 0.25, 1.0, 1.0)
    v.inputs["Sigma"].default_value = 0.25
    nt7.links.new(v.outputs[0], out7.inputs["Surface"])
    c = materials.convert(mat7)
    bt.check(c.data.get("model") == "velvet" and c.data["reflectance"] == [0.5, 0.25, 1.0]
             and abs(c.data["sigma"] - 0.25) < 1e-6 and not c.problems,
             "Velvet -> velvet: %s %s" % (c.data, c.problems))


def scene_reports():
    """Lamps and the world through the exporter."""
    from facet_blender import export
    bt.factory_scene(8, 8)
    scene = bpy.context.scene
    # The factory scene's point light "Light" has a radius of 0.1.
    world = scene.world
    env = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    world.node_tree.links.new(env.outputs[0], world.node_tree.nodes["Background"].inputs[0])
    for kind, attrs in (('SUN', {"angle": 0.1}), ('SPOT', {"spot_blend": 0.3}),
                        ('AREA', {"spread": 1.0})):
        lt = bpy.data.lights.new(kind.lower(), kind)
        for k, v in attrs.items():
            setattr(lt, k, v)
        ob = bpy.data.objects.new(kind.lower(), lt)
        scene.collection.objects.link(ob)
    bpy.data.lights["spot"].cycles.cast_shadow = False
    bpy.context.view_layer.update()
    # The default Lamp Model (Cycles 3.4) converts Radius and Angle exactly: no line, the
    # core's Cycles 3.4 models named.
    data, problems = export.export_scene(bpy.context.evaluated_depsgraph_get())
    bt.check(not any("Radius" in p or "Angle" in p for p in problems),
             "Cycles 3.4 lamp models: Radius and Angle are not reported: %s" % problems)
    models = sorted((lt["type"], lt.get("radius_model", lt.get("angle_model")))
                    for lt in data["lights"] if lt["type"] in ("point", "directional"))
    bt.check(models == [("directional", "cycles34"), ("point", "cycles34_disc")],
             "the lamps name the Cycles 3.4 models: %s" % models)
    # Lamp Model Physical: the sphere and the uniform cone, each reported.
    scene.facet.lamp_model = "physical"
    data, problems = export.export_scene(bpy.context.evaluated_depsgraph_get())
    scene.facet.lamp_model = "cycles34"
    for who, what in (("light 'Light'", "Radius = 0.1: converted to a sphere"),
                      ("light 'sun'", "Angle = 5.73 deg: converted to a cone"),
                      ("light 'spot'", "Cast Shadow = False"),
                      ("light 'area'", "Spread = 57.3 deg"),
                      ("world 'World'", "Environment Texture")):
        bt.check(any(who in p and what in p for p in problems),
                 "%s: %s reported: %s" % (who, what, problems))
    # Radius and the Sun's Angle are converted (and reported above with how Cycles 3.4
    # differs): the factory point light's 0.1 m radius, the sun's 0.1 rad = 5.7296 degrees.
    point = [lt for lt in data["lights"] if lt["type"] == "point"]
    sun = [lt for lt in data["lights"] if lt["type"] == "directional"]
    bt.check(len(point) == 1 and abs(point[0].get("radius", 0.0) - 0.1) < 1e-6,
             "the point lamp's radius is exported: %s" % point)
    bt.check(len(sun) == 1 and abs(sun[0].get("angle", 0.0) - 5.729578) < 1e-5,
             "the sun's angle is exported in degrees: %s" % sun)
    env_light = [lt for lt in data["lights"] if lt["type"] == "environment"]
    bt.check(len(env_light) == 1 and np.allclose(env_light[0]["radiance"], [0.0509] * 3,
                                                 atol=1e-3),
             "the world still converts with the Background's own colour: %s" % env_light)


def world_mix():
    """A world Mix Shader of two Backgrounds (a Fac of 0.25 through a reroute) is the exact
    mix of their radiances; an Add Shader adds an Emission."""
    from facet_blender import export, sync_world
    bt.factory_scene(8, 8)
    world = bpy.context.scene.world
    nt = world.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputWorld")
    a = nt.nodes.new("ShaderNodeBackground")
    a.inputs["Color"].default_value = (1.0, 0.5, 0.25, 1.0)
    a.inputs["Strength"].default_value = 2.0
    b = nt.nodes.new("ShaderNodeBackground")
    b.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
    mix = nt.nodes.new("ShaderNodeMixShader")
    nt.links.new(reroute(nt, value_node(nt, 0.25)), mix.inputs["Fac"])
    nt.links.new(a.outputs[0], mix.inputs[1])
    nt.links.new(b.outputs[0], mix.inputs[2])
    e = nt.nodes.new("ShaderNodeEmission")
    e.inputs["Color"].default_value = (0.0, 0.0, 0.5, 1.0)
    add = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(mix.outputs[0], add.inputs[0])
    nt.links.new(e.outputs[0], add.inputs[1])
    nt.links.new(add.outputs[0], out.inputs["Surface"])
    problems = []
    env = sync_world.export_environment(bpy.context.scene, problems)
    # 0.75 (2, 1, 0.5) + 0.25 (0.5, 0.5, 0.5) + (0, 0, 0.5)
    bt.check(env["radiance"] == [1.625, 0.875, 1.0] and problems == [],
             "world Mix Shader of Backgrounds + Emission: exact: %s %s" % (env, problems))


# --- against Cycles ------------------------------------------------------------------------

def cases():
    """[(name, builder(nt) -> output socket feeding the Emission: colour -> Color, float ->
    Strength)]."""
    out = []

    def add(name):
        def deco(f):
            out.append((name, f))
            return f
        return deco

    for op, a, b, c in (('ADD', 0.3, 0.45, 0), ('DIVIDE', 0.7, 0.0, 0), ('POWER', 0.6, 2.5, 0),
                        ('POWER', -0.5, 0.5, 0), ('LOGARITHM', 0.4, 3.0, 0),
                        ('SQRT', 0.37, 0, 0), ('INVERSE_SQRT', 0.37, 0, 0),
                        ('SMOOTH_MIN', 0.3, 0.4, 0.25), ('SMOOTH_MAX', 0.3, 0.4, 0.25),
                        ('PINGPONG', 1.7, 0.6, 0), ('WRAP', 1.3, 0.5, 0.1),
                        ('MODULO', -1.3, 0.5, 0), ('SNAP', 0.77, 0.2, 0),
                        ('ARCTAN2', 0.3, -0.4, 0), ('COMPARE', 0.5, 0.55, 0.1),
                        ('TANH', 0.8, 0, 0), ('FRACT', -1.25, 0, 0), ('SIGN', -0.2, 0, 0)):
        def f(nt, op=op, a=a, b=b, c=c):
            return math_node(nt, 'ABSOLUTE', math_node(nt, op, value_node(nt, a), b, c))
        add("math %s" % op)(f)
    c1, c2 = (0.8, 0.3, 0.1), (0.2, 0.6, 0.9)
    for blend in ('OVERLAY', 'SCREEN', 'SOFT_LIGHT', 'LINEAR_LIGHT', 'DODGE', 'BURN', 'HUE',
                  'SATURATION', 'VALUE', 'COLOR', 'DIVIDE', 'DIFFERENCE'):
        add("mixrgb %s" % blend)(lambda nt, blend=blend: mixrgb_node(
            nt, blend, 0.6, rgb_node(nt, c1), c2, clamp=blend == 'LINEAR_LIGHT'))

    @add("mix color linear light fac 1.3 unclamped")
    def _(nt):
        n = nt.nodes.new("ShaderNodeMix")
        n.data_type = 'RGBA'
        n.blend_type = 'LINEAR_LIGHT'
        n.clamp_factor = False
        ins = {s.identifier: s for s in n.inputs}
        ins["Factor_Float"].default_value = 1.3
        ins["A_Color"].default_value = c1 + (1.0,)
        nt.links.new(rgb_node(nt, c2), ins["B_Color"])
        return next(s for s in n.outputs if s.identifier == "Result_Color")

    @add("invert gamma hsv")
    def _(nt):
        inv = nt.nodes.new("ShaderNodeInvert")
        inv.inputs["Fac"].default_value = 0.7
        nt.links.new(rgb_node(nt, c1), inv.inputs["Color"])
        gam = nt.nodes.new("ShaderNodeGamma")
        gam.inputs["Gamma"].default_value = 2.2
        nt.links.new(inv.outputs[0], gam.inputs["Color"])
        hsv = nt.nodes.new("ShaderNodeHueSaturation")
        hsv.inputs["Hue"].default_value = 0.8
        hsv.inputs["Saturation"].default_value = 1.4
        hsv.inputs["Value"].default_value = 0.9
        hsv.inputs["Fac"].default_value = 0.8
        nt.links.new(gam.outputs[0], hsv.inputs["Color"])
        return hsv.outputs[0]

    @add("separate HSL, combine HSV")
    def _(nt):
        sep = nt.nodes.new("ShaderNodeSeparateColor")
        sep.mode = 'HSL'
        nt.links.new(rgb_node(nt, c1), sep.inputs[0])
        comb = nt.nodes.new("ShaderNodeCombineColor")
        comb.mode = 'HSV'
        for i in range(3):
            nt.links.new(sep.outputs[i], comb.inputs[2 - i])
        return comb.outputs[0]

    for rgb in ((0.3, 0.6, 0.9), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)):
        add("colour %s -> float (luminance)" % (rgb,))(
            lambda nt, rgb=rgb: math_node(nt, 'ADD', rgb_node(nt, rgb), 0.0))

    @add("vector -> float (mean), separate/combine XYZ")
    def _(nt):
        comb = nt.nodes.new("ShaderNodeCombineXYZ")
        for i, v in enumerate((0.2, 0.9, 0.4)):
            comb.inputs[i].default_value = v
        sep = nt.nodes.new("ShaderNodeSeparateXYZ")
        nt.links.new(comb.outputs[0], sep.inputs[0])
        comb2 = nt.nodes.new("ShaderNodeCombineXYZ")
        nt.links.new(sep.outputs[2], comb2.inputs[0])
        nt.links.new(sep.outputs[0], comb2.inputs[1])
        comb2.inputs[2].default_value = 0.15
        return math_node(nt, 'ADD', comb2.outputs[0], 0.0)

    for kind, f0, f1, clamp in (('LINEAR', 0.2, 0.8, True), ('STEPPED', 0.1, 0.9, False),
                                ('SMOOTHSTEP', 0.9, 0.2, False), ('SMOOTHERSTEP', 0.1, 0.7, False)):
        def f(nt, kind=kind, f0=f0, f1=f1, clamp=clamp):
            n = nt.nodes.new("ShaderNodeMapRange")
            n.interpolation_type = kind
            n.clamp = clamp
            for k, x in (("From Min", f0), ("From Max", f1), ("To Min", 0.3), ("To Max", 1.7),
                         ("Steps", 3.0)):
                n.inputs[k].default_value = x
            nt.links.new(value_node(nt, 0.62), n.inputs["Value"])
            return n.outputs["Result"]
        add("map range %s" % kind)(f)

    @add("map range vector smoother step")
    def _(nt):
        n = nt.nodes.new("ShaderNodeMapRange")
        n.data_type = 'FLOAT_VECTOR'
        n.interpolation_type = 'SMOOTHERSTEP'
        ins = {s.identifier: s for s in n.inputs}
        ins["From_Min_FLOAT3"].default_value = (0.0, 0.1, 0.2)
        ins["To_Max_FLOAT3"].default_value = (0.9, 1.5, 0.7)
        comb = nt.nodes.new("ShaderNodeCombineXYZ")
        for i, x in enumerate((0.3, 0.5, 0.95)):
            comb.inputs[i].default_value = x
        nt.links.new(comb.outputs[0], ins["Vector"])
        out = next(s for s in n.outputs if s.identifier == "Vector")
        sep = nt.nodes.new("ShaderNodeSeparateXYZ")  # vector -> colour via Combine Color
        nt.links.new(out, sep.inputs[0])
        cc = nt.nodes.new("ShaderNodeCombineColor")
        for i in range(3):
            nt.links.new(sep.outputs[i], cc.inputs[i])
        return cc.outputs[0]

    @add("bright/contrast")
    def _(nt):
        n = nt.nodes.new("ShaderNodeBrightContrast")
        n.inputs["Bright"].default_value = 0.1
        n.inputs["Contrast"].default_value = 0.4
        nt.links.new(rgb_node(nt, c1), n.inputs["Color"])
        return n.outputs[0]

    for op in ('CROSS_PRODUCT', 'PROJECT', 'REFLECT', 'REFRACT', 'NORMALIZE', 'WRAP',
               'DOT_PRODUCT', 'DISTANCE', 'SNAP'):
        def f(nt, op=op):
            n = nt.nodes.new("ShaderNodeVectorMath")
            n.operation = op
            ins = {s.identifier: s for s in n.inputs}
            ins["Vector"].default_value = (0.3, -0.6, 0.5)
            ins["Vector_001"].default_value = (0.2, 0.7, -0.4)
            ins["Vector_002"].default_value = (-0.5, 0.1, 0.3)
            ins["Scale"].default_value = 0.8
            out = next(s for s in n.outputs if s.enabled)
            if out.type == 'VALUE':
                return math_node(nt, 'ABSOLUTE', out)
            # |v| per component through Vector Math Absolute, into the Color.
            a = nt.nodes.new("ShaderNodeVectorMath")
            a.operation = 'ABSOLUTE'
            nt.links.new(out, a.inputs[0])
            n2 = nt.nodes.new("ShaderNodeMix")
            n2.data_type = 'RGBA'
            ins2 = {s.identifier: s for s in n2.inputs}
            ins2["Factor_Float"].default_value = 0.0
            nt.links.new(a.outputs[0], ins2["A_Color"])
            return next(s for s in n2.outputs if s.identifier == "Result_Color")
        add("vector math %s" % op)(f)

    for interp, fac, alpha in (('LINEAR', 0.37, False), ('B_SPLINE', 0.6123, False),
                               ('EASE', 0.6, True), ('CONSTANT', 0.52, False)):
        def f(nt, interp=interp, fac=fac, alpha=alpha):
            n = nt.nodes.new("ShaderNodeValToRGB")
            r = n.color_ramp
            r.interpolation = interp
            r.elements[0].color = (0.9, 0.2, 0.1, 1.0)
            r.elements[1].position = 0.8
            r.elements[1].color = (0.1, 0.4, 0.9, 0.3)
            mid = r.elements.new(0.45)
            mid.color = (0.3, 0.9, 0.2, 0.6)
            nt.links.new(value_node(nt, fac), n.inputs["Fac"])
            return n.outputs["Alpha" if alpha else "Color"]
        add("color ramp %s%s" % (interp, " alpha" if alpha else ""))(f)

    @add("muted node, unlinked input -> 0")
    def _(nt):
        m = math_node(nt, 'ADD', 0.6, 0.2)
        m.node.mute = True
        return math_node(nt, 'ADD', m, 0.25)

    @add("muted mix rgb passes Color1, colour into a float")
    def _(nt):
        m = mixrgb_node(nt, 'MULTIPLY', 1.0, rgb_node(nt, c1), c2)
        m.node.mute = True
        return math_node(nt, 'ADD', m, 0.0)

    @add("unconnected reroute -> 0")
    def _(nt):
        r = nt.nodes.new("NodeReroute")
        return math_node(nt, 'ADD', r.outputs[0], 0.125)

    @add("muted group passes its input; group socket float")
    def _(nt):
        g, gi, go = group_tree("passf", "NodeSocketFloat", "NodeSocketFloat")
        g.links.new(math_node(g, 'MULTIPLY', gi.outputs[0], 3.0), go.inputs[0])
        n1 = group_node(nt, g, rgb_node(nt, c2))  # colour -> float at the group's input
        n2 = group_node(nt, g, n1.outputs[0])
        n2.mute = True
        return math_node(nt, 'ADD', n2.outputs[0], 0.0)
    return out


def against_cycles(outdir):
    from facet_blender import materials
    bpy.ops.wm.read_homefile(use_factory_startup=True)
    scene = bpy.context.scene
    for ob in list(scene.objects):
        bpy.data.objects.remove(ob)
    todo = cases()
    n = len(todo)
    # One quad per case: x in [i, i + 1], y in [-4, 4]; the camera sees n x 4 pixels (Blender's
    # smallest height), y in [-2, 2]: pixel column i is quad i.
    verts, faces = [], []
    for i in range(n):
        verts += [(i, -4, 0), (i + 1, -4, 0), (i + 1, 4, 0), (i, 4, 0)]
        faces.append((4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3))
    me = bpy.data.meshes.new("strip")
    me.from_pydata(verts, [], faces)
    ob = bpy.data.objects.new("strip", me)
    scene.collection.objects.link(ob)
    expected = []
    for i, (name, build) in enumerate(todo):
        mat, nt, out = new_material("case%d" % i)
        em = nt.nodes.new("ShaderNodeEmission")
        nt.links.new(em.outputs[0], out.inputs["Surface"])
        src = build(nt)
        target = em.inputs["Color"] if src.type == 'RGBA' else em.inputs["Strength"]
        nt.links.new(src, target)
        me.materials.append(mat)
        me.polygons[i].material_index = i
        bpy.context.view_layer.update()
        c = materials.convert(mat)
        bt.check(c.problems == [], "%s: folds without a report: %s" % (name, c.problems))
        expected.append(c.emission)
    bt.ortho_camera(scene, n, (n / 2.0, 0.0, 5.0))
    scene.render.engine = 'CYCLES'
    scene.render.resolution_x, scene.render.resolution_y = n, 4
    scene.render.resolution_percentage = 100
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.pixel_filter_type = 'BOX'
    scene.cycles.filter_width = 1.0
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    path = os.path.join(outdir, "nodegraph_cycles.exr")
    bt.render(scene, path)
    img = bt.load_exr(path)
    bt.check(img.shape == (4, n, 3) and (img == img[:1]).all(), "%d x 4 pixels, the rows "
             "equal" % n)
    worst = 0.0
    for (name, _), want, got in zip(todo, expected, img[0]):
        # Cycles evaluates in float32 (a few operations, ~6e-8 relative each, transcendental
        # functions within an ulp or two); the addon in double from the same float32 inputs.
        # Measured worst difference 1.4e-7 relative (about one float32 ulp); the bound 1e-6
        # leaves 7x margin and still fails the smallest real error met while writing this:
        # the config's srgb_to_xyz luminance row instead of Cycles' rgb_to_y (1.3e-6).
        err = max(abs(w - g) / max(1.0, abs(w)) for w, g in zip(want, got))
        worst = max(worst, err)
        ok = err <= 1e-6
        bt.check(ok, "%s: addon %s == Cycles %s" % (name, [round(x, 7) for x in want],
                                                    [round(float(x), 7) for x in got]))
    print("worst relative difference addon - Cycles: %.3g" % worst)


def main():
    bt.enable_addon()
    outdir = bt.args()[0]
    structure()
    reports()
    scene_reports()
    world_mix()
    against_cycles(outdir)


bt.run(main)
