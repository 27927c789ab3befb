"""Object > Visibility > Ray Visibility and Light Path switches: Facet's render against Cycles
3.4's (issue 35, item 3).

Scene (64 x 64, orthographic camera looking straight down, 64 spp, Facet max_depth 3 = Cycles
2 bounces, Cycles' transparent bounces 8 (Facet's `null` crossings are not bounces); a 3 m
emitting plane overhead (strength 20, facing down, Camera off) and a dim constant world of
0.1):
- a floor, Diffuse 0.8, with a Glossy (GGX 0.05, white) patch in one corner, tilted 22.5
  degrees;
- a sphere with Camera off: its shadow on the floor, no sphere;
- a cube with Shadow off: the cube, no shadow;
- a red sphere with Diffuse off: seen, casts its shadow, no red bounce light on the floor;
- an emitting panel (strength 8) standing at the floor's edge with Diffuse off: a light source
  still (glossy rays see it), lighting the floor through light samples at their MIS weight
  while diffuse rays pass it, as Cycles does;
- an emitting plane (strength 3, facing down) with Camera off: it lights the floor, unseen;
- an emitting panel (strength 8) at the floor's other edge with Glossy off, facing the glossy
  patch, which is tilted to reflect the camera's rays toward it: absent from the reflection (and
  from the patch's light samples), while it lights the floor;
- a cube whose material is Mix Shader(Diffuse, Transparent BSDF, Is Shadow Ray): no shadow;
- a sphere whose material is Mix Shader(Emission white 3, Emission blue 1, Is Camera Ray): the
  camera sees it blue, the floor is lit white.

Bounds, as the real-scene suite states them (tests/realscenes/test_realscene.py), on the
luminance: |mean ratio Facet / Cycles - 1| <= 2% (Cycles: the mean of its two seeds) and block
RMSE (8 x 8 blocks' means, Facet seed 1 against Cycles seed 1) <= 3 x the noise floor (the same
between Cycles seeds 1 and 2). Ability to fail: Facet with the visibility flags ignored (the
export's ray_visibility returning nothing), and Facet with the Light Path switches dropped,
must each break a bound (printed)."""
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


def material(name, idname, inputs):
    mat = bpy.data.materials.new(name)
    bt.single_shader(mat, idname, inputs)
    return mat


def emission(name, strength):
    mat = bpy.data.materials.new(name)
    bt.single_shader(mat, "ShaderNodeEmission", {"Color": (1.0, 1.0, 1.0, 1.0),
                                                 "Strength": strength})
    return mat


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
    white = material("white", "ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.8, 0.8, 1.0),
                                                        "Roughness": 0.0})
    red = material("red", "ShaderNodeBsdfDiffuse", {"Color": (0.9, 0.1, 0.1, 1.0),
                                                    "Roughness": 0.0})
    glossy = material("glossy", "ShaderNodeBsdfGlossy", {"Color": (0.9, 0.9, 0.9, 1.0),
                                                         "Roughness": 0.05})
    glossy.node_tree.nodes["Glossy BSDF"].distribution = 'GGX'

    def add(op, mat, flags=None, **kw):
        op(**kw)
        ob = bpy.context.object
        ob.data.materials.append(mat)
        for k, v in (flags or {}).items():
            setattr(ob, k, v)
        return ob

    add(bpy.ops.mesh.primitive_plane_add, white, size=4.0, location=(0.0, 0.0, 0.0))
    # The glossy patch tilted 22.5 degrees toward -x: it sends the camera's rays 45 degrees
    # up toward the panel at x = -2.
    add(bpy.ops.mesh.primitive_plane_add, glossy, size=1.2, location=(-1.1, -1.2, 0.3),
        rotation=(0.0, -0.3926991, 0.0))
    obs = {
        "camera": add(bpy.ops.mesh.primitive_uv_sphere_add, white, {"visible_camera": False},
                      radius=0.4, location=(-1.2, 1.2, 0.8)),
        "shadow": add(bpy.ops.mesh.primitive_cube_add, white, {"visible_shadow": False},
                      size=0.6, location=(0.0, 1.3, 0.4)),
        "diffuse": add(bpy.ops.mesh.primitive_uv_sphere_add, red, {"visible_diffuse": False},
                       radius=0.4, location=(1.2, -0.2, 0.45)),
        "emitter": add(bpy.ops.mesh.primitive_plane_add, emission("glow", 3.0),
                       {"visible_camera": False}, size=0.6, location=(0.3, 0.5, 1.8),
                       rotation=(3.14159265, 0.0, 0.0)),
        # An emitting panel at the floor's other edge with Glossy off, where the tilted glossy
        # patch's reflections of the camera rays go: the patch shows it only with Glossy on.
        "glossy": add(bpy.ops.mesh.primitive_plane_add, emission("mirrored", 8.0),
                      {"visible_glossy": False}, size=1.5, location=(-2.0, -1.2, 0.75),
                      rotation=(0.0, 1.5707963, 0.0)),
    }
    # An emitting panel standing at the floor's edge, facing it, with Diffuse off: still a
    # light (glossy rays see it), so light samples light the floor with their MIS weight
    # while the floor's diffuse rays pass it (Cycles' rule).
    obs["panel"] = add(bpy.ops.mesh.primitive_plane_add, emission("panel", 8.0),
                       {"visible_diffuse": False}, size=1.5, location=(2.0, -1.0, 0.75),
                       rotation=(0.0, -1.5707963, 0.0))
    # Light Path switches.
    lp_shadow = bpy.data.materials.new("no shadow")
    lp_shadow.use_nodes = True
    nt = lp_shadow.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out, mix = nt.nodes.new("ShaderNodeOutputMaterial"), nt.nodes.new("ShaderNodeMixShader")
    d, t = nt.nodes.new("ShaderNodeBsdfDiffuse"), nt.nodes.new("ShaderNodeBsdfTransparent")
    lp = nt.nodes.new("ShaderNodeLightPath")
    d.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1.0)
    nt.links.new(lp.outputs["Is Shadow Ray"], mix.inputs["Fac"])
    nt.links.new(d.outputs[0], mix.inputs[1])
    nt.links.new(t.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], out.inputs["Surface"])
    obs["lp_shadow"] = add(bpy.ops.mesh.primitive_cube_add, lp_shadow, size=0.6,
                           location=(1.2, 1.2, 0.4))
    lp_camera = bpy.data.materials.new("seen blue")
    lp_camera.use_nodes = True
    nt = lp_camera.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out, mix = nt.nodes.new("ShaderNodeOutputMaterial"), nt.nodes.new("ShaderNodeMixShader")
    e1, e2 = nt.nodes.new("ShaderNodeEmission"), nt.nodes.new("ShaderNodeEmission")
    lp = nt.nodes.new("ShaderNodeLightPath")
    e1.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    e1.inputs["Strength"].default_value = 3.0
    e2.inputs["Color"].default_value = (0.1, 0.2, 1.0, 1.0)
    e2.inputs["Strength"].default_value = 1.0
    nt.links.new(lp.outputs["Is Camera Ray"], mix.inputs["Fac"])
    nt.links.new(e1.outputs[0], mix.inputs[1])
    nt.links.new(e2.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], out.inputs["Surface"])
    obs["lp_camera"] = add(bpy.ops.mesh.primitive_uv_sphere_add, lp_camera, radius=0.3,
                           location=(-0.2, -0.3, 0.5))
    for ob in obs.values():
        if ob.type == 'MESH' and len(ob.data.polygons) > 6:
            bpy.context.view_layer.objects.active = ob
            bpy.ops.object.shade_smooth()
    # The key light: a 3 m emitting plane overhead, facing down, that the camera does not see
    # (an emitter rays can hit, so that the glossy patch's highlight is sampled with MIS in
    # both renderers; Facet's lamps are found by light samples only).
    obs["lamp"] = add(bpy.ops.mesh.primitive_plane_add, emission("lamp", 20.0),
                      {"visible_camera": False}, size=3.0, location=(0.0, 0.0, 4.0),
                      rotation=(3.14159265, 0.0, 0.0))
    cd = bpy.data.cameras.new("cam")
    cd.type = 'ORTHO'
    cd.ortho_scale = 4.0
    cam = bpy.data.objects.new("cam", cd)
    cam.location = (0.0, 0.0, 6.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.facet.max_depth = 3
    scene.facet.spp = SPP
    cs.cycles_settings(scene, samples=SPP, max_depth=3)
    # Shadow rays through the Transparent cube cross two faces; Facet's `null` crossings are no
    # bounces.
    scene.cycles.transparent_max_bounces = 8
    return scene


def check_reports():
    """A switch Facet cannot take where it is is reported, naming the node: a Mix Shader by Is
    Shadow Ray with a Transparent BSDF inside an Add Shader (the core switches shadow rays for
    a whole surface; its first shader is used). Other ray outputs inside a Mix or Add Shader
    convert to light_path weights (test_cycles_light_path.py)."""
    from facet_blender import materials
    mat = bpy.data.materials.new("shadow inside add")
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out, mix = nt.nodes.new("ShaderNodeOutputMaterial"), nt.nodes.new("ShaderNodeMixShader")
    d, t = nt.nodes.new("ShaderNodeBsdfDiffuse"), nt.nodes.new("ShaderNodeBsdfTransparent")
    lp = nt.nodes.new("ShaderNodeLightPath")
    nt.links.new(lp.outputs["Is Shadow Ray"], mix.inputs["Fac"])
    nt.links.new(d.outputs[0], mix.inputs[1])
    nt.links.new(t.outputs[0], mix.inputs[2])
    top = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(mix.outputs[0], top.inputs[0])
    nt.links.new(nt.nodes.new("ShaderNodeBsdfGlossy").outputs[0], top.inputs[1])
    nt.links.new(top.outputs[0], out.inputs["Surface"])
    conv = materials.convert(mat)
    lines = [p for p in conv.problems if "Is Shadow Ray" in p]
    bt.check(len(lines) == 1 and not conv.light_path,
             "reported, no switch: %s" % conv.problems)
    bpy.data.materials.remove(mat)


def within(res):
    return abs(res[0] - 1.0) <= MEAN_TOL and res[1] <= RMSE_FACTOR


def main():
    out = bt.args()[0]
    bt.enable_addon()
    check_reports()
    scene = build_scene()
    c1, _ = cs.render(scene, 'CYCLES', os.path.join(out, "rayvis_cycles1.exr"), 1)
    c2, _ = cs.render(scene, 'CYCLES', os.path.join(out, "rayvis_cycles2.exr"), 2)
    data = json.loads(cs.facet_description(scene))
    from facet_blender import export
    _, problems = export.export_scene(bpy.context.evaluated_depsgraph_get(), mesh_cache={})
    lines = sorted(p for p in problems if p.startswith("object 'Plane"))
    bt.check(len(lines) == 2 and any("Diffuse off" in p for p in lines)
             and any("Glossy off" in p for p in lines),
             "the diffuse-off and glossy-off emitters are reported (mixed materials lit "
             "whole): %s" % problems)
    flags = sorted(tuple(sorted(s["visibility"])) for s in data["shapes"] if "visibility" in s)
    bt.check(flags == [("camera",)] * 3 + [("diffuse",)] * 2 + [("glossy",), ("shadow",)],
             "the export carries each object's flag: %s" % flags)
    switches = sorted(json.dumps(s["light_path"], sort_keys=True) for s in data["shapes"]
                      if "light_path" in s)
    bt.check(len(switches) == 2 and '"ray": "shadow"' in switches[1]
             and '"null"' in switches[1] and '"ray": "camera"' in switches[0]
             and '"emission"' in switches[0],
             "the export carries the Light Path switches: %s" % switches)
    f, _ = cs.render(scene, 'FACET', os.path.join(out, "rayvis_facet1.exr"), 1)
    res = cs.compare_to_cycles("Facet", f, c1, c2, BLOCK)
    bt.check(within(res), "Facet matches Cycles with ray visibility (mean within %g, block "
             "RMSE <= %g x floor)" % (MEAN_TOL, RMSE_FACTOR))

    # Control: the flags ignored must break a bound.
    saved = export.ray_visibility
    export.ray_visibility = lambda obj, inst=None: {}
    try:
        f, _ = cs.render(scene, 'FACET', os.path.join(out, "rayvis_facet_ignored.exr"), 1)
    finally:
        export.ray_visibility = saved
    bt.check(not within(cs.compare_to_cycles("Facet, flags ignored", f, c1, c2, BLOCK)),
             "with the flags ignored a bound breaks: the test can fail")
    # Each flag ignored alone (on every object) must break a bound too.
    for flag in ("camera", "diffuse", "glossy", "shadow"):
        export.ray_visibility = (lambda obj, inst=None, flag=flag:
                                 {k: v for k, v in saved(obj, inst).items() if k != flag})
        try:
            f, _ = cs.render(scene, 'FACET', os.path.join(out, "rayvis_facet_no_%s.exr" % flag),
                             1)
        finally:
            export.ray_visibility = saved
        bt.check(not within(cs.compare_to_cycles("Facet, no %s flag" % flag, f, c1, c2, BLOCK)),
                 "with the %s flags ignored a bound breaks" % flag)
    # Control: the Light Path switches dropped must break a bound.
    from facet_blender import materials
    saved = materials.light_path_switches

    def dropped(data, emission, notes):
        d, e, _ = saved(data, emission, notes)
        return d, e, []
    materials.light_path_switches = dropped
    try:
        f, _ = cs.render(scene, 'FACET', os.path.join(out, "rayvis_facet_nolp.exr"), 1)
    finally:
        materials.light_path_switches = saved
    bt.check(not within(cs.compare_to_cycles("Facet, no switches", f, c1, c2, BLOCK)),
             "with the Light Path switches dropped a bound breaks: the test can fail")


bt.run(main)
