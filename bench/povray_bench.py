#!/usr/bin/python3
"""povray-facet benchmark: render time of scenes with `brdf` finishes against the same scenes
with POV-Ray's classic phong/specular finishes, in the same run and with the same binary
(povray-facet renders classic finishes with POV-Ray's own code: no core call).

Usage: bench/povray_bench.py [POVRAY_FACET] [--reps N] [--size WxH] [--threads T]
                             [--facet FACET_CLI] [--vs-size WxH]

With --facet, a second table: the same JSON scene rendered by `facet export-pov` + povray-facet
and by the standalone renderer `facet render --integrator direct --spp 1` at matched settings
(one ray through each pixel centre, the same lights, the same threads; the cross-check tests show
the two images equal within 1e-3): tests/support/scenes/export_coverage.json (3 delta lights,
every shape kind and model, mirrors) and the Cornell box with its light as 16 x 16 cells
(povray-facet: export-pov --area-grid 16; Facet: the same cells as spot lights,
facet_testsupport.quadrature.quadrature_twin).
Wall time of each whole process (parse/build included), interleaved, medians and the median of
the per-repetition ratios povray-facet / facet.

Each repetition renders every variant once, in alternating order, so that a drift of the
machine's speed hits all variants alike; the table shows the median wall time per variant and
the median of the per-repetition ratios brdf / classic (target <= 1.10 for the lights-only
case). Glossy reflection rays (`samples N`) do work that classic finishes do not do at all;
their rows are reported against classic `reflection`, for scale, with no target.
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

SCENE = """#version 3.7;
global_settings {{ assumed_gamma 1.0 max_trace_level 5 }}
camera {{ location <0, 3, -9> look_at <0, 0.8, 0> angle 45 }}
light_source {{ <6, 9, -6> rgb 0.8 }}
light_source {{ <-7, 6, -3> rgb 0.4 }}
light_source {{ <0, 8, 2> rgb 0.5 spotlight point_at <0, 0, 0> radius 20 falloff 30 }}
sky_sphere {{ pigment {{ gradient y color_map {{ [0 rgb <0.6, 0.7, 0.9>] [1 rgb <0.2, 0.3, 0.6>] }} }} }}
plane {{ y, 0 pigment {{ checker rgb 0.8 rgb 0.3 }} finish {{ {floor} }} }}
#for (i, 0, 4)
  #for (j, 0, 2)
    sphere {{ <(i - 2) * 1.6, 0.6, j * 1.6>, 0.6
      pigment {{ rgb <0.3 + 0.15 * i, 0.8 - 0.2 * j, 0.4> }} finish {{ {ball} }} }}
  #end
#end
"""

VARIANTS = [
    # name, floor finish, ball finish
    ("classic phong/specular", "diffuse 0.7 specular 0.3 roughness 0.02",
     "diffuse 0.6 phong 0.5 phong_size 60 specular 0.3 roughness 0.01"),
    ("brdf lights only (samples 0)",
     "brdf { composite diffuse_reflectance 0.7 distribution ggx alpha 0.15 samples 0 }",
     "brdf { composite diffuse_reflectance 0.6 distribution ggx alpha 0.1 fresnel dielectric ior 1.5 samples 0 }"),
    ("classic + reflection 0.2", "diffuse 0.7 specular 0.3 roughness 0.02 reflection 0.2",
     "diffuse 0.6 phong 0.5 phong_size 60 reflection 0.2"),
    ("brdf + glossy rays (samples 8)",
     "brdf { composite diffuse_reflectance 0.7 distribution ggx alpha 0.15 samples 8 }",
     "brdf { composite diffuse_reflectance 0.6 distribution ggx alpha 0.1 fresnel dielectric ior 1.5 samples 8 }"),
]


def render(binary, scene, out, size, threads):
    w, h = size
    t0 = time.perf_counter()
    proc = subprocess.run([binary, f"+I{scene}", f"+O{out}", f"+W{w}", f"+H{h}", "-D", "-V",
                           "-GA", f"+WT{threads}", "-A"], cwd=os.path.dirname(out),
                          env=dict(os.environ, HOME=os.path.dirname(out)),
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    t = time.perf_counter() - t0
    if proc.returncode != 0:
        sys.exit(f"render failed:\n{proc.stderr.decode()[-2000:]}")
    return t


def timed(args, cwd):
    t0 = time.perf_counter()
    proc = subprocess.run(args, cwd=cwd, env=dict(os.environ, HOME=cwd),
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    t = time.perf_counter() - t0
    if proc.returncode != 0:
        sys.exit(f"{args[0]} failed:\n{proc.stderr.decode()[-2000:]}")
    return t


def vs_facet(binary, facet, reps, size, threads):
    """povray-facet (exported scene) against the standalone renderer, same run, interleaved."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    sys.path.insert(0, os.path.join(root, "tests", "support", "python"))
    from facet_testsupport.quadrature import quadrature_twin  # spot lights at the cell centres
    w, h = size
    cases = []
    with tempfile.TemporaryDirectory() as tmp:
        cov = json.load(open(os.path.join(root, "tests", "support", "scenes",
                                          "export_coverage.json")))
        cb = json.load(open(os.path.join(root, "scenes", "cornell_box.json")))
        for name, scene, pov_scene, grid in (
                ("export_coverage (3 delta lights)", cov, cov, None),
                ("cornell_box, light as 16x16 cells", quadrature_twin(cb, 16), cb, 16)):
            for sc in (scene, pov_scene):
                sc["camera"]["width"], sc["camera"]["height"] = w, h
            js = os.path.join(tmp, f"c{len(cases)}.json")
            pjs = os.path.join(tmp, f"p{len(cases)}.json")
            json.dump(scene, open(js, "w"))
            json.dump(pov_scene, open(pjs, "w"))
            pov = pjs[:-5] + ".pov"
            t_export = timed([facet, "export-pov", pjs, "-o", pov]
                             + (["--area-grid", str(grid)] if grid else []), tmp)
            pov_cmd = [binary, f"+I{pov}", f"+O{tmp}/o.exr", "+FE", f"+W{w}", f"+H{h}", "-A",
                       "-UA", "-D", "-V", f"+WT{threads}"]
            facet_cmd = [facet, "render", js, "-o", f"{tmp}/f.exr", "--integrator", "direct",
                         "--spp", "1", "--threads", str(threads), "-q"]
            # The fixed cost of each process (start-up, parsing / scene build and BVH): the same
            # command for one pixel (POV-Ray: a 1x1 image; Facet: --region 0,0,1,1).
            pov_one = [a for a in pov_cmd if a[:2] not in ("+W", "+H")] + ["+W1", "+H1"]
            facet_one = facet_cmd + ["--region", "0,0,1,1"]
            tp, tf, tp1, tf1 = [], [], [], []
            for r in range(reps):
                runs = [(pov_cmd, tp), (facet_cmd, tf), (pov_one, tp1), (facet_one, tf1)]
                for cmd, out in (runs if r % 2 == 0 else runs[::-1]):
                    out.append(timed(cmd, tmp))
            cases.append((name, t_export, tp, tf, tp1, tf1))
    print(f"\nexport-pov + povray-facet vs facet render --integrator direct --spp 1, {w}x{h}, "
          f"{threads} threads, {reps} repetitions (median wall time of the process, s)")
    print(f"  {'scene':36s} {'export-pov':>10s} {'povray-facet':>12s} {'facet':>8s}  "
          "ratio pov/facet: of medians, median per rep (range)")
    med = statistics.median
    for name, te, tp, tf, tp1, tf1 in cases:
        ratios = [a / b for a, b in zip(tp, tf)]
        print(f"  {name:36s} {te:10.3f} {med(tp):12.3f} {med(tf):8.3f}"
              f"  {med(tp) / med(tf):.2f}, {med(ratios):.2f} ({min(ratios):.2f}-{max(ratios):.2f})")
        net = [(a - a1) / (b - b1) for a, b, a1, b1 in zip(tp, tf, tp1, tf1)]
        print(f"  {'  one pixel (fixed cost)':36s} {'':10s} {med(tp1):12.3f} {med(tf1):8.3f}"
              f"  rendering alone (total - one pixel): {med(tp) - med(tp1):.3f} s vs "
              f"{med(tf) - med(tf1):.3f} s, ratio per rep {med(net):.2f} ({min(net):.2f}-{max(net):.2f})")


def main():
    args = sys.argv[1:]
    binary = "build/povray_patch/bin/povray-facet"
    reps, size, threads = 5, (320, 240), 2
    facet, vs_size = None, (640, 480)
    while args:
        a = args.pop(0)
        if a == "--reps":
            reps = int(args.pop(0))
        elif a == "--size":
            size = tuple(int(v) for v in args.pop(0).split("x"))
        elif a == "--threads":
            threads = int(args.pop(0))
        elif a == "--facet":
            facet = os.path.abspath(args.pop(0))
        elif a == "--vs-size":
            vs_size = tuple(int(v) for v in args.pop(0).split("x"))
        else:
            binary = a
    binary = os.path.abspath(binary)
    times = {v[0]: [] for v in VARIANTS}
    with tempfile.TemporaryDirectory() as tmp:
        scenes = {}
        for name, floor, ball in VARIANTS:
            path = os.path.join(tmp, f"v{len(scenes)}.pov")
            with open(path, "w") as f:
                f.write(SCENE.format(floor=floor, ball=ball))
            scenes[name] = path
        for r in range(reps):
            order = VARIANTS if r % 2 == 0 else VARIANTS[::-1]
            for name, _, _ in order:
                times[name].append(render(binary, scenes[name], os.path.join(tmp, "o.png"),
                                          size, threads))
    print(f"povray-facet, {size[0]}x{size[1]}, {threads} threads, no AA, {reps} repetitions "
          "(median wall time, s)")
    pairs = [(VARIANTS[1][0], VARIANTS[0][0]), (VARIANTS[3][0], VARIANTS[2][0])]
    for name in times:
        print(f"  {name:34s} {statistics.median(times[name]):7.3f}   "
              f"(range {min(times[name]):.3f}-{max(times[name]):.3f})")
    for a, b in pairs:
        ratios = [x / y for x, y in zip(times[a], times[b])]
        print(f"  ratio {a} / {b}: median {statistics.median(ratios):.3f} "
              f"(range {min(ratios):.3f}-{max(ratios):.3f})")
    if facet:
        vs_facet(binary, facet, reps, vs_size, threads)


if __name__ == "__main__":
    main()
