"""Light units checked by render against Cycles and against the analytic irradiance.

Each case is a Lambertian plane (rho = 0.5, z = 0, Diffuse BSDF: Facet converts it to lambert
exactly) lit by one Blender light, seen from a camera 1.5 m above it looking straight down
(90 degree vertical field of view, 64 x 64; lights above the camera, so none is in view), direct
lighting only (Facet max_depth 1 = Cycles 0 bounces). Facet renders through the addon's export
(units.py's conversions), Cycles renders the same Blender light natively. The pixel of plane
point p is rho/pi E(p), the irradiance E (Cycles' units, units.py):
- point of Power P at height h: E = P/(4 pi) cos(theta) / r^2;
- spot (blend 0): Cycles 3.4's intensity is P/(4 pi) cos(angle from the axis) inside the
  cone, 0 outside (measured: the ratio to P/(4 pi) is cos to 1e-3 in every ring); the addon
  exports Blender's form of Facet's spot (outer_angle + spot_blend), which has the same
  fall-off, so both are checked against it;
- point of Power P and Radius R: Cycles 3.4's disc facing the point, E d^2 / (d^2 + R^2), in
  both (the addon's default Lamp Model, Facet's "radius_model": "cycles34_disc");
- sun of Strength S tilted 30 degrees: E = S cos 30;
- square area light of Power P and size a: radiance L = P / (4 a^2) one-sided, E = pi L F with
  F the form factor of a differential area to a parallel rectangle (corner decomposition);
- disc area light of diameter a: L = P / (4 pi a^2 / 4); F of a parallel disc off axis,
  F = (1 - (h^2 + d^2 - R^2) / sqrt((h^2 + d^2 + R^2)^2 - 4 R^2 d^2)) / 2;
- an emissive quad of the Facet scene format (a mesh light in Cycles, through
  cycles_scene.convert with one-sided emission): radiance L given, the square's F.
The analytic pixel value averages 8 x 8 points per pixel; pixels a spot's cone edge crosses are
left out (their value depends on the exact sub-pixel position of a discontinuity).

Tolerance from the measured noise: every renderer renders twice (seeds 1, 2); over blocks of
8 x 8 pixels, z = (a - b) / sqrt(var) with the variance from the seed pairs
(cycles_scene.block_z), for Facet vs Cycles and for each renderer vs the analytic values
(whose own error, the 8 x 8 quadrature, is below 1e-4 relative here). |z| < 5 everywhere;
the mean ratio to the analytic value is printed per case."""
import json
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

RES = 64
CAM_H = 1.5
RHO = 0.5
BLOCK = 8
Z_MAX = 5.0
SUB = 8


def plane_points():
    """(RES, RES, SUB*SUB, 2) plane points of each pixel's sub-samples (FORMAT.md's camera)."""
    t = (np.arange(SUB) + 0.5) / SUB
    px = np.arange(RES)[:, None] + t[None, :]  # (RES, SUB)
    s = 2.0 * px / RES - 1.0  # tan 45 = 1
    sx = s[None, :, None, :]           # x along columns
    sy = -s[:, None, :, None]          # y up, rows downward
    x = np.broadcast_to(CAM_H * sx, (RES, RES, SUB, SUB)).reshape(RES, RES, -1)
    y = np.broadcast_to(CAM_H * sy, (RES, RES, SUB, SUB)).reshape(RES, RES, -1)
    return x, y


def rect_ff(x, y, h, x0, x1, y0, y1):
    """Form factor from a point (x, y) on z = 0 (normal +z) to the parallel rectangle
    [x0, x1] x [y0, y1] at height h (facing down)."""
    def corner(a, b):
        X, Y = a / h, b / h
        sx, sy = np.sqrt(1 + X * X), np.sqrt(1 + Y * Y)
        return (X / sx * np.arctan(Y / sx) + Y / sy * np.arctan(X / sy)) / (2 * math.pi)
    return (corner(x1 - x, y1 - y) - corner(x0 - x, y1 - y) - corner(x1 - x, y0 - y)
            + corner(x0 - x, y0 - y))


def disc_ff(x, y, h, cx, cy, r):
    d2 = (x - cx) ** 2 + (y - cy) ** 2
    return 0.5 * (1.0 - (h * h + d2 - r * r) / np.sqrt((h * h + d2 + r * r) ** 2
                                                        - 4.0 * r * r * d2))


def base_scene():
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x = scene.render.resolution_y = RES
    scene.render.resolution_percentage = 100
    scene.world = None
    bpy.ops.mesh.primitive_plane_add(size=8.0)
    mat = bpy.data.materials.new("plane")
    bt.single_shader(mat, "ShaderNodeBsdfDiffuse",
                     {"Color": (RHO, RHO, RHO, 1.0), "Roughness": 0.0})
    bpy.context.object.data.materials.append(mat)
    cd = bpy.data.cameras.new("cam")
    cd.sensor_fit = 'VERTICAL'
    cd.angle_y = math.radians(90.0)
    cam = bpy.data.objects.new("cam", cd)
    cam.location = (0.0, 0.0, CAM_H)
    scene.collection.objects.link(cam)
    scene.camera = cam
    return scene


def quad_scene(out, L, a, h):
    """A Facet JSON scene: the plane, the camera and an emissive quad (a mesh light)."""
    hx = 0.5 * a
    data = {"format": "facet-scene", "version": 1,
            "camera": {"position": [0, 0, CAM_H], "look_at": [0, 0, 0], "up": [0, 1, 0],
                       "fov": 90, "width": RES, "height": RES},
            "materials": {"plane": {"model": "lambert", "reflectance": RHO}},
            "shapes": [{"type": "quad", "name": "plane", "material": "plane",
                        "vertices": [[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]]},
                       {"type": "quad", "name": "light", "emission": L,
                        "vertices": [[-hx, -hx, h], [-hx, hx, h], [hx, hx, h], [hx, -hx, h]]}],
            "render": {"max_depth": 1}}
    path = os.path.join(out, "lights_quad.json")
    with open(path, "w") as f:
        json.dump(data, f)
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.import_scene.facet(filepath=path)
    scene = bpy.context.scene
    notes = cs.convert(scene, exact=True)
    bt.check(notes == [], "the emissive-quad scene converts exactly")
    return scene


def run_case(name, scene, analytic, spp, out, keep=None):
    """analytic: the expected image (h, w), or {engine: image} where the two models differ."""
    scene.facet.max_depth = 1
    scene.facet.spp = spp
    cs.cycles_settings(scene, samples=spp, max_depth=1)
    if not isinstance(analytic, dict):
        analytic = {'FACET': analytic, 'CYCLES': analytic}
    ref = {e: np.repeat(v[..., None], 3, axis=2) for e, v in analytic.items()}
    imgs = {}
    for engine in ('FACET', 'CYCLES'):
        imgs[engine] = tuple(cs.render(scene, engine, os.path.join(
            out, "lights_%s_%s_%d.exr" % (name, engine.lower(), seed)), seed)[0]
            for seed in (1, 2))
    z = cs.block_z(imgs['FACET'], imgs['CYCLES'], BLOCK, keep=keep,
                   expected_diff=ref['FACET'] - ref['CYCLES'])[0]
    worst = np.abs(z).max()
    line = ["Facet-Cycles%s max|z| %.2f" % (
        "" if ref['FACET'] is ref['CYCLES'] or np.array_equal(ref['FACET'], ref['CYCLES'])
        else " (less the models' difference)", np.abs(z).max())]
    k = np.ones(z.shape[:0] + ref['FACET'].shape[:2], bool) if keep is None else keep
    for engine in ('FACET', 'CYCLES'):
        a, b = imgs[engine]
        r = ref[engine]
        # the analytic image as a noiseless "renderer": both seeds equal
        za = cs.block_z((a, b), (r, r), BLOCK, keep=keep)[0]
        worst = max(worst, np.abs(za).max())
        ratio = (0.5 * (a + b))[k].mean() / r[k].mean()
        line.append("%s/analytic %.5f (max|z| %.2f)" % (engine.capitalize(), ratio,
                                                        np.abs(za).max()))
    print("%-6s %s" % (name, ", ".join(line)))
    bt.check(worst < Z_MAX, "%s light: Facet, Cycles and the analytic irradiance agree "
             "within the noise (|z| < %g)" % (name, Z_MAX))


def main():
    out = bt.args()[0]
    bt.enable_addon()
    x, y = plane_points()
    h = 2.0

    # point light
    scene = base_scene()
    P, lx, ly = 100.0, 0.3, -0.2
    cs.add_light(scene, 'POINT', P, (lx, ly, h), shadow_soft_size=0.0)
    r2 = (x - lx) ** 2 + (y - ly) ** 2 + h * h
    E = P / (4 * math.pi) * h / r2 ** 1.5
    run_case("point", scene, (RHO / math.pi * E).mean(axis=2), 16, out)

    # point light of radius 0.5: Cycles 3.4 renders the lamp as a disc of radius R facing each
    # shaded point, a circular cone, so its E is exactly E d^2 / (d^2 + R^2) (measured 0.7995
    # against 0.8000 at d = 2R; Cycles 4 has spheres); the addon's default Lamp Model gives
    # Facet the same disc (test_cycles34_lamps.py: the Physical model's sphere).
    scene = base_scene()
    Rs = 0.5
    cs.add_light(scene, 'POINT', P, (lx, ly, h), shadow_soft_size=Rs)
    r2 = (x - lx) ** 2 + (y - ly) ** 2 + h * h
    E = P / (4 * math.pi) * h / r2 ** 1.5
    run_case("disc", scene, (RHO / math.pi * E * r2 / (r2 + Rs * Rs)).mean(axis=2), 64, out)

    # spot light, half-angle 40 degrees, blend 0
    scene = base_scene()
    half = math.radians(40.0)
    cs.add_light(scene, 'SPOT', P, (0.0, 0.0, h), spot_size=2 * half, spot_blend=0.0,
                 shadow_soft_size=0.0)
    r2 = x ** 2 + y ** 2 + h * h
    inside = h / np.sqrt(r2) > math.cos(half)
    E = np.where(inside, P / (4 * math.pi) * h / r2 ** 1.5, 0.0)
    # Cycles 3.4 (measured here, and its spot_attenuation starts from dot(dir, axis)): the
    # intensity in the cone is P/(4 pi) cos(angle from the axis). The addon exports Blender's
    # form of Facet's spot (outer_angle, spot_blend: FORMAT.md), whose fall-off is Cycles'
    # g(mu) = mu inside the cone: both renderers have that factor.
    cos_axis = h / np.sqrt(r2)
    keep = inside.all(axis=2) | (~inside).all(axis=2)
    run_case("spot", scene, {'FACET': (RHO / math.pi * E * cos_axis).mean(axis=2),
                             'CYCLES': (RHO / math.pi * E * cos_axis).mean(axis=2)},
             16, out, keep=keep)

    # sun tilted 30 degrees about x
    scene = base_scene()
    S = 3.0
    cs.add_light(scene, 'SUN', S, (0.0, 0.0, h), rotation=(math.radians(30.0), 0.0, 0.0),
                 angle=0.0)
    E = np.full(x.shape, S * math.cos(math.radians(30.0)))
    run_case("sun", scene, (RHO / math.pi * E).mean(axis=2), 4, out)

    # square and disc area lights, size 1, facing down
    a, Pa = 1.0, 50.0
    for shape in ('SQUARE', 'DISK'):
        scene = base_scene()
        cs.add_light(scene, 'AREA', Pa, (0.0, 0.0, h), shape=shape, size=a)
        if shape == 'SQUARE':
            L = Pa / (4 * a * a)
            F = rect_ff(x, y, h, -a / 2, a / 2, -a / 2, a / 2)
        else:
            L = Pa / (4 * math.pi * a * a / 4)
            F = disc_ff(x, y, h, 0.0, 0.0, a / 2)
        run_case(shape.lower(), scene, (RHO * L * F).mean(axis=2), 256, out)

    # a Facet emissive quad: a mesh light in Cycles (one-sided by cycles_scene.convert)
    L = 10.0
    scene = quad_scene(out, L, a, h)
    F = rect_ff(x, y, h, -a / 2, a / 2, -a / 2, a / 2)
    run_case("quad", scene, (RHO * L * F).mean(axis=2), 256, out)


bt.run(main)
