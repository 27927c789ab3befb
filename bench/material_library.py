"""Blender's own material library (the `materials_library_vx` addon shipped with Debian's
blender: sample_materials.blend, 35 Cycles materials nobody here made) through the Facet
engine against Cycles 3.4: each material on a subdivided Suzanne on a grey floor under the
studio HDRI and a sun, rendered by both engines, with the engine's report lines.

    blender -b --factory-startup -noaudio --python bench/material_library.py -- OUTDIR \
        [--size 128x96] [--spp 64] [--docs] [--from-json] [NAME ...]

(with BLENDER_USER_SCRIPTS / BLENDER_USER_CONFIG of a build where the addon is installed:
`ctest --test-dir build -R blender.install`, then `build/tests/blender/user_scripts`). Facet
seed 1, Cycles seeds 1 and 2 (unbiased, non-adaptive: cycles_settings; 8 bounces each); the
measures of the real-scene suite: mean luminance Facet / Cycles, and the RMSE of 8 x 8 block
means of Facet against Cycles seed 1 over the same between Cycles' seeds (the noise floor).
A material converts "within noise" when the mean is within 2% and the block RMSE within 3x
the floor. With --docs the table goes between the markers of docs/blender.md
("Blender's material library"); --from-json rewrites them from OUTDIR/material_library.json
without rendering."""
import json
import os
import sys
import time

import bpy
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "support", "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

LIBRARY = "/usr/share/blender/scripts/addons/materials_library_vx/sample_materials.blend"
HDRI = "/usr/share/blender/datafiles/studiolights/world/forest.exr"
BEGIN, END = "<!-- material-library:begin -->", "<!-- material-library:end -->"
MEAN_TOL, RMSE_FACTOR = 0.02, 3.0
MAX_DEPTH = 9  # Cycles 8 bounces


def options():
    a = bt.args()
    out, size, spp, docs, names, again = a[0], "128x96", 64, False, [], False
    i = 1
    while i < len(a):
        if a[i] == "--size":
            size, i = a[i + 1], i + 2
        elif a[i] == "--spp":
            spp, i = int(a[i + 1]), i + 2
        elif a[i] == "--docs":
            docs, i = True, i + 1
        elif a[i] == "--from-json":
            again, i = True, i + 1
        else:
            names.append(a[i])
            i += 1
    w, h = (int(v) for v in size.split("x"))
    return out, w, h, spp, docs, names, again


def library_names():
    with bpy.data.libraries.load(LIBRARY) as (src, _):
        return [n for n in src.materials if n != "Material"]  # 'Material': the file's default


def stage(name, w, h, spp):
    """The test scene with material `name` appended from the library on Suzanne."""
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    scene.render.use_compositing = scene.render.use_sequencer = False
    with bpy.data.libraries.load(LIBRARY) as (src, dst):
        dst.materials = [name]
    mat = dst.materials[0]
    bpy.ops.mesh.primitive_monkey_add(location=(0.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.6))
    monkey = bpy.context.active_object
    mod = monkey.modifiers.new("sub", 'SUBSURF')
    mod.levels = mod.render_levels = 2
    bpy.ops.object.shade_smooth()
    monkey.data.materials.append(mat)
    bpy.ops.mesh.primitive_plane_add(size=12.0, location=(0.0, 0.0, -0.75))
    floor, nt, out = bt.new_material("floor")
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (0.4, 0.4, 0.4, 1.0)
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    bpy.context.active_object.data.materials.append(floor)
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    env = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    env.image = bpy.data.images.load(HDRI)
    world.node_tree.links.new(env.outputs[0], world.node_tree.nodes["Background"].inputs[0])
    scene.world = world
    world.cycles.sample_map_resolution = 256
    cs.add_light(scene, 'SUN', 2.0, (0.0, 0.0, 5.0), rotation=(0.7, 0.2, 0.5),
                 visible_camera=False)
    cd = bpy.data.cameras.new("cam")
    cam = bpy.data.objects.new("cam", cd)
    cam.location = (0.0, -4.2, 1.2)
    cam.rotation_euler = (1.33, 0.0, 0.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.facet.spp = spp
    scene.facet.max_depth = MAX_DEPTH
    cs.cycles_settings(scene, samples=spp, seed=1, max_depth=MAX_DEPTH)
    return scene


def measure(name, out, w, h, spp):
    from facet_blender import hooks
    scene = stage(name, w, h, spp)
    base = os.path.join(out, "matlib_%s" % "".join(c if c.isalnum() else "_" for c in name))
    t0 = time.perf_counter()
    f, tf = cs.render(scene, 'FACET', base + "_facet.exr", 1, problems_are_errors=False)
    report = [p for p in hooks.last_problems]
    c1, tc = cs.render(scene, 'CYCLES', base + "_cycles1.exr", 1)
    c2, _ = cs.render(scene, 'CYCLES', base + "_cycles2.exr", 2)
    ratio, rel = cs.compare_to_cycles(name, f, c1, c2)
    return {"material": name, "mean_ratio": float(ratio), "rmse_over_floor": float(rel),
            "facet_s": tf, "cycles_s": tc, "report": report,
            "within": bool(abs(ratio - 1.0) <= MEAN_TOL and rel <= RMSE_FACTOR),
            "size": [w, h], "spp": spp,
            "seconds": time.perf_counter() - t0}


def table(rows, w, h, spp):
    ok = sum(r["within"] for r in rows)
    # Lines about the material itself (the others are the scene's: the world's HDRI, the sun).
    quiet = [r for r in rows if not any("'%s'" % r["material"] in p or
                                        "/materials/%s" % r["material"] in p
                                        for p in r["report"])]
    lines = ["| material | mean Facet / Cycles | block RMSE / floor | within noise | report "
             "lines |", "|---|---:|---:|---|---|"]
    for r in rows:
        rep = "<br>".join(p.replace("|", "\\|") for p in r["report"]) or "none"
        lines.append("| %s | %.4f | %.2f× | %s | %s |"
                     % (r["material"], r["mean_ratio"], r["rmse_over_floor"],
                        "yes" if r["within"] else "**no**", rep))
    lines += ["", "%d materials, %d × %d pixels, %d spp (Facet seed 1, Cycles seeds 1 and 2), "
              "8 bounces. Within noise (mean within 2%%, block RMSE within 3× the floor): "
              "**%d of %d**; of the %d converted without a report line about the material, "
              "%d are within noise."
              % (len(rows), w, h, spp, ok, len(rows), len(quiet),
                 sum(r["within"] for r in quiet))]
    return "\n".join(lines)


def main():
    out, w, h, spp, docs, names, again = options()
    os.makedirs(out, exist_ok=True)
    bt.enable_addon()
    rows = []
    if again:
        with open(os.path.join(out, "material_library.json")) as f:
            rows = json.load(f)
        w, h, spp = rows[0]["size"] + [rows[0]["spp"]]
    for name in [] if again else names or library_names():
        try:
            rows.append(measure(name, out, w, h, spp))
        except Exception as e:  # one material's failure is a row, not the end of the run
            rows.append({"material": name, "mean_ratio": float("nan"),
                         "rmse_over_floor": float("nan"), "within": False,
                         "size": [w, h], "spp": spp,
                         "report": ["bench error: %s" % e]})
    if not again:
        with open(os.path.join(out, "material_library.json"), "w") as f:
            json.dump(rows, f, indent=1)
    text = table(rows, w, h, spp)
    print(text)
    if docs:
        path = os.path.join(ROOT, "docs", "blender.md")
        doc = open(path).read()
        a, b = doc.index(BEGIN) + len(BEGIN), doc.index(END)
        with open(path, "w") as f:
            f.write(doc[:a] + "\n" + text + "\n" + doc[b:])
    sys.stdout.flush()


bt.run(main)
