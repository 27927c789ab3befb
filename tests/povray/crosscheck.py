#!/usr/bin/python3
"""Cross-check of `facet export-pov` + povray-facet against `facet render --integrator direct`.

usage: crosscheck.py POVRAY_FACET FACET_CLI COMMAND [ARGS]

  scene NAME [N]  scenes/NAME.json (or tests/povray/NAME.json), --area-grid N (16), exported and rendered by povray-facet at a small size, against
               facet render --integrator direct of the same JSON (docs/povray.md, "Cross-check")
  coverage     tests/support/scenes/export_coverage.json: every shape kind, model and delta light
  scenes-errors  the scenes of scenes/ that POV-Ray cannot express fail to export, each with an
               error naming the JSON path of the reason
  errors       export-pov errors: each names the file and the JSON path (or the flag)
  glossy       povray-facet's glossy reflection rays (export-pov --glossy-samples) against
               `facet render --integrator path` at the matching depth, within noise (block t-test)
  float        +FE32 (povray-facet's 32-bit float EXR) of point_plane against the analytic
               pixel-centre radiance within 2e-6 relative; +FE (half) must fail that check
  radiosity-furnace  POV-Ray radiosity on brdf { lambert }: inside a glowing sphere the radiance
               is exactly rho e sum_{k=0..R} rho^k (R = recursion_limit)
  radiosity-cornell  export-pov --radiosity on the Cornell box against facet render --integrator
               path (POV-Ray's radiosity is interpolated and biased: stated tolerances)
  envmap       an environment map (export-pov --environment background: a sky_sphere image_map)
               seen by the camera across the seam, tilted and rotated, against facet render
  skylight     brdf_sky_sampling (export-pov --environment light): brdf finishes lit by an HDR
               sky_sphere against facet render --integrator direct within noise; 0 = no keyword
  skylight-errors  bad brdf_sky_sampling settings are parse errors naming file and line
  textures     image and checker textures (uv_mapping pigments on mesh2 uv_vectors and spheres,
               textured emission) and instances against facet render; wrong UV flips and colour
               spaces must fail
  texture-errors  textures export-pov cannot write exactly fail naming the JSON path
  principled   principled spheres (sheen, clearcoat, metallic, Disney diffuse retro-reflection)
               on an oren_nayar floor under point lights: povray-facet's brdf finish against
               facet direct (deterministic, REL_TOL); a wrong parameter in the export fails
  media        homogeneous media as POV-Ray media (docs/povray.md, "Media"): an absorbing and
               emitting interior exactly; scattering fog in a null box and a world medium
               within noise (t-test), with a control whose anisotropy sign is flipped that
               must fail; the media export errors
  principled-sky  the same materials lit by an HDR sky (brdf_sky_sampling): the diffuse, glossy
               and mirror parts of the split finish against facet within noise (t-test)

Images travel as EXR (povray-facet writes half floats: relative rounding <= 2^-11 = 4.9e-4,
half of the 1e-3 tolerance) and are read through `facet convert x.exr -o x.pfm` (float32).
Facet renders with 1 sample per pixel through the pixel centre (render.h), as POV-Ray does
without antialiasing, so silhouettes coincide; delta lights make both renders deterministic.
"""
import json
import math
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SUPPORT = os.path.join(ROOT, "tests", "support")
sys.path.insert(0, os.path.join(SUPPORT, "python"))
from facet_testsupport.quadrature import emitters, quadrature_twin, rgb3  # noqa: E402
REL_TOL = 1e-3        # per channel, relative to the Facet value
REQUIRED = 0.995      # fraction of pixels within REL_TOL
BLACK = 1e-6          # both values below this (shadow, black back side) count as equal


def read_pfm(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"PF":
            raise RuntimeError(path + ": not a colour PFM")
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        a = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4").reshape(h, w, 3)
    return a[::-1].astype(np.float64)


class Env:
    def __init__(self, pov, facet, tmp):
        self.pov, self.facet, self.tmp = pov, facet, tmp
        self.n = 0

    def path(self, stem):
        self.n += 1
        return os.path.join(self.tmp, f"{self.n:03d}_{stem}")

    def run(self, args, check=True):
        p = subprocess.run(args, capture_output=True, text=True)
        if check and p.returncode != 0:
            raise RuntimeError(f"{' '.join(args)} failed ({p.returncode}):\n{p.stdout}{p.stderr}")
        return p

    def image(self, exr):
        pfm = exr[:-4] + ".pfm"
        self.run([self.facet, "convert", exr, "-o", pfm])
        return read_pfm(pfm)

    def write_scene(self, scene, stem):
        js = self.path(stem + ".json")
        with open(js, "w") as f:
            json.dump(scene, f)
        return js

    def export(self, js, *extra):
        pov = self.path(os.path.basename(js)[4:-5] + ".pov")  # a new name per export
        self.run([self.facet, "export-pov", js, "-o", pov] + list(extra))
        return pov

    def povray(self, pov, w, h, fmt="+FE", extra=("-A",)):
        exr = pov[:-4] + "_pov%s.exr" % fmt[3:]
        # -A: no antialiasing (one ray through each pixel centre); +WT2: the result does not
        # depend on the thread count (no jitter, no radiosity).
        p = self.run([self.pov, f"+I{pov}", f"+O{exr}", fmt, f"+W{w}", f"+H{h}", "-UA",
                      "-D", "-V", "+WT2"] + list(extra), check=False)
        if p.returncode != 0 or not os.path.exists(exr):
            raise RuntimeError(f"povray-facet failed on {pov} ({p.returncode}):\n{p.stderr[-3000:]}")
        return self.image(exr)

    def render(self, js, *extra, integrator="direct"):
        exr = self.path(os.path.basename(js)[4:-5] + "_facet.exr")  # a new name per render
        self.run([self.facet, "render", js, "-o", exr, "--integrator", integrator, "-q"] + list(extra))
        return self.image(exr)


def compare(name, test, ref, mask=None, rel=REL_TOL, required=REQUIRED):
    """Fraction of pixels (within mask) whose every channel is within rel of ref (or both
    black); prints the worst pixels; True when >= required."""
    err = np.abs(test - ref) / np.maximum(np.abs(ref), 1e-30)
    err[(np.abs(test) < BLACK) & (np.abs(ref) < BLACK)] = 0.0
    # Below half's smallest normal (6.1e-5) EXR half floats have a fixed step of 2^-24: a
    # difference within one step is the file format's rounding.
    err[np.abs(test - ref) <= 2.0 ** -24] = 0.0
    e = err.max(axis=2)
    if mask is None:
        mask = np.ones(e.shape, bool)
    within = (e <= rel) & mask
    frac = within.sum() / max(mask.sum(), 1)
    ok = frac >= required
    print(f"{'ok  ' if ok else 'FAIL'} {name}: {100 * frac:.3f}% of {mask.sum()} pixels within "
          f"{rel:g} (required {100 * required:g}%); median error {np.median(e[mask]):.2e}, "
          f"max {e[mask].max():.2e}")
    ys, xs = np.nonzero(mask & ~within)
    order = np.argsort(-e[ys, xs])[:6]
    for k in order:
        y, x = ys[k], xs[k]
        print(f"      pixel ({x}, {y}): povray {test[y, x]} facet {ref[y, x]} (error {e[y, x]:.2e})")
    return ok


def small(scene, max_width=96):
    """The scene at a test size (same aspect ratio, width <= max_width)."""
    cam = scene["camera"]
    if cam["width"] > max_width:
        cam["height"] = max(1, round(cam["height"] * max_width / cam["width"]))
        cam["width"] = max_width
    return scene


def cmd_scene(env, name, n=16):
    path = os.path.join(ROOT, "scenes", name + ".json")
    if not os.path.exists(path):
        path = os.path.join(HERE, name + ".json")  # a scene of tests/povray
    scene = small(json.load(open(path)))
    w, h = scene["camera"]["width"], scene["camera"]["height"]
    js = env.write_scene(scene, name)
    ok = True
    if not emitters(scene):
        pov = env.povray(env.export(js), w, h)
        ok &= compare(f"{name} {w}x{h}: povray-facet vs facet direct", pov, env.render(js, "--spp", "1"))
        return ok
    # Emitters: POV-Ray sees a midpoint quadrature of each emitter (export-pov --area-grid N).
    # (1) Against Facet rendering the same quadrature (spot lights): deterministic, 1e-3.
    pov = env.povray(env.export(js, "--area-grid", str(n)), w, h)
    twin = quadrature_twin(scene, n)
    ref = env.render(env.write_scene(twin, name + "_twin"), "--spp", "1")
    # The pixels whose centre ray hits an emitter: Facet at 1 spp through the pixel centre adds
    # exactly the emission there (the emitters reflect nothing).
    direct = env.render(js, "--spp", "1")
    on_light = np.zeros((h, w), bool)
    for q in emitters(scene):
        le = np.array(rgb3(q["emission"]))
        on_light |= np.all(np.abs(direct - le) <= 1e-6 * le, axis=2)
    ok &= compare(f"{name} {w}x{h}: povray-facet (grid {n}) vs facet direct with the same "
                  f"{n}x{n} cells as spot lights, off the emitter", pov, ref, ~on_light)
    if on_light.any():
        ok &= compare(f"{name}: pixels seeing the emitter = its emission", pov, direct, on_light,
                      required=1.0)
    # (2) Against the exact integral: Facet's area light, sampled (1024 spp, two seeds). The
    # tolerance per pixel is derived, not chosen:
    #   1e-3             what (1) allows for the export itself (half floats, float vs double),
    #   + E_N            the midpoint grid's own error, estimated from its convergence: the
    #                    midpoint rule's error falls as 1/N^2 for a smooth integrand, so
    #                    E_N = |P_N - P_2N| * 4/3 (Richardson), from povray-facet at N and 2N,
    #   + 4 sigma        Facet's sampling noise, sigma = |A - B| / 2 from two seeds.
    # Only "smooth" pixels are compared: Facet's 1024 samples average over the pixel while
    # POV-Ray samples its centre, which agrees to 2.5e-4 only where the image is smooth at the
    # pixel scale: |discrete Laplacian| / 24 <= 2.5e-4 of the value (the box filter's
    # second-order term) in the pixel-centre image (1), and not next to an emitter.
    pov2 = env.povray(env.export(js, "--area-grid", str(2 * n)), w, h)
    a = env.render(js, "--spp", "1024", "--seed", "1")
    b = env.render(js, "--spp", "1024", "--seed", "2")
    mean = 0.5 * (a + b)
    lum = ref.mean(axis=2)
    lap = np.full(lum.shape, np.inf)
    lap[1:-1, 1:-1] = np.abs(lum[1:-1, :-2] + lum[1:-1, 2:] + lum[:-2, 1:-1] + lum[2:, 1:-1]
                             - 4 * lum[1:-1, 1:-1])
    near_light = on_light.copy()
    near_light[1:, :] |= on_light[:-1, :]
    near_light[:-1, :] |= on_light[1:, :]
    near_light[:, 1:] |= on_light[:, :-1]
    near_light[:, :-1] |= on_light[:, 1:]
    smooth = (lap / 24 <= 2.5e-4 * lum) & ~near_light
    floor = 1e-4  # relative errors of near-black pixels are noise
    rel = lambda x, y: (np.abs(x - y) / np.maximum(np.abs(y), floor)).max(axis=2)
    grid_err = rel(pov, pov2) * 4 / 3
    sigma = rel(a, b) / 2
    tol = 1e-3 + grid_err + 4 * sigma
    err = rel(pov, mean)
    frac = (err[smooth] <= tol[smooth]).mean()
    good = frac >= 0.99
    print(f"{'ok  ' if good else 'FAIL'} {name}: povray-facet (grid {n}) vs facet direct area "
          f"light (1024 spp x 2 seeds) on {smooth.sum()} smooth pixels: {100 * frac:.2f}% within "
          f"1e-3 + E_{n} + 4 sigma (required 99%); E_{n}: median {np.median(grid_err[smooth]):.1e}, "
          f"p99 {np.percentile(grid_err[smooth], 99):.1e}; sigma median "
          f"{np.median(sigma[smooth]):.1e}; error median {np.median(err[smooth]):.1e}, "
          f"p99 {np.percentile(err[smooth], 99):.1e}")
    return ok and good


def cmd_coverage(env):
    scene = json.load(open(os.path.join(SUPPORT, "scenes", "export_coverage.json")))
    w, h = scene["camera"]["width"], scene["camera"]["height"]
    js = env.write_scene(scene, "coverage")
    pov = env.povray(env.export(js), w, h)
    return compare(f"export_coverage {w}x{h}: povray-facet vs facet direct", pov, env.render(js, "--spp", "1"))


# Scenes of scenes/ that POV-Ray cannot express, and the JSON path export-pov must name.
INEXPRESSIBLE = {
    "furnace": "/shapes/0/emission",            # an emissive sphere (a closed emitter)
    "showcase": "/materials/brushed/alpha_u",   # anisotropic: POV-Ray has no tangents
    "material_sweep": "/materials/beckmann_4/alpha_u",
    "mirrors_fresnel": "/lights/0",             # the environment light
    "big_mesh": "/lights/0",
    "brushed": "/materials/brushed floor/alpha_u",  # anisotropic (bench/time_error.py's scene)
    "glass": "/materials/rough/model",          # a dielectric transmits: POV's interior differs
    "fog_box": "/render/max_depth",             # media: POV-Ray's scatter once (max_depth 1)
    "subsurface": "/materials/skin/subsurface",  # random-walk SSS: a finish is the fallback
    "showcase_media": "/render/max_depth",       # the juice's medium (POV's scatter once)
}


def cmd_scenes_errors(env):
    ok = True
    names = sorted(f[:-5] for f in os.listdir(os.path.join(ROOT, "scenes")) if f.endswith(".json"))
    for name in names:
        src = os.path.join(ROOT, "scenes", name + ".json")
        p = env.run([env.facet, "export-pov", src, "-o", env.path(name + ".pov")], check=False)
        want = INEXPRESSIBLE.get(name)
        if want is None:
            good = p.returncode == 0
            print(f"{'ok  ' if good else 'FAIL'} {name}: exports (cross-checked by povray_crosscheck_{name})"
                  + ("" if good else "\n      " + p.stderr.strip()))
        else:
            good = p.returncode == 1 and f"{src}: {want}: " in p.stderr
            print(f"{'ok  ' if good else 'FAIL'} {name}: not expressible: {p.stderr.strip()}")
        ok &= good
    missing = set(INEXPRESSIBLE) - set(names)
    if missing:
        print(f"FAIL listed but not in scenes/: {sorted(missing)}")
        ok = False
    return ok


def cmd_errors(env):
    base = json.load(open(os.path.join(ROOT, "scenes", "point_plane.json")))

    def variant(edit):
        s = json.loads(json.dumps(base))
        edit(s)
        return s

    mat = {"model": "lambert", "reflectance": 0.5}
    cases = [
        ("environment light", lambda s: s["lights"].append({"type": "environment", "radiance": 0.1}),
         [], "/lights/1: an environment light"),
        ("anisotropic lobe", lambda s: s["shapes"][0].update(material={"model": "ggx", "alpha_u": 0.1, "alpha_v": 0.3}),
         [], "/shapes/0/material/alpha_u: anisotropic"),
        ("emissive sphere", lambda s: s["shapes"].append({"type": "sphere", "center": [0, 1, 0], "radius": 0.2, "emission": 1}),
         [], "/shapes/1/emission: an emissive sphere"),
        ("soft spot edge", lambda s: s["lights"].append({"type": "spot", "position": [0, 3, 0], "direction": [0, -1, 0],
                                                         "power": 10, "outer_angle": 30, "inner_angle": 20}),
         [], "/lights/1/inner_angle: "),
        ("spot wider than 90", lambda s: s["lights"].append({"type": "spot", "position": [0, 3, 0], "direction": [0, -1, 0],
                                                             "power": 10, "outer_angle": 120}),
         [], "/lights/1/outer_angle: "),
        ("mirror deeper than POV-Ray", lambda s: (s["shapes"][0].update(material={"model": "mirror"}),
                                                  s["render"].update(max_depth=300)),
         [], "/render/max_depth: 300 bounces"),
        ("too many light cells", lambda s: s["shapes"].append({"type": "icosphere", "center": [0, 1, 0], "radius": 0.2,
                                                               "subdivisions": 3, "emission": 1}),
         ["--area-grid", "8"], "/shapes/1/emission: the emitters need more than 20000 light cells"),
        ("polygonal aperture", lambda s: s["camera"].update(aperture_radius=0.1, focus_distance=5, blades=6),
         [], "/camera/blades: POV-Ray's focal_blur aperture is round"),
        ("orthographic focal blur", lambda s: (s["camera"].pop("fov"), s["camera"].update(
            type="orthographic", scale=4, aperture_radius=0.1, focus_distance=5)),
         [], "/camera/aperture_radius: POV-Ray 3.7's orthographic focal_blur"),
        ("shift with focal blur", lambda s: s["camera"].update(fstop=2, focal_length=50, focus_distance=5, shift_y=0.1),
         [], "/camera/shift_y: with focal_blur"),
        ("bad scene (the loader's pointer)", lambda s: s["shapes"][0].update(radus=1),
         [], "/shapes/0/radus: unknown key"),
        ("bad material (build_scene's pointer)", lambda s: s["shapes"][0].update(material={"model": "ggx", "alpha": 12}),
         [], "/shapes/0/material/alpha: "),
    ]
    ok = True
    for title, edit, extra, want in cases:
        js = env.write_scene(variant(edit), "err")
        p = env.run([env.facet, "export-pov", js, "-o", env.path("err.pov")] + extra, check=False)
        good = p.returncode == 1 and f"{js}: {want}" in p.stderr
        print(f"{'ok  ' if good else 'FAIL'} {title}: rc {p.returncode}: {p.stderr.strip()}")
        ok &= good
    # --environment background: the approximation is written when asked for (and only then).
    js = env.write_scene(variant(lambda s: s["lights"].append({"type": "environment", "radiance": [0.1, 0.2, 0.3]})), "bg")
    out = env.path("bg.pov")
    p = env.run([env.facet, "export-pov", js, "-o", out, "--environment", "background"], check=False)
    good = p.returncode == 0 and "background { rgb <0.1" in open(out).read()
    print(f"{'ok  ' if good else 'FAIL'} --environment background writes the background: rc {p.returncode}")
    ok &= good
    # Free text cannot inject SDL: a shape name with a newline stays inside its comment.
    js = env.write_scene(variant(lambda s: s["shapes"][0].update(name="x\nsphere { 0, 100 }")), "name")
    out = env.path("name.pov")
    p = env.run([env.facet, "export-pov", js, "-o", out], check=False)
    good = p.returncode == 0 and not any(l.startswith("sphere { 0, 100 }") for l in open(out))
    print(f"{'ok  ' if good else 'FAIL'} a newline in a shape name stays in the comment")
    ok &= good
    # A flag out of range: CLI11 names the flag.
    js = env.write_scene(base, "flag")
    p = env.run([env.facet, "export-pov", js, "-o", env.path("f.pov"), "--area-grid", "0"], check=False)
    good = p.returncode != 0 and "--area-grid" in p.stderr
    print(f"{'ok  ' if good else 'FAIL'} --area-grid 0: rc {p.returncode}: {p.stderr.strip()}")
    ok &= good
    for bad, want in (("medum", "expected off, low, medium, high or COUNT,ERROR_BOUND,RECURSION_LIMIT"),
                      ("200,0.4", "expected off"), ("200,0.4,8,1", "expected off"),
                      ("0,0.4,8", "count must be in [1, 1600]"),
                      ("200,0,8", "error_bound must be in (0, 10]"),
                      ("200,0.4,21", "recursion_limit must be in [1, 20]")):
        p = env.run([env.facet, "export-pov", js, "-o", env.path("r.pov"), "--radiosity", bad], check=False)
        good = p.returncode == 1 and "--radiosity" in p.stderr and want in p.stderr
        print(f"{'ok  ' if good else 'FAIL'} --radiosity {bad}: rc {p.returncode}: {p.stderr.strip()}")
        ok &= good
    # --radiosity writes the block, hides emitters from radiosity rays behind a black twin.
    out = env.path("rad.pov")
    p = env.run([env.facet, "export-pov", os.path.join(ROOT, "scenes", "cornell_box.json"), "-o", out,
                 "--radiosity", "200,0.4,8"], check=False)
    text = open(out).read() if p.returncode == 0 else ""
    good = ("recursion_limit 8" in text and "count 200" in text and text.count("no_radiosity") == 1
            and text.count("no_image no_reflection no_shadow") == 1 and "max_trace_level 17" in text)
    print(f"{'ok  ' if good else 'FAIL'} --radiosity 200,0.4,8 writes the radiosity block and the emitter's twin")
    return ok and good


def sphere_pixels(cam, centre, radius):
    """The pixels whose centre ray (FORMAT.md camera) hits the sphere (centre, radius)."""
    w, h = cam["width"], cam["height"]
    pos, look = np.array(cam["position"], float), np.array(cam["look_at"], float)
    f = (look - pos) / np.linalg.norm(look - pos)
    r = np.cross(f, cam.get("up", [0, 1, 0])); r /= np.linalg.norm(r)
    u = np.cross(r, f)
    ty = math.tan(math.radians(cam["fov"]) / 2); tx = ty * w / h
    xs, ys = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    d = f + ((2 * xs / w - 1) * tx)[..., None] * r + ((1 - 2 * ys / h) * ty)[..., None] * u
    d /= np.linalg.norm(d, axis=2, keepdims=True)
    oc = pos - np.asarray(centre, float)
    b = (d * oc).sum(axis=2)
    return b * b - (oc @ oc - radius ** 2) > 0


def t_test(name, where, pov, ref, on):
    """Two noisy images agree within their noise on the pixels `on`: 4x4 blocks of per-pixel
    differences are t-tested (|mean| / (std / sqrt n) below 5 for >= 97% of the blocks with at
    least 12 pixels), and the mean over all of them is within 3 standard errors plus half-float
    rounding. A wrong weight or a missing lobe moves whole blocks and the mean."""
    h, w = on.shape
    diff = (pov - ref).mean(axis=2)
    zs = []
    for y0 in range(0, h, 4):
        for x0 in range(0, w, 4):
            m = on[y0:y0 + 4, x0:x0 + 4]
            if m.sum() < 12:
                continue
            v = diff[y0:y0 + 4, x0:x0 + 4][m]
            se = v.std(ddof=1) / math.sqrt(v.size)
            zs.append(abs(v.mean()) / max(se, 1e-9))
            if zs[-1] > 4: print(f"      block at ({x0}, {y0}): t {zs[-1]:.2f}, mean difference {v.mean():.2e} over {v.size} pixels")
    zs = np.array(zs)
    frac = (zs < 5).mean()
    v = diff[on]
    mean_p, mean_f = pov.mean(axis=2)[on].mean(), ref.mean(axis=2)[on].mean()
    se = v.std(ddof=1) / math.sqrt(v.size)
    ok_blocks = frac >= 0.97
    ok_mean = abs(v.mean()) <= 3 * se + 2.0 ** -11 * mean_f
    print(f"{'ok  ' if ok_blocks else 'FAIL'} {name}: {100 * frac:.1f}% of "
          f"{zs.size} 4x4 blocks on the {where} with |t| < 5 (required 97%); median |t| "
          f"{np.median(zs):.2f}, max {zs.max():.2f}")
    print(f"{'ok  ' if ok_mean else 'FAIL'} mean over {on.sum()} {where} pixels: povray-facet "
          f"{mean_p:.5f}, facet {mean_f:.5f} (ratio {mean_p / mean_f:.4f}; difference "
          f"{v.mean():.2e}, standard error {se:.2e})")
    return ok_blocks and ok_mean


def cmd_glossy(env):
    """A rough gold sphere reflecting a checkered Lambert floor and a coloured wall, lit by two
    point lights, black background. On the sphere, povray-facet computes the lights' highlights
    plus `samples` importance-sampled glossy rays, each seeing the floor or wall shaded by the
    lights (Lambert: no further rays). Facet's path tracer with max_depth 2 computes exactly that
    on the sphere: NEE at the sphere, one BSDF bounce to the floor or wall with NEE there, and at
    depth 2 only emission (none: delta lights, black background). Elsewhere path also has light
    reflected by the sphere onto the floor, which POV-Ray does not trace, so only pixels whose
    centre ray hits the sphere (radius shrunk by 5% against silhouettes) are compared. Both
    images are noisy: 4x4 blocks of per-pixel differences are t-tested (|mean| / (std / sqrt n)
    below 5 for >= 97% of blocks, and the mean over the sphere within 3 standard errors plus
    half-float rounding), which catches a wrong weight (f cos / pdf) or a wrong lobe."""
    w, h = 64, 48
    tiles = []
    for i in range(-3, 3):
        for j in range(-3, 2):
            tiles.append({"type": "quad", "material": "a" if (i + j) % 2 == 0 else "b",
                          "vertices": [[i, 0, j], [i, 0, j + 1], [i + 1, 0, j + 1], [i + 1, 0, j]]})
    centre, radius = np.array([0.0, 0.7, 0.0]), 0.7
    scene = {"format": "facet-scene", "version": 1,
             "camera": {"position": [0, 1.2, 3.2], "look_at": [0, 0.6, 0], "fov": 38, "width": w, "height": h},
             "materials": {"a": {"model": "lambert", "reflectance": 0.8},
                           "b": {"model": "lambert", "reflectance": [0.1, 0.3, 0.6]},
                           "wall": {"model": "lambert", "reflectance": [0.7, 0.2, 0.1]},
                           "gold": {"model": "ggx", "alpha": 0.3, "fresnel": "conductor",
                                    "eta": [0.143, 0.374, 1.442], "k": [3.983, 2.385, 1.603]}},
             "shapes": tiles + [
                 {"type": "quad", "material": "wall", "vertices": [[-3, 0, -3], [3, 0, -3], [3, 3, -3], [-3, 3, -3]]},
                 {"type": "sphere", "center": centre.tolist(), "radius": radius, "material": "gold"}],
             "lights": [{"type": "point", "position": [2, 3, 2], "power": 120},
                        {"type": "point", "position": [-2.5, 2, 0.5], "power": [40, 60, 90]}],
             "render": {"integrator": "path", "spp": 256, "max_depth": 2, "seed": 1}}
    js = env.write_scene(scene, "glossy")
    pov = env.povray(env.export(js, "--glossy-samples", "64"), w, h)
    # POV-Ray samples each pixel's centre, Facet averages over the pixel, which differs where
    # the reflection has sharp detail (measured: up to 4% in a 4x4 block on the checker's
    # reflection). So Facet renders at 5x the resolution and the pixel in the middle of each
    # 5x5 group is taken: its centre is the POV pixel's centre and its footprint is 1/5 as wide,
    # which shrinks the box filter's (second-order) difference 25-fold.
    fine = json.loads(json.dumps(scene))
    fine["camera"]["width"], fine["camera"]["height"] = 5 * w, 5 * h
    ref = env.render(env.write_scene(fine, "glossy_fine"), "--spp", "64", integrator="path")[2::5, 2::5]
    # Pixels whose centre ray hits the sphere (FORMAT.md camera), shrunk by 5%.
    on = sphere_pixels(scene["camera"], centre, 0.95 * radius)
    return t_test("glossy rays vs path (max_depth 2)", "sphere", pov, ref, on)


def point_plane_centres(scene):
    """The analytic radiance of point_plane.json at every pixel centre (double precision):
    rho/pi * Phi cos(theta) / (4 pi r^2), the camera of scenes/FORMAT.md."""
    cam = scene["camera"]
    w, h = cam["width"], cam["height"]
    pos, look, up = (np.array(cam[k], float) for k in ("position", "look_at", "up"))
    f = (look - pos) / np.linalg.norm(look - pos)
    r = np.cross(f, up); r /= np.linalg.norm(r)
    u = np.cross(r, f)
    ty = math.tan(math.radians(cam["fov"]) / 2); tx = ty * w / h
    xs, ys = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    d = f + ((2 * xs / w - 1) * tx)[..., None] * r + ((1 - 2 * ys / h) * ty)[..., None] * u
    (plane,), (light,) = scene["shapes"], scene["lights"]
    assert plane["type"] == "plane" and plane["normal"] == [0, 1, 0] and plane["point"] == [0, 0, 0]
    p = pos + (-pos[1] / d[..., 1])[..., None] * d
    to_light = np.array(light["position"], float) - p
    dist2 = (to_light ** 2).sum(-1)
    cos_t = to_light[..., 1] / np.sqrt(dist2)
    rho, phi = rgb3(plane["material"]["reflectance"]), rgb3(light["power"])
    return np.stack([rho[c] / math.pi * phi[c] * cos_t / (4 * math.pi * dist2) for c in range(3)], axis=2)


FLOAT_TOL = 2e-6   # relative: POV-Ray shades in double, its colours and the bridge in float (~6e-8 each)


def cmd_float(env):
    """povray-facet's +FE32 writes 32-bit float EXR: point_plane (a Lambert plane under a point
    light, exported) equals the analytic pixel-centre radiance within FLOAT_TOL relative. The
    same render written with +FE (half floats, relative rounding up to 2^-11 = 4.9e-4) must fail
    the check, so the check can fail. A bad bit depth for EXR is an option error."""
    scene = small(json.load(open(os.path.join(ROOT, "scenes", "point_plane.json"))))
    w, h = scene["camera"]["width"], scene["camera"]["height"]
    ref = point_plane_centres(scene)
    pov = env.export(env.write_scene(scene, "point_plane"))
    ok = True
    for fmt, want in (("+FE32", True), ("+FE", False)):
        img = env.povray(pov, w, h, fmt)
        e = np.abs(img - ref) / ref
        passed = bool(e.max() <= FLOAT_TOL)
        good = passed == want
        print(f"{'ok  ' if good else 'FAIL'} point_plane {w}x{h} {fmt}: max relative error "
              f"{e.max():.2e}, median {np.median(e):.2e}, RMSE {math.sqrt(((img - ref) ** 2).mean()):.3g} "
              f"(tolerance {FLOAT_TOL:g}: {'passes' if passed else 'fails'}, must {'pass' if want else 'fail'})")
        ok &= good
    # POV-Ray 3.7's Unix front end reports any +F parse error (stock's +FTg too) as "Problem
    # with option setting", the command line and "Failed to parse command-line option", exit 1.
    p = env.run([env.pov, f"+I{pov}", "+O" + env.path("bad.exr"), "+FE24", "+W8", "+H6", "-D"], check=False)
    out = p.stdout + p.stderr
    good = p.returncode != 0 and "+FE24" in out and "Failed to parse command-line option" in out
    print(f"{'ok  ' if good else 'FAIL'} +FE24 is an option error: rc {p.returncode}: "
          f"{' / '.join(l for l in out.splitlines() if l.strip())[-160:]}")
    return ok and good


def write_exr(path, rgb):
    """A float RGB OpenEXR file, scanlines uncompressed (OpenEXR file layout 2.0): the map of
    cmd_envmap, written here so that the test needs no image library."""
    import struct
    h, w, _ = rgb.shape

    def attr(name, kind, data):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(data)) + data

    chlist = b"".join(c.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in "BGR") + b"\0"
    box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
    header = (struct.pack("<ii", 20000630, 2) + attr("channels", "chlist", chlist)
              + attr("compression", "compression", b"\0") + attr("dataWindow", "box2i", box)
              + attr("displayWindow", "box2i", box) + attr("lineOrder", "lineOrder", b"\0")
              + attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
              + attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
              + attr("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    line = 3 * 4 * w
    first = len(header) + 8 * h
    offsets = b"".join(struct.pack("<Q", first + y * (8 + line)) for y in range(h))
    body = b"".join(struct.pack("<ii", y, line)
                    + b"".join(rgb[y, :, c].astype("<f4").tobytes() for c in (2, 1, 0))
                    for y in range(h))
    with open(path, "wb") as f:
        f.write(header + offsets + body)


def write_png(path, img):
    """An 8- or 16-bit (by dtype) grey or RGB PNG without colour chunks (no gAMA, sRGB or
    iCCP: the core and POV-Ray both take the colour space from the scene), row 0 at the top."""
    import struct
    import zlib
    img = img if img.ndim == 3 else img[..., None]
    h, w, c = img.shape
    bits = 16 if img.dtype == np.uint16 else 8
    raw = b"".join(b"\0" + img[y].astype(">u2" if bits == 16 else "u1").tobytes() for y in range(h))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n"
                + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bits, {1: 0, 3: 2}[c], 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def texture_scene(d, w=96, h=64):
    """A small scene of every texture path export-pov writes, images in directory d: a floor
    quad with an 8-bit sRGB PNG (bilinear, repeat, UV scale, rotation and offset), a rotated
    sphere with a float EXR (bilinear), a box with a checker diffuse colour under a glossy
    composite, a mesh with UVs inside [0.1, 0.9] and a 16-bit linear grey
    PNG (closest, clamp = POV-Ray's once), an emitter textured by an 8-bit PNG (scale [2, 1.5,
    1]), and a prototype (a checker quad and a PNG box) placed by two instances. Textures of
    distinct texels (a seeded generator), two point lights."""
    rng = np.random.default_rng(7)
    write_png(os.path.join(d, "floor.png"), rng.integers(0, 256, (8, 8, 3), dtype=np.uint8))
    write_png(os.path.join(d, "panel.png"), rng.integers(0, 65536, (6, 5), dtype=np.uint16))
    write_png(os.path.join(d, "glow.png"), rng.integers(40, 256, (4, 4, 3), dtype=np.uint8))
    write_exr(os.path.join(d, "globe.exr"), rng.uniform(0.05, 0.95, (8, 16, 3)).astype(np.float32))
    floor = {"texture": "floor.png", "filter": "linear", "uv_scale": [2, 2], "uv_rotation": 30,
             "uv_offset": [0.1, 0.2]}
    return {"format": "facet-scene", "version": 1,
            "camera": {"position": [0.4, 2.6, 5.2], "look_at": [0, 0.5, 0], "fov": 40,
                       "width": w, "height": h},
            "materials": {
                "floor": {"model": "lambert", "reflectance": floor},
                "globe": {"model": "lambert", "reflectance": {"texture": "globe.exr", "filter": "linear"}},
                "tiles": {"model": "composite", "distribution": "ggx", "alpha": 0.3,
                          "fresnel": "dielectric", "ior": 1.5,
                          "diffuse_reflectance": {"checker": {"colors": [[0.9, 0.2, 0.1], [0.1, 0.3, 0.8]],
                                                              "scale": 4}}},
                "panel": {"model": "lambert", "reflectance": {"texture": "panel.png", "colorspace": "linear",
                                                              "filter": "closest", "wrap": "clamp"}},
                "proto": {"model": "lambert", "reflectance": {"checker": {"colors": [0.85, 0.25], "scale": 3},
                                                              "uv_rotation": 15}},
                "crate": {"model": "lambert", "reflectance": {"texture": "floor.png", "filter": "linear"}}},
            "prototypes": {"tile": [
                {"type": "quad", "material": "proto",
                 "vertices": [[-0.4, 0, 0], [0.4, 0, 0], [0.4, 0.8, 0], [-0.4, 0.8, 0]]},
                {"type": "box", "min": [-0.15, 0, 0.05], "max": [0.15, 0.3, 0.35], "material": "crate"}]},
            "shapes": [
                {"type": "quad", "material": "floor",
                 "vertices": [[-3, 0, 3], [3, 0, 3], [3, 0, -3], [-3, 0, -3]]},
                {"type": "sphere", "center": [0, 0, 0], "radius": 0.7, "material": "globe",
                 "transform": {"rotate": {"axis": [1, 0.3, 0], "angle": -80}, "translate": [-1.1, 0.7, 0.2]}},
                {"type": "box", "min": [-0.45, 0, -0.45], "max": [0.45, 0.9, 0.45], "material": "tiles",
                 "transform": {"rotate": {"axis": [0, 1, 0], "angle": 25}, "translate": [1.0, 0, 0.3]}},
                {"type": "mesh", "material": "panel",
                 "positions": [-1.5, 0, -1.5, 0.5, 0, -1.7, 0.6, 1.6, -1.6, -1.4, 1.5, -1.4],
                 "indices": [0, 1, 2, 0, 2, 3], "uvs": [0.1, 0.1, 0.9, 0.12, 0.88, 0.9, 0.12, 0.85]},
                {"type": "quad", "emission": {"texture": "glow.png", "filter": "linear", "scale": [2, 1.5, 1]},
                 "vertices": [[1.2, 0.3, -1.6], [2.2, 0.3, -1.4], [2.2, 1.3, -1.4], [1.2, 1.3, -1.6]]},
                {"type": "instance", "of": "tile",
                 "transform": {"rotate": {"axis": [0, 1, 0], "angle": -20}, "translate": [-0.2, 0, 1.6]}},
                {"type": "instance", "of": "tile",
                 "transform": {"scale": [1.2, 0.9, 1.2], "translate": [2.0, 0, 1.2]}}],
            "lights": [{"type": "point", "position": [2, 4, 3], "power": 300},
                       {"type": "point", "position": [-3, 3, 1], "power": [60, 80, 120]}],
            "render": {"max_depth": 1}}


def cmd_textures(env):
    """Textures through export-pov (docs/povray.md, "Textures"): the scene of texture_scene,
    96 x 64, povray-facet (+FE32) against facet render --integrator direct at 1 spp (both
    through the pixel centres, delta lights: deterministic). Tolerance REL_TOL per channel for
    99.5% of the pixels (as export_coverage: POV-Ray shades in double, Facet's UVs and
    intersections are float, so a pixel on a silhouette or, with `closest`, next to a texel edge
    may differ). Then the SDL with each texture flipped in v (scale <1, -1, 1> after the pattern's transform),
    or the sRGB images read as linear (gamma 1.0), or the sphere's axes not swapped, must fail,
    so the check can see each convention."""
    w, h = 96, 64
    scene = texture_scene(env.tmp, w, h)
    js = env.write_scene(scene, "textures")
    sdl = env.export(js)
    text = open(sdl).read()
    ref = env.render(js, "--spp", "1")
    pov = env.povray(sdl, w, h, "+FE32")
    written = all(k in text for k in ("uv_mapping image_map { png", "gamma srgb", "gamma 1.0", " once",
                                      "uv_vectors", "checker", "exr", "object { FacetPrototype0"))
    print(f"{'ok  ' if written else 'FAIL'} the SDL has uv_mapping image_maps (png sRGB and linear, exr), "
          f"once, a checker, uv_vectors and the instances")
    ok = written & compare(f"textures {w}x{h}: povray-facet vs facet direct", pov, ref)
    # The instances are in the picture (not just declared): without them the picture changes.
    bare = env.path("textures_noinst.pov")
    with open(bare, "w") as f:
        f.write(re.sub(r"object \{ FacetPrototype0\n[^}]*\}\n", "", text))
    seen = not compare("without the instances (must fail)", env.povray(bare, w, h, "+FE32"), ref)
    print(f"{'ok  ' if seen else 'FAIL'} POV-Ray renders the instances")
    wrong = {"every texture flipped in v": re.sub(r"(pigment \{ uv_mapping .*?) \} finish", r"\1 scale <1, -1, 1> } finish", text),
             "sRGB images read as linear": text.replace("gamma srgb", "gamma 1.0"),
             "sphere axes not swapped": re.sub(r"sphere \{ 0, 1\n  matrix <([^,]+), 0, 0, 0, 0, ([^,]+), 0, ([^,]+), 0,",
                                               r"sphere { 0, 1\n  matrix <\1, 0, 0, 0, \2, 0, 0, 0, \3,", text)}
    for name, variant in wrong.items():
        if variant == text:
            print(f"FAIL the variant '{name}' did not change the SDL")
            ok = False
            continue
        path = env.path("textures_wrong.pov")
        with open(path, "w") as f:
            f.write(variant)
        failed = not compare(f"{name} (must fail)", env.povray(path, w, h, "+FE32"), ref)
        print(f"{'ok  ' if failed else 'FAIL'} {name}: the comparison fails")
        ok &= failed
    return ok and seen


def cmd_texture_errors(env):
    """What export-pov cannot write exactly about textures is an error naming the JSON path."""
    d = env.tmp
    base = texture_scene(d)
    rng = np.random.default_rng(3)
    # An RGBA PNG (colour type 6): POV-Ray would read its alpha as transparency.
    import struct
    import zlib
    raw = b"".join(b"\0" + rng.integers(0, 256, 8, dtype=np.uint8).tobytes() for _ in range(2))
    png = (b"\x89PNG\r\n\x1a\n" + b"".join(
        struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xffffffff)
        for kind, body in ((b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 6, 0, 0, 0)),
                           (b"IDAT", zlib.compress(raw)), (b"IEND", b""))))
    with open(os.path.join(d, "rgba.png"), "wb") as f:
        f.write(png)
    mats = base["materials"]
    cases = [
        ("mipmap filter (the default)", lambda s: mats_of(s)["floor"]["reflectance"].pop("filter"),
         "/materials/floor/reflectance/filter: the mipmap filter"),
        ("textured roughness", lambda s: mats_of(s)["tiles"].update(alpha={"texture": "panel.png", "filter": "linear"}),
         "/materials/tiles/alpha: a textured 'alpha'"),
        ("normal map", lambda s: mats_of(s)["globe"].update(normal_map={"texture": "floor.png", "filter": "linear"}),
         "/materials/globe/normal_map: a tangent-space normal map"),
        ("bump map", lambda s: mats_of(s)["globe"].update(bump={"texture": "panel.png", "filter": "linear", "colorspace": "linear"}),
         "/materials/globe/bump: POV-Ray's bump_map"),
        ("mirror wrap", lambda s: mats_of(s)["floor"]["reflectance"].update(wrap="mirror"),
         "/materials/floor/reflectance/wrap: "),
        ("clamp beyond [0, 1]", lambda s: mats_of(s)["panel"]["reflectance"].update(uv_scale=[1.2, 1]),
         "/materials/panel/reflectance/wrap: clamp is POV-Ray's image_map `once`"),
        ("image with alpha", lambda s: mats_of(s)["globe"].update(reflectance={"texture": "rgba.png", "filter": "linear"}),
         "/materials/globe/reflectance: 'rgba.png' has 4 channels"),
        ("one channel", lambda s: mats_of(s)["globe"].update(reflectance={"texture": "floor.png", "filter": "linear", "channel": "g"}),
         "/materials/globe/reflectance/channel: "),
        ("textured plane", lambda s: s["shapes"].append({"type": "plane", "point": [0, -1, 0], "normal": [0, 1, 0], "material": "floor"}),
         "/shapes/7/material: a texture read through UVs cannot be exported on this shape kind: POV-Ray's plane"),
        ("textured disc", lambda s: s["shapes"].append({"type": "disc", "center": [0, -1, 0], "normal": [0, 1, 0], "radius": 1, "material": "floor"}),
         "/shapes/7/material: a texture read through UVs cannot be exported on this shape kind: POV-Ray's disc"),
        ("textured icosphere", lambda s: s["shapes"].append({"type": "icosphere", "center": [0, -1, 0], "radius": 1,
                                                               "subdivisions": 1, "material": "floor"}),
         "/shapes/7/material: a texture read through UVs cannot be exported on this shape kind: the icosphere"),
        ("textured emission with a material", lambda s: s["shapes"][4].update(material="floor"),
         "/shapes/4/emission: a textured emission on a shape with a material"),
        ("texture scale on the diffuse colour", lambda s: mats_of(s)["tiles"]["diffuse_reflectance"].update(scale=0.8),
         "/materials/tiles/diffuse_reflectance/scale: a texture scale on the diffuse colour"),
        ("vertex colour", lambda s: (s["shapes"][3].update(colors=[0.5] * 12),
                                     mats_of(s)["panel"].update(reflectance={"vertex_color": True})),
         "/materials/panel/reflectance: a vertex colour"),
    ]
    ok = True
    for title, edit, want in cases:
        s = json.loads(json.dumps(base))
        edit(s)
        js = env.write_scene(s, "texerr")
        p = env.run([env.facet, "export-pov", js, "-o", env.path("texerr.pov")], check=False)
        good = p.returncode == 1 and f"{js}: {want}" in p.stderr
        print(f"{'ok  ' if good else 'FAIL'} {title}: rc {p.returncode}: {p.stderr.strip()}")
        ok &= good
    # --mipmap linear writes the default filter as POV-Ray's bilinear lookup.
    s = json.loads(json.dumps(base))
    mats_of(s)["floor"]["reflectance"].pop("filter")
    js = env.write_scene(s, "mipmap")
    out = env.path("mipmap.pov")
    p = env.run([env.facet, "export-pov", js, "-o", out, "--mipmap", "linear"], check=False)
    good = p.returncode == 0 and "floor.png\" gamma srgb interpolate 2" in open(out).read()
    print(f"{'ok  ' if good else 'FAIL'} --mipmap linear exports the mipmap filter as interpolate 2")
    return ok and good


def mats_of(scene):
    return scene["materials"]


def cmd_envmap(env):
    """An environment map exported as POV-Ray's sky_sphere (map_type 1, interpolate 2, the pigment
    matrix of docs/povray.md) looks the same as in facet render: a 16 x 8 map of distinct texels,
    up [0.2, 0.3, 1] and rotate 40 degrees about [0, 0.5, 1], seen by a 64 x 48 camera looking
    across the seam and away from the map's poles (near the poles POV-Ray's lookup wraps where
    Facet's clamps: stated in the SDL). Tolerance: REL_TOL, every pixel (measured with Debian's
    stock povray 3.7, whose +FE32 still writes half floats: 4.8e-4 at most, the half rounding).
    Then the same with the map un-rotated must differ (the check can fail)."""
    w, h = 16, 8
    ys, xs = np.mgrid[0:h, 0:w].astype(np.float32)
    rgb = np.stack([(xs + 1) / 4, (xs + 1) ** 2 / 64, 0.25 + ys / 8], axis=2).astype(np.float32)
    exr = env.path("map.exr")
    write_exr(exr, rgb)
    ok = True
    scene = {"format": "facet-scene", "version": 1,
             "camera": {"position": [0, 0, 0], "look_at": [-1, 0.3, -0.1], "up": [0, 0, 1],
                        "fov": 70, "width": 64, "height": 48},
             "materials": {}, "shapes": [],
             "lights": [{"type": "environment", "file": exr, "up": [0.2, 0.3, 1],
                         "rotate": {"axis": [0, 0.5, 1], "angle": 40}}]}
    js = env.write_scene(scene, "envmap")
    ref = env.render(js, "--spp", "1")
    test = env.povray(env.export(js, "--environment", "background"), 64, 48, "+FE32")
    ok &= compare("envmap, tilted and rotated", test, ref, required=1.0)
    del scene["lights"][0]["up"], scene["lights"][0]["rotate"]
    other = env.render(env.write_scene(scene, "envmap_plain"), "--spp", "1")
    differs = not compare("envmap against the un-rotated map (must fail)", test, other, required=1.0)
    print(f"{'ok  ' if differs else 'FAIL'} the un-rotated map's render differs")
    return ok and differs


def sky_map(w=32, h=16):
    """A small HDR sky for the sky-light tests: blue above the horizon, brighter toward the
    zenith, dim brown below, and a 2 x 1-texel sun about 100 times the sky at 40 degrees
    elevation (left of the map's centre column, which looks toward +X)."""
    ys, xs = np.mgrid[0:h, 0:w].astype(np.float32)
    theta = (ys + 0.5) / h * np.pi
    up = (theta < np.pi / 2)[..., None]
    sky = np.array([0.25, 0.45, 0.9], np.float32) * (0.6 + 0.6 * np.cos(theta))[..., None]
    ground = np.broadcast_to(np.array([0.12, 0.1, 0.08], np.float32), sky.shape)
    rgb = np.where(up, sky, ground).astype(np.float32)
    rgb[h // 4 - 1, w // 2 - 6:w // 2 - 4] = [60.0, 55.0, 45.0]
    return rgb


def sky_scene(exr, w, h):
    """A Lambert floor, a rough gold sphere (glossy: its sky light is shared between the sky
    samples and the glossy rays by MIS) and a Lambert sphere under the map of sky_map, Z up."""
    return {"format": "facet-scene", "version": 1,
            "camera": {"position": [4.5, -3.5, 2.6], "look_at": [0.3, 0, 0.5], "up": [0, 0, 1],
                       "fov": 40, "width": w, "height": h},
            "materials": {"floor": {"model": "lambert", "reflectance": 0.5},
                          "clay": {"model": "lambert", "reflectance": [0.8, 0.5, 0.3]},
                          "gold": {"model": "ggx", "alpha": 0.3, "fresnel": "conductor",
                                   "eta": [0.143, 0.374, 1.442], "k": [3.983, 2.385, 1.603]}},
            "shapes": [{"type": "quad", "material": "floor",
                        "vertices": [[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]]},
                       {"type": "sphere", "center": [0, 0, 0.7], "radius": 0.7, "material": "gold"},
                       {"type": "sphere", "center": [1.4, -1.2, 0.45], "radius": 0.45, "material": "clay"}],
            "lights": [{"type": "environment", "file": exr, "rotate": {"axis": [0, 0, 1], "angle": 25}}]}


def cmd_skylight(env):
    """povray-facet's brdf_sky_sampling (export-pov --environment light) against facet render
    --integrator direct: the scene of sky_scene, 64 x 48. On the sky pixels both look the map up
    through the pixel centre (deterministic): REL_TOL, every pixel. On the objects both are
    unbiased estimates of the same direct light (the sky's, occluded by the objects, through
    the core's BRDFs): POV-Ray with 64 sky samples and 16 glossy rays per pixel centre, Facet
    with 64 samples per pixel at 5x the resolution, of which the middle pixel of each 5 x 5 group
    is taken (its centre is the POV pixel's, cmd_glossy), then the block t-test of t_test.
    Pixels next to a silhouette are left out (the 1/5-pixel footprint still straddles it).
    Then the same SDL with `brdf_sky_sampling 0` is bit-identical to the export without the
    keyword (--environment background), whose objects are black, so the keyword is what lights
    them (the check can fail), and its sky pixels equal the lit render's."""
    w, h = 64, 48
    exr = env.path("sky.exr")
    write_exr(exr, sky_map())
    scene = sky_scene(exr, w, h)
    js = env.write_scene(scene, "skylight")
    sdl = env.export(js, "--environment", "light", "--sky-samples", "64", "--glossy-samples", "16")
    text = open(sdl).read()
    ok = "brdf_sky_sampling 64" in text
    print(f"{'ok  ' if ok else 'FAIL'} export-pov --environment light writes brdf_sky_sampling 64")
    pov = env.povray(sdl, w, h, "+FE32")
    fine = json.loads(json.dumps(scene))
    fine["camera"]["width"], fine["camera"]["height"] = 5 * w, 5 * h
    fine_js = env.write_scene(fine, "skylight_fine")
    ref = env.render(fine_js, "--spp", "64", "--seed", "3")[2::5, 2::5]
    # On the gold sphere the glossy rays see the floor and the clay sphere lit by the sky (one
    # bounce more than direct): Facet's path tracer with max_depth 2 computes exactly that there
    # (cmd_glossy). Elsewhere the surfaces are Lambert, and `direct` is exact.
    gold = sphere_pixels(scene["camera"], [0, 0, 0.7], 1.05 * 0.7)
    ref_gold = env.render(fine_js, "--spp", "64", "--seed", "3", "--max-depth", "2",
                          integrator="path")[2::5, 2::5]
    # Without glossy rays every object is black here (no lights), so black = geometry.
    bg_sdl = env.export(js, "--environment", "background", "--glossy-samples", "0")
    bg = env.povray(bg_sdl, w, h, "+FE32")
    geometry = bg.max(axis=2) <= 0.0  # unlit objects are black; the map is positive everywhere
    sky = ~geometry
    ok &= compare("sky pixels, brdf_sky_sampling 64 vs facet direct (pixel centres)", pov,
                  env.render(js, "--spp", "1"), sky, required=1.0)
    interior = geometry.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            interior &= np.roll(np.roll(geometry, dy, 0), dx, 1)
    ok &= t_test("brdf_sky_sampling 64 vs facet direct", "Lambert", pov, ref, interior & ~gold)
    ok &= t_test("brdf_sky_sampling 64 + 16 glossy rays (MIS) vs facet path max_depth 2", "gold sphere",
                 pov, ref_gold, interior & sphere_pixels(scene["camera"], [0, 0, 0.7], 0.95 * 0.7))
    off_sdl = env.path("skylight_off.pov")
    with open(off_sdl, "w") as f:
        f.write(open(bg_sdl).read().replace("  ambient_light 0\n", "  ambient_light 0\n  brdf_sky_sampling 0\n", 1))
    off = env.povray(off_sdl, w, h, "+FE32")
    same = bool(np.array_equal(off, bg))
    print(f"{'ok  ' if same else 'FAIL'} brdf_sky_sampling 0 is bit-identical to no keyword")
    dark = bool(np.all(bg[interior] == 0.0)) and bool(np.all(pov[interior].max(axis=1) > 0.0))
    print(f"{'ok  ' if dark else 'FAIL'} without the keyword the objects are black, with it lit")
    return ok and same and dark


# brdf_sky_sampling errors: (name, global_settings text, other SDL, message pattern, line).
SKY_ERRORS = [
    ("negative", "brdf_sky_sampling -1", "sky_sphere { pigment { rgb 1 } }",
     r"brdf_sky_sampling expects a whole number of samples from 0 \(off\) to 4096, found -1 instead", 2),
    ("fraction", "brdf_sky_sampling 2.5", "sky_sphere { pigment { rgb 1 } }",
     r"found 2\.5 instead", 2),
    ("missing", "brdf_sky_sampling", "sky_sphere { pigment { rgb 1 } }",
     r"Expected 'numeric expression', } found instead", 2),
    ("no_sky", "brdf_sky_sampling 4", "", r"brdf_sky_sampling in global_settings needs a sky_sphere", None),
]


def cmd_skylight_errors(env):
    """Bad brdf_sky_sampling settings are POV-Ray parse errors naming the file and line."""
    ok = True
    for name, setting, other, pattern, line in SKY_ERRORS:
        sdl = env.path(f"sky_{name}.pov")
        with open(sdl, "w") as f:
            f.write(f"#version 3.7;\nglobal_settings {{ {setting} }}\n{other}\n"
                    "camera { location <0, 0, -3> look_at 0 }\n"
                    "sphere { 0, 1 texture { pigment { rgb 1 } finish { brdf { lambert } } } }\n")
        p = env.run([env.pov, f"+I{sdl}", "-F", "+W8", "+H8", "-D", "-V"], check=False)
        err = p.stderr.replace("\n", "")
        where = re.search(rf"File '.*sky_{name}\.pov' line (\d+):", err)
        good = (p.returncode != 0 and "Parse Error" in err and re.search(pattern, err) is not None
                and where is not None and (line is None or int(where.group(1)) == line))
        print(f"{'ok  ' if good else 'FAIL'} {name}: " + (err[where.start():where.start() + 200] if where else err[-600:]))
        ok &= good
    return ok


def cmd_radiosity_furnace(env):
    """Radiosity on a brdf { lambert } surface: the camera inside a sphere of reflectance rho
    that glows with e (POV-Ray emission is tinted by the pigment: exitance rho e), no lights.
    Every radiosity sample sees the same radiance, so interpolation is exact and POV-Ray's
    gather with recursion_limit R gives exactly rho e (1 + rho + ... + rho^R). A wrong albedo of
    the brdf finish in the gather (e.g. a missing or doubled pi, or the pigment not applied)
    changes the series. Classic `diffuse 1` is rendered too, as POV-Ray's own answer."""
    ok = True
    w = h = 16
    for rho in (0.5, 0.8):
        for R in (1, 3, 8):
            for finish in ("brdf { lambert }", "diffuse 1"):
                pov = env.path(f"furnace_{rho}_{R}.pov")
                with open(pov, "w") as f:
                    f.write(f"""#version 3.7;
global_settings {{ assumed_gamma 1.0 ambient_light 0 adc_bailout 0 max_trace_level 40
  radiosity {{ count 50 error_bound 1 recursion_limit {R} adc_bailout 1e-7 nearest_count 5 gray_threshold 0 brightness 1 }} }}
camera {{ location <0, 0, 0> look_at <0, 0, 1> right x up y }}
sphere {{ 0, 10 texture {{ pigment {{ rgb {rho} }} finish {{ ambient 0 emission 0.25 {finish} }} }} }}
""")
                img = env.povray(pov, w, h, "+FE32")
                want = rho * 0.25 * sum(rho ** k for k in range(R + 1))
                e = float(np.abs(img / want - 1).max())
                good = e <= 1e-5
                print(f"{'ok  ' if good else 'FAIL'} furnace rho {rho}, recursion_limit {R}, "
                      f"finish {{ {finish} }}: {img.mean():.7f} vs rho e sum rho^k = {want:.7f} "
                      f"(max relative error {e:.1e}, tolerance 1e-5)")
                ok &= good
    return ok


def cmd_radiosity_cornell(env):
    """The Cornell box exported with --radiosity 200,0.4,8 (--area-grid 8) against Facet's path
    tracer (max_depth 16, 1024 spp), 64 x 64, POV-Ray antialiased with +AM1 +R3 (a 3 x 3
    jittered grid and the centre: a box filter like Facet's). POV-Ray's radiosity interpolates
    a sparse cache of irradiance samples and stops after recursion_limit bounces (here 8:
    with the walls' reflectance ~0.6-0.74 the missing tail is ~1%), so the images differ by a
    bias, not noise alone. Compared off the light and the pixels next to it (the emitter's
    17-unit edge is decided by 10 samples per pixel in POV-Ray): the mean per channel within
    3% and 8 x 8 block means within 8% for >= 90% of blocks. Measured (povray-facet, +WT2, so
    radiosity varies a little from run to run): means 0.982 0.988 0.993, block differences
    median 2.3%, max 9.7%, 56 of 60 blocks within 6%. Without --radiosity (direct light only)
    the same checks fail (means 0.53-0.60)."""
    scene = small(json.load(open(os.path.join(ROOT, "scenes", "cornell_box.json"))), 64)
    w, h = scene["camera"]["width"], scene["camera"]["height"]
    js = env.write_scene(scene, "cornell_box")
    ref = env.render(js, "--spp", "1024", integrator="path")
    light = ref.max(axis=2) > 1.0
    near = light.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            near |= np.roll(np.roll(light, dy, 0), dx, 1)
    aa = ("+AM1", "+A0.0", "+R3", "+J")

    def check(label, img, want):
        ratio = img[~near].mean(axis=0) / ref[~near].mean(axis=0)
        good_mean = bool(np.all(np.abs(ratio - 1) <= 0.03))
        b = 8
        bm = lambda x: x.reshape(h // b, b, w // b, b, 3).mean(axis=(1, 3))
        keep = ~near.reshape(h // b, b, w // b, b).any(axis=(1, 3))
        rel = np.abs(bm(img) / np.maximum(bm(ref), 1e-6) - 1).max(axis=2)[keep]
        frac = float((rel <= 0.08).mean())
        passed = good_mean and frac >= 0.9
        good = passed == want
        print(f"{'ok  ' if good else 'FAIL'} Cornell box {w}x{h}, {label}: mean POV-Ray / Facet path off the "
              f"light {ratio[0]:.4f} {ratio[1]:.4f} {ratio[2]:.4f} (tolerance 3%); {b}x{b} blocks within 8%: "
              f"{100 * frac:.1f}% of {rel.size} (required 90%), median {np.median(rel):.2%}, max {rel.max():.2%}; "
              f"RMSE off the light {math.sqrt(((img - ref)[~near] ** 2).mean()):.4g}, whole image "
              f"{math.sqrt(((img - ref) ** 2).mean()):.4g} (must {'pass' if want else 'fail'})")
        return good

    rad = env.povray(env.export(js, "--area-grid", "8", "--radiosity", "200,0.4,8"), w, h, "+FE32", aa)
    ok = check("--radiosity 200,0.4,8", rad, True)
    direct = env.povray(env.export(js, "--area-grid", "8"), w, h, "+FE32", aa)
    return check("no radiosity (direct light only)", direct, False) and ok


def principled_scene(w, h):
    """Four principled spheres on an oren_nayar floor, Y up: "sheen" (dark blue, sheen 1, lit
    from behind), "coat" (red, clearcoat 1), "metal" (metallic 1) and "retro" (Disney diffuse
    alone, roughness 1: its retro-reflection brightens the limb under the light beside the
    camera). Delta lights only, so both renders are deterministic."""
    spheres = [("sheen", -1.5), ("coat", -0.5), ("metal", 0.5), ("retro", 1.5)]
    return {"format": "facet-scene", "version": 1,
            "camera": {"position": [0, 1.1, 5], "look_at": [0, 0.45, 0], "fov": 32, "width": w, "height": h},
            "materials": {
                "floor": {"model": "oren_nayar", "reflectance": [0.5, 0.45, 0.4], "sigma": 0.6},
                "sheen": {"model": "principled", "base_color": [0.05, 0.08, 0.3], "sheen": 1.0,
                          "sheen_tint": 0.0, "specular": 0.2, "roughness": 0.8},
                "coat": {"model": "principled", "base_color": [0.6, 0.05, 0.05], "roughness": 0.6,
                         "clearcoat": 1.0, "clearcoat_roughness": 0.15},
                "metal": {"model": "principled", "base_color": [0.95, 0.7, 0.3], "metallic": 1.0,
                          "roughness": 0.35},
                "retro": {"model": "principled", "base_color": 0.7, "roughness": 1.0, "specular": 0.0}},
            "shapes": [{"type": "quad", "material": "floor",
                        "vertices": [[-4, 0, -3], [-4, 0, 3], [4, 0, 3], [4, 0, -3]]}] +
                      [{"type": "sphere", "name": n, "center": [x, 0.45, 0], "radius": 0.45, "material": n}
                       for n, x in spheres],
            "lights": [{"type": "point", "position": [0.4, 1.3, 5.5], "power": 80},
                       {"type": "point", "position": [3, 4, 2], "power": 150},
                       {"type": "point", "position": [-1.5, 2.2, -1.2], "power": [150, 150, 200]}]}


PRINCIPLED_CENTRES = {"sheen": [-1.5, 0.45, 0], "coat": [-0.5, 0.45, 0], "metal": [0.5, 0.45, 0],
                      "retro": [1.5, 0.45, 0]}


def cmd_principled(env):
    """The brdf finish's principled and oren_nayar (export-pov writes them) against facet render
    --integrator direct, 96 x 48: delta lights, no glossy rays (--glossy-samples 0, as direct),
    so povray-facet computes pi f cos per light through the core's lobes, the same numbers as
    Facet up to float rounding and EXR half floats: REL_TOL per pixel (compare). Then each
    feature is perturbed in the exported scene alone (sheen 1 -> 0.8, clearcoat 1 -> 0.8,
    metallic 1 -> 0.9, the retro sphere's roughness 1 -> 0.8, the floor's sigma 0.6 -> 0.5)
    and the comparison on that object's pixels must fail: the check sees each parameter. The
    retro-reflection itself: on the retro sphere's limb (the outer 15% of its radius) Facet's
    image is brighter than with a Lambert sphere of the same base colour (printed ratio), and so
    is povray-facet's."""
    w, h = 96, 48
    scene = principled_scene(w, h)
    cam = scene["camera"]
    js = env.write_scene(scene, "principled")
    ref = env.render(js, "--spp", "1")
    pov = env.povray(env.export(js), w, h)
    ok = compare(f"principled + oren_nayar {w}x{h}: povray-facet vs facet direct", pov, ref)
    r = 0.45
    masks = {n: sphere_pixels(cam, c, 0.97 * r) for n, c in PRINCIPLED_CENTRES.items()}
    any_sphere = np.zeros((h, w), bool)
    for m in masks.values():
        any_sphere |= m
    masks["floor"] = ~any_sphere & (np.arange(h)[:, None] > h * 0.75)
    for name, (mat, key, value) in {"sheen": ("sheen", "sheen", 0.8), "coat": ("coat", "clearcoat", 0.8),
                                    "metal": ("metal", "metallic", 0.9), "retro": ("retro", "roughness", 0.8),
                                    "floor": ("floor", "sigma", 0.5)}.items():
        bad = json.loads(json.dumps(scene))
        bad["materials"][mat][key] = value
        wrong = env.povray(env.export(env.write_scene(bad, "principled_bad")), w, h)
        caught = not compare(f"  {mat} {key} {scene['materials'][mat][key]} -> {value} in the export, "
                             f"on the {name} pixels (must fail)", wrong, ref, masks[name])
        print(f"{'ok  ' if caught else 'FAIL'} a wrong {key} is caught")
        ok &= caught
    # Retro-reflection at grazing: the limb against a Lambert sphere of the same base colour.
    lam = json.loads(json.dumps(scene))
    lam["materials"]["retro"] = {"model": "lambert", "reflectance": 0.7}
    lam_img = env.render(env.write_scene(lam, "principled_lambert"), "--spp", "1")
    limb = masks["retro"] & ~sphere_pixels(cam, PRINCIPLED_CENTRES["retro"], 0.85 * r)
    rf, rp = ref[limb].mean() / lam_img[limb].mean(), pov[limb].mean() / lam_img[limb].mean()
    retro = rf > 1.05 and rp > 1.05
    print(f"{'ok  ' if retro else 'FAIL'} retro-reflection on the limb ({limb.sum()} pixels): facet "
          f"{rf:.3f}, povray-facet {rp:.3f} times a Lambert sphere of the same colour (required > 1.05; Lambert is 1)")
    return ok and retro


def media_scene(media, materials, shapes, w=48, h=36, position=(0, 1.3, 5), look_at=(0, 0.6, 0),
                world=None):
    """A media test scene: a grey Lambert floor and the given shapes under a point light at
    (-1.1, 2.2, 1), 60 W, max_depth 1 (POV-Ray's media scatter once)."""
    s = {"format": "facet-scene", "version": 1,
         "camera": {"position": list(position), "look_at": list(look_at), "up": [0, 1, 0], "fov": 40,
                    "width": w, "height": h},
         "media": media,
         "materials": dict({"floor": {"model": "lambert", "reflectance": 0.5}}, **materials),
         "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"}] + shapes,
         "lights": [{"type": "point", "position": [-1.1, 2.2, 1.0], "power": 60}],
         "render": {"max_depth": 1}}
    if world:
        s["world_medium"] = world
    return s


def media_blocks(name, pov, quad, ref):
    """POV-Ray's media (pov) against Facet's noisy render at 5x resolution (ref, the middle
    pixel of each 5x5 group), by 4x4 blocks of the luminance difference d. Allowed per block,
    each term derived:
      5 se         Facet's noise: the standard error of d over the block's 16 pixels;
      quad         POV-Ray's quadrature error, |P_200 - P_100| of the luminance: its media sum
                   takes each interval's samples over the first sampleCount/(sampleCount + 1)
                   of it (interior/media.cpp, ComputeMediaAdaptiveSampling), a bias falling as
                   1/intervals (measured: +1.9%, +0.42%, +0.08% at 16, 64, 200 intervals on a
                   fog column), so the error at N is about P_{N/2} - P_N;
      footprint    Facet's pixel is a box 1/5 of POV-Ray's pixel wide around its centre, whose
                   average differs from the centre value by (1/5)^2 |Laplacian| / 24 (the box
                   filter's second-order term; Laplacian of POV-Ray's image, per pixel^2);
      1e-5 |ref|   float rounding (32-bit EXR from POV-Ray's double, Facet's float).
    Passes when >= 97% of the blocks and the image mean are within."""
    lum = lambda x: x.mean(axis=2)
    d, q, r = lum(pov) - lum(ref), quad, lum(ref)
    lp = lum(pov)
    lap = np.zeros(lp.shape)
    lap[1:-1, 1:-1] = np.abs(lp[1:-1, :-2] + lp[1:-1, 2:] + lp[:-2, 1:-1] + lp[2:, 1:-1] - 4 * lp[1:-1, 1:-1])
    q = q + lap * 0.04 / 24
    h, w = d.shape
    within, worst = [], []
    for y0 in range(0, h - 3, 4):
        for x0 in range(0, w - 3, 4):
            b = np.s_[y0:y0 + 4, x0:x0 + 4]
            se = d[b].std(ddof=1) / 4.0
            allowed = 5 * se + q[b].mean() + 1e-5 * abs(r[b].mean())
            within.append(abs(d[b].mean()) <= allowed)
            worst.append((abs(d[b].mean()) / max(allowed, 1e-30), x0, y0, d[b].mean(), se, q[b].mean()))
    frac = np.mean(within)
    se_all = d.std(ddof=1) / math.sqrt(d.size)
    ok_mean = abs(d.mean()) <= 5 * se_all + q.mean() + 1e-5 * abs(r.mean())
    ok = frac >= 0.97 and ok_mean
    print(f"{'ok  ' if ok else 'FAIL'} {name}: {100 * frac:.1f}% of {len(within)} 4x4 blocks "
          f"within 5 se + quadrature + float (required 97%); image mean povray-facet "
          f"{lum(pov).mean():.5f}, facet {r.mean():.5f} (ratio {lum(pov).mean() / r.mean():.4f}, "
          f"difference {d.mean():.2e}, se {se_all:.2e}, quadrature {q.mean():.2e})")
    for ratio, x0, y0, dm, se, qm in sorted(worst, reverse=True)[:3]:
        print(f"      block ({x0}, {y0}): difference {dm:.2e}, se {se:.2e}, quadrature {qm:.2e} "
              f"({ratio:.2f} of the allowed)")
    return ok


def cmd_media(env):
    """Homogeneous media through export-pov (docs/povray.md, "Media"), against facet render."""
    ok = True
    box = {"type": "box", "min": [-1.7, 0.001, -0.6], "max": [-0.5, 1.2, 0.6], "material": "boundary"}
    ball = {"type": "sphere", "center": [0.6, 0.5, -0.3], "radius": 0.5, "material": "red"}
    red = {"model": "lambert", "reflectance": [0.6, 0.1, 0.1]}
    # (1) Absorption only: both renderers are exact (Facet's closed form at one sample through
    # the pixel centre, POV-Ray's constant media), so the deterministic 1e-3 per-pixel check
    # of the other scenes applies, shadows through the box included.
    s = media_scene({"juice": {"kind": "homogeneous", "sigma_a": [0.5, 1.0, 2.0]}},
                    {"boundary": {"model": "null", "interior": "juice"}, "red": red}, [box, ball])
    js = env.write_scene(s, "absorb")
    w, h = s["camera"]["width"], s["camera"]["height"]
    ref = env.render(js, "--spp", "1")
    ok &= compare("media: an absorbing interior", env.povray(env.export(js), w, h), ref)
    # (2) Scattering fog in a null box (sigma_t 3.1, forward g 0.3) and (3) a world medium
    # (backward g -0.4) seen from above, so that every camera ray ends on a surface, against
    # Facet's path at 128 spp. Facet renders at 5x the resolution and the middle pixel of each
    # 5x5 group is taken (as in cmd_glossy: POV-Ray samples pixel centres, Facet averages over
    # its pixel). The control exports the anisotropy with the opposite sign (g -> -g: forward
    # and backward scattering swapped), which must fail.
    fog = media_scene({"fog": {"kind": "homogeneous", "sigma_s": 3.0, "sigma_a": 0.1, "g": 0.3}},
                      {"boundary": {"model": "null", "interior": "fog"}}, [box])
    air = media_scene({"air": {"kind": "homogeneous", "sigma_s": 0.3, "sigma_a": 0.02, "g": -0.4}},
                      {"red": red}, [ball], position=(0, 4, 3), look_at=(0, 0, 0), world="air")
    for name, scene in (("fog in a null box", fog), ("world medium", air)):
        js = env.write_scene(scene, "media")
        pov_file = env.export(js, "--media-intervals", "200")
        pov = env.povray(pov_file, w, h, fmt="+FE32")
        half = env.povray(env.export(js, "--media-intervals", "100"), w, h, fmt="+FE32")
        fine = json.loads(json.dumps(scene))
        fine["camera"]["width"], fine["camera"]["height"] = 5 * w, 5 * h
        ref = env.render(env.write_scene(fine, "media_fine"), "--spp", "128", "--seed", "3",
                         integrator="path")[2::5, 2::5]
        quad = np.abs(half.mean(axis=2) - pov.mean(axis=2))
        ok &= media_blocks(f"media: {name}", pov, quad, ref)
        text = open(pov_file).read()
        g = re.search(r"eccentricity (\S+) ", text).group(1)
        flipped = env.path("flipped.pov")
        with open(flipped, "w") as fl:
            fl.write(text.replace(f"eccentricity {g} ", f"eccentricity {-float(g)!r} "))
        bad = media_blocks(f"media: {name}, control with the anisotropy's sign flipped (must fail)",
                           env.povray(flipped, w, h, fmt="+FE32"), quad, ref)
        print(f"{'ok  ' if not bad else 'FAIL'} the flipped control fails")
        ok &= not bad
    # (4) What cannot be exported exactly is an error naming the JSON path (or the flag).
    open_mesh = {"type": "quad", "vertices": [[-1, 0.5, -1], [1, 0.5, -1], [1, 0.5, 1], [-1, 0.5, 1]],
                 "material": "boundary"}
    deep = json.loads(json.dumps(fog))
    deep["render"]["max_depth"] = 2
    both = json.loads(json.dumps(air))
    both["materials"]["boundary"] = {"model": "null", "interior": "air"}
    both["shapes"].append(box)
    escaping = json.loads(json.dumps(air))
    escaping["camera"].update(position=[0, 1.3, 5], look_at=[0, 0.6, 0])
    mirror = json.loads(json.dumps(fog))
    mirror["materials"]["red"] = {"model": "mirror"}
    mirror["shapes"].append(dict(ball))
    cases = [("max_depth above 1", deep, [], "/render/max_depth: media (/materials/boundary/interior)"),
             ("an open mesh as a boundary", media_scene(fog["media"], fog["materials"], [open_mesh]), [],
              "/shapes/1: a medium boundary"),
             ("an interior in a world medium", both, [], "/materials/boundary/interior: an interior medium in a scene with a world medium"),
             ("escaping camera rays in a world medium", escaping, [], "/world_medium: the camera ray of pixel (0, 0) leaves the scene"),
             ("a null boundary and a mirror", mirror, [], "/materials/boundary: a null boundary in a scene with mirror reflection"),
             ("an emitting medium", media_scene({"glow": {"kind": "homogeneous", "sigma_a": 1, "emission": 0.5}},
                                                {"boundary": {"model": "null", "interior": "glow"}}, [box]), [],
              "/media/glow/emission: an emitting medium")]
    for title, scene, extra, want in cases:
        js = env.write_scene(scene, "err")
        p = env.run([env.facet, "export-pov", js, "-o", env.path("err.pov")] + extra, check=False)
        good = p.returncode == 1 and f"{js}: {want}" in p.stderr
        print(f"{'ok  ' if good else 'FAIL'} {title}: rc {p.returncode}: {p.stderr.strip()}")
        ok &= good
    js = env.write_scene(fog, "flag")
    for args, want in ((["--media-intervals", "0"], "--media-intervals"), (["--media-intervals", "201"], "--media-intervals"),
                       (["--radiosity", "low"], "--radiosity: not with media")):
        p = env.run([env.facet, "export-pov", js, "-o", env.path("f.pov")] + args, check=False)
        good = p.returncode != 0 and want in p.stderr
        print(f"{'ok  ' if good else 'FAIL'} {' '.join(args)}: rc {p.returncode}: {p.stderr.strip()}")
        ok &= good
    return ok


def cmd_principled_sky(env):
    """The principled materials of principled_scene lit by the HDR sky of sky_map through
    brdf_sky_sampling, 64 x 32 (the light comes from everywhere, so every lobe of the split
    finish is exercised at every angle): (1) --glossy-samples 0: the sky samples alone shade
    the cosine (diffuse + sheen) and glossy parts, against facet direct within noise (t_test,
    Facet at 5x the resolution, middle pixels, as cmd_skylight); (2) the metal sphere with 16
    glossy rays per hit, whose escape to the sky shares the light with the sky samples by MIS,
    against facet path with max_depth 2 (its glossy rays also see the floor and the other
    spheres lit by the sky, cmd_glossy), on that sphere's pixels. The coat sphere's clearcoat
    is smooth enough to be a delta lobe (clearcoat_roughness 0): POV-Ray's mirror rays with the
    mirror part's weight at wo, as Facet's direct follows delta directions."""
    w, h = 96, 48
    exr = env.path("sky.exr")
    write_exr(exr, sky_map())
    scene = principled_scene(w, h)
    scene["lights"] = [{"type": "environment", "file": exr, "up": [0, 1, 0], "rotate": {"axis": [0, 1, 0], "angle": 25}}]
    scene["materials"]["coat"]["clearcoat_roughness"] = 0.0
    cam = scene["camera"]
    js = env.write_scene(scene, "principled_sky")
    fine = json.loads(json.dumps(scene))
    fine["camera"]["width"], fine["camera"]["height"] = 5 * w, 5 * h
    fine_js = env.write_scene(fine, "principled_sky_fine")
    ok = True
    pov = env.povray(env.export(js, "--environment", "light", "--sky-samples", "64", "--glossy-samples", "0"), w, h, "+FE32")
    ref = env.render(fine_js, "--spp", "64", "--seed", "3")[2::5, 2::5]
    spheres = {n: sphere_pixels(cam, c, 0.95 * 0.45) for n, c in PRINCIPLED_CENTRES.items()}
    for n in ("sheen", "coat", "metal", "retro"):
        ok &= t_test(f"principled {n}: brdf_sky_sampling 64, no glossy rays, vs facet direct", f"{n} sphere",
                     pov, ref, spheres[n])
    # The metal (no cosine lobe: metallic 1) through glossy rays that see the floor and the
    # other spheres lit by the sky: one bounce more than direct, as path max_depth 2 (a sphere
    # with a cosine lobe would get that bounce in Facet and not in POV-Ray, which leaves it to
    # radiosity).
    pov2 = env.povray(env.export(js, "--environment", "light", "--sky-samples", "64", "--glossy-samples", "16"), w, h, "+FE32")
    ref2 = env.render(fine_js, "--spp", "64", "--seed", "4", "--max-depth", "2", integrator="path")[2::5, 2::5]
    ok &= t_test("principled metal: 64 sky samples + 16 glossy rays (MIS) vs facet path max_depth 2",
                 "metal sphere", pov2, ref2, spheres["metal"])
    return ok


def main():
    pov, facet, cmd, args = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2]), sys.argv[3], sys.argv[4:]
    keep = os.environ.get("FACET_CROSSCHECK_KEEP")  # a directory: keep the files there
    if keep:
        os.makedirs(keep, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="facet-crosscheck-") as tmp:
        env = Env(pov, facet, keep or tmp)
        ok = {"scene": lambda: cmd_scene(env, args[0], *(int(a) for a in args[1:])),
              "coverage": lambda: cmd_coverage(env),
              "scenes-errors": lambda: cmd_scenes_errors(env),
              "errors": lambda: cmd_errors(env),
              "glossy": lambda: cmd_glossy(env),
              "float": lambda: cmd_float(env),
              "radiosity-furnace": lambda: cmd_radiosity_furnace(env),
              "radiosity-cornell": lambda: cmd_radiosity_cornell(env),
              "envmap": lambda: cmd_envmap(env),
              "skylight": lambda: cmd_skylight(env),
              "skylight-errors": lambda: cmd_skylight_errors(env),
              "textures": lambda: cmd_textures(env),
              "texture-errors": lambda: cmd_texture_errors(env),
              "principled": lambda: cmd_principled(env),
              "principled-sky": lambda: cmd_principled_sky(env),
              "media": lambda: cmd_media(env)}[cmd]()
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
