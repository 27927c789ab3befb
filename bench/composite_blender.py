"""Reference values of Blender 3.4's Math, Vector Math, Mix RGB / Mix (Color) and ColorRamp nodes
as Cycles evaluates them, for tests/render/test_composite_textures.cpp: the addon's nodevalues.py
(an independent port of Cycles' svm_math / svm_vector_math / svm_mix / rgb_ramp_lookup, in
double, checked against
Cycles renders by tests/blender/test_nodegraph.py) on constant inputs, and, for the ramps,
Blender's own ColorRamp.evaluate (BKE_colorband_evaluate) through Cycles' 256-entry table.

    blender -b --factory-startup --python bench/composite_blender.py -- \\
        tests/render/composite_blender.json
"""
import importlib.util
import json
import math
import os
import sys
from types import SimpleNamespace

import bpy

OUT = sys.argv[sys.argv.index("--") + 1]
HERE = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location(
    "nodevalues", os.path.join(HERE, "..", "blender_addon", "facet_blender", "nodevalues.py"))
nv = importlib.util.module_from_spec(spec)
spec.loader.exec_module(nv)

cases = []

# Math: every operation on input triples away from each operation's discontinuities and poles.
TRIPLES = [(0.3, 0.7, 0.2), (-1.3, 0.4, 0.25), (2.5, -1.5, 0.6), (0.8, 2.0, 0.1),
           (-0.45, -2.2, 1.7), (3.7, 1.3, -0.8)]
for op in nv.MATH:
    for a, b, c in TRIPLES:
        for clamp in (False, True):
            node = SimpleNamespace(operation=op, use_clamp=clamp)
            v = nv._math(node, {"Value": a, "Value_001": b, "Value_002": c}, "Value")
            if not math.isfinite(v):
                continue
            cases.append({"kind": "math",
                          "params": {"operation": op.lower(), "use_clamp": clamp,
                                     "a": a, "b": b, "c": c},
                          "value": [v]})

# Vector Math: every operation on vector triples and scales away from the discontinuities
# (floor, snap, wrap, modulo) and the poles of tangent; a zero a (normalize) and a zero b (safe
# divide, project, reflect, refract, modulo, snap).
VECTORS = [((0.3, -0.7, 1.2), (0.5, 0.25, -0.8), (-0.4, 0.9, 0.6), 1.7),
           ((-1.3, 0.4, 2.5), (2.0, -1.5, 0.3), (0.8, -0.2, -1.1), -0.6),
           ((0.8, 2.2, -0.45), (-0.35, 1.3, 0.7), (1.9, 0.1, -0.3), 0.4),
           ((0.15, 0.2, -0.1), (0.3, -0.9, 0.2), (0.7, 0.35, -0.25), 1.35),
           ((0.0, 0.0, 0.0), (0.6, 0.0, -0.8), (0.2, 0.3, 0.4), 1.2),
           ((0.5, -0.3, 0.2), (0.0, 0.0, 0.0), (-0.6, 0.4, 0.5), 0.8)]
for op in list(nv._VEC) + list(nv._VEC_VALUE):
    value = op in nv._VEC_VALUE
    for a, b, c, sc in VECTORS:
        node = SimpleNamespace(operation=op)
        v = nv._vector_math(node, {"Vector": a, "Vector_001": b, "Vector_002": c, "Scale": sc},
                            "Value" if value else "Vector")
        params = {"operation": op.lower(), "a": list(a), "b": list(b), "c": list(c), "scale": sc}
        if value:
            params["output"] = "value"
        cases.append({"kind": "vector_math", "params": params,
                      "value": [v] if value else list(v)})

# Mix RGB (fac clamped) and the Mix node's Color mode with an unclamped factor.
COLOURS = [((0.2, 0.6, 0.9), (0.7, 0.3, 0.1)), ((0.8, 0.45, 0.05), (0.25, 0.9, 0.6)),
           ((0.0, 0.5, 1.2), (1.5, 0.0, 0.3)), ((0.3, 0.3, 0.3), (0.6, 0.2, 0.8))]
for blend in nv.MIX:
    for t in (0.0, 0.35, 1.0, 1.4, -0.3):
        for a, b in COLOURS:
            for clamp in (False, True):
                node = SimpleNamespace(blend_type=blend, use_clamp=clamp)
                v = nv._mix_rgb(node, {"Fac": t, "Color1": a, "Color2": b}, "Color")
                cases.append({"kind": "mix_rgb",
                              "params": {"blend_type": blend.lower(), "use_clamp": clamp,
                                         "fac": t, "color1": list(a), "color2": list(b)},
                              "value": list(v)})
            if t in (1.4, -0.3):  # the Mix node with Clamp Factor off
                node = SimpleNamespace(data_type='RGBA', blend_type=blend, clamp_factor=False,
                                       clamp_result=False)
                v = nv._mix(node, {"Factor_Float": t, "A_Color": a, "B_Color": b}, "Result")
                cases.append({"kind": "mix_rgb",
                              "params": {"blend_type": blend.lower(), "clamp_factor": False,
                                         "fac": t, "color1": list(a), "color2": list(b)},
                              "value": list(v)})

# ColorRamp: stops through Blender's own evaluate, each interpolation, read as Cycles reads it.
bpy.ops.wm.read_factory_settings(use_empty=True)
mat = bpy.data.materials.new("ramps")
mat.use_nodes = True
RAMPS = [
    [(0.0, (0.0, 0.0, 0.0, 1.0)), (1.0, (1.0, 1.0, 1.0, 1.0))],
    [(0.2, (0.9, 0.1, 0.05, 1.0)), (0.45, (0.1, 0.8, 0.3, 0.5)), (0.8, (0.05, 0.2, 0.9, 0.0))],
    [(0.1, (1.0, 0.5, 0.0, 1.0)), (0.3, (0.0, 0.2, 1.0, 0.8)), (0.3, (0.6, 0.6, 0.1, 0.6)),
     (0.55, (0.2, 0.9, 0.9, 0.4)), (0.95, (0.7, 0.0, 0.4, 1.0))],
    [(0.6, (0.4, 0.7, 0.2, 0.3))],
]
FACS = [i / 37.0 * 1.3 - 0.15 for i in range(38)]
for stops in RAMPS:
    for interp in ('CONSTANT', 'LINEAR', 'EASE', 'CARDINAL', 'B_SPLINE'):
        node = mat.node_tree.nodes.new("ShaderNodeValToRGB")
        ramp = node.color_ramp
        ramp.interpolation = interp
        els = ramp.elements
        while len(els) > 1:
            els.remove(els[-1])
        els[0].position = stops[0][0]
        els[0].color = stops[0][1]
        for pos, col in stops[1:]:
            e = els.new(pos)
            e.color = col
        stops_json = [{"position": e.position, "color": list(e.color)} for e in els]
        for out in ("Color", "Alpha"):
            vals = []
            for f in FACS:
                v = nv._color_ramp(node, {"Fac": f}, out)
                vals.append(list(v) if out == "Color" else [v])
            cases.append({"kind": "color_ramp",
                          "params": {"interpolation": interp.lower(), "stops": stops_json,
                                     "output": out.lower()},
                          "facs": FACS, "values": vals})
        mat.node_tree.nodes.remove(node)

with open(OUT, "w") as f:
    json.dump({"cases": cases}, f, indent=None)
    f.write("\n")
print("wrote", OUT, len(cases), "cases")
