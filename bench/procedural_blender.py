"""Reference values of Blender 3.4's procedural textures at fixed points, for
tests/render/test_procedural.cpp: Blender evaluates each texture node in a Geometry Nodes tree
(Store Named Attribute of the node's output at each vertex's Position; Blender's CPU code,
BLI_noise, ports Cycles' kernels), independently of Facet's implementation.

    blender -b --factory-startup --python bench/procedural_blender.py -- \\
        tests/render/procedural_blender.json
"""
import json
import random
import sys

import bpy

OUT = sys.argv[sys.argv.index("--") + 1]

rng = random.Random(7)
POINTS = [tuple(round(rng.uniform(-3, 3), 4) for _ in range(3)) for _ in range(40)]
# Negative integers and cell borders: Cycles' floor of negative integers is the cell below.
POINTS += [(-1.0, -2.0, 0.5), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0), (-0.2, 0.0, -3.0)]

# (kind, node, {property: value}, {input: value}, output socket, facet params)
CASES = []
for dims in ("1D", "2D", "3D", "4D"):
    for out in ("Fac", "Color"):
        CASES.append(("noise", "ShaderNodeTexNoise", {"noise_dimensions": dims},
                      {"Scale": 2.5, "Detail": 3.4, "Roughness": 0.6, "Distortion": 0.7,
                       "W": 0.37}, out,
                      {"dimensions": int(dims[0]), "scale": 2.5, "detail": 3.4,
                       "roughness": 0.6, "distortion": 0.7, "w": 0.37,
                       "output": "fac" if out == "Fac" else "color"}))
    CASES.append(("noise", "ShaderNodeTexNoise", {"noise_dimensions": dims},
                  {"Scale": 5.0, "Detail": 0.0, "Roughness": 0.5, "Distortion": 0.0,
                   "W": -1.3}, "Fac",
                  {"dimensions": int(dims[0]), "scale": 5.0, "detail": 0.0, "w": -1.3}))
    for out in ("Value", "Color"):
        CASES.append(("white_noise", "ShaderNodeTexWhiteNoise", {"noise_dimensions": dims},
                      {"W": 0.61}, out,
                      {"dimensions": int(dims[0]), "w": 0.61,
                       "output": "value" if out == "Value" else "color"}))
    for feature in ("F1", "F2", "SMOOTH_F1", "DISTANCE_TO_EDGE", "N_SPHERE_RADIUS"):
        metrics = ("EUCLIDEAN",) if dims == "1D" or feature in (
            "DISTANCE_TO_EDGE", "N_SPHERE_RADIUS") else (
            "EUCLIDEAN", "MANHATTAN", "CHEBYCHEV", "MINKOWSKI")
        for metric in metrics:
            outs = ("Radius",) if feature == "N_SPHERE_RADIUS" else (
                ("Distance",) if feature == "DISTANCE_TO_EDGE" else ("Distance", "Color"))
            for out in outs:
                CASES.append(("voronoi", "ShaderNodeTexVoronoi",
                              {"voronoi_dimensions": dims, "feature": feature,
                               "distance": metric},
                              {"Scale": 1.7, "Smoothness": 0.8, "Exponent": 1.3,
                               "Randomness": 0.9, "W": 0.23}, out,
                              {"dimensions": int(dims[0]), "scale": 1.7, "smoothness": 0.8,
                               "exponent": 1.3, "randomness": 0.9, "w": 0.23,
                               "feature": feature.lower(), "distance": metric.lower(),
                               "output": out.lower()}))
for dims in ("1D", "2D", "3D", "4D"):
    for mtype in ("FBM", "MULTIFRACTAL", "HETERO_TERRAIN", "HYBRID_MULTIFRACTAL",
                  "RIDGED_MULTIFRACTAL"):
        for detail in (2.0, 3.7):
            CASES.append(("musgrave", "ShaderNodeTexMusgrave",
                          {"musgrave_dimensions": dims, "musgrave_type": mtype},
                          {"Scale": 1.9, "Detail": detail, "Dimension": 1.6,
                           "Lacunarity": 2.1, "Offset": 0.8, "Gain": 1.3, "W": 0.44}, "Fac",
                          {"dimensions": int(dims[0]), "type": mtype.lower(), "scale": 1.9,
                           "detail": detail, "dimension": 1.6, "lacunarity": 2.1,
                           "offset": 0.8, "gain": 1.3, "w": 0.44}))
for wtype, dirs in (("BANDS", ("X", "Y", "Z", "DIAGONAL")), ("RINGS", ("X", "Y", "Z",
                                                                    "SPHERICAL"))):
    for d in dirs:
        for profile in ("SIN", "SAW", "TRI"):
            for dist in (0.0, 2.5):
                prop = "bands_direction" if wtype == "BANDS" else "rings_direction"
                CASES.append(("wave", "ShaderNodeTexWave",
                              {"wave_type": wtype, prop: d, "wave_profile": profile},
                              {"Scale": 0.7, "Distortion": dist, "Detail": 2.5,
                               "Detail Scale": 1.3, "Detail Roughness": 0.6,
                               "Phase Offset": 0.4}, "Fac",
                              {"type": wtype.lower(), prop.replace("wave_", ""): d.lower(),
                               "profile": profile.lower(), "scale": 0.7, "distortion": dist,
                               "detail": 2.5, "detail_scale": 1.3, "detail_roughness": 0.6,
                               "phase": 0.4}))
for depth in (0, 1, 2, 3, 5, 7, 10):
    for out in ("Fac", "Color"):
        CASES.append(("magic", "ShaderNodeTexMagic", {"turbulence_depth": depth},
                      {"Scale": 1.3, "Distortion": 1.7}, out,
                      {"depth": depth, "scale": 1.3, "distortion": 1.7,
                       "output": out.lower()}))
for gtype in ("LINEAR", "QUADRATIC", "EASING", "DIAGONAL", "SPHERICAL", "QUADRATIC_SPHERE",
              "RADIAL"):
    CASES.append(("gradient", "ShaderNodeTexGradient", {"gradient_type": gtype}, {}, "Fac",
                  {"type": gtype.lower()}))

BRICKS = [({"offset": 0.5, "offset_frequency": 2, "squash": 1.0, "squash_frequency": 2},
           {"Scale": 1.7, "Mortar Size": 0.02, "Mortar Smooth": 0.1, "Bias": 0.0,
            "Brick Width": 0.5, "Row Height": 0.25}),
          ({"offset": 0.3, "offset_frequency": 3, "squash": 1.6, "squash_frequency": 2},
           {"Scale": 2.3, "Mortar Size": 0.05, "Mortar Smooth": 0.0, "Bias": -0.3,
            "Brick Width": 0.8, "Row Height": 0.35}),
          ({"offset": 0.75, "offset_frequency": 1, "squash": 0.7, "squash_frequency": 3},
           {"Scale": 3.1, "Mortar Size": 0.09, "Mortar Smooth": 0.6, "Bias": 0.4,
            "Brick Width": 0.3, "Row Height": 0.2})]
BRICK_COLOURS = {"Color1": (0.9, 0.4, 0.2, 1.0), "Color2": (0.1, 0.5, 0.7, 1.0),
                 "Mortar": (0.3, 0.3, 0.25, 1.0)}
for props, inputs in BRICKS:
    for out in ("Fac", "Color"):
        params = dict(props)
        params.update({k.lower().replace(" ", "_"): v for k, v in inputs.items()})
        params.update({k.lower(): list(v[:3]) for k, v in BRICK_COLOURS.items()})
        params["output"] = out.lower()
        CASES.append(("brick", "ShaderNodeTexBrick", props, dict(inputs, **BRICK_COLOURS), out,
                      params))

bpy.ops.wm.read_factory_settings(use_empty=True)
mesh = bpy.data.meshes.new("points")
mesh.from_pydata(POINTS, [], [])
obj = bpy.data.objects.new("points", mesh)
bpy.context.scene.collection.objects.link(obj)

results = []
for kind, idname, props, inputs, out, params in CASES:
    tree = bpy.data.node_groups.new("t", 'GeometryNodeTree')
    tree.inputs.new('NodeSocketGeometry', "Geometry")
    tree.outputs.new('NodeSocketGeometry', "Geometry")
    gin = tree.nodes.new('NodeGroupInput')
    gout = tree.nodes.new('NodeGroupOutput')
    tex = tree.nodes.new(idname)
    for k, v in props.items():
        setattr(tex, k, v)
    for k, v in inputs.items():
        sock = next(s for s in tex.inputs if s.name == k)
        sock.default_value = v
    is_color = out == "Color"
    store = tree.nodes.new('GeometryNodeStoreNamedAttribute')
    store.data_type = 'FLOAT_COLOR' if is_color else 'FLOAT'
    store.domain = 'POINT'
    store.inputs['Name'].default_value = "v"
    value_in = next(s for s in store.inputs if s.name == "Value" and s.enabled)
    tree.links.new(gin.outputs[0], store.inputs[0])
    tree.links.new(next(s for s in tex.outputs if s.name == out), value_in)
    tree.links.new(store.outputs[0], gout.inputs[0])
    mod = obj.modifiers.new("gn", 'NODES')
    mod.node_group = tree
    dg = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(dg).data
    attr = ev.attributes["v"]
    vals = [[float("%.8g" % x) for x in (d.color[:3] if is_color else [d.value])]
            for d in attr.data]
    results.append({"kind": kind, "params": params, "values": vals})
    obj.modifiers.remove(mod)
    bpy.data.node_groups.remove(tree)

with open(OUT, "w") as f:
    json.dump({"points": POINTS, "cases": results}, f, indent=None)
    f.write("\n")
print("wrote", OUT, len(results), "cases")
