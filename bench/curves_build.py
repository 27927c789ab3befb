"""Build time and peak memory of a curves shape of N hair strands (docs/curves.md).

N strands of K Catmull-Rom control points (the first and last repeated, as Blender's exporter
writes them) with a radius per point, rooted on a unit sphere and bent a little, built from
numpy arrays through the Python module (facet.build_scene), then one small render to show it
traces. Peak memory is the process's maximum resident set (ru_maxrss) after the build against
before it (the arrays made, the module loaded):

    PYTHONPATH=build/core/python /usr/bin/python3 bench/curves_build.py --strands 1000000
"""
import argparse
import json
import resource
import time

import numpy as np

import facet


def strands(n, keys, seed=1):
    """Points (n * keys, 3) float32 and radii (n * keys,) of n strands of `keys` points."""
    rng = np.random.default_rng(seed)
    root = rng.normal(size=(n, 3))
    root /= np.linalg.norm(root, axis=1, keepdims=True)
    bend = rng.normal(scale=0.05, size=(n, 3))
    inner = keys - 2
    t = np.linspace(0.0, 1.0, inner)
    p = root[:, None, :] * (1.0 + 0.3 * t[None, :, None]) + bend[:, None, :] * t[None, :, None] ** 2
    p = np.concatenate([p[:, :1], p, p[:, -1:]], axis=1)  # ends repeated
    r = np.concatenate([[1.0], np.linspace(1.0, 0.2, inner), [0.2]]) * 0.002
    return p.reshape(-1, 3).astype(np.float32), np.tile(r, n).astype(np.float32)


def cpu_s():
    """User plus system CPU seconds of this process (every thread: Embree builds in parallel).
    On a loaded machine the wall time grows, the CPU time much less."""
    ru = resource.getrusage(resource.RUSAGE_SELF)
    return ru.ru_utime + ru.ru_stime


def maxrss_mib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--strands", type=int, default=1000000)
    ap.add_argument("--keys", type=int, default=6)
    ap.add_argument("--profile", default="round", choices=("round", "flat"))
    args = ap.parse_args()
    points, radius = strands(args.strands, args.keys)
    counts = np.full(args.strands, args.keys, np.uint32)
    d = facet.parse_scene_description(json.dumps({
        "format": "facet-scene", "version": 1,
        "camera": {"position": [0, -4, 0], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 40,
                   "width": 64, "height": 64},
        "materials": {"hair": {"model": "lambert", "reflectance": 0.5}},
        "shapes": [],
        "lights": [{"type": "directional", "direction": [-1, 1, -1], "irradiance": 2}]}),
        name="bench")
    d.shapes = [facet.ShapeDesc("curves", basis="catmull_rom", profile=args.profile,
                                curves=facet.CurveData(points=points, radius=radius,
                                                       counts=counts),
                                material_ref="hair")]
    before = maxrss_mib()
    cpu0 = cpu_s()
    t0 = time.perf_counter()
    scene = facet.build_scene(d, name="bench")
    build = time.perf_counter() - t0
    build_cpu = cpu_s() - cpu0
    after = maxrss_mib()
    t0 = time.perf_counter()
    image = facet.render(scene, spp=1, threads=1)
    render = time.perf_counter() - t0
    covered = float((np.asarray(image)[..., 1] > 0).mean())
    print(json.dumps({
        "strands": args.strands, "control_points": int(len(points)),
        "segments": int(args.strands * (args.keys - 3)), "profile": args.profile,
        "build_s": round(build, 3), "build_cpu_s": round(build_cpu, 3),
        "bvh_s": round(scene.seconds_bvh, 3),
        "before_bvh_s": round(scene.seconds_before_bvh, 3),
        "maxrss_before_mib": round(before, 1), "maxrss_after_build_mib": round(after, 1),
        "build_peak_mib": round(after - before, 1),
        "render_64x64_1spp_s": round(render, 3), "covered_fraction": round(covered, 3)}))


if __name__ == "__main__":
    main()
