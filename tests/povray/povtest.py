#!/usr/bin/python3
"""Tests of povray-facet (CTest label `povray`): renders scenes with povray-facet and with the
stock Debian /usr/bin/povray and compares decoded pixels (never files: POV-Ray's PNGs carry the
render date). Standard library only (Debian's /usr/bin/python3).

Usage: povtest.py POVRAY_FACET COMMAND [ARGS]
  regress SCENE [SCENE...]  render each scene (a path under the examples dir) with both binaries;
                            the pixels must be identical
  lambert                   brdf { lambert } vs classic diffuse 1 brilliance 1, every light type
  parse-errors              malformed brdf blocks and light options: POV-Ray parse errors with
                            file and line, never a crash
  clash                     every model / parameter / bare word as a #declare identifier
  falloff                   physical_falloff is the exact inverse square
  glossy [FACET_CLI]        a white furnace: the glossy rays' weights average to the albedo
                            (with the facet CLI: to the core's albedo table)
  threads                   glossy images do not depend on the thread count
  light FACET_CLI           diffuse + glossy lobes under a light = pi f cos I / d^2 of the core
  models FACET_CLI          every model of the core's table renders as a brdf finish or is a
                            parse error that leaves it out of the finish's model list
"""
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport.png import read_png  # noqa: E402

EXAMPLES = "/usr/share/doc/povray/examples"
STOCK = "/usr/bin/povray"

# ---------------------------------------------------------------------------------------------
# Rendering


def render(binary, scene, out, width=96, height=72, extra=(), cwd=None):
    """Renders scene to out (16-bit PNG); returns (returncode, stderr)."""
    args = [binary, f"+I{scene}", f"+O{out}", f"+W{width}", f"+H{height}", "-D", "-V",
            "+FN16", "-GA", "+GF"] + list(extra)
    scene_dir = os.path.dirname(os.path.abspath(scene))
    args.append(f"+L{scene_dir}")
    env = dict(os.environ)
    env["HOME"] = cwd or os.path.dirname(out)  # no user povray.conf / povray.ini
    proc = subprocess.run(args, cwd=cwd or os.path.dirname(out), env=env,
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=600)
    return proc.returncode, proc.stderr.decode("utf-8", "replace")


def compare(a, b):
    """Number of differing samples and the largest difference of two decoded PNGs."""
    if a[:4] != b[:4]:
        return -1, -1
    diff, worst = 0, 0
    for ra, rb in zip(a[4], b[4]):
        for x, y in zip(ra, rb):
            if x != y:
                diff += 1
                worst = max(worst, abs(x - y))
    return diff, worst


class Failure(Exception):
    pass


def check(cond, message):
    if not cond:
        raise Failure(message)


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


# ---------------------------------------------------------------------------------------------
# Commands


def cmd_regress(facet, scenes):
    failures = 0
    for rel in scenes:
        scene = os.path.join(EXAMPLES, rel)
        extra = ["+WT1"]  # radiosity, jittered area lights: thread-count dependent otherwise
        m = re.match(r"(.*)\[(.*)\]$", rel)
        if m:  # "scene.pov[+A0.3 +AM2]": per-scene options
            scene = os.path.join(EXAMPLES, m.group(1))
            extra += m.group(2).split()
        with tempfile.TemporaryDirectory() as tmp:
            a, b = os.path.join(tmp, "stock.png"), os.path.join(tmp, "facet.png")
            rc1, err1 = render(STOCK, scene, a, extra=extra, cwd=tmp)
            rc2, err2 = render(facet, scene, b, extra=extra, cwd=tmp)
            if rc1 != 0 or not os.path.exists(a):
                print(f"FAIL {rel}: stock povray failed ({rc1}):\n{err1[-2000:]}")
                failures += 1
                continue
            if rc2 != 0 or not os.path.exists(b):
                print(f"FAIL {rel}: povray-facet failed ({rc2}):\n{err2[-2000:]}")
                failures += 1
                continue
            ia, ib = read_png(a), read_png(b)
            diff, worst = compare(ia, ib)
            if diff != 0:
                print(f"FAIL {rel}: {diff} samples differ (largest difference {worst})")
                failures += 1
            else:
                print(f"ok   {rel}: {ia[0]}x{ia[1]} pixel-identical")
    return failures


LAMBERT_SCENE = """#version 3.7;
global_settings {{ assumed_gamma 1.0 }}
camera {{ location <0, 2.2, -5> look_at <0, 0.4, 0> angle 50 }}
{lights}
plane {{ y, 0 texture {{ pigment {{ checker rgb <0.9, 0.8, 0.3> rgb <0.2, 0.5, 0.7> scale 0.7 }} finish {{ {finish} }} }} }}
sphere {{ <0, 1, 0>, 1 texture {{ pigment {{ bozo color_map {{ [0 rgb <1, 0.2, 0.1>] [1 rgb <0.3, 0.9, 0.4>] }} scale 0.4 }} finish {{ {finish} }} }} }}
box {{ <-2.6, 0, 0.5>, <-1.6, 1.2, 1.5> rotate y*30 texture {{ pigment {{ rgb 0.85 }} finish {{ {finish} }} }} }}
"""

LIGHTS = {
    "point": "light_source { <3, 5, -3> color rgb <1, 0.95, 0.9> }",
    "spot": "light_source { <2, 6, -2> color rgb 1.2 spotlight point_at <0, 0.5, 0> radius 15 falloff 25 tightness 5 }",
    "parallel": "light_source { <-4, 6, -2> color rgb 0.8 parallel point_at <0, 0, 0> }",
    "cylinder": "light_source { <0, 6, -1> color rgb 1 cylinder point_at <0, 0, 0> radius 1.5 falloff 2.5 }",
    "area": "light_source { <3, 5, -3> color rgb 1 area_light <1.5, 0, 0>, <0, 0, 1.5>, 4, 4 }",
    "area_illumination": "light_source { <3, 5, -3> color rgb 1 area_light <1.5, 0, 0>, <0, 0, 1.5>, 3, 3 area_illumination on }",
    "fill": "light_source { <-3, 4, -4> color rgb 0.5 shadowless }",
    "faded": "light_source { <3, 5, -3> color rgb 2 fade_distance 3 fade_power 2 }",
    "group": "light_group { light_source { <1, 4, -4> color rgb 0.7 } sphere { <2.3, 0.4, -1>, 0.4 pigment { rgb 1 } finish { diffuse 1 } } global_lights off }",
    # radiosity and photons see the core's diffuse reflectance (= the pigment for lambert)
    "radiosity": "global_settings { radiosity { count 60 recursion_limit 2 nearest_count 5 error_bound 0.8 } } "
                 "light_source { <3, 5, -3> color rgb 1 } sky_sphere { pigment { rgb <0.3, 0.4, 0.6> } }",
    "photons": "global_settings { photons { spacing 0.03 } } light_source { <3, 5, -3> color rgb 1 } "
               "sphere { <1.4, 0.6, -1.2>, 0.5 pigment { rgbf 1 } finish { diffuse 0 } interior { ior 1.5 } "
               "photons { target refraction on reflection off } }",
}

# The constant: povray-facet returns pi f cos per unit light colour; the core's Lambert is
# f = rho / pi, and the pigment is rho. So brdf { lambert } IS `diffuse 1 brilliance 1` with
# factor pi * (1 / pi) = 1. The two differ only by float (bridge) vs double (POV-Ray) rounding:
# at most 1 step of the 16-bit output.
LAMBERT_TOLERANCE = 1


def cmd_lambert(facet):
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        for name, light in LIGHTS.items():
            classic = os.path.join(tmp, f"{name}_classic.pov")
            brdf = os.path.join(tmp, f"{name}_brdf.pov")
            write(classic, LAMBERT_SCENE.format(lights=light, finish="diffuse 1 brilliance 1"))
            write(brdf, LAMBERT_SCENE.format(lights=light, finish="brdf { lambert }"))
            a, b = os.path.join(tmp, f"{name}_a.png"), os.path.join(tmp, f"{name}_b.png")
            rc1, err1 = render(STOCK, classic, a, 120, 90, ["+WT1"], cwd=tmp)
            rc2, err2 = render(facet, brdf, b, 120, 90, ["+WT1"], cwd=tmp)
            if rc1 != 0 or rc2 != 0:
                print(f"FAIL {name}: render failed\n{err1[-1500:]}\n{err2[-1500:]}")
                failures += 1
                continue
            ia, ib = read_png(a), read_png(b)
            diff, worst = compare(ia, ib)
            lit = sum(1 for r in ib[4] for v in r if v > 1000)
            if worst > LAMBERT_TOLERANCE or diff < 0 or lit < 1000:
                print(f"FAIL {name}: {diff} samples differ, largest {worst} (tolerance "
                      f"{LAMBERT_TOLERANCE}/65535); {lit} lit samples")
                failures += 1
            else:
                print(f"ok   {name}: {diff} samples differ by <= {worst}/65535; {lit} lit samples")
    return failures


ERROR_CASES = [
    # (name, finish or light text, expected message regex, expected line)
    ("empty", "finish { brdf { } }", r"Expected a brdf model \('lambert', 'mirror', 'ggx', 'beckmann', 'blinn', 'composite', 'principled', 'oren_nayar', 'velvet'\), found '\}' instead", 3),
    ("bad_model", "finish { brdf { phong 0.3 } }", r"Expected a brdf model .*found 'phong' instead", 3),
    ("alpha_range", "finish { brdf { ggx\n  alpha 12 } }", r"alpha.*must be in \[0, 10\] \(got 12\)", 4),
    ("typo", "finish { brdf { ggx alpah 0.3 } }", r"unknown parameter 'alpah' for model 'ggx' \(did you mean 'alpha'\?\)", 3),
    ("distribution", "finish { brdf { composite\n distribution ggz } }", r"distribution: expected 'ggx', 'beckmann', 'blinn', found 'ggz' instead", 4),
    ("fresnel_word", "finish { brdf { mirror fresnel metal } }", r"fresnel: expected 'none', 'dielectric', 'conductor', 'schlick', found 'metal' instead", 3),
    ("no_effect", "finish { brdf { ggx alpha 0.3\n\n ior 1.5 } }", r"parameter 'ior' of model 'ggx': has no effect with fresnel = none", 5),
    ("twice", "finish { brdf { ggx alpha 0.3 alpha 0.2 } }", r"parameter 'alpha' given twice", 3),
    ("samples", "finish { brdf { ggx alpha 0.3 samples 2.5 } }", r"samples': must be an integer in \[0, 10000\] \(got 2.5\)", 3),
    ("colour_range", "finish { brdf { lambert reflectance rgb <2, 0, 0> } }", r"reflectance.*must be in \[0, 1\] \(got 2\)", 3),
    ("eta_zero", "finish { brdf { mirror fresnel conductor eta 0 } }", r"parameter 'eta'.*must be > 0", 3),
    ("nan", "finish { brdf { ggx alpha sqrt(-1) } }", r"(alpha|sqrt|Domain)", 3),
    ("no_brace", "finish { brdf lambert }", r"Missing \{ after 'brdf', 'lambert' found instead", 3),
    ("punct", "finish { brdf { ggx , } }", r"Expected a parameter of brdf model 'ggx' or '\}'", 3),
    # principled (reflection part) and oren_nayar: the registry's ranges and names, the
    # transmission that POV-Ray's interior does instead, combinations that are not finish models
    ("principled_range", "finish { brdf { principled\n sheen 1.5 } }", r"parameter 'sheen' of model 'principled': must be in \[0, 1\] \(got 1.5\)", 4),
    ("principled_colour", "finish { brdf { principled metallic 1 base_color rgb <1.2, 0, 0> } }", r"base_color.*must be in \[0, 1\] \(got 1.2\)", 3),
    ("principled_typo", "finish { brdf { principled\n\n clearcoat_gloss 0.5 } }", r"unknown parameter 'clearcoat_gloss' for model 'principled'", 5),
    ("principled_transmission", "finish { brdf { principled roughness 0.2\n transmission 1 } }", r"parameter 'transmission' of model 'principled': the brdf finish is reflection only.*interior", 4),
    ("principled_word", "finish { brdf { principled distribution beckmann } }", r"distribution: expected 'ggx', 'multi_ggx', found 'beckmann' instead", 3),
    ("principled_twice", "finish { brdf { principled specular 0.5\n specular 0.2 } }", r"parameter 'specular' given twice", 4),
    ("oren_nayar_sigma", "finish { brdf { oren_nayar\n sigma -0.5 } }", r"sigma.*must be in \[0, 1\] \(got -0.5\)", 4),
    ("mix_model", "finish { brdf { mix weight 0.5 } }", r"Expected a brdf model .*found 'mix' instead", 3),
    ("falloff_fade", "}\nlight_source { <0, 5, 0> rgb 1 physical_falloff fade_distance 2 fade_power 2 } #declare Dummy = finish {", r"physical_falloff replaces fade_distance and fade_power", 4),
    ("falloff_parallel", "}\nlight_source { <0, 5, 0> rgb 1 parallel point_at <0,0,0> physical_falloff } #declare Dummy = finish {", r"physical_falloff needs a light with a position", 4),
]


def cmd_parse_errors(facet):
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        for name, text, pattern, line in ERROR_CASES:
            scene = os.path.join(tmp, f"{name}.pov")
            write(scene, "#version 3.7;\n#declare F = finish {}\nsphere { 0, 1 pigment { rgb 1 } "
                  + text + " }\n")
            rc, err = render(facet, scene, os.path.join(tmp, f"{name}.png"), 8, 8, ["+GA"], cwd=tmp)
            err = err.replace("\n", "")  # POV-Ray wraps messages at 80 columns
            where = re.search(rf"File '.*{name}\.pov' line (\d+):", err)
            ok = (rc == 1 and re.search(r"Parse Error", err) and re.search(pattern, err)
                  and where and int(where.group(1)) == line)
            if ok:
                print(f"ok   {name}: {err[where.start():where.start() + 220]}")
            else:
                print(f"FAIL {name}: exit {rc}, expected /{pattern}/ at line {line}:\n{err[-1500:]}")
                failures += 1
    return failures


# Every model, parameter and bare-word value of the core's registry plus the patch's own words.
CLASH_NAMES = [
    "brdf", "physical_falloff", "brdf_sky_sampling", "brdf_convert_classic", "brdf_convert_lights",
    "null", "lambert", "mirror", "ggx", "beckmann", "blinn", "composite",
    "reflectance", "diffuse_reflectance", "glossy_reflectance", "mirror_reflectance",
    "distribution", "alpha", "alpha_u", "alpha_v", "exponent", "exponent_u", "exponent_v",
    "fresnel", "ior", "eta", "k", "f0", "energy_compensation", "none", "dielectric",
    "conductor", "schlick", "samples", "principled", "oren_nayar", "sigma", "base_color",
    "sheen", "sheen_tint", "clearcoat", "clearcoat_roughness", "specular_tint", "anisotropic",
    "transmission", "velvet",
]


# Models the brdf finish does not take: transmissive ones (POV-Ray's interior refracts),
# combinations (the finish gives no sub-materials) and `holdout` (a hole in the film's alpha,
# which POV-Ray's finishes have no way to make), and the fibre models `principled_hair` and `hair`
# (they scatter about the surface's tangent, which POV-Ray does not give a finish).
NOT_FINISH_MODELS = {"dielectric", "thin_dielectric", "translucent", "null", "mix", "add",
                     "holdout", "principled_hair", "hair", "subsurface"}


def cmd_models(facet, cli):
    """Every model of the core's table (`facet brdf models --markdown`) either renders as
    `brdf { model }` or is a parse error at its name whose list of models leaves it out; the
    list is exactly the models that render, and those are all but NOT_FINISH_MODELS."""
    out = subprocess.run([cli, "brdf", "models", "--markdown"], capture_output=True, text=True,
                         check=True).stdout
    models = re.findall(r"^#### `([a-z_0-9]+)`", out, re.M)
    failures, rendered, listed = 0, set(), None
    with tempfile.TemporaryDirectory() as tmp:
        for m in models:
            scene = os.path.join(tmp, f"{m}.pov")
            write(scene, "#version 3.7;\nlight_source { <2, 4, -3>, 1 }\n"
                  f"sphere {{ 0, 1 pigment {{ rgb 0.8 }}\n finish {{ brdf {{ {m} }} }} }}\n")
            rc, err = render(facet, scene, os.path.join(tmp, f"{m}.png"), 8, 8, ["+GA"], cwd=tmp)
            err = err.replace("\n", "")
            if rc == 0:
                rendered.add(m)
                continue
            e = re.search(r"File '.*\.pov' line 4:.*Expected a brdf model \(([^)]*)\), found "
                          rf"'{m}' instead", err)
            if not e:
                print(f"FAIL {m}: neither renders nor a parse error at its name:\n{err[-800:]}")
                failures += 1
                continue
            listed = set(re.findall(r"'([a-z_0-9]+)'", e.group(1)))
            print(f"ok   {m}: a parse error at line 4, not in the finish's list")
    expected = set(models) - NOT_FINISH_MODELS
    if rendered != expected:
        print(f"FAIL the finish renders {sorted(rendered)}, expected {sorted(expected)}")
        failures += 1
    if listed is not None and listed != rendered:
        print(f"FAIL the error lists {sorted(listed)}, but {sorted(rendered)} render")
        failures += 1
    print(f"{len(models)} models: {len(rendered)} render as brdf finishes, "
          f"{len(models) - len(rendered)} are parse errors")
    return failures


def cmd_clash(facet):
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        # Which of the names stock 3.7 accepts as identifiers (the others are 3.7 keywords).
        declarable = []
        for n in CLASH_NAMES:
            scene = os.path.join(tmp, f"probe_{n}.pov")
            write(scene, f"#version 3.7;\n#declare {n} = 0.5;\n")
            rc, _ = render(STOCK, scene, os.path.join(tmp, "probe.png"), 4, 4, cwd=tmp)
            if rc == 0:
                declarable.append(n)
        print(f"names stock 3.7 accepts as identifiers: {' '.join(declarable)}")
        check(len(declarable) >= 20, "too few declarable names: the probe is broken")
        decl = "".join(f"#declare {n} = {0.3 + 0.02 * i:.2f};\n" for i, n in enumerate(declarable))
        use = " + ".join(declarable)
        body = ("#version 3.7;\n" + decl +
                "#macro ggx_m(k, alpha_u) (k + alpha_u) #end\n"
                f"#declare Height = ({use}) / {len(declarable)};\n"
                "#declare lambert = finish { diffuse 0.7 }\n"   # names as finish identifiers
                "#declare brdf = finish { diffuse 0.5 specular 0.4 }\n"
                "camera { location <0, 1, -4> look_at 0 }\n"
                "light_source { <2, 4, -3> rgb 0.5 + physical_falloff }\n"
                f"sphere {{ 0, 1 pigment {{ rgb <k, ggx, mirror> }} finish {{ lambert }} }}\n"
                "box { -1, 1 scale 0.3 translate <2, Height, 0> "
                "pigment { rgb ggx_m(k, eta) } finish { brdf } }\n")
        a, b = os.path.join(tmp, "stock.png"), os.path.join(tmp, "facet.png")
        scene = os.path.join(tmp, "clash.pov")
        write(scene, body)
        rc1, err1 = render(STOCK, scene, a, 64, 48, ["+WT1", "+GA"], cwd=tmp)
        rc2, err2 = render(facet, scene, b, 64, 48, ["+WT1", "+GA"], cwd=tmp)
        if rc1 != 0 or rc2 != 0:
            print(f"FAIL clash scene: stock {rc1}, povray-facet {rc2}\n{err1[-1500:]}\n{err2[-1500:]}")
            failures += 1
        else:
            diff, worst = compare(read_png(a), read_png(b))
            if diff != 0:
                print(f"FAIL clash scene: {diff} samples differ")
                failures += 1
            else:
                print("ok   clash scene: parses and renders pixel-identically")
        # The names stay usable inside brdf blocks while declared (read from the token text),
        # and a declared value is still a value.
        scene2 = os.path.join(tmp, "clash_brdf.pov")
        write(scene2, body + "sphere { <-2, 0, 0>, 0.6 pigment { rgb 0.5 } finish { brdf { composite "
              "diffuse_reflectance 0.8 distribution ggx alpha k fresnel dielectric ior 1.5 } } }\n"
              "sphere { <0, -2, 0>, 0.6 finish { brdf { mirror fresnel conductor eta rgb <0.2, 0.9, 1.1> "
              "k rgb <3.9, 2.4, 2.2> } } }\n"
              "sphere { <0, 2, 0>, 0.6 finish { brdf { \"ggx\" alpha_u eta alpha_v k "
              "energy_compensation on } } }\n"
              "sphere { <0, 0, 2>, 0.6 finish { brdf { principled base_color rgb <0.8, 0.2, 0.1> "
              "sheen 0.5 clearcoat 1 metallic 0.2 specular 0.3 roughness 0.4 } } }\n"
              "sphere { <2, 2, 0>, 0.6 pigment { rgb 0.6 } finish { brdf { oren_nayar sigma k } } }\n")
        rc3, err3 = render(facet, scene2, os.path.join(tmp, "c2.png"), 64, 48, ["+WT1", "+GA"], cwd=tmp)
        if rc3 != 0:
            print(f"FAIL brdf blocks with declared names: exit {rc3}\n{err3[-1500:]}")
            failures += 1
        else:
            print("ok   brdf blocks parse with every name declared as an identifier")
    return failures


FALLOFF_SCENE = """#version 3.7;
global_settings {{ assumed_gamma 1.0 ambient_light 0 }}
camera {{ orthographic location <0, 0, -1> look_at 0 right x * 2 up y * 2 }}
light_source {{ <0, 0, -{d}> color rgb {c} {opt} }}
plane {{ -z, 0 pigment {{ rgb 0.6 }} finish {{ ambient 0 {finish} }} }}
"""


def cmd_falloff(facet):
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        for d in (0.5, 2.0, 4.0):
            for finish in ("diffuse 1", "brdf { lambert }"):
                scene = os.path.join(tmp, "f.pov")
                write(scene, FALLOFF_SCENE.format(d=d, c=0.5, opt="physical_falloff", finish=finish))
                out = os.path.join(tmp, "f.png")
                rc, err = render(facet, scene, out, 33, 33, ["File_Gamma=1.0"], cwd=tmp)
                check(rc == 0, f"render failed: {err[-1500:]}")
                w, h, ch, mx, rows = read_png(out)
                centre = rows[16][16 * ch] / mx
                # centre: distance d, normal incidence: 0.6 * 0.5 / d^2 (clipped at 1)
                expected = min(1.0, 0.6 * 0.5 / (d * d))
                # off-centre pixel (x = 1 in scene units): distance sqrt(d^2 + 1), cos = d / r
                r2 = d * d + 1.0
                edge = rows[16][32 * ch] / mx
                x_edge = (32 + 0.5) / 33 * 2 - 1
                r2 = d * d + x_edge * x_edge
                expected_edge = min(1.0, 0.6 * 0.5 * (d / r2 ** 0.5) / r2)
                ok = abs(centre - expected) < 2e-3 and abs(edge - expected_edge) < 2e-3
                print(f"{'ok  ' if ok else 'FAIL'} d={d} {finish}: centre {centre:.5f} (expected "
                      f"{expected:.5f}), edge {edge:.5f} (expected {expected_edge:.5f})")
                failures += 0 if ok else 1
        # Without the option nothing changes: the light's colour at any distance.
        scene = os.path.join(tmp, "n.pov")
        write(scene, FALLOFF_SCENE.format(d=4.0, c=0.5, opt="", finish="diffuse 1"))
        a, b = os.path.join(tmp, "n1.png"), os.path.join(tmp, "n2.png")
        render(STOCK, scene, a, 33, 33, ["File_Gamma=1.0"], cwd=tmp)
        render(facet, scene, b, 33, 33, ["File_Gamma=1.0"], cwd=tmp)
        diff, _ = compare(read_png(a), read_png(b))
        print(f"{'ok  ' if diff == 0 else 'FAIL'} no physical_falloff: identical to stock ({diff} samples differ)")
        failures += 0 if diff == 0 else 1
    return failures


GLOSSY_FURNACE = """#version 3.7;
global_settings {{ assumed_gamma 1.0 ambient_light 0 max_trace_level 10 }}
camera {{ orthographic location <0, 0, -3> look_at 0 right x * 2.2 up y * 2.2 }}
sky_sphere {{ pigment {{ rgb 0.5 }} }}
sphere {{ 0, 1 pigment {{ rgb 0 }} finish {{ ambient 0 diffuse 0 brdf {{ {brdf} }} }} }}
"""


def cmd_glossy(facet, cli):
    """A sphere in a uniform environment of radiance 0.5, no lights. With F = 1 and energy
    compensation the lobe's albedo is 1 at every angle (the core's tests check that); so every
    pixel of the sphere is 0.5 up to the Monte Carlo noise of its glossy rays. Without
    compensation the albedo is below 1 and the mean must drop."""
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        means = {}
        for name, brdf in (("compensated", "ggx alpha 0.5 energy_compensation on samples 16"),
                           ("plain", "ggx alpha 1.0 samples 16")):
            scene = os.path.join(tmp, f"{name}.pov")
            write(scene, GLOSSY_FURNACE.format(brdf=brdf))
            out = os.path.join(tmp, f"{name}.png")
            rc, err = render(facet, scene, out, 48, 48, ["File_Gamma=1.0"], cwd=tmp)
            check(rc == 0, f"render failed: {err[-1500:]}")
            w, h, ch, mx, rows = read_png(out)
            vals, plain_r2 = [], []
            for y in range(h):
                for x in range(w):
                    px, py = (x + 0.5) / w * 2.2 - 1.1, 1.1 - (y + 0.5) / h * 2.2
                    if px * px + py * py < 0.9 ** 2:  # inside the sphere, off the silhouette
                        vals.append(sum(rows[y][x * ch + c] for c in range(3)) / (3 * mx))
                        plain_r2.append(px * px + py * py)
            mean = sum(vals) / len(vals)
            means[name] = mean
            print(f"{name}: {len(vals)} pixels, mean {mean:.4f}, min {min(vals):.4f}, max {max(vals):.4f}")
        ok = abs(means["compensated"] - 0.5) < 0.01 and means["plain"] < means["compensated"] - 0.01
        print(f"{'ok  ' if ok else 'FAIL'} furnace: compensated mean {means['compensated']:.4f} "
              f"(expected 0.5 +- 0.01), uncompensated alpha 1 mean {means['plain']:.4f} (expected lower)")
        failures += 0 if ok else 1
        if cli:
            # The uncompensated lobe against the core's own albedo E(theta) (quadrature, `facet
            # reflectance`): 0.5 times the mean of E over the same pixels. Noise of the mean
            # ~6e-4 (1216 pixels x 16 rays); tolerance 3e-3.
            thetas = list(range(0, 90)) + [89.5]
            proc = subprocess.run([cli, "reflectance", "--model", "ggx", "--alpha", "1.0", "--table",
                                   "--thetas", ",".join(str(t) for t in thetas), "--json"],
                                  stdout=subprocess.PIPE, check=True)
            import json
            table = [(row["theta_i"], row["ggx"][0]) for row in json.loads(proc.stdout)]
            def albedo(mu):
                import math
                th = math.degrees(math.acos(min(1.0, mu)))
                for (t0, e0), (t1, e1) in zip(table, table[1:]):
                    if t0 <= th <= t1:
                        return e0 + (e1 - e0) * (th - t0) / (t1 - t0)
                return table[-1][1]
            expected = 0.5 * sum(albedo((1 - r2) ** 0.5) for r2 in plain_r2) / len(plain_r2)
            ok = abs(means["plain"] - expected) < 3e-3
            print(f"{'ok  ' if ok else 'FAIL'} uncompensated alpha 1: mean {means['plain']:.4f}, the core's "
                  f"albedo gives {expected:.4f} (tolerance 3e-3)")
            failures += 0 if ok else 1
    return failures


LIGHT_SCENE = """#version 3.7;
global_settings {{ assumed_gamma 1.0 ambient_light 0 }}
camera {{ orthographic location <0, 0, -1> look_at 0 right x * 2 up y * 2 }}
light_source {{ <0.3, 0, -0.5> color rgb 0.2 physical_falloff }}
plane {{ -z, 0 pigment {{ rgb 1 }} finish {{ ambient 0 brdf {{ {brdf} samples 0 }} }} }}
"""

LIGHT_CASES = [
    # (POV-Ray brdf block, the same model for `facet brdf eval`)
    ("composite diffuse_reflectance 0.5 alpha 0.3",
     ["--model", "composite", "--diffuse_reflectance", "0.5", "--alpha", "0.3"]),
    ("ggx alpha 0.2 fresnel conductor", ["--model", "ggx", "--alpha", "0.2", "--fresnel", "conductor"]),
    ("beckmann alpha 0.4 fresnel schlick f0 rgb <0.9, 0.5, 0.2>",
     ["--model", "beckmann", "--alpha", "0.4", "--fresnel", "schlick", "--f0", "0.9,0.5,0.2"]),
    # A model unit's lobe: the bridge's diffuse part, its colour 1 under the white pigment (the
    # path velvet takes too; velvet reflects too little toward wo = normal to be seen here).
    ("oren_nayar sigma 0.8", ["--model", "oren_nayar", "--sigma", "0.8", "--reflectance", "1"]),
]


def cmd_light(facet, cli):
    """The glossy and diffuse lobes under a light against the core: a plane seen head-on
    (wo = normal) lit by a physical_falloff point light; every pixel of the centre row must be
    pi f(wo, wi) cos(theta_i) I / d^2 with f from `facet brdf eval` (the core), per channel,
    within 1e-4 (16-bit output: 1.5e-5 per step; float evaluation). Checks the frames, wo/wi conventions and the
    pi scale of the glossy lobe, which the Lambert test cannot see."""
    import json
    import math
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        for brdf, model in LIGHT_CASES:
            scene = os.path.join(tmp, "l.pov")
            write(scene, LIGHT_SCENE.format(brdf=brdf))
            out = os.path.join(tmp, "l.png")
            rc, err = render(facet, scene, out, 33, 33, ["File_Gamma=1.0", "+WT1"], cwd=tmp)
            check(rc == 0, f"render failed: {err[-1500:]}")
            w, h, ch, mx, rows = read_png(out)
            worst, peak = 0.0, 0.0
            for i in range(0, 33, 2):
                x = (i + 0.5) / 33 * 2 - 1
                lx, lz = 0.3 - x, -0.5           # light - point, the point is (x, 0, 0)
                d2 = lx * lx + lz * lz
                cos_i = 0.5 / math.sqrt(d2)
                theta = math.degrees(math.acos(cos_i))
                phi = 0.0 if lx >= 0 else 180.0
                proc = subprocess.run([cli, "brdf", "eval"] + model +
                                      ["--wi", f"{theta},{phi}", "--wo", "0,0", "--json"],
                                      stdout=subprocess.PIPE, check=True)
                f = json.loads(proc.stdout)["f"]
                for c in range(3):
                    expected = min(1.0, math.pi * f[c] * cos_i * 0.2 / d2)
                    got = rows[16][i * ch + c] / mx
                    worst = max(worst, abs(got - expected))
                    peak = max(peak, expected)
            ok = worst < 1e-4 and peak > 0.05
            print(f"{'ok  ' if ok else 'FAIL'} {brdf}: largest |pixel - pi f cos I / d^2| {worst:.2e} "
                  f"(tolerance 1e-4; brightest expected {peak:.3f})")
            failures += 0 if ok else 1
    return failures


THREADS_SCENE = """#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <0, 1.5, -4> look_at <0, 0.6, 0> }
light_source { <3, 5, -3> rgb 1 }
plane { y, 0 pigment { checker rgb 0.8 rgb 0.2 } finish { brdf { composite diffuse_reflectance 0.6 distribution ggx alpha 0.25 fresnel dielectric ior 1.5 samples 4 } } }
sphere { <0, 1, 0>, 1 finish { brdf { ggx alpha 0.15 fresnel conductor samples 8 } } }
sphere { <1.8, 0.5, -0.5>, 0.5 pigment { rgb <1, 0.3, 0.2> } finish { brdf { lambert } } }
"""


def cmd_threads(facet):
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "t.pov")
        write(scene, THREADS_SCENE)
        outs = []
        for opts in (["+WT1"], ["+WT2"], ["+WT2", "+A0.1", "+AM2", "+R2"], ["+WT1", "+A0.1", "+AM2", "+R2"]):
            out = os.path.join(tmp, f"t{len(outs)}.png")
            rc, err = render(facet, scene, out, 80, 60, opts, cwd=tmp)
            check(rc == 0, f"render failed: {err[-1500:]}")
            outs.append(read_png(out))
        d1, _ = compare(outs[0], outs[1])
        d2, _ = compare(outs[2], outs[3])
        ok = d1 == 0 and d2 == 0
        print(f"{'ok  ' if ok else 'FAIL'} +WT1 vs +WT2: {d1} samples differ; with AA: {d2}")
        return 0 if ok else 1


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    facet, cmd, args = os.path.abspath(sys.argv[1]), sys.argv[2], sys.argv[3:]
    check(os.access(facet, os.X_OK), f"{facet}: not built")
    commands = {
        "regress": lambda: cmd_regress(facet, args),
        "lambert": lambda: cmd_lambert(facet),
        "parse-errors": lambda: cmd_parse_errors(facet),
        "clash": lambda: cmd_clash(facet),
        "falloff": lambda: cmd_falloff(facet),
        "glossy": lambda: cmd_glossy(facet, os.path.abspath(args[0]) if args else None),
        "light": lambda: cmd_light(facet, os.path.abspath(args[0])),
        "models": lambda: cmd_models(facet, os.path.abspath(args[0])),
        "threads": lambda: cmd_threads(facet),
    }
    try:
        failures = commands[cmd]()
    except Failure as e:
        print(f"FAIL {e}")
        return 1
    print(f"{cmd}: {'FAILED ' + str(failures) if failures else 'passed'}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
