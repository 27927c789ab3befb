"""Principled Hair BSDF and Hair BSDF nodes -> the core's `principled_hair` and `hair`
(facet_blender/materials.py), in headless Blender: every parametrization of the Principled Hair
BSDF with its inputs by name (Direct Coloring, Melanin Concentration with Tint and Random Color,
Absorption Coefficient), Roughness, Radial Roughness, Coat, IOR, Offset, Random Roughness and
Random; the Hair BSDF's Component, Color, Offset and roughnesses. Each conversion is validated
by the core (native.check_material). Reported by node and input name: values outside the core's
ranges (an IOR below 1, a colour above 1), a linked Tangent; converted without a line: the
defaults. An unlinked Random that matters (Random Roughness or Random Color > 0) is the
strand's random value, a hair_info texture, as Cycles reads it; Hair Info's Random through a
Color Ramp into Direct Coloring's Color is a texture.
Rendering against Cycles needs curves (Cycles' Principled Hair is a curve closure), so it is
not here."""
import json
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402


def hair_material(name, idname, props=None, **inputs):
    mat, nt, out = bt.new_material(name)
    n = nt.nodes.new(idname)
    for k, v in (props or {}).items():
        setattr(n, k, v)
    for k, v in inputs.items():
        n.inputs[k.replace("_", " ")].default_value = v
    nt.links.new(n.outputs[0], out.inputs["Surface"])
    return mat, nt, n


def close(a, b, tol=1e-6):
    a = a if isinstance(a, (list, tuple)) else [a]
    b = b if isinstance(b, (list, tuple)) else [b]
    return len(a) == len(b) and all(abs(x - y) <= tol for x, y in zip(a, b))


def main():
    bt.enable_addon()
    from facet_blender import materials, native

    def conv(mat):
        c = materials.convert(mat)
        # (Textured inputs are checked by the scene tests that render them.)
        native.check_material(c.data["model"], {k: v for k, v in c.data.items()
                                                if k != "model" and not isinstance(v, dict)})
        return c

    # Defaults (Direct Coloring): every input by its own name, no report.
    m, _, _ = hair_material("PH", "ShaderNodeBsdfHairPrincipled")
    c = conv(m)
    d = c.data
    bt.check(d["model"] == "principled_hair" and d["parametrization"] == "color"
             and close(d["color"], [0.017513, 0.005763, 0.002059]) and close(d["roughness"], 0.3)
             and close(d["radial_roughness"], 0.3) and d["coat"] == 0.0
             and close(d["ior"], 1.55) and close(d["offset"], math.radians(2.0))
             and d["random_roughness"] == 0.0 and d["random"] == 0.0
             and "melanin" not in d and "absorption_coefficient" not in d and not c.problems,
             "Principled Hair defaults -> principled_hair, color: %s %s" % (d, c.problems))

    # Melanin Concentration with Tint, Random Color and a linked Random (a Value node: folded).
    m, nt, n = hair_material("PHM", "ShaderNodeBsdfHairPrincipled",
                             {"parametrization": 'MELANIN'}, Melanin=0.4, Melanin_Redness=0.2,
                             Tint=(0.9, 0.7, 0.6, 1.0), Random_Color=0.3, Random_Roughness=0.2,
                             Roughness=0.45, Radial_Roughness=0.6, Coat=0.25, IOR=1.4,
                             Offset=math.radians(3.0))
    val = nt.nodes.new("ShaderNodeValue")
    val.outputs[0].default_value = 0.7
    nt.links.new(val.outputs[0], n.inputs["Random"])
    c = conv(m)
    d = c.data
    bt.check(d["parametrization"] == "melanin" and close(d["melanin"], 0.4)
             and close(d["melanin_redness"], 0.2) and close(d["tint"], [0.9, 0.7, 0.6])
             and close(d["random_color"], 0.3) and close(d["random_roughness"], 0.2)
             and close(d["random"], 0.7) and close(d["coat"], 0.25) and close(d["ior"], 1.4)
             and close(d["offset"], math.radians(3.0)) and "color" not in d and not c.problems,
             "Melanin parametrization with a linked Random: %s %s" % (d, c.problems))
    # The same with Random unlinked: Cycles reads the strand's random value, a hair_info
    # texture; with a Random value of 0.4 the mesh case (Cycles: 0.4, Facet 0) is reported.
    nt.links.remove(n.inputs["Random"].links[0])
    c = conv(m)
    bt.check(c.data["random"] == {"hair_info": {"output": "random"}} and not c.problems,
             "an unlinked Random that matters: the strand's value: %s %s"
             % (c.data["random"], c.problems))
    n.inputs["Random"].default_value = 0.4
    c = conv(m)
    bt.check(c.data["random"] == {"hair_info": {"output": "random"}} and len(c.problems) == 1
             and "'Random'" in c.problems[0] and "mesh" in c.problems[0],
             "an unlinked Random of 0.4: %s" % c.problems)
    # Random Roughness and Random Color 0: the Random value does not matter, no line.
    n.inputs["Random Roughness"].default_value = 0.0
    n.inputs["Random Color"].default_value = 0.0
    c = conv(m)
    bt.check(not c.problems and close(c.data["random"], 0.4),
             "Random unlinked but unused: its value, no line: %s" % c.problems)
    # Hair Info Random through a Color Ramp into Direct Coloring's Color: a texture; Hair Info
    # Intercept into Random (noted: the position along the strand).
    m, nt, n = hair_material("PHC", "ShaderNodeBsdfHairPrincipled",
                             {"parametrization": 'COLOR'}, Random_Roughness=0.5)
    info = nt.nodes.new("ShaderNodeHairInfo")
    ramp = nt.nodes.new("ShaderNodeValToRGB")
    nt.links.new(info.outputs["Random"], ramp.inputs["Fac"])
    nt.links.new(ramp.outputs["Color"], n.inputs["Color"])
    nt.links.new(info.outputs["Intercept"], n.inputs["Random"])
    c = conv(m)
    col, rnd = c.data["color"], c.data["random"]
    bt.check(isinstance(col, dict) and "color_ramp" in json.dumps(col)
             and '"hair_info": {"output": "random"}' in json.dumps(col)
             and "intercept" in json.dumps(rnd) and len(c.problems) == 1
             and "Intercept" in c.problems[0],
             "Hair Info into Color and Random: %s %s %s" % (col, rnd, c.problems))

    # Absorption Coefficient.
    m, _, _ = hair_material("PHA", "ShaderNodeBsdfHairPrincipled",
                            {"parametrization": 'ABSORPTION'},
                            Absorption_Coefficient=(0.3, 0.6, 1.2))
    c = conv(m)
    bt.check(c.data["parametrization"] == "absorption"
             and close(c.data["absorption_coefficient"], [0.3, 0.6, 1.2])
             and "color" not in c.data and not c.problems,
             "Absorption parametrization: %s %s" % (c.data, c.problems))

    # Outside the core's ranges: reported by input name and clamped (IOR 0.8 -> 1, Color > 1).
    m, _, _ = hair_material("PHX", "ShaderNodeBsdfHairPrincipled", IOR=0.8,
                            Color=(1.5, 0.5, 0.2, 1.0))
    c = conv(m)
    bt.check(c.data["ior"] == 1.0 and close(c.data["color"], [1.0, 0.5, 0.2])
             and len(c.problems) == 2 and any("'IOR'" in p for p in c.problems)
             and any("'Color'" in p for p in c.problems),
             "IOR < 1 and Color > 1 reported and clamped: %s" % c.problems)

    # Hair BSDF: Reflection and Transmission.
    m, nt, n = hair_material("HR", "ShaderNodeBsdfHair", {"component": 'Reflection'},
                             Color=(0.7, 0.5, 0.3, 1.0), Offset=0.1, RoughnessU=0.2,
                             RoughnessV=0.6)
    c = conv(m)
    bt.check(c.data == {"model": "hair", "component": "reflection",
                        "color": c.data["color"], "offset": c.data["offset"],
                        "roughness_u": c.data["roughness_u"],
                        "roughness_v": c.data["roughness_v"]}
             and close(c.data["color"], [0.7, 0.5, 0.3]) and close(c.data["offset"], 0.1)
             and close(c.data["roughness_u"], 0.2) and close(c.data["roughness_v"], 0.6)
             and not c.problems, "Hair BSDF Reflection -> hair: %s %s" % (c.data, c.problems))
    n.component = 'Transmission'
    c = conv(m)
    bt.check(c.data["component"] == "transmission" and not c.problems
             and materials.crosses(c.data), "Hair BSDF Transmission -> hair transmission")
    # A linked Tangent is not read: reported.
    geo = nt.nodes.new("ShaderNodeNewGeometry")
    nt.links.new(geo.outputs["Tangent"], n.inputs["Tangent"])
    c = conv(m)
    bt.check(len(c.problems) == 1 and "Tangent" in c.problems[0],
             "a linked Tangent reported: %s" % c.problems)


bt.run(main)
