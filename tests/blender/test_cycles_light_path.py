"""Light Path outputs as values: Facet's render against Cycles 3.4's (issue 35, item 2): Ray
Depth, Ray Length and Diffuse Depth through Math nodes into factors and colours, and a Mix
Shader by Is Camera Ray inside an Add Shader (the core's light_path texture, FORMAT.md "Light
Path outputs").

Scene (64 x 64, orthographic camera looking straight down from 6 m, 64 spp, Facet max_depth 3
= Cycles 2 bounces; a 3 m emitting plane overhead, strength 20, facing down, Camera off, and a
dim constant world of 0.1), on a floor of Diffuse 0.8:
- a sphere Mix Shader(Glossy, Diffuse green, Fac = Ray Depth > 0.5): glossy to the camera,
  green to the floor's bounce rays;
- a tilted plane of Diffuse whose Color is Ray Length x 0.5 - 2 (Multiply Add, clamped): a
  gradient across it to the camera, other values to bounce rays;
- a cube Add Shader(Mix Shader(Diffuse red, Diffuse blue, Is Camera Ray), Glossy 0.2): blue to
  the camera, red bounce light;
- a sphere Mix Shader(Diffuse white, Diffuse orange, Fac = Diffuse Depth): white to the camera,
  orange to diffuse bounce rays.

Bounds, as the real-scene suite states them, on the luminance: |mean ratio Facet / Cycles - 1|
<= 2% and block RMSE (8 x 8 blocks) <= 3 x the Cycles seed-to-seed floor. Ability to fail: every
Light Path output converted as the constant 1 must break a bound (printed). The conversion is
also checked: each object's material carries its light_path texture, and what Facet does not
read from a ray (a Light Path output into an Emission's Color, Transparent Depth, Is Shadow Ray
through a Math node) is reported, naming the node."""
import json
import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

RES = 64
BLOCK = 8
SPP = 64
MEAN_TOL = 0.02
RMSE_FACTOR = 3.0


def new_tree(name):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    return mat, nt, nt.nodes.new("ShaderNodeOutputMaterial")


def bsdf(nt, idname, color, **inputs):
    n = nt.nodes.new(idname)
    n.inputs["Color"].default_value = color
    for k, v in inputs.items():
        n.inputs[k].default_value = v
    return n


def math(nt, op, a, b=None, c=None, clamp=False):
    """A Math node of op on (socket or value) a, b, c."""
    m = nt.nodes.new("ShaderNodeMath")
    m.operation = op
    m.use_clamp = clamp
    for i, v in enumerate((a, b, c)):
        if v is None:
            continue
        if isinstance(v, (int, float)):
            m.inputs[i].default_value = v
        else:
            nt.links.new(v, m.inputs[i])
    return m.outputs[0]


def mix_shader(nt, fac, s1, s2):
    mix = nt.nodes.new("ShaderNodeMixShader")
    nt.links.new(fac, mix.inputs["Fac"])
    nt.links.new(s1.outputs[0], mix.inputs[1])
    nt.links.new(s2.outputs[0], mix.inputs[2])
    return mix


def materials():
    out = {}
    mat, nt, o = new_tree("by depth")
    lp = nt.nodes.new("ShaderNodeLightPath")
    g = bsdf(nt, "ShaderNodeBsdfGlossy", (0.9, 0.9, 0.9, 1.0), Roughness=0.15)
    g.distribution = 'GGX'
    d = bsdf(nt, "ShaderNodeBsdfDiffuse", (0.1, 0.8, 0.1, 1.0))
    mix = mix_shader(nt, math(nt, 'GREATER_THAN', lp.outputs["Ray Depth"], 0.5), g, d)
    nt.links.new(mix.outputs[0], o.inputs["Surface"])
    out["depth"] = mat

    mat, nt, o = new_tree("by length")
    lp = nt.nodes.new("ShaderNodeLightPath")
    d = bsdf(nt, "ShaderNodeBsdfDiffuse", (0.8, 0.8, 0.8, 1.0))
    nt.links.new(math(nt, 'MULTIPLY_ADD', lp.outputs["Ray Length"], 0.5, -2.0, clamp=True),
                 d.inputs["Color"])
    nt.links.new(d.outputs[0], o.inputs["Surface"])
    out["length"] = mat

    mat, nt, o = new_tree("nested camera")
    lp = nt.nodes.new("ShaderNodeLightPath")
    red = bsdf(nt, "ShaderNodeBsdfDiffuse", (0.7, 0.05, 0.05, 1.0))
    blue = bsdf(nt, "ShaderNodeBsdfDiffuse", (0.05, 0.1, 0.7, 1.0))
    mix = mix_shader(nt, lp.outputs["Is Camera Ray"], red, blue)
    g = bsdf(nt, "ShaderNodeBsdfGlossy", (0.2, 0.2, 0.2, 1.0), Roughness=0.3)
    g.distribution = 'GGX'
    add = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(mix.outputs[0], add.inputs[0])
    nt.links.new(g.outputs[0], add.inputs[1])
    nt.links.new(add.outputs[0], o.inputs["Surface"])
    out["nested"] = mat

    mat, nt, o = new_tree("by diffuse depth")
    lp = nt.nodes.new("ShaderNodeLightPath")
    w = bsdf(nt, "ShaderNodeBsdfDiffuse", (0.8, 0.8, 0.8, 1.0))
    orange = bsdf(nt, "ShaderNodeBsdfDiffuse", (0.9, 0.4, 0.05, 1.0))
    mix = mix_shader(nt, lp.outputs["Diffuse Depth"], w, orange)
    nt.links.new(mix.outputs[0], o.inputs["Surface"])
    out["diffuse_depth"] = mat
    return out


def build_scene():
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x = scene.render.resolution_y = RES
    scene.render.resolution_percentage = 100
    world = bpy.data.worlds.new("dim")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bg.inputs["Strength"].default_value = 0.1
    scene.world = world
    mats = materials()
    white = bpy.data.materials.new("white")
    bt.single_shader(white, "ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.8, 0.8, 1.0),
                                                       "Roughness": 0.0})
    lamp = bpy.data.materials.new("lamp")
    bt.single_shader(lamp, "ShaderNodeEmission", {"Color": (1.0, 1.0, 1.0, 1.0),
                                                  "Strength": 20.0})

    def add(op, mat, **kw):
        op(**kw)
        ob = bpy.context.object
        ob.data.materials.append(mat)
        return ob

    add(bpy.ops.mesh.primitive_plane_add, white, size=4.0, location=(0.0, 0.0, 0.0))
    for ob in (add(bpy.ops.mesh.primitive_uv_sphere_add, mats["depth"], radius=0.5,
                   location=(-0.9, 0.9, 0.5)),
               add(bpy.ops.mesh.primitive_uv_sphere_add, mats["diffuse_depth"], radius=0.45,
                   location=(0.9, -0.9, 0.45))):
        bpy.context.view_layer.objects.active = ob
        bpy.ops.object.shade_smooth()
    add(bpy.ops.mesh.primitive_plane_add, mats["length"], size=1.4, location=(0.9, 0.9, 0.6),
        rotation=(0.7, 0.0, 0.0))
    add(bpy.ops.mesh.primitive_cube_add, mats["nested"], size=0.7, location=(-0.9, -0.9, 0.35))
    ob = add(bpy.ops.mesh.primitive_plane_add, lamp, size=3.0, location=(0.0, 0.0, 4.0),
             rotation=(3.14159265, 0.0, 0.0))
    ob.visible_camera = False
    cd = bpy.data.cameras.new("cam")
    cd.type = 'ORTHO'
    cd.ortho_scale = 4.0
    # Cycles measures a camera ray's Ray Length from Clip Start (reported by the export when
    # > 0, checked in main()); a negligible one compares the rest exactly.
    cd.clip_start = 1e-5
    cam = bpy.data.objects.new("cam", cd)
    cam.location = (0.0, 0.0, 6.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.facet.max_depth = 3
    scene.facet.spp = SPP
    cs.cycles_settings(scene, samples=SPP, max_depth=3)
    return scene


def check_reports():
    """Light Path outputs where Facet reads no ray are reported, naming the node, and the
    conversion falls back to the input's value: into an Emission's Color, Transparent Depth,
    and Is Shadow Ray through a Math node."""
    from facet_blender import materials as fm
    for case in ("emission", "transparent depth", "shadow math"):
        mat, nt, o = new_tree(case)
        lp = nt.nodes.new("ShaderNodeLightPath")
        if case == "emission":
            e = nt.nodes.new("ShaderNodeEmission")
            nt.links.new(lp.outputs["Is Camera Ray"], e.inputs["Color"])
            nt.links.new(e.outputs[0], o.inputs["Surface"])
        else:
            d = bsdf(nt, "ShaderNodeBsdfDiffuse", (0.8, 0.8, 0.8, 1.0))
            out = lp.outputs["Transparent Depth" if case == "transparent depth"
                             else "Is Shadow Ray"]
            nt.links.new(math(nt, 'MULTIPLY', out, 0.5), d.inputs["Color"])
            nt.links.new(d.outputs[0], o.inputs["Surface"])
        conv = fm.convert(mat)
        text = json.dumps([conv.data, conv.emission])
        lines = [p for p in conv.problems if "Light Path" in p]
        bt.check(len(lines) == 1 and "light_path" not in text,
                 "%s: reported, not converted: %s %s" % (case, conv.problems, text))
        bpy.data.materials.remove(mat)


def main():
    out = bt.args()[0]
    bt.enable_addon()
    check_reports()
    scene = build_scene()
    data = json.loads(cs.facet_description(scene))
    mats = json.dumps(data["materials"])
    for output in ("ray_depth", "ray_length", "is_camera_ray", "diffuse_depth"):
        bt.check('"%s"' % output in mats, "the export reads %s: %s" % (output, mats))
    from facet_blender import export
    _, problems = export.export_scene(bpy.context.evaluated_depsgraph_get(), mesh_cache={})
    bt.check([p for p in problems if "Ray Length" in p] ==
             ["material 'by length': Light Path Ray Length of camera rays is measured from the "
              "camera; Cycles measures it from Clip Start (1e-05 m nearer along the view axis), "
              "so camera rays read it longer by 1e-05 m / cos(angle to the view axis)"],
             "the Clip Start offset of camera rays' Ray Length is reported: %s" % problems)
    c1, _ = cs.render(scene, 'CYCLES', os.path.join(out, "lightpath_cycles1.exr"), 1)
    c2, _ = cs.render(scene, 'CYCLES', os.path.join(out, "lightpath_cycles2.exr"), 2)
    f, _ = cs.render(scene, 'FACET', os.path.join(out, "lightpath_facet1.exr"), 1)
    res = cs.compare_to_cycles("Facet", f, c1, c2, BLOCK)
    bt.check(abs(res[0] - 1.0) <= MEAN_TOL and res[1] <= RMSE_FACTOR,
             "Facet matches Cycles with Light Path outputs (mean within %g, block RMSE <= %g x "
             "floor)" % (MEAN_TOL, RMSE_FACTOR))

    # Control: every Light Path output the constant 1 must break a bound.
    from facet_blender import textures
    saved = textures._light_path
    textures._light_path = lambda src: textures.Result(None, const=1.0)
    try:
        f, _ = cs.render(scene, 'FACET', os.path.join(out, "lightpath_facet_const.exr"), 1)
    finally:
        textures._light_path = saved
    res = cs.compare_to_cycles("Facet, outputs 1", f, c1, c2, BLOCK)
    bt.check(not (abs(res[0] - 1.0) <= MEAN_TOL and res[1] <= RMSE_FACTOR),
             "with every output 1 a bound breaks: the test can fail")


bt.run(main)
