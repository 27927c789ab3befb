#!/usr/bin/env python3
"""Export speed of the Blender addon on big meshes (issue 24: "Export speed on a 10^7-triangle
scene: measured, with foreach_get throughout").

Runs Blender headless (the addon installed in a user scripts directory, as the Blender tests
install it: `ctest -R blender.install` first) on a square grid mesh of ~N triangles built with
foreach_set, and times facet_blender.export.export_scene (the whole scene: camera, materials,
mesh arrays) for each case:
  - flat:        flat faces: positions and triangle indices (one vertex per mesh vertex);
  - smooth:      smooth faces: + vertex normals;
  - auto smooth: auto smooth on: split normals, one vertex per face corner (loop);
  - textured:    smooth + an Image Texture material: + the render UV map per loop;
  - colours:     smooth + a Color Attribute material: + float corner colours per loop;
  - instanced:   the N-triangle mesh in a collection placed 4 times (one prototype).
Peer in the same run: Blender's own floor for reading the mesh, the calls any exporter makes
(calc_loop_triangles() and foreach_get of the positions and the triangles' vertex indices, on
the evaluated mesh without a copy); `export / floor` is the exporter's cost over that. The core's build_scene
(Embree BVH) of the flat case is timed too. Times are medians over `--reps` runs (the machine
is shared: medians and same-run ratios only).

Usage: bench/blender_export_bench.py [--build build] [--tris 1e7] [--reps 3] [--profile]
(--profile prints the cProfile of one export of the largest per-loop case: where the time
goes, to find Python loops).
"""
import argparse
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def driver(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--tris", type=float, default=1e7)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--cases", default="flat,smooth,auto smooth,textured,colours,instanced")
    a = ap.parse_args(argv)
    scripts = os.path.join(a.build, "tests", "blender", "user_scripts")
    if not os.path.isdir(os.path.join(scripts, "addons", "facet_blender")):
        sys.exit("the addon is not installed in %s: run `ctest --test-dir %s -R blender.install`"
                 % (scripts, a.build))
    env = dict(os.environ, BLENDER_USER_SCRIPTS=scripts,
               BLENDER_USER_CONFIG=os.path.join(a.build, "tests", "blender", "user_config"),
               PYTHONNOUSERSITE="1")
    cmd = ["blender", "-b", "--factory-startup", "-noaudio", "--python-exit-code", "1",
           "--python", os.path.abspath(__file__), "--", "--inside", str(int(a.tris)),
           str(a.reps), "1" if a.profile else "0", a.cases]
    sys.exit(subprocess.call(cmd, env=env))


def inside(tris, reps, profile, cases):
    import statistics
    import time

    import addon_utils
    import bpy
    import numpy as np

    addon_utils.enable("facet_blender", default_set=True)
    from facet_blender import export, native

    def grid_mesh(name, n_tris):
        """A square grid of ~n_tris triangles (2 per quad) in the XY plane, built with
        foreach_set (from_pydata would take minutes at 10^7)."""
        q = max(1, int(round((n_tris / 2) ** 0.5)))
        nv = q + 1
        x, y = np.meshgrid(np.linspace(-1, 1, nv, dtype=np.float32),
                           np.linspace(-1, 1, nv, dtype=np.float32))
        z = 0.05 * np.sin(7 * x) * np.cos(5 * y)
        co = np.stack([x, y, z], -1).reshape(-1)
        i, j = np.meshgrid(np.arange(q), np.arange(q))
        v0 = (j * nv + i).reshape(-1)
        loops = np.stack([v0, v0 + 1, v0 + nv + 1, v0 + nv], -1).reshape(-1).astype(np.int32)
        me = bpy.data.meshes.new(name)
        me.vertices.add(nv * nv)
        me.vertices.foreach_set("co", co)
        me.loops.add(len(loops))
        me.loops.foreach_set("vertex_index", loops)
        me.polygons.add(q * q)
        me.polygons.foreach_set("loop_start", np.arange(0, len(loops), 4, dtype=np.int32))
        me.polygons.foreach_set("loop_total", np.full(q * q, 4, np.int32))
        me.update(calc_edges=True)
        return me

    def set_smooth(me, smooth, auto):
        me.polygons.foreach_set("use_smooth", np.full(len(me.polygons), smooth))
        me.use_auto_smooth = auto
        me.update()

    def material(kind):
        mat = bpy.data.materials.new(kind)
        mat.use_nodes = True
        nt = mat.node_tree
        bsdf = next(n for n in nt.nodes if n.bl_idname == 'ShaderNodeBsdfPrincipled')
        if kind == "textured":
            img = bpy.data.images.new("tex", 16, 16)
            img.filepath_raw = "/tmp/facet_export_bench_tex.png"
            img.file_format = 'PNG'
            img.save()
            t = nt.nodes.new("ShaderNodeTexImage")
            t.image = img
            nt.links.new(t.outputs["Color"], bsdf.inputs["Base Color"])
        elif kind == "colours":
            ca = nt.nodes.new("ShaderNodeVertexColor")
            ca.layer_name = "col"
            nt.links.new(ca.outputs["Color"], bsdf.inputs["Base Color"])
        return mat

    def timed_export():
        dg = bpy.context.evaluated_depsgraph_get()
        ts = []
        data = None
        for _ in range(reps):
            data = None
            t0 = time.perf_counter()
            data, problems = export.export_scene(dg, mesh_cache={})
            ts.append(time.perf_counter() - t0)
        return statistics.median(ts), data

    def floor(ob):
        dg = bpy.context.evaluated_depsgraph_get()
        ts = []
        for _ in range(reps):
            t0 = time.perf_counter()
            me = ob.evaluated_get(dg).data
            me.calc_loop_triangles()
            co = np.empty(len(me.vertices) * 3, np.float32)
            me.vertices.foreach_get("co", co)
            tri = np.empty(len(me.loop_triangles) * 3, np.int32)
            me.loop_triangles.foreach_get("vertices", tri)
            ts.append(time.perf_counter() - t0)
        return statistics.median(ts)

    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = 'FACET'
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    cam.location = (0, 0, 5)
    scene.collection.objects.link(cam)
    scene.camera = cam
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", 'SUN'))
    scene.collection.objects.link(sun)  # build_scene needs a light
    t0 = time.perf_counter()
    me = grid_mesh("grid", tris)
    print("BENCH grid: %d triangles, %d vertices, %d loops (built in %.1f s)"
          % (2 * len(me.polygons), len(me.vertices), len(me.loops), time.perf_counter() - t0))
    ob = bpy.data.objects.new("grid", me)
    scene.collection.objects.link(ob)
    rows = []
    wanted = cases.split(",")
    for case in ("flat", "smooth", "auto smooth", "textured", "colours", "instanced"):
        if case not in wanted:
            continue
        me.materials.clear()
        set_smooth(me, case != "flat", case == "auto smooth")
        if case in ("textured", "colours"):
            me.materials.append(material(case))
            if case == "textured" and not me.uv_layers:
                me.uv_layers.new(name="UVMap")
            if case == "colours" and "col" not in me.color_attributes:
                a = me.color_attributes.new("col", 'FLOAT_COLOR', 'CORNER')
                c = np.random.default_rng(1).uniform(0, 1, len(me.loops) * 4).astype(np.float32)
                a.data.foreach_set("color", c)
        coll = None
        if case == "instanced":
            coll = bpy.data.collections.new("c")
            scene.collection.objects.unlink(ob)
            coll.objects.link(ob)
            for k in range(4):
                e = bpy.data.objects.new("e%d" % k, None)
                e.instance_type = 'COLLECTION'
                e.instance_collection = coll
                e.location = (2.5 * k, 0, 0)
                scene.collection.objects.link(e)
        t_floor = floor(ob)
        t_exp, data = timed_export()
        shapes = data["shapes"]
        placed = sum(len(s["indices"]) for s in shapes if s["type"] == "mesh") + sum(
            len(p["indices"]) for v in data.get("prototypes", {}).values() for p in v
        ) * sum(1 for s in shapes if s["type"] == "instance")
        nverts = sum(len(s["positions"]) for s in shapes if s["type"] == "mesh") + sum(
            len(p["positions"]) for v in data.get("prototypes", {}).values() for p in v)
        t_build = None
        if case == "flat":
            t1 = time.perf_counter()
            native.build(data)
            t_build = time.perf_counter() - t1
        rows.append((case, placed, nverts, t_exp, t_floor, t_build))
        print("BENCH %-12s %11d triangles placed, %10d vertices exported: export %.3f s "
              "(%.3f s per 1e6 triangles), Blender's read floor %.3f s, export / floor %.2f%s"
              % (case, placed, nverts, t_exp, t_exp * 1e6 / max(1, placed), t_floor,
                 t_exp / t_floor,
                 "" if t_build is None else ", build_scene %.2f s" % t_build))
        sys.stdout.flush()
        if profile and case == "colours":
            import cProfile
            import pstats
            dg = bpy.context.evaluated_depsgraph_get()
            pr = cProfile.Profile()
            pr.enable()
            export.export_scene(dg, mesh_cache={})
            pr.disable()
            pstats.Stats(pr).sort_stats("cumulative").print_stats(18)
        data = None
        if coll is not None:
            for e in [o for o in scene.objects if o.type == 'EMPTY']:
                bpy.data.objects.remove(e)
            coll.objects.unlink(ob)
            scene.collection.objects.link(ob)
    print("\n| case | triangles placed | vertices exported | export (s) | s per 10⁶ "
          "triangles | Blender read floor (s) | export / floor |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for case, placed, nverts, t_exp, t_floor, t_build in rows:
        print("| %s | %s | %s | %.2f | %.3f | %.2f | %.2f |"
              % (case, format(placed, ","), format(nverts, ","), t_exp,
                 t_exp * 1e6 / max(1, placed), t_floor, t_exp / t_floor))
    for case, placed, nverts, t_exp, t_floor, t_build in rows:
        if t_build is not None:
            print("\nbuild_scene (Embree BVH) of the flat case: %.2f s" % t_build)


if __name__ == "__main__":
    if "--inside" in sys.argv:
        rest = sys.argv[sys.argv.index("--inside") + 1:]
        try:
            inside(int(rest[0]), int(rest[1]), rest[2] == "1", rest[3])
        except Exception:
            import traceback
            traceback.print_exc()
            sys.stdout.flush()
            os._exit(1)
    else:
        driver(sys.argv[1:])
