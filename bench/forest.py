#!/usr/bin/env python3
"""The forest benchmark (issue 25, "Instancing"): N instances of one procedurally generated
tree mesh of ~1e5 triangles, rendered by `facet render` under /usr/bin/time -v.

For each case it reports the load + build time (process wall time minus the render's own
seconds from --stats-json), the peak RSS (time -v's "Maximum resident set size"), and the
render's paths/s. Cases:
  - inst-1:       one instance (the prototype's memory: the baseline of the RSS target);
  - inst-N:       N instances (default 10^4: 10^9 triangles as placed);
  - inst-M/flat-M: M placements (default 100: 10^7 triangles), instanced and flattened (each
                  placement a mesh shape of the same file with the composed transform), the
                  same image: the paths/s comparison at equal visible complexity. 10^9 flat
                  triangles need ~100 GB, beyond this machine's 24 GiB.
Targets: peak RSS(inst-N) <= 2 (RSS(inst-1) + 200 B x N); paths/s(inst-M) >= 0.7 flat-M.

Usage: bench/forest.py [--facet build/core/cli/facet] [--instances 10000] [--flat 100]
                       [--spp 16] [--size 320x240] [--out /tmp/forest] [--threads 2]
"""
import argparse
import json
import math
import pathlib
import re
import subprocess
import sys
import time

import numpy as np


def tree_mesh(target=100_000, seed=1):
    """A tree of ~`target` triangles: a tapered trunk and a lumpy crown (a displaced UV
    sphere). Returns (positions float32 (n, 3), indices int32 (m, 3)); z up, base at z = 0."""
    rng = np.random.default_rng(seed)
    trunk_seg = 500  # 2 * 500 side triangles
    n_lat = 140
    n_lon = (target - 2 * trunk_seg) // (2 * n_lat)
    # Trunk: a cone frustum from radius 0.15 at z = 0 to 0.08 at z = 1.2.
    a = np.linspace(0, 2 * np.pi, trunk_seg, endpoint=False)
    bottom = np.stack([0.15 * np.cos(a), 0.15 * np.sin(a), np.zeros_like(a)], 1)
    top = np.stack([0.08 * np.cos(a), 0.08 * np.sin(a), np.full_like(a, 1.2)], 1)
    pos = [bottom, top]
    i = np.arange(trunk_seg)
    j = (i + 1) % trunk_seg
    tri = [np.stack([i, j, trunk_seg + j], 1), np.stack([i, trunk_seg + j, trunk_seg + i], 1)]
    # Crown: a sphere of radius ~1 centred at z = 2, rows of constant latitude (poles included
    # as rows of coincident points would make zero-area triangles: keep away from them).
    base = 2 * trunk_seg
    th = np.linspace(0.05, np.pi - 0.05, n_lat + 1)
    ph = np.linspace(0, 2 * np.pi, n_lon, endpoint=False)
    T, P = np.meshgrid(th, ph, indexing="ij")
    r = 1.0 + 0.12 * np.sin(5 * T) * np.cos(7 * P) + 0.03 * rng.standard_normal(T.shape)
    crown = np.stack([r * np.sin(T) * np.cos(P), r * np.sin(T) * np.sin(P),
                      2.0 + 1.1 * r * np.cos(T)], -1).reshape(-1, 3)
    pos.append(crown)
    row = np.arange(n_lat)[:, None] * n_lon
    col = np.arange(n_lon)[None, :]
    c0 = base + row + col
    c1 = base + row + (col + 1) % n_lon
    c2 = c0 + n_lon
    c3 = c1 + n_lon
    tri += [np.stack([c0, c2, c1], -1).reshape(-1, 3), np.stack([c1, c2, c3], -1).reshape(-1, 3)]
    return np.concatenate(pos).astype(np.float32), np.concatenate(tri).astype(np.int32)


def write_ply(path, positions, indices):
    with open(path, "wb") as f:
        f.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {len(positions)}\n"
                 "property float x\nproperty float y\nproperty float z\n"
                 f"element face {len(indices)}\nproperty list uchar int vertex_indices\n"
                 "end_header\n").encode())
        f.write(positions.astype("<f4").tobytes())
        faces = np.zeros(len(indices), dtype=[("n", "u1"), ("v", "<i4", 3)])
        faces["n"] = 3
        faces["v"] = indices
        f.write(faces.tobytes())


def placements(n, seed=2):
    """n tree transforms (4x4, row-major lists) on a jittered square grid of spacing 3:
    a random turn about z and a scale in [0.7, 1.3]."""
    rng = np.random.default_rng(seed)
    side = math.ceil(math.sqrt(n))
    out = []
    for k in range(n):
        gx, gy = k % side, k // side
        x = 3.0 * (gx - (side - 1) / 2) + rng.uniform(-1, 1)
        y = 3.0 * gy + rng.uniform(-1, 1)
        a = rng.uniform(0, 2 * np.pi)
        s = rng.uniform(0.7, 1.3)
        c, si = math.cos(a) * s, math.sin(a) * s
        out.append([c, -si, 0, x, si, c, 0, y, 0, 0, s, 0, 0, 0, 0, 1])
    return out, side


def scene(n, flat, width, height, spp):
    xfs, side = placements(n)
    extent = 3.0 * side
    d = {
        "format": "facet-scene", "version": 1,
        "description": f"forest: {n} trees of tree.ply ({'flattened' if flat else 'instanced'})",
        "camera": {"position": [0, -12, 9], "look_at": [0, 0.35 * extent, 1.5], "up": [0, 0, 1],
                   "fov": 50, "width": width, "height": height},
        "materials": {"ground": {"model": "lambert", "reflectance": [0.25, 0.2, 0.15]},
                      "leaf": {"model": "lambert", "reflectance": [0.15, 0.4, 0.1]}},
        "shapes": [{"type": "quad", "material": "ground",
                    "vertices": [[-extent, -extent, 0], [extent, -extent, 0],
                                 [extent, 2 * extent, 0], [-extent, 2 * extent, 0]]}],
        "lights": [{"type": "directional", "direction": [0.4, 0.6, -0.7], "irradiance": 3},
                   {"type": "environment", "radiance": [0.3, 0.4, 0.6]}],
        "render": {"integrator": "path", "spp": spp, "max_depth": 4, "seed": 1},
    }
    tree = {"type": "mesh", "file": "tree.ply", "material": "leaf"}
    if flat:
        for m in xfs:
            d["shapes"].append(dict(tree, transform={"matrix": m}))
    else:
        d["prototypes"] = {"tree": [tree]}
        for m in xfs:
            d["shapes"].append({"type": "instance", "of": "tree", "transform": {"matrix": m}})
    return d


def timed(cmd):
    """Runs cmd under /usr/bin/time -v: (wall s, CPU s = user + system, peak RSS MiB)."""
    t0 = time.monotonic()
    p = subprocess.run(["/usr/bin/time", "-v"] + cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{p.stderr[-2000:]}")
    field = lambda name: float(re.search(name + r": ([\d.]+)", p.stderr).group(1))
    cpu = field(r"User time \(seconds\)") + field(r"System time \(seconds\)")
    return wall, cpu, field(r"Maximum resident set size \(kbytes\)") / 1024


def run(facet, path, out, threads):
    """One case: the full render, and a one-pixel one-sample render of the same scene whose CPU
    time is the load and build's. Paths per CPU second (the render's CPU time: the full run's
    minus the build-only run's) are the comparison that survives a shared, loaded machine;
    wall-clock paths/s are reported too."""
    stats = path.with_suffix(".stats.json")
    base = [facet, "render", str(path), "-q", "--threads", str(threads)]
    wall, cpu, rss = timed(base + ["--stats-json", str(stats), "-o", str(out)])
    _, cpu_build, _ = timed(base + ["--spp", "1", "--region", "0,0,1,1", "-o",
                                    str(out.with_suffix(".pixel.exr"))])
    s = json.loads(stats.read_text())
    return {"wall_s": wall, "build_s": wall - s["seconds"], "render_s": s["seconds"],
            "peak_rss_mib": rss, "paths_per_s": s["paths_per_s"], "paths": s["paths"],
            "cpu_s": cpu, "build_cpu_s": cpu_build,
            "paths_per_cpu_s": s["paths"] / max(cpu - cpu_build, 1e-9)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--facet", default="build/core/cli/facet")
    ap.add_argument("--instances", type=int, default=10_000)
    ap.add_argument("--flat", type=int, default=100)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--size", default="320x240")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", default="/tmp/forest")
    a = ap.parse_args()
    w, h = map(int, a.size.split("x"))
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.monotonic()
    pos, idx = tree_mesh()
    write_ply(out / "tree.ply", pos, idx)
    print(f"tree: {len(idx)} triangles, {len(pos)} vertices "
          f"(generated in {time.monotonic() - t0:.2f} s)")
    cases = [("inst-1", 1, False), (f"inst-{a.instances}", a.instances, False),
             (f"inst-{a.flat}", a.flat, False), (f"flat-{a.flat}", a.flat, True)]
    results = {}
    for name, n, flat in cases:
        path = out / f"{name}.json"
        path.write_text(json.dumps(scene(n, flat, w, h, a.spp)))
        r = run(a.facet, path, out / f"{name}.exr", a.threads)
        r["placed_triangles"] = n * len(idx)
        results[name] = r
        print(f"{name:>12}: {n * len(idx):>14,} triangles placed, build {r['build_s']:7.2f} s, "
              f"peak RSS {r['peak_rss_mib']:8.1f} MiB, {r['paths_per_s'] / 1e3:7.1f} k paths/s "
              f"wall, {r['paths_per_cpu_s'] / 1e3:7.1f} k paths per CPU s")
    one = results["inst-1"]["peak_rss_mib"]
    many = results[f"inst-{a.instances}"]["peak_rss_mib"]
    target = 2 * (one + 200 * a.instances / 2**20)
    ratio = (results[f"inst-{a.flat}"]["paths_per_cpu_s"] /
             results[f"flat-{a.flat}"]["paths_per_cpu_s"])
    print(f"RSS target: {many:.1f} MiB <= 2 x ({one:.1f} + 200 B x {a.instances}) = "
          f"{target:.1f} MiB: {'met' if many <= target else 'MISSED'}")
    print(f"paths per CPU s, instanced / flattened at {a.flat}: {ratio:.3f} (target >= 0.7: "
          f"{'met' if ratio >= 0.7 else 'MISSED'})")
    (out / "results.json").write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
