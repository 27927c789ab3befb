"""Peak memory and time of a render with an OpenVDB grid medium of N^3 voxels, against the same
scene with a homogeneous medium (docs/media.md, "What a medium is").

Run in headless Blender (it makes the grid: a filled cube through Mesh to Volume, saved with
VolumeGrids.save), which then runs `facet render` under /usr/bin/time for both scenes:

    blender -b --factory-startup -noaudio --python bench/grid_memory.py -- \
        --facet build/core/cli/facet --voxels 256 --out /tmp/grid_memory
"""
import argparse
import json
import os
import re
import subprocess
import sys

import bpy


def parse():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("--facet", required=True)
    ap.add_argument("--voxels", type=int, default=256)
    ap.add_argument("--out", default="/tmp/grid_memory")
    ap.add_argument("--spp", type=int, default=16)
    return ap.parse_args(argv)


def make_grid(n, path):
    """A VDB whose active voxels fill a cube of n^3 voxels (Mesh to Volume, filled)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_cube_add(size=2.0)
    cube = bpy.context.active_object
    vo = bpy.data.objects.new("Grid", bpy.data.volumes.new("grid"))
    bpy.context.scene.collection.objects.link(vo)
    m = vo.modifiers.new("m2v", 'MESH_TO_VOLUME')
    m.object = cube
    m.resolution_mode = 'VOXEL_SIZE'
    m.voxel_size = 2.0 / n
    m.use_fill_volume = True
    dg = bpy.context.evaluated_depsgraph_get()
    grids = vo.evaluated_get(dg).data.grids
    grids.load()
    if not grids.save(path):
        raise SystemExit("could not save %s" % path)


def scene(medium):
    return {
        "format": "facet-scene", "version": 1,
        "camera": {"position": [0, -6, 1], "look_at": [0, 0, 0], "fov": 35,
                   "width": 160, "height": 120},
        "media": {"m": medium},
        "materials": {"b": {"model": "null", "interior": "m"}},
        "shapes": [{"type": "box", "min": [-1.1, -1.1, -1.1], "max": [1.1, 1.1, 1.1],
                    "material": "b"}],
        "lights": [{"type": "environment", "radiance": 1}],
    }


def run(facet, path, spp, out):
    cmd = ["/usr/bin/time", "-v", facet, "render", path, "--spp", str(spp), "-o", out]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(r.stderr)
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", r.stderr).group(1))
    wall = re.search(r"Elapsed \(wall clock\) time.*: (\S+)", r.stderr).group(1)
    return rss / 1024.0, wall


def main():
    a = parse()
    os.makedirs(a.out, exist_ok=True)
    vdb = os.path.join(a.out, "grid.vdb")
    make_grid(a.voxels, vdb)
    rows = []
    for name, medium in (("homogeneous", {"kind": "homogeneous", "sigma_s": 0.5}),
                         ("grid %d^3" % a.voxels, {"kind": "grid", "file": vdb, "sigma_s": 0.5})):
        path = os.path.join(a.out, name.split()[0] + ".json")
        with open(path, "w") as f:
            json.dump(scene(medium), f)
        rss, wall = run(a.facet, path, a.spp, os.path.join(a.out, name.split()[0] + ".exr"))
        rows.append((name, rss, wall))
    print("| medium | peak RSS (MiB) | wall time |")
    print("|---|---:|---:|")
    for name, rss, wall in rows:
        print("| %s | %.0f | %s |" % (name, rss, wall))
    print("grid over homogeneous: +%.0f MiB (the grid's floats: %.1f MiB)"
          % (rows[1][1] - rows[0][1], a.voxels ** 3 * 4 / 2.0 ** 20))


main()
