"""Blender volumes -> the core's homogeneous media (issue 36, item 4), against Cycles 3.4.

Conversions (exported JSON, no render): a Principled Volume, a Volume Scatter, a Volume
Absorption and an Emission on a material's Volume output, an Add and a Mix Shader of volume
shaders, Glass + Volume (the medium is the glass's interior), an opaque surface + Volume
(reported, the surface alone), Blackbody Intensity and a textured Density (reported by node and
input), the world's Volume (world_medium), an empty VOLUME object and Cycles' factory Volume bounces
(reported). Each coefficient is checked against Cycles 3.4's formulas written here
independently (svm_node_principled_volume, svm_node_closure_volume), to float precision.

Renders, Facet (through the export) against Cycles (cycles_scene.cycles_settings: box filter,
no clamping, bounces = Facet's max_depth - 1 in every category, volumes included), 64 x 48, two
seeds each:
- cube: the factory cube with a Principled Volume (density 1, a colour, anisotropy 0.3) and
  nothing on its Surface, on a grey floor, under a point lamp (radius 0) and a grey world;
- fog: a world Volume Scatter of density 0.05 (Color 0.8: Cycles' Volume Scatter has no
  absorption, which this checks) with a spot lamp above the frame over a floor; the world's
  background is black (inside a world medium neither renderer sees the environment: an
  infinite ray's transmittance is 0; black makes the two agree whatever either does with it).
Tolerances, from the noise as the other Cycles tests (cycles_scene.block_z): per 8 x 8 block
and channel, z = (Facet - Cycles) / sqrt(var) with the variance from each renderer's seed pair,
|z| < 5; and the image means within 2% (the issue's bound; the noise of the mean is far below
it at these sample counts, printed). Ability to fail: Facet with the density halved (the cube),
the fog's density halved, or the fog with sigma_a = 0.05 (1 - Color) added must break one of
the two bounds, and does (numbers printed)."""
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

W, H = 64, 48
BLOCK = 8
Z_MAX = 5.0
MEAN_TOL = 0.02
MAX_DEPTH = 8


def export():
    from facet_blender import export as ex
    return ex.export_scene(bpy.context.evaluated_depsgraph_get(), mesh_cache={})


def close(a, b, tol=1e-6):
    a, b = np.atleast_1d(np.asarray(a, float)), np.atleast_1d(np.asarray(b, float))
    return a.shape == b.shape and np.allclose(a, b, rtol=tol, atol=tol)


def volume_material(name, kind, inputs=None, surface=None):
    """A material with `kind` (a volume node's bl_idname) on the output's Volume and, when
    given, a `surface` node on its Surface."""
    mat, nt, out = bt.new_material(name)
    node = nt.nodes.new(kind)
    for k, v in (inputs or {}).items():
        node.inputs[k].default_value = v
    nt.links.new(node.outputs[0], out.inputs["Volume"])
    if surface is not None:
        s = nt.nodes.new(surface)
        nt.links.new(s.outputs[0], out.inputs["Surface"])
    return mat, node


def use(mat, obj_name="Cube"):
    ob = bpy.data.objects[obj_name]
    ob.data.materials.clear()
    ob.data.materials.append(mat)


# --- Cycles 3.4's formulas, written independently of the addon -------------------------------

def principled(density, color, absorption):
    c, a = np.asarray(color[:3], float), np.asarray(absorption[:3], float)
    d = max(density, 0.0)
    ss = d * c
    sa = d * np.maximum(1 - c, 0) * np.maximum(1 - np.sqrt(np.maximum(a, 0)), 0)
    return sa, ss


def case_conversions():
    bt.factory_scene(W, H)
    scene = bpy.context.scene
    # Principled Volume: every constant input.
    col, absn, em = (0.8, 0.5, 0.2, 1), (0.1, 0.2, 0.3, 1), (1.0, 0.5, 0.25, 1)
    mat, node = volume_material("PV", "ShaderNodeVolumePrincipled", {
        "Density": 2.0, "Color": col, "Absorption Color": absn, "Anisotropy": 0.3,
        "Emission Strength": 1.5, "Emission Color": em})
    use(mat)
    data, problems = export()
    m = data["media"]["PV"]
    sa, ss = principled(2.0, col, absn)
    bt.check(dict(data["materials"])["PV"] == {"model": "null", "interior": "PV"},
             "a volume alone: the null boundary of medium 'PV'")
    bt.check(m["kind"] == "homogeneous" and close(m["sigma_a"], sa) and close(m["sigma_s"], ss)
             and close(m["g"], 0.3) and close(m["emission"], [1.5, 0.75, 0.375]),
             "Principled Volume: sigma_a %s, sigma_s %s, g, emission %s" % (
                 m["sigma_a"], m["sigma_s"], m["emission"]))
    bt.check(not [p for p in problems if "'PV'" in p],
             "no line for a converted volume (and never 'nothing connected'): %s"
             % [p for p in problems if "'PV'" in p])
    bt.check(any("Max Bounces > Volume = 0" in p for p in problems),
             "Cycles' factory Volume bounces (single scattering) are reported")
    # Blackbody and a textured Density: reported by material, node and input.
    node.inputs["Blackbody Intensity"].default_value = 1.0
    tex = mat.node_tree.nodes.new("ShaderNodeTexNoise")
    mat.node_tree.links.new(tex.outputs["Fac"], node.inputs["Density"])
    data, problems = export()
    mine = [p for p in problems if "material 'PV'" in p]
    bt.check(any("'Principled Volume' input 'Blackbody Intensity'" in p for p in mine),
             "Blackbody Intensity reported by node and input: %s" % mine)
    bt.check(any("Noise Texture 'Noise Texture'" in p and "input 'Density'" in p for p in mine),
             "a textured Density reported by node and input: %s" % mine)
    bt.check(close(data["media"]["PV"]["sigma_s"], principled(2.0, col, absn)[1]),
             "the textured Density uses the input's own value")

    # Volume Scatter, Volume Absorption, Emission on a Volume output.
    mat, _ = volume_material("VS", "ShaderNodeVolumeScatter", {
        "Color": (0.9, 0.6, 0.3, 1), "Density": 0.5, "Anisotropy": -0.4})
    use(mat)
    m = export()[0]["media"]["VS"]
    bt.check(close(m["sigma_s"], [0.45, 0.3, 0.15]) and close(m["sigma_a"], [0, 0, 0])
             and close(m["g"], -0.4), "Volume Scatter: sigma_s = Density Color, no absorption")
    mat, _ = volume_material("VA", "ShaderNodeVolumeAbsorption", {
        "Color": (0.9, 0.6, 0.3, 1), "Density": 0.5})
    use(mat)
    m = export()[0]["media"]["VA"]
    bt.check(close(m["sigma_a"], [0.05, 0.2, 0.35]) and close(m["sigma_s"], [0, 0, 0])
             and "g" not in m, "Volume Absorption: sigma_a = Density (1 - Color)")
    mat, _ = volume_material("VE", "ShaderNodeEmission", {"Color": (1, 0.5, 0, 1),
                                                          "Strength": 2.0})
    use(mat)
    m = export()[0]["media"]["VE"]
    bt.check(close(m["emission"], [2, 1, 0]) and close(m["sigma_a"] + m["sigma_s"], [0] * 6),
             "Emission on Volume: emission = Color x Strength per unit length")

    # Add and Mix Shaders of volume shaders: the sigmas (and emissions) add, weighted.
    mat, nt, out = bt.new_material("MIX")
    a = nt.nodes.new("ShaderNodeVolumeScatter")
    a.inputs["Density"].default_value = 1.0
    a.inputs["Anisotropy"].default_value = 0.5
    b = nt.nodes.new("ShaderNodeVolumeAbsorption")
    b.inputs["Density"].default_value = 2.0
    b.inputs["Color"].default_value = (0.5, 0.25, 0.0, 1)
    mix = nt.nodes.new("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = 0.25
    nt.links.new(a.outputs[0], mix.inputs[1])
    nt.links.new(b.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], out.inputs["Volume"])
    use(mat)
    data, problems = export()
    m = data["media"]["MIX"]
    bt.check(close(m["sigma_s"], [0.75 * 0.8] * 3) and close(m["sigma_a"], [0.25, 0.375, 0.5])
             and close(m["g"], 0.5), "Mix Shader 0.25: 0.75 scatter + 0.25 absorption: %s" % m)
    add = nt.nodes.new("ShaderNodeAddShader")
    c = nt.nodes.new("ShaderNodeVolumeScatter")
    c.inputs["Anisotropy"].default_value = -0.2
    nt.links.new(a.outputs[0], add.inputs[0])
    nt.links.new(c.outputs[0], add.inputs[1])
    nt.links.new(add.outputs[0], out.inputs["Volume"])
    data, problems = export()
    m = data["media"]["MIX"]
    mine = [p for p in problems if "material 'MIX'" in p]
    bt.check(close(m["sigma_s"], [1.6] * 3) and any("Add Shader" in p and "Anisotropy" in p
                                                    for p in mine),
             "Add Shader: sigmas add; different anisotropies reported: %s" % mine)

    # Glass + Volume: the medium is the glass' interior. Diffuse + Volume: reported.
    mat, _ = volume_material("GV", "ShaderNodeVolumeAbsorption", {"Density": 1.0},
                             surface="ShaderNodeBsdfGlass")
    use(mat)
    data, problems = export()
    d = dict(data["materials"])["GV"]
    bt.check(d.get("model") == "dielectric" and d.get("interior") == "GV" and "GV" in
             data["media"], "Glass + Volume: dielectric with the interior 'GV': %s" % d)
    mat, _ = volume_material("DV", "ShaderNodeVolumeScatter", surface="ShaderNodeBsdfDiffuse")
    use(mat)
    data, problems = export()
    d = dict(data["materials"])["DV"]
    mine = [p for p in problems if "material 'DV'" in p]
    bt.check(d.get("model") == "lambert" and "interior" not in d and "media" not in data
             and len(mine) == 1 and "opaque" in mine[0] and "Volume Scatter" in mine[0],
             "Diffuse + Volume: the surface alone, reported: %s" % mine)

    # The world's Volume -> world_medium.
    world = scene.world
    wo = next(n for n in world.node_tree.nodes if n.bl_idname == 'ShaderNodeOutputWorld')
    fog = world.node_tree.nodes.new("ShaderNodeVolumeScatter")
    fog.inputs["Density"].default_value = 0.05
    world.node_tree.links.new(fog.outputs[0], wo.inputs["Volume"])
    data, problems = export()
    wm = data.get("world_medium")
    bt.check(wm is not None and close(data["media"][wm]["sigma_s"], [0.04] * 3),
             "world Volume Scatter -> world_medium %s" % data["media"].get(wm))

    # A VOLUME object without grids: named in the report (test_cycles_smoke.py converts
    # one with grids).
    vo = bpy.data.objects.new("Smoke", bpy.data.volumes.new("smoke"))
    scene.collection.objects.link(vo)
    _, problems = export()
    bt.check(any(p.startswith("object 'Smoke': volume has no grids") for p in problems),
             "the empty VOLUME object is reported by name")


def block_compare(name, facet, cycles):
    """(max |z| over 8 x 8 blocks, mean ratio Facet / Cycles, the means' relative noise)."""
    z = cs.block_z(facet, cycles, BLOCK)[0]
    mf, mc = 0.5 * (facet[0] + facet[1]), 0.5 * (cycles[0] + cycles[1])
    ratio = mf.mean() / mc.mean()
    # The noise of each image mean from its seed pair (one render's variance (a - b)^2 / 2
    # summed over pixels, so the pair mean's is that / 2): relative standard error.
    se = math.sqrt(sum(((p[0] - p[1]) ** 2).sum() / 4.0 for p in (facet, cycles))) / \
        mf.size / mc.mean()
    print("%-10s max|z| %.2f, mean Facet/Cycles %.4f (noise of the ratio %.4f)"
          % (name, np.abs(z).max(), ratio, se))
    return float(np.abs(z).max()), float(ratio), se


def renders(scene, name, out, spp, engines=('FACET', 'CYCLES')):
    scene.facet.max_depth = MAX_DEPTH
    scene.facet.spp = spp
    cs.cycles_settings(scene, samples=spp, max_depth=MAX_DEPTH)
    return {e: tuple(cs.render(scene, e, os.path.join(out, "volume_%s_%s_%d.exr"
                                                        % (name, e.lower(), seed)), seed)[0]
                     for seed in (1, 2)) for e in engines}


def agree(name, imgs):
    zmax, ratio, _ = block_compare(name, imgs['FACET'], imgs['CYCLES'])
    bt.check(zmax < Z_MAX and abs(ratio - 1.0) < MEAN_TOL,
             "%s: Facet and Cycles agree (max|z| %.2f < %g, mean ratio %.4f within %g)"
             % (name, zmax, Z_MAX, ratio, MEAN_TOL))
    return imgs['CYCLES']


def fails(name, facet, cycles):
    zmax, ratio, _ = block_compare(name, facet, cycles)
    bt.check(zmax >= Z_MAX or abs(ratio - 1.0) >= MEAN_TOL,
             "%s: the wrong medium breaks the bounds (max|z| %.2f, mean ratio %.4f)"
             % (name, zmax, ratio))


def floor(scene, size=20.0, z=-1.05):
    bpy.ops.mesh.primitive_plane_add(size=size, location=(0.0, 0.0, z))
    ob = bpy.context.active_object
    ob.name = "Floor"
    mat, nt, out = bt.new_material("FloorMat")
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1)
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    ob.data.materials.append(mat)


def case_cube(out):
    scene = bt.factory_scene(W, H)
    light = bpy.data.objects["Light"].data
    light.shadow_soft_size = 0.0  # Cycles 3.4's radius is a disc (reported): a point lamp
    mat, node = volume_material("Smoke", "ShaderNodeVolumePrincipled", {
        "Density": 1.0, "Color": (0.8, 0.5, 0.3, 1), "Anisotropy": 0.3})
    use(mat)
    floor(scene)
    imgs = renders(scene, "cube", out, 128)
    cyc = agree("cube", imgs)
    node.inputs["Density"].default_value = 0.5
    half = renders(scene, "cube_half", out, 128, engines=('FACET',))['FACET']
    fails("cube/2", half, cyc)


def case_fog(out):
    scene = bt.factory_scene(W, H)
    bpy.data.objects.remove(bpy.data.objects["Cube"])
    lamp = bpy.data.objects["Light"]
    ld = bpy.data.lights.new("Spot", 'SPOT')
    ld.energy = 1000.0
    ld.shadow_soft_size = 0.0
    ld.spot_size = math.radians(40.0)
    ld.spot_blend = 0.15
    spot = bpy.data.objects.new("Spot", ld)
    # Pointing down (-Z), above the frame: near a point lamp Facet's distance sampling of
    # the fog has a heavy-tailed estimate (NEE's 1/r^2 along rays passing close to it; Cycles
    # samples equiangularly), so with the lamp in view (z = 3) two seeds of 256 spp
    # under-estimate those blocks (measured 0.78 of Cycles, max|z| 3.6: the seed pairs
    # under-estimate the variance too).
    spot.location = (0.0, 0.0, 6.0)
    scene.collection.objects.link(spot)
    bpy.data.objects.remove(lamp)
    floor(scene)
    world = scene.world
    nt = world.node_tree
    bg = next(n for n in nt.nodes if n.bl_idname == 'ShaderNodeBackground')
    bg.inputs["Strength"].default_value = 0.0  # inside the fog neither renderer sees it
    wo = next(n for n in nt.nodes if n.bl_idname == 'ShaderNodeOutputWorld')
    fog = nt.nodes.new("ShaderNodeVolumeScatter")
    fog.inputs["Density"].default_value = 0.05
    nt.links.new(fog.outputs[0], wo.inputs["Volume"])
    imgs = renders(scene, "fog", out, 256)
    cyc = agree("fog", imgs)
    fog.inputs["Density"].default_value = 0.025
    half = renders(scene, "fog_half", out, 256, engines=('FACET',))['FACET']
    fails("fog/2", half, cyc)
    # The same fog with absorption: sigma_a = 0.05 (1 - 0.8) as a Principled Volume of
    # Absorption Color 0 has it (the former reading of Volume Scatter in FORMAT.md): must
    # differ from Cycles' Volume Scatter, which has none.
    pv = nt.nodes.new("ShaderNodeVolumePrincipled")
    pv.inputs["Density"].default_value = 0.05
    pv.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1)
    pv.inputs["Absorption Color"].default_value = (0, 0, 0, 1)
    nt.links.new(pv.outputs[0], wo.inputs["Volume"])
    absorbing = renders(scene, "fog_absorbing", out, 256, engines=('FACET',))['FACET']
    fails("fog+sigma_a", absorbing, cyc)


def main():
    out = bt.args()[0]
    bt.enable_addon()
    case_conversions()
    case_cube(out)
    case_fog(out)


bt.run(main)
