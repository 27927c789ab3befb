#!/usr/bin/python3
"""`global_settings { brdf_convert_classic on }` in povray-facet (CTest label `povray`).

Usage: convert_classic.py POVRAY_FACET FACET_CLI COMMAND
  units   the exact parts of the mapping are exact in POV-Ray (diffuse, also on an object
          with POV-Ray's own interior media, Fresnel reflection
          against the classic render and against the bridge's own brdf mirror, ambient as
          emission), the fitted highlight keeps POV-Ray's energy and metallic tint, lights
          convert to physical falloff normalised at the look_at point, and the summary names
          what it approximated and where
  scenes  stock scenes of Debian's povray-examples with the switch injected by +HI: exit 0, a
          summary with N > 0, no NaN, an image that differs from the classic render and keeps
          its mean brightness within a stated band

Images travel as povray-facet's float EXR, read through `facet convert x.exr -o x.pfm`.
"""
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from crosscheck import read_pfm  # noqa: E402

EXAMPLES = "/usr/share/doc/povray/examples"
# Kinds hold no parentheses; each "(first at FILE:LINE)" is one level of them.
_LIST = r"((?:[^()]|\([^()]*\))*?)"
SUMMARY = re.compile(r"brdf_convert_classic: (\d+) finishes converted \((\d+) approximated" + _LIST +
                     r"; (\d+) reported" + _LIST + r"\)")


class Env:
    def __init__(self, pov, cli, tmp):
        self.pov, self.cli, self.tmp = pov, cli, tmp
        self.n = 0

    def render(self, scene_text=None, scene_path=None, w=96, h=72, extra=(), header=None):
        """Renders to float EXR; returns (image, stderr, seconds)."""
        self.n += 1
        if scene_text is not None:
            scene_path = os.path.join(self.tmp, f"s{self.n}.pov")
            with open(scene_path, "w") as f:
                f.write(scene_text)
        out = os.path.join(self.tmp, f"o{self.n}.exr")
        args = [self.pov, f"+I{scene_path}", f"+O{out}", "+FE32", f"+W{w}", f"+H{h}", "-D", "-V",
                f"+L{os.path.dirname(os.path.abspath(scene_path))}"]
        if header:
            inc = os.path.join(self.tmp, f"h{self.n}.inc")
            with open(inc, "w") as f:
                f.write(header)
            args.append(f"+HI{inc}")
        args += list(extra)
        env = dict(os.environ, HOME=self.tmp)  # no user povray.conf / povray.ini
        t0 = time.perf_counter()
        p = subprocess.run(args, cwd=self.tmp, env=env, capture_output=True, text=True,
                           timeout=900)
        dt = time.perf_counter() - t0
        if p.returncode != 0 or not os.path.exists(out):
            raise RuntimeError(f"{' '.join(args)} failed ({p.returncode}):\n{p.stderr[-3000:]}")
        pfm = out[:-4] + ".pfm"
        subprocess.run([self.cli, "convert", out, "-o", pfm], check=True, capture_output=True)
        return read_pfm(pfm), p.stderr, dt


def summary(stderr):
    # POV-Ray's debug stream wraps lines at 80 columns (at a space, which it keeps, or inside
    # a word): removing the line breaks gives the message back.
    m = SUMMARY.search(stderr.replace("\n", ""))
    if not m:
        return None
    return {"converted": int(m.group(1)), "approximated": int(m.group(2)),
            "approx_text": m.group(3), "reported": int(m.group(4)), "reported_text": m.group(5)}


failures = 0


def check(ok, message):
    global failures
    print(("ok   " if ok else "FAIL ") + message)
    failures += 0 if ok else 1


ON = "global_settings { brdf_convert_classic on }\n"

# An orthographic view of a plane at normal incidence: every pixel sees theta_o = 0.
PLANE = """#version 3.7;
global_settings {{ assumed_gamma 1.0 ambient_light {ambient_light} {settings} }}
camera {{ orthographic location <0, 0, -5> look_at 0 right x * {size} up y * {size} }}
{lights}
plane {{ -z, 0 pigment {{ {pigment} }} finish {{ {finish} }} {interior} }}
"""

# A sphere mirroring a checkered environment (a sky_sphere): reflection weights at all angles.
MIRROR = """#version 3.7;
global_settings {{ assumed_gamma 1.0 ambient_light 0 }}
camera {{ orthographic location <0, 0, -5> look_at 0 right x * 2.1 up y * 2.1 }}
sky_sphere {{ pigment {{ checker rgb <0.9, 0.6, 0.3> rgb <0.2, 0.4, 0.8> scale 0.15 }} }}
sphere {{ 0, 1 pigment {{ rgb 0 }} finish {{ ambient 0 diffuse 0 {finish} }} interior {{ ior 1.5 }} }}
"""


def cmd_units(env):
    light = "light_source { <0.5, 0.3, -6> color rgb 1 }"
    # 1. diffuse: Lambert rho = d exactly. Float (bridge) against double (POV-Ray): 1e-6.
    scene = PLANE.format(ambient_light=0, settings="", size=8, lights=light,
                         pigment="rgb <0.9, 0.5, 0.2>", finish="ambient 0 diffuse 0.7",
                         interior="")
    a, _, _ = env.render(scene, w=48, h=48)
    b, err, _ = env.render(scene.replace("assumed_gamma 1.0", "assumed_gamma 1.0 brdf_convert_classic on"), w=48, h=48)
    s = summary(err)
    check(s is not None and s["converted"] == 1 and s["approximated"] == 0 and s["reported"] == 0,
          f"diffuse: summary {s}")
    d = np.abs(a - b).max()
    check(d < 1e-5 * max(1.0, a.max()), f"diffuse 0.7: converted = classic (largest difference {d:.2e}, tolerance 1e-5 relative)")

    # 1b. POV-Ray's own interior media on an object with a brdf finish: a partly transmitting
    # hollow sphere filled with absorbing and scattering media, in front of a lit plane, its
    # light attenuated by the media (media_attenuation). The converted render (Lambert brdf,
    # exact as above) equals the classic one: the media along camera and shadow rays are POV-
    # Ray's in both. Without the media the image differs (the check can fail).
    media_scene = """#version 3.7;
global_settings {{ assumed_gamma 1.0 ambient_light 0 }}
camera {{ location <0, 0.5, -4> look_at <0, 0.3, 0> }}
light_source {{ <-2, 4, -3> color rgb 1 media_attenuation on }}
plane {{ y, -1 pigment {{ checker rgb 0.8 rgb 0.2 }} finish {{ ambient 0 diffuse 0.7 }} }}
sphere {{ <0, 0.3, 0>, 1 hollow
  pigment {{ rgbt <0.8, 0.5, 0.3, 0.6> }} finish {{ ambient 0 diffuse 0.7 }}
  interior {{ {media} }} }}
"""
    with_media = media_scene.format(media="media { absorption 0.6 scattering { 1, 0.8 } intervals 20 samples 2, 2 jitter 0 }")
    a, _, _ = env.render(with_media, w=48, h=48)
    b, err, _ = env.render(with_media, w=48, h=48, header=ON)
    c, _, _ = env.render(media_scene.format(media=""), w=48, h=48, header=ON)
    s = summary(err)
    check(s is not None and s["converted"] == 2 and s["approximated"] == 0, f"interior media: summary {s}")
    d, dm = np.abs(a - b).max(), np.abs(b - c).max()
    check(d < 1e-5 * max(1.0, a.max()) and dm > 1e-2,
          f"brdf finish with POV-Ray's interior media: converted = classic (largest difference {d:.2e}, "
          f"tolerance 1e-5 relative); the media change the image by {dm:.2e} (> 1e-2)")

    # 2. reflection { 0, 1 fresnel on } with ior 1.5: the core's Fresnel = POV-Ray's formula;
    # the converted render equals the classic one and the bridge's own brdf mirror.
    classic, _, _ = env.render(MIRROR.format(finish="reflection { 0, 1 fresnel on }"), w=64, h=64)
    conv, err, _ = env.render(MIRROR.format(finish="reflection { 0, 1 fresnel on }"), w=64, h=64, header=ON)
    brdf, _, _ = env.render(MIRROR.format(finish="brdf { mirror fresnel dielectric ior 1.5 }"), w=64, h=64)
    s = summary(err)
    check(s is not None and s["converted"] == 1 and s["approximated"] == 0, f"fresnel: summary {s}")
    d1, d2 = np.abs(conv - classic).max(), np.abs(conv - brdf).max()
    check(classic.max() > 0.1 and d1 < 1e-5 and d2 < 1e-5,
          f"fresnel reflection: converted vs classic {d1:.2e}, vs brdf mirror {d2:.2e} (tolerance 1e-5: float Fresnel)")

    # 3. ambient with ambient_light: the same light as emission; with radiosity on POV-Ray adds
    # none, and neither does the conversion.
    for settings, what in (("", "ambient_light 0.5"), ("radiosity { count 20 }", "radiosity on")):
        scene = PLANE.format(ambient_light=0.5, settings=settings, size=4, lights="",
                             pigment="rgb <0.8, 0.4, 0.2>", finish="ambient 0.3 diffuse 0",
                             interior="")
        a, _, _ = env.render(scene, w=16, h=16)
        b, err, _ = env.render(scene, w=16, h=16, header=ON)
        ok = np.abs(a - b).max() < 1e-6
        expect = 0.0 if settings else 0.3 * 0.5 * 0.8
        check(ok and abs(b[8, 8, 0] - expect) < 1e-4 and (settings or "ambient as emission in 1" in err.replace("\n", "")),
              f"ambient ({what}): converted {b[8, 8, 0]:.5f} = classic {a[8, 8, 0]:.5f} (expected {expect})")

    # 4. The fitted phong / specular lobes keep POV-Ray's highlight energy at normal incidence:
    # a light on the camera axis, an orthographic view at theta_o = 0, the image's sum over the
    # highlight. The lobes differ in shape by the fit error (<= 0.6% for these sizes,
    # tests/core PovClassic.FittedLobes) and in the plane's dA = r^3 / D dw weighting; 2%.
    axis = "light_source { <0, 0, -6> color rgb 1 }"
    for finish in ("phong 0.8 phong_size 60", "specular 0.7 roughness 0.01",
                   "specular 0.8 roughness 0.01 metallic"):
        scene = PLANE.format(ambient_light=0, settings="", size=3, lights=axis,
                             pigment="rgb <1, 0.3, 0.2>", finish="ambient 0 diffuse 0 " + finish,
                             interior="")
        a, _, _ = env.render(scene, w=128, h=128)
        b, err, _ = env.render(scene, w=128, h=128, header=ON)
        ra = a.sum(axis=(0, 1))
        rb = b.sum(axis=(0, 1))
        ratio = rb[0] / ra[0]
        tint_a, tint_b = ra[1] / ra[0], rb[1] / rb[0]
        check(abs(ratio - 1) < 0.02 and abs(tint_a - tint_b) < 0.01 * max(tint_a, 0.1),
              f"{finish}: highlight energy converted / classic {ratio:.4f} (band 2%), "
              f"green/red {tint_b:.4f} vs classic {tint_a:.4f}")
        # able to fail: without the conversion the summary is absent
    check(summary(env.render(PLANE.format(ambient_light=0, settings="", size=3, lights=axis,
                                          pigment="rgb 1", finish="phong 1", interior=""),
                             w=8, h=8)[1]) is None, "no switch: no summary")

    # 5. The summary names the approximated and dropped terms and their first place.
    scene = PLANE.format(ambient_light=0, settings="brdf_convert_classic on", size=8, lights=light,
                         pigment="rgb 0.5", finish="diffuse 0.6 brilliance 3 irid { 0.3 }",
                         interior="")
    _, err, _ = env.render(scene, w=16, h=16)
    s = summary(err)
    check(s is not None and "brilliance 1 (first at " in s["approx_text"] and
          "irid dropped 1 (first at " in s["reported_text"] and "s" in s["approx_text"] and
          re.search(r"first at \S+\.pov:5\)", s["approx_text"]) is not None,
          f"summary with places: {s}")

    # 6. A value that is not on/off/a number: POV-Ray's own parse error, with file and line.
    bad = os.path.join(env.tmp, "bad.pov")
    with open(bad, "w") as f:
        f.write("#version 3.7;\nglobal_settings { assumed_gamma 1 brdf_convert_classic maybe }\n"
                "sphere { 0, 1 pigment { rgb 1 } }\n")
    p = subprocess.run([env.pov, f"+I{bad}", "-D", "-V", "+W8", "+H8", f"+O{bad}.png"],
                       cwd=env.tmp, env=dict(os.environ, HOME=env.tmp), capture_output=True,
                       text=True, timeout=60)
    err = p.stderr.replace("\n", "")
    check(p.returncode != 0 and re.search(r"File '[^']*bad\.pov' line 2: Parse Error: No matching "
                                          r"\} in 'global_settings', undeclared identifier "
                                          r"'maybe' found instead", err) is not None,
          f"bad value: exit {p.returncode}, POV-Ray parse error at line 2")

    # 7. brdf_convert_lights: a point light 4 units from the plane's look_at point keeps its
    # light there (colour x 16, 1/d^2) and falls off physically elsewhere.
    scene = PLANE.format(ambient_light=0, settings="brdf_convert_lights on", size=8,
                         lights="light_source { <0, 0, -4> color rgb 0.5 }", pigment="rgb 1",
                         finish="ambient 0 diffuse 1", interior="")
    b, err, _ = env.render(scene, w=33, h=33)
    centre = b[16, 16, 0]
    x = (32 + 0.5) / 33 * 8 - 4  # the right edge pixel, scene units
    r2 = 16 + x * x
    edge = b[16, 32, 0]
    expect_edge = 0.5 * 16 * (4 / r2 ** 0.5) / r2
    check(abs(centre - 0.5) < 1e-3 and abs(edge - expect_edge) < 2e-3 and
          "brdf_convert_lights: 1 lights to physical falloff" in err.replace("\n", ""),
          f"lights: centre {centre:.4f} (0.5), edge {edge:.4f} ({expect_edge:.4f})")


# Stock scenes (96x72 unless the brackets say otherwise), each under ~15 s with the stock binary.
SCENES = [
    "advanced/woodbox.pov", "advanced/chess2.pov", "advanced/blocks/stackergold.pov",
    "advanced/balcony/balcony.pov", "incdemo/metals/chromes.pov", "incdemo/finish.pov",
    "textures/finishes/metallicreflection.pov", "textures/finishes/var_refl.pov",
    "lights/shadows.pov", "objects/blob.pov", "radiosity/cornell.pov",
    "incdemo/glasses/glass.pov", "advanced/wineglass.pov", "incdemo/woods/woods1.pov",
    "textures/pigments/irid.pov", "objects/lathe2.pov",
]

EXACT = {"radiosity/cornell.pov"}

# The converted scene's mean over the classic's: classic scenes are tuned with non-physical
# terms (brilliance, highlights without an energy bound, diffuse + reflection above 1), so the
# physical version's brightness moves; measured 0.954 (wineglass) to 1.227 (stackergold) at
# 96x72. The band catches a conversion gone wrong (black, blown out, a lost term), not a look.
BAND = (0.8, 1.4)


def cmd_scenes(env):
    rows = []
    for rel in SCENES:
        path = os.path.join(EXAMPLES, rel)
        if not os.path.exists(path):
            check(False, f"{rel}: not in povray-examples")
            continue
        a, _, ta = env.render(scene_path=path, extra=["+WT1"])
        b, err, tb = env.render(scene_path=path, extra=["+WT1"], header=ON)
        s = summary(err)
        finite = bool(np.isfinite(b).all())
        differ = int((np.abs(a - b) > 1e-4).any(axis=2).sum())
        ratio = b.mean() / max(a.mean(), 1e-9)
        # Diffuse-only scenes (radiosity/cornell.pov) convert exactly: the same image.
        exact = rel in EXACT
        ok = (s is not None and s["converted"] > 0 and finite and
              (differ == 0 if exact else differ > 0) and BAND[0] <= ratio <= BAND[1])
        check(ok, f"{rel}: {s['converted'] if s else '?'} converted, {s['approximated'] if s else '?'} "
                  f"approximated, {s['reported'] if s else '?'} reported; {differ} pixels differ; "
                  f"mean ratio {ratio:.3f}; time {tb / ta:.2f}x of classic; finite {finite}")
        rows.append((rel, ratio, tb / ta))
    print("| scene | mean converted / classic | time converted / classic |")
    print("|---|---|---|")
    for rel, ratio, t in rows:
        print(f"| {rel} | {ratio:.3f} | {t:.2f} |")


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        return 2
    pov, cli, cmd = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2]), sys.argv[3]
    with tempfile.TemporaryDirectory() as tmp:
        env = Env(pov, cli, tmp)
        {"units": cmd_units, "scenes": cmd_scenes}[cmd](env)
    print(f"{cmd}: {'FAILED ' + str(failures) if failures else 'passed'}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
