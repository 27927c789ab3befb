"""Cycles node materials -> Facet materials (materials.py): Diffuse, Glossy GGX / Beckmann /
Sharp / Multiscatter GGX, Anisotropic, Principled (dielectric, metal, mixed), Emission; a
texture feeding an input and an unsupported distribution are reported by material, node and
input name; a Color above 1 becomes an `add` of copies (exact) or is clamped (reported); a
Normal Map of a texture that reads more than UVs is reported (the node graph itself: tests/blender/test_nodegraph.py); the
Facet panel's model and parameters reach the core by the core's names (and the core validates
them)."""
import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402


def node_material(name, idname, **inputs):
    """inputs: "Base_Color" sets input "Base Color"; "_distribution" sets a node property."""
    mat = bpy.data.materials.new(name)
    node = bt.single_shader(
        mat, idname, {k.replace("_", " "): v for k, v in inputs.items() if not k.startswith("_")},
        {k[1:]: v for k, v in inputs.items() if k.startswith("_")})
    return mat, node


def close(a, b, tol=1e-6):
    a = a if isinstance(a, (list, tuple)) else [a]
    b = b if isinstance(b, (list, tuple)) else [b]
    return len(a) == len(b) and all(abs(x - y) <= tol for x, y in zip(a, b))


def main():
    bt.enable_addon()
    from facet_blender import materials, native

    def conv(mat):
        c = materials.convert(mat)
        native.check_material(c.data["model"], {k: v for k, v in c.data.items()
                                                if k != "model"})
        return c

    m, _ = node_material("D", "ShaderNodeBsdfDiffuse", Color=(0.2, 0.4, 0.6, 1.0))
    c = conv(m)
    bt.check(c.data["model"] == "lambert" and close(c.data["reflectance"], [0.2, 0.4, 0.6])
             and not c.problems, "Diffuse -> lambert")

    for dist, model in (("GGX", "ggx"), ("BECKMANN", "beckmann")):
        m, _ = node_material("G" + dist, "ShaderNodeBsdfGlossy", _distribution=dist,
                             Roughness=0.5, Color=(0.9, 0.8, 0.7, 1.0))
        c = conv(m)
        bt.check(c.data["model"] == model and close(c.data["alpha"], 0.25)
                 and c.data["fresnel"] == "none" and close(c.data["reflectance"], [0.9, 0.8, 0.7]),
                 "Glossy %s -> %s, alpha = roughness^2, F = 1" % (dist, model))
    m, _ = node_material("GS", "ShaderNodeBsdfGlossy", _distribution='SHARP')
    bt.check(conv(m).data["model"] == "mirror", "Glossy Sharp -> mirror")
    m, _ = node_material("GM", "ShaderNodeBsdfGlossy", _distribution='MULTI_GGX', Roughness=0.7)
    bt.check(conv(m).data.get("energy_compensation") is True, "Multiscatter GGX -> compensated")
    m, _ = node_material("GA", "ShaderNodeBsdfGlossy", _distribution='ASHIKHMIN_SHIRLEY')
    c = conv(m)
    bt.check(c.data["model"] == "ggx" and any("GA" in p and "ASHIKHMIN" in p for p in c.problems),
             "Ashikhmin-Shirley reported: %s" % c.problems)
    # A BSDF Color above 1 (Cycles' plain factor; the core's reflectance is at most 1): the
    # add of ceil(max) copies of Color / n, exact (f is linear in it), the normal map on the
    # combination (render against Cycles: test_cycles_over_unity.py).
    m, _ = node_material("G125", "ShaderNodeBsdfGlossy", _distribution='SHARP',
                         Color=(1.25, 1.25, 0.5, 1.0))
    c = materials.convert(m)
    kids = c.data.get("materials", [])
    bt.check(c.data["model"] == "add" and len(kids) == 2 and
             all(k["model"] == "mirror" and close(k["reflectance"], [0.625, 0.625, 0.25])
                 for k in kids) and not c.problems,
             "Glossy Sharp Color 1.25 -> add of 2 mirrors of 0.625: %s" % c.data)
    m, _ = node_material("D25", "ShaderNodeBsdfDiffuse", Color=(2.5, 1.0, 0.1, 1.0))
    c = materials.convert(m)
    flat = [c.data["materials"][0], c.data["materials"][1]["materials"][0],
            c.data["materials"][1]["materials"][1]] if c.data["model"] == "add" else []
    bt.check(len(flat) == 3 and all(close(k["reflectance"], [2.5 / 3, 1 / 3, 0.1 / 3])
                                     for k in flat),
             "Diffuse Color 2.5 -> 3 lamberts of Color / 3: %s" % c.data)
    m, _ = node_material("GM2", "ShaderNodeBsdfGlossy", _distribution='MULTI_GGX',
                         Roughness=0.4, Color=(1.5, 1.0, 1.0, 1.0))
    c = conv(m)
    bt.check(c.data["model"] == "ggx" and close(c.data["reflectance"], [1.0, 1.0, 1.0]) and
             any("GM2" in p and "clamped" in p for p in c.problems),
             "Multiscatter GGX Color 1.5 (not linear in it): clamped, reported: %s" % c.problems)
    # A Normal Map of a procedural texture in Object coordinates: the core's normal maps read
    # UVs only; reported (not a failed render), the shading normal used.
    m, node = node_material("NMO", "ShaderNodeBsdfDiffuse")
    nt = m.node_tree
    tc, magic = nt.nodes.new("ShaderNodeTexCoord"), nt.nodes.new("ShaderNodeTexMagic")
    nm = nt.nodes.new("ShaderNodeNormalMap")
    nt.links.new(tc.outputs["Object"], magic.inputs["Vector"])
    nt.links.new(magic.outputs["Color"], nm.inputs["Color"])
    nt.links.new(nm.outputs["Normal"], node.inputs["Normal"])
    c = conv(m)
    bt.check("normal_map" not in c.data and
             any("NMO" in p and "Object coordinates" in p and "UVs only" in p
                 for p in c.problems),
             "Normal Map of an Object-coordinate Magic texture: reported: %s" % c.problems)

    # Cycles 3.4's Anisotropic BSDF (SVM closure setup, not Principled's aspect): alpha 0.25,
    # anisotropy 0.5 -> alpha_x 0.125, alpha_y 0.5; -0.5 swaps them.
    for aniso, want in ((0.5, (0.125, 0.5)), (-0.5, (0.5, 0.125))):
        m, _ = node_material("AN", "ShaderNodeBsdfAnisotropic", Roughness=0.5, Anisotropy=aniso)
        c = conv(m)
        bt.check(close(c.data["alpha_u"], want[0]) and close(c.data["alpha_v"], want[1]),
                 "Anisotropic %g -> alpha_u/alpha_v %s: got %s/%s" % (
                     aniso, want, c.data["alpha_u"], c.data["alpha_v"]))

    m, _ = node_material("P", "ShaderNodeBsdfPrincipled", Base_Color=(0.8, 0.1, 0.1, 1.0),
                         Roughness=0.4, Specular=0.5, Metallic=0.0, Specular_Tint=0.0)
    c = conv(m)
    bt.check(c.data["model"] == "principled" and close(c.data["base_color"], [0.8, 0.1, 0.1])
             and close(c.data["roughness"], 0.4) and close(c.data["specular"], 0.5)
             and close(c.data["metallic"], 0.0) and close(c.data["ior"], 1.45),
             "Principled -> principled, inputs by name: %s" % c.data)
    m, _ = node_material("PM", "ShaderNodeBsdfPrincipled", Base_Color=(0.9, 0.6, 0.2, 1.0),
                         Metallic=1.0, Roughness=0.2, Anisotropic_Rotation=1.25)
    c = conv(m)
    bt.check(close(c.data["metallic"], 1.0) and close(c.data["anisotropic_rotation"], 0.25),
             "Principled metal; Anisotropic Rotation wrapped to [0, 1): %s" % c.data)
    m, n = node_material("PX", "ShaderNodeBsdfPrincipled", Clearcoat=0.5, Sheen=0.3,
                         Transmission=0.2, Subsurface=0.1)
    n.distribution = 'MULTI_GGX'
    tex = m.node_tree.nodes.new("ShaderNodeTexSky")  # no core kind: reported
    m.node_tree.links.new(tex.outputs["Color"], n.inputs["Base Color"])
    c = conv(m)
    bt.check(close(c.data["clearcoat"], 0.5) and close(c.data["sheen"], 0.3)
             and close(c.data["transmission"], 0.2) and close(c.data["subsurface"], 0.1),
             "Principled: clearcoat, sheen, transmission, subsurface converted: %s" % c.data)
    bt.check(c.data.get("distribution") == "multi_ggx",
             "Principled Multiscatter GGX -> distribution multi_ggx: %s" % c.data)
    bt.check(c.data.get("subsurface_method") == "random_walk"
             and close(c.data["subsurface_ior"], 1.4)
             and all(close(a, b) for a, b in zip(c.data["subsurface_radius"], (1.0, 0.2, 0.1))),
             "Principled: the subsurface walk's radius, IOR and method converted: %s" % c.data)
    bt.check(not any("PX" in p and "Subsurface" in p for p in c.problems)
             and not any("MULTI_GGX" in p or "Multiscatter" in p for p in c.problems)
             and not any("Clearcoat" in p or "Sheen" in p or "Transmission" in p
                         for p in c.problems)
             and any("PX" in p and "Base Color" in p and "Sky Texture" in p
                     for p in c.problems),
             "Principled: subsurface converted, linked inputs named, multiscatter converted "
             "silently (Specular Tint 0): %s"
             % c.problems)
    # The Subsurface Scattering node; Christensen-Burley is reported (converted as Fixed Radius).
    m, n = node_material("SS", "ShaderNodeSubsurfaceScattering", Color=(0.8, 0.5, 0.3, 1.0),
                         Scale=0.5, Radius=(1.0, 0.5, 0.25), IOR=1.3, Anisotropy=0.95)
    n.falloff = 'BURLEY'
    c = conv(m)
    bt.check(c.data.get("model") == "subsurface" and close(c.data["scale"], 0.5)
             and close(c.data["ior"], 1.3) and close(c.data["anisotropy"], 0.9)
             and c.data["method"] == "random_walk_fixed_radius"
             and any("SS" in p and "Christensen-Burley" in p for p in c.problems),
             "Subsurface Scattering node -> subsurface (anisotropy clamped as Cycles, Burley "
             "reported): %s %s" % (c.data, c.problems))
    n.falloff = 'RANDOM_WALK'
    c = conv(m)
    bt.check(c.data["method"] == "random_walk" and not c.problems,
             "Subsurface Scattering node, Random Walk: exact: %s" % c.problems)
    # Multiscatter glass with Specular Tint: Facet's compensated glass reflection is untinted.
    m, n = node_material("PT", "ShaderNodeBsdfPrincipled", Transmission=1.0, Roughness=0.5,
                         Specular_Tint=0.5)
    n.distribution = 'MULTI_GGX'
    c = conv(m)
    bt.check(c.data.get("distribution") == "multi_ggx"
             and any("PT" in p and "Specular Tint" in p for p in c.problems),
             "Principled Multiscatter glass with Specular Tint reported: %s" % c.problems)
    m2, n2 = node_material("PA", "ShaderNodeBsdfPrincipled", Metallic=1.0, Anisotropic=0.5)
    n2.distribution = 'MULTI_GGX'
    bt.check(any("PA" in p and "Anisotropic" in p for p in conv(m2).problems),
             "Principled Multiscatter GGX with Anisotropic reported (isotropic compensation)")
    n.distribution = 'GGX'
    bt.check(not any("Specular Tint" in p for p in conv(m).problems),
             "Principled GGX glass with Specular Tint: exact, not reported")
    # Glass Multiscatter GGX -> the dielectric's energy compensation, not reported.
    m, n = node_material("GLM", "ShaderNodeBsdfGlass", _distribution='MULTI_GGX', Roughness=0.5)
    c = conv(m)
    bt.check(c.data["model"] == "dielectric" and c.data.get("energy_compensation") is True
             and close(c.data["alpha"], 0.25) and not c.problems,
             "Glass Multiscatter GGX -> dielectric with energy_compensation: %s %s"
             % (c.data, c.problems))
    n.distribution = 'GGX'
    bt.check(conv(m).data.get("energy_compensation") is None, "Glass GGX -> not compensated")
    m, _ = node_material("ANM", "ShaderNodeBsdfAnisotropic", _distribution='MULTI_GGX',
                         Roughness=0.5, Anisotropy=0.5)
    c = conv(m)
    bt.check(c.data.get("energy_compensation") is True and "alpha_u" in c.data
             and not c.problems, "Anisotropic Multiscatter GGX -> compensated: %s" % c.data)
    m, _ = node_material("E", "ShaderNodeEmission", Color=(1.0, 0.5, 0.25, 1.0), Strength=4.0)
    c = conv(m)
    bt.check(close(c.emission, [4.0, 2.0, 1.0]), "Emission: radiance = Color x Strength")

    m = bpy.data.materials.new("F")
    m.facet.source = 'FACET'
    m.facet.model = 'ggx'
    m.facet.ggx__alpha = 0.3
    m.facet.ggx__alpha__set = True
    m.facet.ggx__fresnel = "conductor"
    m.facet.ggx__fresnel__set = True
    c = conv(m)
    bt.check(c.data == {"model": "ggx", "alpha": m.facet.ggx__alpha, "fresnel": "conductor"},
             "Facet panel: only the parameters set, by the core's names: %s" % c.data)
    m.facet.ggx__ior__set = True  # ior is meaningless with fresnel conductor
    try:
        conv(m)
        rejected = False
    except Exception as e:
        rejected = "ior" in str(e)
    bt.check(rejected, "the core rejects ior with fresnel conductor, naming it")

    # Editing a Facet setting reaches the evaluated material (what the viewport exports).
    m = bpy.data.materials.new("tagged")
    m.facet.source = 'FACET'
    bpy.ops.mesh.primitive_cube_add()
    bpy.context.object.data.materials.append(m)
    dg = bpy.context.evaluated_depsgraph_get()
    m.facet.source = 'NODES'
    m.facet.lambert__reflectance = (0.25, 0.5, 0.75)
    dg = bpy.context.evaluated_depsgraph_get()
    ev = bpy.context.object.evaluated_get(dg).material_slots[0].material
    bt.check(ev.facet.source == 'NODES' and close(list(ev.facet.lambert__reflectance),
                                                   [0.25, 0.5, 0.75]),
             "a Facet material edit reaches the evaluated depsgraph")

    # The panel's lobe and albedo plot, from the core's f and albedo.
    from facet_blender import plot
    import numpy as np
    img = plot.lobe_image({"model": "lambert", "reflectance": 0.5})
    S = plot.SIZE
    black = (img[..., :3].sum(axis=2) < 0.05)
    # Lambert: f cos = rho/pi cos theta_o: the lobe's peak (scaled to r) straight up.
    top = int(150 - 115)
    bt.check(black[top - 2:top + 3, S // 2 - 2:S // 2 + 3].any(), "lambert lobe peaks at the normal")
    # albedo 0.5 at every angle: a horizontal black line half way up the strip.
    y_half = int(round((S - 12) - ((S - 12) - 172) * 0.5))
    bt.check(black[y_half - 1:y_half + 2, S // 2].any(), "lambert albedo 0.5 drawn")
    img = plot.lobe_image({"model": "ggx", "alpha": 0.1, "fresnel": "conductor",
                           "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.2]})
    red = (img[..., 0] > 0.7) & (img[..., 1] < 0.3)
    ys, xs = np.nonzero(red[:150])
    bt.check(xs.size > 0 and np.median(xs[ys < 100]) < S // 2,
             "a coloured GGX lobe drawn per channel, toward the mirror direction (left)")


bt.run(main)
