"""Texture Coordinate's view-dependent outputs (Normal, Reflection, Camera, Window) feeding
procedural textures, converted natively (facet_blender/textures.py _affine -> the core's
"coordinates" "normal", "reflection", "camera", "window", FORMAT.md "Procedural textures").

1. Exported data: each output converts to its coordinates, without a report and without a bake.
2. Renders against Cycles, 16 spp in both, box filter 1 px, emission only (the radiance is the
   texture):
   - spheres (smooth UV spheres, 64 x 32, each turned so that object space differs from world
     space), one mode each, under an orthographic camera, and one more with Object coordinates
     through the Mix node's Vector mode (factor 0.3 toward a constant vector). The criterion
     is issue 35's: per sphere, the mean over its pixels of |Facet - Cycles| <= 1e-3 of
     Cycles' range over them.
     The pixels are those whose whole footprint lies 3 px inside the sphere's silhouette
     (the silhouette's partly covered pixels differ by the two renderers' own jittered
     coverage, not by the texture: 16 samples of a 0/1 coverage, not the texture's error);
   - a tilted plane filling a perspective camera's view (lens shift x 0.1), once with Window
     and once with Camera coordinates, where the projection matters (the same criterion over
     the whole image).
   The differences are unbiased sampling noise (their signed mean is ~1e-5 at every radius);
   Cycles seed 1 against seed 2 is printed beside each, the floor.
   Controls that must fail the same criterion, each the plausible mistake rendered by Facet
   through a Mapping node put in front of the texture: Normal in world space (the object's
   rotation undone), Reflection negated (the view direction's sign), Camera with z toward the
   viewer (Blender's camera looks down its -z), Window with y from the top (film rows).
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
PX = 96  # pixels per sphere block
RADIUS = 0.45
new_material = bt.new_material

# (Texture Coordinate output, noise scale, the sphere's rotation, the control's Mapping:
# (location, rotation, scale) applied to the coordinates before the texture).
ROT = (0.5, 0.8, 1.2)
MODES = [
    ("Normal", 1.5, ROT, None),  # control: the object's rotation undone (set below)
    # (Reflection turns twice as fast as the normal: a larger noise feature for the same
    # variation per pixel.)
    ("Reflection", 1.0, ROT, ((0, 0, 0), (0, 0, 0), (-1, -1, -1))),
    ("Camera", 1.2, ROT, ((0, 0, 0), (0, 0, 0), (1, 1, -1))),
    ("Window", 6.0, ROT, ((0, 1, 0), (0, 0, 0), (1, -1, 1))),
    # The Mix node's Vector mode between Object coordinates and a constant, factor 0.3
    # (control: the factor's weight on the wrong side, as a scale).
    ("Mix", 2.0, ROT, ((0, 0, 0), (0, 0, 0), (1.5, 1.5, 1.5))),
]


def emission_noise(name, which, scale, control=None):
    """A material emitting a Noise Texture's colour at Texture Coordinate `which` (through a
    Mapping (location, rotation, scale) when `control`)."""
    mat, nt, out = new_material(name)
    tc = nt.nodes.new("ShaderNodeTexCoord")
    if which == "Mix":
        mix = nt.nodes.new("ShaderNodeMix")
        mix.data_type = 'VECTOR'
        mix.inputs["Factor"].default_value = 0.3
        nt.links.new(tc.outputs["Object"], mix.inputs[4])  # A (Vector)
        mix.inputs[5].default_value = (0.2, 0.5, -0.1)  # B (Vector)
        vec = mix.outputs[1]  # Result (Vector)
    else:
        vec = tc.outputs[which]
    if control is not None:
        m = nt.nodes.new("ShaderNodeMapping")
        m.vector_type = 'POINT'
        m.inputs["Location"].default_value = control[0]
        m.inputs["Rotation"].default_value = control[1]
        m.inputs["Scale"].default_value = control[2]
        nt.links.new(vec, m.inputs["Vector"])
        vec = m.outputs[0]
    t = nt.nodes.new("ShaderNodeTexNoise")
    for k, v in {"Scale": scale, "Detail": 2.0, "Roughness": 0.5, "Distortion": 0.0}.items():
        t.inputs[k].default_value = v
    nt.links.new(vec, t.inputs["Vector"])
    e = nt.nodes.new("ShaderNodeEmission")
    nt.links.new(t.outputs["Color"], e.inputs["Color"])
    nt.links.new(e.outputs[0], out.inputs["Surface"])
    return mat


def empty_scene(w, h):
    bpy.ops.wm.read_homefile(use_factory_startup=True)
    scene = bpy.context.scene
    for ob in list(scene.objects):
        bpy.data.objects.remove(ob)
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    scene.facet.spp = SPP
    scene.facet.max_depth = 1
    cs.cycles_settings(scene, samples=SPP, seed=1, max_depth=1)
    return scene


def sphere_scene(controls=False):
    n = len(MODES)
    scene = empty_scene(PX * n, PX)
    for i, (which, scale, rot, control) in enumerate(MODES):
        bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=RADIUS,
                                             location=(i + 0.5, 0.5, 0.0), rotation=rot)
        ob = bpy.context.active_object
        ob.name = "sphere_" + which.lower()
        bpy.ops.object.shade_smooth()
        if controls and which == "Normal":
            # World space instead of object space: the object's rotation applied to the
            # object-space normal (Mapping rotates by Rz Ry Rx, Blender's XYZ Euler).
            control = ((0, 0, 0), rot, (1, 1, 1))
        ob.data.materials.append(emission_noise("tc_" + which.lower(), which, scale,
                                                control if controls else None))
    bt.ortho_camera(scene, n, (n / 2.0, 0.5, 5.0))
    return scene


def inner_mask():
    """Pixels (of one block) whose footprint lies 3 px inside the sphere's silhouette (the
    64-gon's inscribed circle)."""
    y, x = np.mgrid[0:PX, 0:PX] + 0.5
    r = np.hypot(x - PX / 2.0, y - PX / 2.0)
    return r + math.sqrt(0.5) <= RADIUS * math.cos(math.pi / 64) * PX - 3.0


def plane_scene(which, control=None):
    """A plane tilted in front of a perspective camera with lens shift, filling its view."""
    scene = empty_scene(192, 128)
    bpy.ops.mesh.primitive_plane_add(size=40.0, location=(0.0, 0.0, 0.0),
                                     rotation=(0.35, -0.2, 0.0))
    ob = bpy.context.active_object
    ob.data.materials.append(emission_noise("plane_" + which.lower(), which,
                                            6.0 if which == "Window" else 0.8, control))
    cam = bpy.data.cameras.new("cam")
    cam.lens = 35.0
    cam.shift_x = 0.1
    cob = bpy.data.objects.new("cam", cam)
    cob.location = (0.3, -0.2, 4.0)
    cob.rotation_euler = (0.1, 0.05, 0.2)
    scene.collection.objects.link(cob)
    scene.camera = cob
    return scene


def exported():
    from facet_blender import materials
    sphere_scene()
    for which, _, _, _ in MODES:
        ob = bpy.data.objects["sphere_" + which.lower()]
        c = materials.convert(ob.data.materials[0], ob)
        em = c.emission
        want = "object" if which == "Mix" else which.lower()
        bt.check(isinstance(em, dict) and not c.baked and c.problems == []
                 and em.get("coordinates") == want and "noise" in em,
                 "%s converts natively: %s, problems %s" % (which, em, c.problems))
        if which == "Mix":
            m = em["mapping"]["matrix"]
            bt.check(abs(m[0][0] - 0.7) < 1e-6 and abs(m[1][3] - 0.15) < 1e-6
                     and abs(m[2][3] + 0.03) < 1e-6, "Mix Vector -> mapping %s" % m)


def criterion(name, a, b, mask=None, control=False):
    if mask is not None:
        a, b = a[mask], b[mask]
    rng = max(float(b.max() - b.min()), 1e-3)
    d = float(np.abs(a - b).mean())
    print("%-26s mean |Facet - Cycles| %.3g = %.3g of the range %.3g"
          % (name, d, d / rng, rng))
    if control:
        bt.check(d > 1e-3 * rng, "control %s fails the criterion (%.3g)" % (name, d / rng))
        return None
    return None if d <= 1e-3 * rng else "%s: %.3g > 1e-3 x range %.3g" % (name, d, rng)


def rendered(outdir):
    from facet_blender import hooks
    failed = []
    mask = inner_mask()
    scene = sphere_scene()
    a, _ = cs.render(scene, 'FACET', os.path.join(outdir, "texcoord_facet.exr"), seed=1)
    bt.check(list(hooks.last_problems) == [], "the spheres convert without a report: %s"
             % list(hooks.last_problems))
    b, _ = cs.render(scene, 'CYCLES', os.path.join(outdir, "texcoord_cycles.exr"), seed=1)
    # Cycles against itself (another seed): the floor the 16-sample difference sits on.
    b2, _ = cs.render(scene, 'CYCLES', os.path.join(outdir, "texcoord_cycles2.exr"), seed=2)
    scene = sphere_scene(controls=True)
    c, _ = cs.render(scene, 'FACET', os.path.join(outdir, "texcoord_control.exr"), seed=1)
    for i, (which, _, _, _) in enumerate(MODES):
        blk = slice(PX * i, PX * (i + 1))
        bt.check(float(b[:, blk][mask].min()) >= 0.0 and float(b[:, blk][mask].max()) > 0.0,
                 "Cycles renders sphere %s" % which)
        failed.append(criterion("sphere " + which, a[:, blk], b[:, blk], mask))
        criterion("(floor: Cycles seed 2) " + which, b2[:, blk], b[:, blk], mask)
        criterion("control sphere " + which, c[:, blk], b[:, blk], mask, control=True)
    for which, control in (("Window", ((0, 1, 0), (0, 0, 0), (1, -1, 1))),
                           ("Camera", ((0, 0, 0), (0, 0, 0), (1, 1, -1)))):
        scene = plane_scene(which)
        a, _ = cs.render(scene, 'FACET', os.path.join(outdir, "texcoord_plane_facet.exr"),
                         seed=1)
        b, _ = cs.render(scene, 'CYCLES', os.path.join(outdir, "texcoord_plane_cycles.exr"),
                         seed=1)
        failed.append(criterion("perspective plane " + which, a, b))
        scene = plane_scene(which, control)
        c, _ = cs.render(scene, 'FACET', os.path.join(outdir, "texcoord_plane_control.exr"),
                         seed=1)
        criterion("control perspective " + which, c, b, control=True)
    failed = [f for f in failed if f]
    bt.check(not failed, "within 1e-3 of the range: " + "; ".join(failed))


def main():
    bt.enable_addon()
    outdir = bt.args()[0]
    exported()
    rendered(outdir)


bt.run(main)
