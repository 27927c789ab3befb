#!/usr/bin/python3
"""Benchmarks of the facet Python module (issue 9). Registered nowhere; run by hand:

    PYTHONPATH=build/core/python /usr/bin/python3 bench/python_bench.py [--reps 5] [--spp N]

1. Building a 1M-triangle scene from numpy arrays: MeshData from the arrays (dtype/shape/NaN/
   index checks, zero copy), the SceneDescription, and build_scene, split by its BuildReport
   into the time before the BVH build and the BVH build. Target: <= 0.1 s before the BVH build.
2. The Python-driven render against the CLI (`facet render`) on scenes/cornell_box.json, in
   alternating runs of the same process tree. Target: <= 2 % slower.
3. A session at its smallest pass size (1 spp per pass, a Python callback after each) against one
   render() call. Target: <= 3 % overhead.
4. The cost of one pass beyond its samples, on a one-tile region (robust against the load of a
   shared machine, which moves whole-image timings by 10-25 % between runs).

Every figure is the median of --reps runs; ratios are of medians from the same run.
"""
import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import facet

ROOT = pathlib.Path(__file__).resolve().parents[1]


def median_time(fn, reps):
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times


def grid_mesh(n):
    """An n x n vertex grid over [0, 1]^2 at z = 0: 2 (n-1)^2 triangles, float32 / int32."""
    xs = np.linspace(0.0, 1.0, n, dtype=np.float32)
    x, y = np.meshgrid(xs, xs)
    positions = np.stack([x.ravel(), y.ravel(), np.zeros(n * n, np.float32)], axis=1)
    k = np.arange(n * n, dtype=np.int32).reshape(n, n)[:-1, :-1].ravel()
    quads = np.stack([k, k + 1, k + n + 1, k + n], axis=1)
    indices = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]).astype(np.int32)
    return np.ascontiguousarray(positions), np.ascontiguousarray(indices)


def base_description():
    d = facet.SceneDescription()
    d.camera = facet.CameraDesc(position=(0.5, 0.5, 2), look_at=(0.5, 0.5, 0), up=(0, 1, 0),
                                fov=40, width=64, height=64)
    d.materials["white"] = facet.MaterialDesc("lambert", reflectance=0.7)
    d.lights.append(facet.LightDesc("point", position=(0.5, 0.5, 1), power=10))
    d.shapes.append(facet.ShapeDesc("sphere", center=(0.5, 0.5, 0.2), radius=0.1,
                                    material_ref="white"))
    return d


def bench_build(reps):
    positions, indices = grid_mesh(709)  # 2 * 708^2 = 1,002,528 triangles
    ntri = indices.shape[0]
    t_mesh, _ = median_time(lambda: facet.MeshData(positions, indices), reps)

    def describe():
        d = base_description()
        d.shapes.append(facet.ShapeDesc("mesh", mesh=facet.MeshData(positions, indices),
                                        material_ref="white"))
        return d

    t_desc, _ = median_time(describe, reps)
    d = describe()
    before, bvh = [], []

    def build():
        scene = facet.build_scene(d, name="bench")
        before.append(scene.seconds_before_bvh)
        bvh.append(scene.seconds_bvh)

    t_build, _ = median_time(build, reps)
    t_before, t_bvh = statistics.median(before), statistics.median(bvh)
    return [
        ("triangles", f"{ntri:,}", ""),
        ("MeshData(positions, indices)  (checks, zero copy)", f"{t_mesh * 1e3:.1f} ms", ""),
        ("description incl. MeshData", f"{t_desc * 1e3:.1f} ms", ""),
        ("build_scene: before the BVH (BuildReport)", f"{t_before * 1e3:.1f} ms", ""),
        ("build_scene: BVH (BuildReport)", f"{t_bvh * 1e3:.1f} ms", ""),
        ("build_scene call, total", f"{t_build * 1e3:.1f} ms", ""),
        ("numpy -> scene before the BVH (description + before)",
         f"{(t_desc + t_before) * 1e3:.1f} ms", "target 100"),
    ]


def cli_render(cli, scene_path, spp, stats_path):
    # Only the sample loop's seconds (--stats-json) are compared; the EXR goes to a temp dir.
    out = pathlib.Path(tempfile.gettempdir()) / "facet_bench_cli.exr"
    cmd = [str(cli), "render", str(scene_path), "-o", str(out), "-q", "--stats-json",
           str(stats_path)]
    if spp:
        cmd += ["--spp", str(spp)]
    subprocess.run(cmd, check=True)
    return json.loads(pathlib.Path(stats_path).read_text())["seconds"]


def bench_render(cli, reps, spp, per_pass):
    scene_path = ROOT / "scenes" / "cornell_box.json"
    scene = facet.load_scene(str(scene_path))
    opts = {"spp": spp} if spp else {}
    stats_path = pathlib.Path(tempfile.gettempdir()) / "facet_bench_stats.json"
    cli_s, py_wall, py_loop, sess_wall, sess_loop, passes = [], [], [], [], [], []
    # Warm-up (page cache, CPU frequency).
    facet.render(scene, spp=1)
    for _ in range(reps):
        # Alternate: CLI, facet.render, 1-spp-pass session.
        cli_s.append(cli_render(cli, scene_path, spp, stats_path))

        s = facet.RenderSession(scene, **opts)
        t0 = time.perf_counter()
        s.render()
        img = s.image()
        py_wall.append(time.perf_counter() - t0)
        py_loop.append(s.stats.seconds)

        s1 = facet.RenderSession(scene, pass_seconds=1e-9, **opts)
        t0 = time.perf_counter()
        s1.render(lambda info: True)
        img1 = s1.image()
        sess_wall.append(time.perf_counter() - t0)
        sess_loop.append(s1.stats.seconds)
        passes.append(s1.stats.passes)
        assert np.array_equal(img, img1)
    m = statistics.median
    c = m(cli_s)
    rows = [
        ("CLI `facet render` (sample loop, 16-spp passes)", f"{c:.3f} s", "1.000"),
        ("facet.render-equivalent session, sample loop", f"{m(py_loop):.3f} s",
         f"{m(py_loop) / c:.3f}"),
        ("  same, wall time of render() + image()", f"{m(py_wall):.3f} s",
         f"{m(py_wall) / c:.3f}"),
        (f"session, 1-spp passes ({passes[0]} passes, Python callback)", f"{m(sess_loop):.3f} s",
         f"{m(sess_loop) / c:.3f}"),
        ("  same, wall time", f"{m(sess_wall):.3f} s", f"{m(sess_wall) / c:.3f}"),
        ("1-spp-pass session / facet.render session (sample loop)", "",
         f"{m(sess_loop) / m(py_loop):.3f}"),
        # Ratios of neighbouring runs, then their median: less sensitive to the load drifting
        # across the whole benchmark than ratios of medians.
        ("median per-rep ratio: facet.render / CLI", "",
         f"{m([p / c for p, c in zip(py_loop, cli_s)]):.3f}"),
        ("median per-rep ratio: 1-spp session / facet.render", "",
         f"{m([q / p for q, p in zip(sess_loop, py_loop)]):.3f}"),
        (f"implied by section 4: {passes[0]} passes x cost per pass / render", "",
         f"{1 + passes[0] * per_pass / m(py_loop):.4f}"),
    ]
    return rows, {"cli": cli_s, "python": py_loop, "session_1spp": sess_loop}


def bench_pass_cost(reps):
    """Cost of one pass beyond its samples: a 16 x 16 region of the Cornell box (one tile) at
    512 spp, in 1-spp passes with a Python callback against one call; the difference per pass is
    what the pass structure (tile dispatch, the GIL round trip, the callback) costs. Small
    renders are far less disturbed by a loaded machine than whole images."""
    scene = facet.load_scene(str(ROOT / "scenes" / "cornell_box.json"))
    opts = dict(region=(248, 248, 264, 264), spp=512, threads=1)
    one, fine, passes = [], [], 0
    for _ in range(reps):
        s = facet.RenderSession(scene, **opts)
        s.render()
        one.append(s.stats.seconds)
        s = facet.RenderSession(scene, pass_seconds=1e-9, **opts)
        s.render(lambda info: True)
        fine.append(s.stats.seconds)
        passes = s.stats.passes
    m = statistics.median
    # Minima as well: on a loaded machine interference only adds time.
    per_pass = (min(fine) - min(one)) / max(1, passes - 1)
    return [
        ("one tile, 512 spp: render() (few passes), median / min",
         f"{m(one) * 1e3:.1f} / {min(one) * 1e3:.1f} ms", ""),
        (f"one tile, 512 spp: {passes} 1-spp passes, median / min",
         f"{m(fine) * 1e3:.1f} / {min(fine) * 1e3:.1f} ms", ""),
        ("cost per pass (difference of medians / passes)",
         f"{(m(fine) - m(one)) / max(1, passes - 1) * 1e6:.0f} us", ""),
        ("cost per pass (difference of minima / passes)", f"{per_pass * 1e6:.0f} us", ""),
    ], per_pass


def table(title, rows):
    print(f"\n{title}")
    w = max(len(r[0]) for r in rows)
    for name, value, ratio in rows:
        print(f"  {name:<{w}}  {value:>14}  {ratio:>7}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--spp", type=int, default=0, help="override the Cornell box's 64 spp")
    ap.add_argument("--cli", default=str(ROOT / "build" / "core" / "cli" / "facet"))
    ap.add_argument("--skip-render", action="store_true")
    a = ap.parse_args()
    print(f"python {sys.version.split()[0]} ({sys.executable}), numpy {np.__version__}, "
          f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.2f}, medians of {a.reps} runs")
    rows = bench_build(a.reps)
    table("1. 1M-triangle scene from numpy arrays", rows)
    rows, per_pass = bench_pass_cost(max(a.reps, 9))
    table("4. What a pass costs beyond its samples", rows)
    if not a.skip_render:
        rows, raw = bench_render(a.cli, a.reps, a.spp, per_pass)
        table("2./3. Cornell box (scenes/cornell_box.json), alternating runs; ratio to the CLI",
              rows)
        print("  raw seconds:", {k: [round(x, 3) for x in v] for k, v in raw.items()})


if __name__ == "__main__":
    main()
