"""The Blender side of bench/time_error.py: a long-lived headless Blender that renders on request,
so that its renders interleave with `facet render` runs and Blender's start-up is paid once.

  blender -b --factory-startup -noaudio --python bench/time_error/blender_worker.py -- <addon zip>

Reads one JSON request per line on stdin and answers each with one line `TE_REPLY <json>` on
stdout (Blender's own output goes there too; the driver reads only the reply lines):
  {"cmd": "load", "scene": path, "threads": 2}   import the JSON scene (File > Import > Facet
                                                 scene) and build its Cycles node twin
  {"cmd": "load", "scene": path, "threads": 2, "twin": "direct"}   build the Cycles twin
      directly (time_error/cycles_new_scenes.py: glTF shapes through Blender's glTF importer);
      no Facet engine then: the Facet importer does not import glTF shapes
  {"cmd": "render", "engine": "FACET"|"CYCLES", "spp": n, "seed": s, "out": path.exr}
      F12 with that engine; "seconds" is the time of bpy.ops.render.render() (scene
      export/sync, BVH build and sampling; not Blender's start-up, not the EXR write)
  {"cmd": "quit"}
Cycles' settings are facet_testsupport.cycles_scene's (box filter 1 px, no clamping, no
denoising, adaptive sampling off, light threshold 0, the given seed, not animated, bounces
matched to Facet's max_depth, 32-bit float EXR); the Cycles materials are time_error/
cycles_twin.py's. Errors are answered as {"error": message}."""
import json
import os
import sys
import time
import traceback

import addon_utils
import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import cycles_twin  # noqa: E402  (the JSON scene -> Cycles nodes conversion)
import cycles_new_scenes  # noqa: E402  (the new scenes' twins, built without the importer)

STATE = {}


def reply(obj):
    sys.stdout.write("TE_REPLY " + json.dumps(obj) + "\n")
    sys.stdout.flush()


def install(zip_path):
    bpy.ops.preferences.addon_install(filepath=os.path.abspath(zip_path), overwrite=True)
    mod = addon_utils.enable("facet_blender", default_set=True, handle_error=None)
    if mod is None:
        raise RuntimeError("the Facet addon did not enable")


def load(req):
    path = os.path.abspath(req["scene"])
    if req.get("twin") == "direct":
        with open(path) as f:
            data = json.load(f)
        scene = cycles_new_scenes.build(data, os.path.dirname(path), int(req.get("threads", 2)))
        im = scene.render.image_settings
        im.file_format, im.color_depth, im.color_mode, im.exr_codec = 'OPEN_EXR', '32', 'RGB', 'ZIP'
        STATE["scene"] = scene
        return {"notes": ["Cycles twin built directly (bench/time_error/cycles_new_scenes.py)"]}
    bpy.ops.wm.read_homefile(use_empty=True)
    res = bpy.ops.import_scene.facet(filepath=path)
    if res != {'FINISHED'}:
        raise RuntimeError("import of %s failed: %s" % (path, res))
    with open(path) as f:
        data = json.load(f)
    scene = bpy.context.scene
    render = data.get("render", {})
    depth = int(render.get("max_depth", 8))
    scene.facet.max_depth = depth
    scene.facet.integrator = render.get("integrator", "path")
    notes = cycles_twin.build(scene, data, int(req.get("threads", 2)))
    im = scene.render.image_settings
    im.file_format, im.color_depth, im.color_mode, im.exr_codec = 'OPEN_EXR', '32', 'RGB', 'ZIP'
    STATE["scene"] = scene
    return {"notes": notes}


def render(req):
    scene = STATE["scene"]
    engine = req["engine"]
    scene.render.engine = engine
    if engine == 'CYCLES':
        scene.cycles.samples = int(req["spp"])
        scene.cycles.seed = int(req["seed"])
    else:
        scene.facet.spp = int(req["spp"])
        scene.facet.integrator = req.get("integrator", "path")
        scene.facet.seed = int(req["seed"])
    c0 = time.process_time()  # CPU of every thread of this Blender process
    t0 = time.perf_counter()
    bpy.ops.render.render()
    seconds = time.perf_counter() - t0
    cpu_seconds = time.process_time() - c0
    img = bpy.data.images["Render Result"]
    img.save_render(os.path.abspath(req["out"]), scene=scene)
    return {"seconds": seconds, "cpu_seconds": cpu_seconds}


def main():
    install(sys.argv[sys.argv.index("--") + 1])
    reply({"ready": True, "blender": bpy.app.version_string})
    for line in sys.stdin:
        line = line.strip()
        if not line:
            continue
        try:
            req = json.loads(line)
            if req["cmd"] == "quit":
                reply({"bye": True})
                break
            reply({"load": load, "render": render}[req["cmd"]](req))
        except Exception as e:  # answered, so that the driver names the failing request
            traceback.print_exc()
            reply({"error": "%s: %s" % (type(e).__name__, e)})
    sys.stdout.flush()
    os._exit(0)


try:
    main()
except Exception:
    traceback.print_exc()
    sys.stdout.flush()
    os._exit(1)
