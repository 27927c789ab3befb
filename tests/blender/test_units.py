"""units.py (no Blender needed): each conversion against its formula and its inverse, and the
spot conversions against the core's own (the facet module on PYTHONPATH)."""
import ast
import math
import os
import random
import sys
import types

ADDON = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "blender_addon",
                     "facet_blender")
# The addon's package without its __init__ (which needs bpy): units and native only.
_pkg = types.ModuleType("facet_blender")
_pkg.__path__ = [ADDON]
sys.modules["facet_blender"] = _pkg
from facet_blender import native, units  # noqa: E402

facet = native.facet


def close(a, b, tol=1e-12):
    return all(abs(x - y) <= tol * max(1.0, abs(y)) for x, y in zip(a, b))


def test_point():
    # Cycles: I = P / (4 pi); Facet: I = Phi / (4 pi)  =>  Phi = P.
    assert close(units.point_power_from_blender([1.0, 0.5, 0.25], 1000.0), [1000, 500, 250])
    col, p = units.point_power_to_blender([1000.0, 500.0, 250.0])
    assert close(col, [1, 0.5, 0.25]) and p == 1000.0


def test_spot():
    outer, inner = units.spot_cone_from_blender(math.radians(90.0), 0.0)
    assert close([outer, inner], [45.0, 45.0])
    # blend 0 must give inner == outer exactly: acos(cos(40 deg)) rounds above 40, and the core
    # rejects inner > outer (found by tests/blender/test_cycles_lights.py).
    for deg in (10.0, 40.0, 45.0, 80.0):
        o, i = units.spot_cone_from_blender(math.radians(2 * deg), 0.0)
        assert i <= o and abs(i - o) < 1e-9, (deg, o, i)
    # Facet's I0 = Phi / (2 pi [(1 - cos i) + (cos i - cos o) / 2]) must be Cycles' P / (4 pi).
    for size, blend in ((math.radians(60), 0.3), (math.radians(150), 1.0), (0.2, 0.0)):
        o, i = units.spot_cone_from_blender(size, blend)
        phi = units.spot_power_from_blender([1, 1, 1], 100.0, o, i)[0]
        ci, co = math.cos(math.radians(i)), math.cos(math.radians(o))
        i0 = phi / (2 * math.pi * ((1 - ci) + 0.5 * (ci - co)))
        assert abs(i0 - 100.0 / (4 * math.pi)) < 1e-9
        # the fade range in cos theta is Cycles' [cos o, cos o + blend (1 - cos o)]
        assert abs(ci - (co + blend * (1 - co))) < 1e-12
        s2, b2 = units.spot_cone_to_blender(o, i)
        assert abs(s2 - size) < 1e-12 and abs(b2 - blend) < 1e-9
        col, p = units.spot_power_to_blender([phi] * 3, o, i)
        assert abs(p - 100.0) < 1e-9


def test_spot_through_the_core():
    # The addon's spot conversions are the core's (light_units.h through the facet module): a
    # Blender spot of Power P has K = P / (4 pi) (Cycles 3.4), and the power the addon writes
    # must give exactly that K in the core's own formula, cycles_spot_intensity (Blender's
    # form), or I0 in spot_intensity (the linear form). Tolerance 1e-12 relative: one division
    # and one multiplication of round-off apart; a different formula (another integral, a
    # missing blend term) is off by far more (the 0.35 s^2 term alone is >= 1e-4 here).
    rng = random.Random(7)
    for _ in range(200):
        outer = rng.uniform(0.5, 90.0)
        blend = rng.choice([0.0, 1.0, rng.random()])
        p = rng.uniform(0.1, 1000.0)
        col = [rng.random() for _ in range(3)]
        phi = units.spot_blend_power_from_blender(col, p, outer, blend)
        k = facet.cycles_spot_intensity(phi, outer, blend)
        for c, ki in zip(col, k):
            assert abs(ki - c * p / (4 * math.pi)) <= 1e-12 * c * p, (outer, blend, ki)
        inner = rng.uniform(0.0, outer)
        phi = units.spot_power_from_blender(col, p, outer, inner)
        i0 = facet.spot_intensity(phi, inner, outer)
        for c, ii in zip(col, i0):
            assert abs(ii - c * p / (4 * math.pi)) <= 1e-12 * c * p, (outer, inner, ii)
        assert abs(units.spot_power_to_blender(phi, outer, inner)[1] - p * max(col)) <= 1e-9 * p


def test_no_spot_formula_in_the_addon():
    # The cone integrals live in the core only: no function of units.py named for spots calls
    # math.cos (their only trigonometry is the cone angle conversion of spot_cone_*).
    tree = ast.parse(open(os.path.join(ADDON, "units.py")).read())
    for fn in tree.body:
        if not isinstance(fn, ast.FunctionDef) or "spot" not in fn.name:
            continue
        if fn.name.startswith("spot_cone_"):
            continue
        for node in ast.walk(fn):
            if isinstance(node, ast.Attribute) and node.attr in ("cos", "sin", "acos"):
                raise AssertionError("units.%s computes a cone formula itself" % fn.name)


def test_sun_area_emission():
    assert close(units.sun_irradiance_from_blender([1, 1, 0.5], 3.0), [3, 3, 1.5])
    # Cycles area light: Facet's "area" lamp takes the same power (the core converts it to
    # radiance: tests/render/test_sized_lights.cpp), and back.
    assert close(units.area_power_from_blender([1, 0.5, 0.25], 16.0), [16, 8, 4])
    col, p = units.area_power_to_blender([16.0, 8.0, 4.0])
    assert close(col, [1, 0.5, 0.25]) and p == 16.0
    assert close(units.emission_from_blender([0.5, 1, 2, 1], 2.0), [1, 2, 4])


def test_camera():
    # [1][1] of the projection is 1 / tan(fov / 2)
    assert abs(units.fov_from_projection(1.0 / math.tan(math.radians(20))) - 40.0) < 1e-12
    f, r, u = units.camera_basis([0, 0, 0], [0, 0, -5], [0, 1, 0])
    assert close(f, [0, 0, -1]) and close(r, [1, 0, 0]) and close(u, [0, 1, 0])



def test_camera_window():
    # Blender's frustum (perspective_m4) and box (orthographic_m4) matrices, rows as
    # mathutils indexes them, for a window [l, r] x [b, t] at the near distance n.
    def frustum(l, r, b, t, n, f=100.0):
        return [[2 * n / (r - l), 0, (r + l) / (r - l), 0], [0, 2 * n / (t - b), (t + b) / (t - b), 0],
                [0, 0, -(f + n) / (f - n), -2 * f * n / (f - n)], [0, 0, -1, 0]]

    def box(l, r, b, t, n=0.1, f=100.0):
        return [[2 / (r - l), 0, 0, -(r + l) / (r - l)], [0, 2 / (t - b), 0, -(t + b) / (t - b)],
                [0, 0, -2 / (f - n), -(f + n) / (f - n)], [0, 0, 0, 1]]

    # Window at distance 1: x in [0.1, 0.9] (h_x 0.4, c_x 0.5), y in [-0.5, 0.1]; n = 0.25.
    n = 0.25
    w = units.camera_window(frustum(0.1 * n, 0.9 * n, -0.5 * n, 0.1 * n, n), False)
    assert close(w, [0.4, 0.3, 0.5, -0.2])
    w = units.camera_window(box(-1.0, 3.0, -2.5, 0.5), True)
    assert close(w, [2.0, 1.5, 1.0, -1.0])
    # No shift: the centre is exactly 0.
    assert units.camera_window(frustum(-0.3, 0.3, -0.2, 0.2, 1.0), False)[2:] == (0.0, 0.0)


if __name__ == "__main__":
    for name, fn in list(globals().items()):
        if name.startswith("test_"):
            fn()
            print("ok", name)
