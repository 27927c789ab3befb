#!/usr/bin/python3
"""Textured against untextured materials (issue 25, the staged material build): writes the
benchmark scenes and times each textured scene against its untextured twin in one run.

  /usr/bin/python3 bench/staged_bench.py [--out DIR] [--facet build/core/cli/facet] [--runs 5]

Scenes (written to --out, default out/bench/staged; the glTF asset is Debian's
assimp-testmodels BoxTextured, copied there and given a metallic-roughness texture):
- box_mr: BoxTextured on a grey ground plane under Blender's studio.exr HDRI
  (/usr/share/blender/datafiles/studiolights/world/; negative texels clamped, hdri()), its baseColor texture also used as the
  metallicRoughness texture (G = roughness, B = metallic), factors 1: every hit on the box has
  textured diffuse reflectance, roughness and F0 (composite through gltf_composite_params).
- box_plain: the same box with constant factors (base colour 0.5, metallic 0.5, roughness 0.5).
- rough_tex: a composite sphere (diffuse + GGX, fresnel dielectric) whose alpha is a checker
  (0.05 / 0.5, 8 cells per uv unit) over a checker-coloured plane, under the same HDRI.
- rough_const: the same with alpha 0.275 constant.
- textured_asset: Debian's ClearCoatTest.gltf (metallic-roughness, base colour, normal and
  emissive textures, alpha) on a ground plane under the HDRI (issue 25's textured-asset scene).
- glass: a smooth and a rough (alpha 0.15) dielectric sphere (ior 1.5) over the checker floor,
  under the HDRI, max_depth 16 (issue 25's glass scene).
- ec_tex / ec_const: rough_tex / rough_const with the sphere a GGX lobe with energy
  compensation and Schlick f0 (0.9, 0.6, 0.3), its alpha the checker / 0.275.
- <model>_tex / <model>_const for principled_hair, translucent, velvet, mix and subsurface (the
  two-stage units, staged through ModelInfo::make): rough_const with the sphere that model,
  some parameters checkers (8 cells per uv unit) / the checkers' means.
With --callgrind, the render phase's instructions of each pair instead (callgrind_table).
Each pair is timed with farm-bench (median of --runs, the ratio pair by pair), 1 thread.
Prints markdown.
"""
import argparse
import json
import os
import shutil
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BOX = "/usr/share/assimp/models/glTF2/BoxTextured-glTF"
STUDIO = "/usr/share/blender/datafiles/studiolights/world/studio.exr"
HDRI = "studio_clamped.exr"  # written by write_scenes (see hdri())


def hdri(out):
    """Blender's studio lights carry tiny negative texels (-3e-6, lossy DWAB compression), which
    Facet rejects as light: a copy with them clamped to 0, stored losslessly (oiiotool)."""
    subprocess.run(["oiiotool", STUDIO, "--clamp:min=0", "-d", "float", "--compression", "zip",
                    "-o", os.path.join(out, HDRI)], check=True)


def box_gltf(out, textured):
    with open(os.path.join(BOX, "BoxTextured.gltf")) as f:
        g = json.load(f)
    if textured:
        g["materials"] = [{"name": "TexturedMR", "pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 0},
            "metallicFactor": 1.0, "roughnessFactor": 1.0}}]
    else:
        g["materials"] = [{"name": "Plain", "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.5,
            "roughnessFactor": 0.5}}]
        g.pop("textures", None), g.pop("images", None), g.pop("samplers", None)
    name = "box_mr.gltf" if textured else "box_plain.gltf"
    with open(os.path.join(out, name), "w") as f:
        json.dump(g, f, indent=1)
    return name


def scene(shapes, materials, size=(256, 192), spp=16):
    return {
        "format": "facet-scene", "version": 1,
        "camera": {"position": [3.2, -4.0, 2.4], "look_at": [0, 0, 0.4], "up": [0, 0, 1],
                   "fov": 35, "width": size[0], "height": size[1]},
        "render": {"integrator": "path", "spp": spp, "max_depth": 8, "seed": 1},
        "materials": materials,
        "lights": [{"type": "environment", "file": HDRI, "radiance": 1}],
        "shapes": shapes,
    }


def write_scenes(out):
    os.makedirs(out, exist_ok=True)
    hdri(out)
    for f in ("BoxTextured0.bin", "CesiumLogoFlat.png"):
        shutil.copy(os.path.join(BOX, f), out)
    ground = {"type": "plane", "point": [0, 0, -0.5], "normal": [0, 0, 1], "material": "ground"}
    mats = {"ground": {"model": "lambert", "reflectance": 0.5}}
    files = {}
    for key, textured in (("box_mr", True), ("box_plain", False)):
        s = scene([ground, {"type": "gltf", "file": box_gltf(out, textured)}], mats)
        files[key] = os.path.join(out, key + ".json")
        with open(files[key], "w") as f:
            json.dump(s, f, indent=1)
    floor = {"model": "lambert", "reflectance": {
        "checker": {"colors": [[0.6, 0.6, 0.6], [0.2, 0.2, 0.25]], "scale": 4}}}
    for key, alpha in (("rough_tex", {"checker": {"colors": [0.05, 0.5], "scale": 8}}),
                       ("rough_const", 0.275)):
        m = {"floor": floor, "ball": {"model": "composite", "diffuse_reflectance": [0.6, 0.2, 0.1],
                                      "alpha": alpha}}
        s = scene([{"type": "sphere", "center": [0, 0, 0.5], "radius": 1, "material": "ball"},
                   {"type": "disc", "center": [0, 0, -0.5], "normal": [0, 0, 1], "radius": 6,
                    "material": "floor"}], m)
        files[key] = os.path.join(out, key + ".json")
        with open(files[key], "w") as f:
            json.dump(s, f, indent=1)
    # Issue 25's two new benchmark scenes (Facet side; see docs/performance.md for the Cycles
    # side): a textured glTF asset under the HDRI, and glass.
    clear = "/usr/share/assimp/models/glTF2/ClearCoat-glTF/ClearCoatTest.gltf"
    s = scene([{"type": "plane", "point": [0, 0, -2.6], "normal": [0, 0, 1], "material": "ground"},
               {"type": "gltf", "file": clear}], mats, size=(192, 128))
    s["camera"].update(position=[0, -16, 1.5], look_at=[0, 0, 0], fov=40)
    files["textured_asset"] = os.path.join(out, "textured_asset.json")
    with open(files["textured_asset"], "w") as f:
        json.dump(s, f, indent=1)
    glass = {"floor": floor,
             "smooth": {"model": "dielectric", "ior": 1.5},
             "rough": {"model": "dielectric", "ior": 1.5, "alpha": 0.15}}
    s = scene([{"type": "sphere", "center": [-0.8, 0.6, 0.2], "radius": 0.7, "material": "smooth"},
               {"type": "sphere", "center": [0.9, -0.4, 0.2], "radius": 0.7, "material": "rough"},
               {"type": "disc", "center": [0, 0, -0.5], "normal": [0, 0, 1], "radius": 6,
                "material": "floor"}], glass, size=(192, 128))
    s["render"]["max_depth"] = 16
    files["glass"] = os.path.join(out, "glass.json")
    with open(files["glass"], "w") as f:
        json.dump(s, f, indent=1)
    # The compensated GGX pair: checker alpha against its constant twin.
    for key, alpha in (("ec_tex", {"checker": {"colors": [0.05, 0.5], "scale": 8}}),
                       ("ec_const", 0.275)):
        with open(files["rough_const"]) as f:
            s = json.load(f)
        s["materials"]["ball"] = {"model": "ggx", "alpha": alpha, "energy_compensation": True,
                                  "fresnel": "schlick", "f0": [0.9, 0.6, 0.3]}
        files[key] = os.path.join(out, key + ".json")
        with open(files[key], "w") as f:
            json.dump(s, f, indent=1)
    # The two-stage model units (ModelInfo::make): the ball textured by checkers against its
    # constant twin (the checkers' mean).
    def checker(a, b):
        return {"checker": {"colors": [a, b], "scale": 8}}
    units = {
        "principled_hair": ({"color": checker([0.3, 0.2, 0.1], [0.6, 0.5, 0.3]),
                             "roughness": checker(0.2, 0.5)},
                            {"color": [0.45, 0.35, 0.2], "roughness": 0.35}),
        "translucent": ({"transmittance": checker([0.3, 0.5, 0.7], [0.8, 0.6, 0.2])},
                        {"transmittance": [0.55, 0.55, 0.45]}),
        "velvet": ({"reflectance": checker([0.3, 0.5, 0.7], [0.8, 0.6, 0.2]),
                    "sigma": checker(0.3, 0.8)},
                   {"reflectance": [0.55, 0.55, 0.45], "sigma": 0.55}),
        "mix": ({"weight": checker(0.2, 0.8)}, {"weight": 0.5}),
        "subsurface": ({"color": checker([0.3, 0.5, 0.7], [0.8, 0.6, 0.2])},
                       {"color": [0.55, 0.55, 0.45]}),
    }
    fixed = {"mix": {"materials": [{"model": "lambert", "reflectance": 0.6},
                                   {"model": "ggx", "alpha": 0.3}]},
             "subsurface": {"radius": [0.3, 0.1, 0.05]}}
    for model, (tex, const) in units.items():
        for key, params in ((model + "_tex", tex), (model + "_const", const)):
            with open(files["rough_const"]) as f:
                s = json.load(f)
            s["materials"]["ball"] = {"model": model, **fixed.get(model, {}), **params}
            files[key] = os.path.join(out, key + ".json")
            with open(files[key], "w") as f:
                json.dump(s, f, indent=1)
    return files


PAIRS = (("box_mr", "box_plain"), ("rough_tex", "rough_const"), ("ec_tex", "ec_const"),
         ("principled_hair_tex", "principled_hair_const"), ("translucent_tex", "translucent_const"),
         ("velvet_tex", "velvet_const"), ("mix_tex", "mix_const"),
         ("subsurface_tex", "subsurface_const"))


def callgrind_table(a, files):
    """Instructions in render_tile (callgrind --toggle-collect, 1 thread, 2 spp, a 32 x 32
    region on the sphere or box) of each textured scene over its untextured twin, each with the
    HDRI replaced by a constant environment (valgrind 3.19 stops on RDTSCP in libhwy, which
    OpenImageIO's plugins load)."""
    def count(key):
        with open(files[key]) as f:
            s = json.load(f)
        s["lights"] = [{"type": "environment", "radiance": 1}]
        path = os.path.join(a.out, key + "_const_env.json")
        with open(path, "w") as f:
            json.dump(s, f, indent=1)
        out = os.path.join(a.out, key + ".callgrind")
        subprocess.run(["valgrind", "--tool=callgrind", "--toggle-collect=*render_tile*",
                        "--callgrind-out-file=" + out, a.facet, "render", path, "--spp", "2",
                        "--threads", "1", "--region", "112,72,144,104", "-o",
                        os.path.join(a.out, key + "_cg.exr")],
                       check=True, capture_output=True)
        with open(out) as f:
            for line in f:
                if line.startswith("summary:") or line.startswith("totals:"):
                    return int(line.split()[1])
        raise RuntimeError("no totals in " + out)
    print("| textured | untextured | render_tile instructions | ratio |")
    print("|---|---|---:|---:|")
    for tex, plain in PAIRS:
        t, p = count(tex), count(plain)
        print("| %s | %s | %.2f M / %.2f M | **%.2f** |" % (tex, plain, t / 1e6, p / 1e6, t / p))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench", "staged"))
    ap.add_argument("--facet", default=os.path.join(ROOT, "build", "core", "cli", "facet"))
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--write-only", action="store_true", help="only write the scenes")
    ap.add_argument("--callgrind", action="store_true",
                    help="instruction counts of the render phase instead of timings")
    a = ap.parse_args()
    files = write_scenes(a.out)
    if a.write_only:
        print("\n".join(files.values()))
        return
    if a.callgrind:
        callgrind_table(a, files)
        return
    print("| textured | untextured | farm-bench output (A = textured, B = untextured) |")
    print("|---|---|---|")
    for tex, plain in PAIRS:
        cmd = lambda k: [a.facet, "render", files[k], "--spp", str(a.spp), "--threads", "1",
                         "-o", os.path.join(a.out, k + ".exr")]
        r = subprocess.run(["farm-bench", "-n", str(a.runs), "--timeout", "1200", "--vs",
                            " ".join(cmd(plain)), "--"] + cmd(tex),
                           capture_output=True, text=True)
        print("| %s | %s | %s |" % (tex, plain, " / ".join(
            l.strip() for l in r.stdout.splitlines() if "ratio" in l or "cpu" in l)))


if __name__ == "__main__":
    main()
