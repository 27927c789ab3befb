#!/usr/bin/python3
"""povray-facet benchmark: render time of scenes with `brdf` finishes against the same scenes
with POV-Ray's classic phong/specular finishes, in the same run and with the same binary
(povray-facet renders classic finishes with POV-Ray's own code: no core call).

Usage: bench/povray_bench.py [POVRAY_FACET] [--reps N] [--size WxH] [--threads T]

Each repetition renders every variant once, in alternating order, so that a drift of the
machine's speed hits all variants alike; the table shows the median wall time per variant and
the median of the per-repetition ratios brdf / classic (target <= 1.10 for the lights-only
case). Glossy reflection rays (`samples N`) do work that classic finishes do not do at all;
their rows are reported against classic `reflection`, for scale, with no target.
"""
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


def main():
    args = sys.argv[1:]
    binary = "build/povray_patch/bin/povray-facet"
    reps, size, threads = 5, (320, 240), 2
    while args:
        a = args.pop(0)
        if a == "--reps":
            reps = int(args.pop(0))
        elif a == "--size":
            size = tuple(int(v) for v in args.pop(0).split("x"))
        elif a == "--threads":
            threads = int(args.pop(0))
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


if __name__ == "__main__":
    main()
