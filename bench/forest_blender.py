#!/usr/bin/env python3
"""The forest through Blender (issue 25, section 3: "Cycles on the same scene through
Blender"): bench/forest.py's tree (~10^5 triangles, the same generator) placed N times (default
10^4: ~10^9 triangles as placed) by geometry nodes (Instance on Points: one object, N
instances, the placements of bench/forest.py: a jittered grid, a turn about z, a scale in
[0.7, 1.3]), under a sun and a sky, rendered in Blender 3.4 by Cycles and by the Facet engine
at equal settings (path tracing, 4 bounces for Facet = 3 for Cycles, no clamping, no
denoising, no adaptive sampling, box filter 1 px; cycles_scene.cycles_settings).

Each renderer runs in its own Blender process under /usr/bin/time -v, twice: at 1 spp and at
`--spp`. Per renderer:
  - F12 wall time at both counts; the **per-sample time** (T(spp) - T(1)) / (spp - 1) gives
    the **paths/s** = W H (spp - 1) / (T(spp) - T(1)) (one camera path per pixel sample for
    both), and T(1) minus one sample's time is the **sync/build time** (export + BVH build +
    start-up of the render, Blender's scene evaluation included for both);
  - the **peak RSS** of the process at `--spp` (time -v's maximum resident set), and of a
    third Blender process that builds the scene and renders nothing (Blender's own share).
Facet's own phase timings (hooks.last_timings: export+build, render) are printed too.

Usage: bench/forest_blender.py [--build build] [--instances 10000] [--spp 16]
                               [--size 320x240] [--threads 2]
(the addon installed in build/tests/blender/user_scripts: `ctest -R blender.install`).
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def timed(cmd, env):
    t0 = time.monotonic()
    p = subprocess.run(["/usr/bin/time", "-v"] + cmd, capture_output=True, text=True, env=env)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        sys.exit("%s failed:\n%s\n%s" % (" ".join(cmd), p.stdout[-3000:], p.stderr[-3000:]))
    rss = float(re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr).group(1))
    m = re.search(r"FOREST_RESULT (\{.*\})", p.stdout)
    return wall, rss / 1024, json.loads(m.group(1)) if m else {}


def driver(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--instances", type=int, default=10_000)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--size", default="320x240")
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args(argv)
    scripts = os.path.join(a.build, "tests", "blender", "user_scripts")
    env = dict(os.environ, BLENDER_USER_SCRIPTS=scripts,
               BLENDER_USER_CONFIG=os.path.join(a.build, "tests", "blender", "user_config"),
               PYTHONNOUSERSITE="1")
    w, h = map(int, a.size.split("x"))

    def blender(engine, spp):
        return ["blender", "-b", "--factory-startup", "-noaudio", "--python-exit-code", "1",
                "--python", os.path.abspath(__file__), "--", "--inside", engine,
                str(a.instances), str(spp), str(w), str(h), str(a.threads)]

    results = {}
    _, rss_none, info = timed(blender("NONE", 1), env)
    print("scene: %s; Blender with the scene built, no render: peak RSS %.0f MiB"
          % (info.get("scene", "?"), rss_none))
    for engine in ("CYCLES", "FACET"):
        _, _, r1 = timed(blender(engine, 1), env)
        _, rss, rs = timed(blender(engine, a.spp), env)
        per_sample = (rs["f12_s"] - r1["f12_s"]) / (a.spp - 1)
        results[engine] = {
            "f12_1": r1["f12_s"], "f12_n": rs["f12_s"], "per_sample_s": per_sample,
            "sync_s": r1["f12_s"] - per_sample, "paths_per_s": w * h / max(per_sample, 1e-9),
            "peak_rss_mib": rss, "phases": rs.get("phases", {})}
        r = results[engine]
        print("%-6s F12 %.2f s at 1 spp, %.2f s at %d spp: %.3f s per sample, sync/build "
              "%.2f s, %.0f k paths/s, peak RSS %.0f MiB %s"
              % (engine.title(), r["f12_1"], r["f12_n"], a.spp, per_sample, r["sync_s"],
                 r["paths_per_s"] / 1e3, rss, r["phases"] or ""))
        sys.stdout.flush()
    c, f = results["CYCLES"], results["FACET"]
    print("\n| renderer | sync/build (s) | paths/s | peak RSS (MiB) | F12 at %d spp (s) |"
          % a.spp)
    print("|---|---:|---:|---:|---:|")
    for name, r in (("Cycles", c), ("Facet engine", f)):
        print("| %s | %.2f | %.0f k | %.0f | %.2f |" % (name, r["sync_s"], r["paths_per_s"] / 1e3,
                                                      r["peak_rss_mib"], r["f12_n"]))
    print("| Blender, scene only | | | %.0f | |" % rss_none)
    print("\nFacet / Cycles: sync/build %.2f, paths/s %.2f, peak RSS above Blender's %.2f"
          % (f["sync_s"] / c["sync_s"], f["paths_per_s"] / c["paths_per_s"],
             (f["peak_rss_mib"] - rss_none) / max(c["peak_rss_mib"] - rss_none, 1e-9)))


def inside(engine, n, spp, w, h, threads):
    import bpy
    import numpy as np
    from mathutils import Vector
    sys.path.insert(0, HERE)
    sys.path.insert(0, os.path.join(ROOT, "tests", "support", "python"))
    import forest  # bench/forest.py: the tree and the placements
    from facet_testsupport import cycles_scene as cs

    import addon_utils
    addon_utils.enable("facet_blender", default_set=True)
    from facet_blender import hooks

    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    pos, idx = forest.tree_mesh()
    me = bpy.data.meshes.new("tree")
    me.vertices.add(len(pos))
    me.vertices.foreach_set("co", pos.ravel())
    me.loops.add(idx.size)
    me.loops.foreach_set("vertex_index", idx.ravel())
    me.polygons.add(len(idx))
    me.polygons.foreach_set("loop_start", np.arange(0, idx.size, 3, dtype=np.int32))
    me.polygons.foreach_set("loop_total", np.full(len(idx), 3, np.int32))
    me.update(calc_edges=True)
    leaf = bpy.data.materials.new("leaf")
    leaf.use_nodes = True
    nt = leaf.node_tree
    for node in list(nt.nodes):
        nt.nodes.remove(node)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (0.15, 0.4, 0.1, 1.0)
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    me.materials.append(leaf)
    tree = bpy.data.objects.new("tree", me)
    scene.collection.objects.link(tree)
    tree.hide_render = True  # placed by the geometry nodes only
    # The placements: points with a rotation about z and a scale (named attributes).
    xfs, side = forest.placements(n)
    m = np.asarray(xfs, np.float64).reshape(-1, 4, 4)
    loc = m[:, :3, 3]
    scale = np.linalg.norm(m[:, :3, 0], axis=1)
    angle = np.arctan2(m[:, 1, 0], m[:, 0, 0])
    pts = bpy.data.meshes.new("placements")
    pts.vertices.add(n)
    pts.vertices.foreach_set("co", loc.astype(np.float32).ravel())
    rot = np.zeros((n, 3), np.float32)
    rot[:, 2] = angle
    pts.attributes.new("rot", 'FLOAT_VECTOR', 'POINT').data.foreach_set("vector", rot.ravel())
    pts.attributes.new("scl", 'FLOAT_VECTOR', 'POINT').data.foreach_set(
        "vector", np.repeat(scale.astype(np.float32), 3))
    pts.update()
    field = bpy.data.objects.new("forest", pts)
    scene.collection.objects.link(field)
    ng = bpy.data.node_groups.new("forest", 'GeometryNodeTree')
    ng.inputs.new('NodeSocketGeometry', "Geometry")
    ng.outputs.new('NodeSocketGeometry', "Geometry")
    gi, go = ng.nodes.new('NodeGroupInput'), ng.nodes.new('NodeGroupOutput')
    info = ng.nodes.new('GeometryNodeObjectInfo')
    info.inputs["Object"].default_value = tree
    info.inputs["As Instance"].default_value = True
    iop = ng.nodes.new('GeometryNodeInstanceOnPoints')
    rattr = ng.nodes.new('GeometryNodeInputNamedAttribute')
    rattr.data_type = 'FLOAT_VECTOR'
    rattr.inputs["Name"].default_value = "rot"
    sattr = ng.nodes.new('GeometryNodeInputNamedAttribute')
    sattr.data_type = 'FLOAT_VECTOR'
    sattr.inputs["Name"].default_value = "scl"
    ng.links.new(gi.outputs[0], iop.inputs["Points"])
    ng.links.new(info.outputs["Geometry"], iop.inputs["Instance"])
    # the output of the node's data type (each type has its own "Attribute" socket)
    ng.links.new(next(o for o in rattr.outputs if o.enabled), iop.inputs["Rotation"])
    ng.links.new(next(o for o in sattr.outputs if o.enabled), iop.inputs["Scale"])
    ng.links.new(iop.outputs[0], go.inputs[0])
    field.modifiers.new("forest", 'NODES').node_group = ng
    # ground, sun, sky, camera: bench/forest.py's scene
    extent = 3.0 * side
    ground = bpy.data.meshes.new("ground")
    ground.from_pydata([(-extent, -extent, 0), (extent, -extent, 0), (extent, 2 * extent, 0),
                        (-extent, 2 * extent, 0)], [], [(0, 1, 2, 3)])
    gmat = bpy.data.materials.new("ground")
    gmat.use_nodes = True
    gnt = gmat.node_tree
    for node in list(gnt.nodes):
        gnt.nodes.remove(node)
    gout = gnt.nodes.new("ShaderNodeOutputMaterial")
    gd = gnt.nodes.new("ShaderNodeBsdfDiffuse")
    gd.inputs["Color"].default_value = (0.25, 0.2, 0.15, 1.0)
    gnt.links.new(gd.outputs[0], gout.inputs["Surface"])
    ground.materials.append(gmat)
    scene.collection.objects.link(bpy.data.objects.new("ground", ground))
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", 'SUN'))
    sun.data.energy = 3.0
    sun.data.angle = 0.0
    sun.rotation_euler = (-Vector((0.4, 0.6, -0.7))).to_track_quat('Z', 'Y').to_euler()
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("sky")
    world.use_nodes = False
    world.color = (0.3, 0.4, 0.6)
    scene.world = world
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    cam.data.sensor_fit = 'VERTICAL'
    cam.data.angle = math.radians(50)  # bench/forest.py's vertical fov
    cam.location = (0, -12, 9)
    cam.rotation_euler = (Vector((0, 0.35 * extent, 1.5)) - cam.location).to_track_quat(
        '-Z', 'Y').to_euler()
    scene.collection.objects.link(cam)
    scene.camera = cam
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = w, h, 100
    r.threads_mode = 'FIXED'
    r.threads = threads
    scene.facet.spp = spp
    scene.facet.seed = 1
    scene.facet.max_depth = 4
    scene.facet.integrator = "path"
    cs.cycles_settings(scene, samples=spp, seed=1, max_depth=4)
    result = {"scene": "%d trees x %d triangles = %.3g placed, %dx%d, %d spp"
                       % (n, len(idx), n * len(idx), w, h, spp)}
    if engine != "NONE":
        scene.render.engine = engine
        scene.render.filepath = "/tmp/forest_blender_%s_%d.exr" % (engine.lower(), spp)
        t0 = time.perf_counter()
        bpy.ops.render.render(write_still=True)
        result["f12_s"] = time.perf_counter() - t0
        if engine == "FACET":
            result["phases"] = {k: round(v, 3) for k, v in hooks.last_timings.items()}
            result["report"] = list(hooks.last_problems)
    else:
        bpy.context.evaluated_depsgraph_get()  # the scene evaluated, as a render would
    print("FOREST_RESULT " + json.dumps(result))
    sys.stdout.flush()


if __name__ == "__main__":
    if "--inside" in sys.argv:
        rest = sys.argv[sys.argv.index("--inside") + 1:]
        try:
            inside(rest[0], *(int(v) for v in rest[1:6]))
        except Exception:
            import traceback
            traceback.print_exc()
            sys.stdout.flush()
            os._exit(1)
    else:
        driver(sys.argv[1:])
