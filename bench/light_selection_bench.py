#!/usr/bin/python3
"""Light selection for next-event estimation: view (the default: each light's contribution
measured from the camera at load time, LightDistribution::view) against power (pbrt-v4's
estimate: Phi, pi A L, pi r^2 E, 4 pi^2 r^2 L for the environment, r the scene's bounding radius),
uniform (Cycles 3.4's) and tree (the light tree, light_tree.h: per shaded point), on the scenes
where the choice matters.

  PYTHONPATH=build/core/python /usr/bin/python3 bench/light_selection_bench.py \
      [--facet build/core/cli/facet] [--spp 64] [--reps 3] [--out /tmp/light-selection]

Per scene and mode: `facet render --light-selection MODE --threads 1` at --spp with two seeds
per rep; noise^2 = the per-pixel variance of one image, (a - b)^2 / 2 averaged over pixels and
channels; time = the renders' CPU seconds (load, pilot and render; one thread). Efficiency is
1 / (noise^2 x time): the reciprocal of the time to a given error. Reported: noise^2 x time
relative to uniform's in the same run (lower is better; median over --reps), the image means
(all modes must agree within noise: the difference of means over its standard error,
|z| < 4), and the pmfs. Scenes (written to --out):
  - hdri_lamp: studio.exr HDRI world, a 40 m ground, a 1.2 m sphere and a 2 x 1 m area light
    (the real-scene suite's engine_dof: power gave the world most shadow rays);
  - hdri_sun: studio.exr world + a sun (2 deg) over a 40 m ground, the textured glTF box
    (box_textured);
  - hidden_lamp: a strong area lamp whose light reaches the view only at grazing angles past a
    wall, and a weak point lamp (arealight_269's case);
  - cornell: the Cornell box (one light: view = power, bit-identical);
  - many_lights: 64 point lights of powers 1..64 W over a plane, and a cube.
"""
import argparse
import json
import os
import pathlib
import resource
import shutil
import statistics
import subprocess
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
import facet  # noqa: E402

MODES = ("uniform", "power", "view", "tree")


def base(width, height, camera):
    return {"format": "facet-scene", "version": 1,
            "camera": dict(camera, width=width, height=height, up=[0, 0, 1]),
            "render": {"integrator": "path", "spp": 16, "max_depth": 6, "seed": 1},
            "materials": {"ground": {"model": "lambert", "reflectance": 0.5},
                          "white": {"model": "lambert", "reflectance": 0.75},
                          "red": {"model": "lambert", "reflectance": [0.7, 0.2, 0.15]}},
            "shapes": [], "lights": []}


def ground(size=40):
    h = size / 2
    return {"type": "quad", "material": "ground",
            "vertices": [[-h, -h, 0], [h, -h, 0], [h, h, 0], [-h, h, 0]]}


def scenes(out, width, height):
    import staged_bench

    staged_bench.hdri(str(out))  # studio_clamped.exr
    box = pathlib.Path(staged_bench.BOX)
    for f in ("BoxTextured.gltf", "BoxTextured0.bin", "CesiumLogoFlat.png"):
        shutil.copy(box / f, out)
    env = {"type": "environment", "file": staged_bench.HDRI, "radiance": 0.5}
    s = {}
    cam = {"position": [3.2, -4.0, 2.2], "look_at": [0, 0, 0.6], "fov": 35}
    d = base(width, height, cam)
    d["shapes"] += [ground(), {"type": "sphere", "center": [0, 0, 0.6], "radius": 0.6,
                               "material": "red"},
                    # 2 x 1 m lamp at (1.5, -2, 3) facing down toward the sphere, 300 W-ish.
                    {"type": "quad", "emission": 25, "material": "white",
                     "vertices": [[0.5, -2.5, 3], [0.5, -1.5, 3], [2.5, -1.5, 3],
                                  [2.5, -2.5, 3]]}]
    d["lights"] = [env]
    s["hdri_lamp"] = d
    d = base(width, height, cam)
    d["shapes"] += [ground(), {"type": "gltf", "file": "BoxTextured.gltf",
                               "transform": {"rotate": {"axis": [1, 0, 0], "angle": 90},
                                             "translate": [0, 0, 0.5]}}]
    d["lights"] = [dict(env, radiance=1.0),
                   {"type": "directional", "direction": [-0.4, 0.5, -0.6], "irradiance": 3,
                    "angle": 2}]
    s["hdri_sun"] = d
    d = base(width, height, {"position": [0, -6, 3], "look_at": [0, 0, 0.5], "fov": 40})
    d["shapes"] += [ground(12), {"type": "box", "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 1],
                                 "material": "white"},
                    # A wall between the lamp and the view; the lamp faces down behind it.
                    {"type": "box", "min": [-6, 1.5, 0], "max": [6, 1.7, 2.5],
                     "material": "white"},
                    {"type": "quad", "emission": 400, "material": "white",
                     "vertices": [[-1, 2, 2.4], [-1, 3, 2.4], [1, 3, 2.4], [1, 2, 2.4]]}]
    d["lights"] = [{"type": "point", "position": [1.5, -2, 2.5], "power": 60},
                   {"type": "environment", "radiance": [0.05, 0.06, 0.08]}]
    s["hidden_lamp"] = d
    c = json.loads((ROOT / "scenes" / "cornell_box.json").read_text())
    c["camera"]["width"], c["camera"]["height"] = width, height
    s["cornell"] = c
    d = base(width, height, {"position": [0, -9, 6], "look_at": [0, 0, 0], "fov": 45})
    d["shapes"] += [ground(16), {"type": "box", "min": [-1, -1, 0], "max": [1, 1, 2],
                                 "material": "white"}]
    rng = np.random.default_rng(4)
    for k in range(64):
        x, y = (k % 8 - 3.5) * 1.6, (k // 8 - 3.5) * 1.6
        d["lights"].append({"type": "point", "position": [x, y, float(rng.uniform(0.5, 2.5))],
                            "power": float(k + 1)})
    s["many_lights"] = d
    files = {}
    for name, d in s.items():
        p = out / f"{name}.json"
        p.write_text(json.dumps(d, indent=1))
        files[name] = p
    return files


def run(facet_cli, scene, mode, seed, spp, out):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([facet_cli, "render", str(scene), "--light-selection", mode, "--seed",
                    str(seed), "--spp", str(spp), "--threads", "1", "-q", "-o", str(out)],
                   check=True, capture_output=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return facet.read_image(str(out)).astype(np.float64), (
        r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)


def pmfs(scene):
    s = facet.load_scene(str(scene))
    try:
        return ([round(x, 3) for x in s.light_pmfs("power")],
                [round(x, 3) for x in s.light_pmfs("view")])
    except AttributeError:
        return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--facet", default=str(ROOT / "build" / "core" / "cli" / "facet"))
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--size", default="160x120")
    ap.add_argument("--out", default="/tmp/light-selection")
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    w, h = map(int, a.size.split("x"))
    files = scenes(out, w, h)
    names = a.scenes or list(files)
    print(f"{w}x{h}, {a.spp} spp, 1 thread, {a.reps} reps of two seeds per mode, alternating "
          "modes in each rep\n")
    print("| scene | pmfs power → view | noise²·time / uniform's: power | view | tree | "
          "noise² (uniform, power, view, tree) | CPU s (uniform, power, view, tree) | "
          "means: max |z| between modes |")
    print("|---|---|---|---|---|---|---|---|")
    for name in names:
        scene = files[name]
        rel = {m: [] for m in MODES}
        noise = {m: [] for m in MODES}
        cpu = {m: [] for m in MODES}
        sums = {m: [] for m in MODES}
        for rep in range(a.reps):
            for m in MODES:
                ia, ta = run(a.facet, scene, m, 100 + 2 * rep, a.spp, out / f"{name}_{m}_a.exr")
                ib, tb = run(a.facet, scene, m, 101 + 2 * rep, a.spp, out / f"{name}_{m}_b.exr")
                noise[m].append(float(np.mean((ia - ib) ** 2) / 2))
                cpu[m].append((ta + tb) / 2)
                sums[m] += [ia, ib]
            for m in MODES:
                rel[m].append(noise[m][-1] * cpu[m][-1] / (noise["uniform"][-1] *
                                                          cpu["uniform"][-1]))
        # Means: every image of a mode averaged; z of the difference of two modes' means, the
        # SE from the per-pixel spread of each mode's images (pixels independent).
        zmax = 0.0
        mean_img = {m: np.mean(sums[m], axis=0) for m in MODES}
        var_img = {m: np.var(sums[m], axis=0, ddof=1) / len(sums[m]) for m in MODES}
        for i, m1 in enumerate(MODES):
            for m2 in MODES[i + 1:]:
                diff = float(np.mean(mean_img[m1] - mean_img[m2]))
                se = float(np.sqrt(np.sum(var_img[m1] + var_img[m2]))) / mean_img[m1].size
                zmax = max(zmax, abs(diff) / max(se, 1e-30))
        p = pmfs(scene)
        ptxt = "" if p is None else (f"{p[0][:4]}{'…' if len(p[0]) > 4 else ''} → "
                                     f"{p[1][:4]}{'…' if len(p[1]) > 4 else ''}")
        med = lambda v: statistics.median(v)
        print(f"| {name} | {ptxt} | {med(rel['power']):.3f} | {med(rel['view']):.3f} | "
              f"{med(rel['tree']):.3f} | "
              + ", ".join(f"{med(noise[m]):.3g}" for m in MODES) + " | "
              + ", ".join(f"{med(cpu[m]):.2f}" for m in MODES) + f" | {zmax:.2f} |")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
