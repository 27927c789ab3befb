#!/usr/bin/env python3
"""Writes the generated scenes of scenes/ (run from anywhere: python3 scenes/tools/make_scenes.py).

The JSON files are committed; this script documents how the repetitive ones were laid out and
regenerates them after a format change. cornell_box.json's colours come from cornell_rgb.py.
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.dirname(HERE)


def write(name, scene):
    path = os.path.join(OUT, name)
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")
    print("wrote", path)


def header(description, camera, render):
    return {"format": "facet-scene", "version": 1, "description": description,
            "camera": camera, "render": render}


# --- Cornell box: Cornell's published geometry (mm) and camera ---------------------------------
def cornell():
    white = [0.7377, 0.7361, 0.7373]   # cornell_rgb.py
    green = [0.0879, 0.3984, 0.0844]
    red = [0.4718, 0.0469, 0.0489]
    light = [17.1969, 11.4748, 3.0609]
    q = lambda name, mat, v: {"type": "quad", "name": name, "material": mat, "vertices": v}
    shapes = [
        q("floor", "white", [[552.8, 0, 0], [0, 0, 0], [0, 0, 559.2], [549.6, 0, 559.2]]),
        q("ceiling", "white", [[556, 548.8, 0], [556, 548.8, 559.2], [0, 548.8, 559.2],
                               [0, 548.8, 0]]),
        q("back wall", "white", [[549.6, 0, 559.2], [0, 0, 559.2], [0, 548.8, 559.2],
                                 [556, 548.8, 559.2]]),
        q("right wall", "green", [[0, 0, 559.2], [0, 0, 0], [0, 548.8, 0], [0, 548.8, 559.2]]),
        q("left wall", "red", [[552.8, 0, 0], [549.6, 0, 559.2], [556, 548.8, 559.2],
                               [556, 548.8, 0]]),
        # Short block.
        q("short block top", "white", [[130, 165, 65], [82, 165, 225], [240, 165, 272],
                                       [290, 165, 114]]),
        q("short block", "white", [[290, 0, 114], [290, 165, 114], [240, 165, 272],
                                   [240, 0, 272]]),
        q("short block", "white", [[130, 0, 65], [130, 165, 65], [290, 165, 114],
                                   [290, 0, 114]]),
        q("short block", "white", [[82, 0, 225], [82, 165, 225], [130, 165, 65], [130, 0, 65]]),
        q("short block", "white", [[240, 0, 272], [240, 165, 272], [82, 165, 225],
                                   [82, 0, 225]]),
        # Tall block.
        q("tall block top", "white", [[423, 330, 247], [265, 330, 296], [314, 330, 456],
                                      [472, 330, 406]]),
        q("tall block", "white", [[423, 0, 247], [423, 330, 247], [472, 330, 406],
                                  [472, 0, 406]]),
        q("tall block", "white", [[472, 0, 406], [472, 330, 406], [314, 330, 456],
                                  [314, 0, 456]]),
        q("tall block", "white", [[314, 0, 456], [314, 330, 456], [265, 330, 296],
                                  [265, 0, 296]]),
        q("tall block", "white", [[265, 0, 296], [265, 330, 296], [423, 330, 247],
                                  [423, 0, 247]]),
        # The light: Cornell's rectangle, 0.1 mm below the ceiling so the two never coincide.
        {"type": "quad", "name": "light", "emission": light,
         "vertices": [[343, 548.7, 227], [343, 548.7, 332], [213, 548.7, 332],
                      [213, 548.7, 227]]},
    ]
    fov = 2 * math.degrees(math.atan(0.0125 / 0.035))  # 25 mm film, 35 mm focal length
    s = header("The Cornell box with Cornell's measured geometry (mm), camera and reflectances "
               "(spectra converted to linear sRGB by tools/cornell_rgb.py).",
               {"position": [278, 273, -800], "look_at": [278, 273, 0], "up": [0, 1, 0],
                "fov": round(fov, 6), "width": 512, "height": 512},
               {"integrator": "path", "spp": 64, "max_depth": 16, "seed": 1})
    s["materials"] = {"white": {"model": "lambert", "reflectance": white},
                      "green": {"model": "lambert", "reflectance": green},
                      "red": {"model": "lambert", "reflectance": red}}
    s["shapes"] = shapes
    s["lights"] = []
    write("cornell_box.json", s)


# --- White furnace: inside a closed, emitting, reflecting sphere L = Le / (1 - rho) -----------
def furnace():
    s = header("White furnace: the camera inside a closed sphere that emits Le = 0.5 and "
               "reflects rho = 0.8 (Lambert); every pixel converges to Le / (1 - rho) = 2.5. "
               "The sphere is turned inside out (flip_normals) so its normals and emission face in.",
               {"position": [0, 0, 0], "look_at": [0, 0, -1], "up": [0, 1, 0], "fov": 60,
                "width": 64, "height": 64},
               {"integrator": "path", "spp": 64, "max_depth": 1024, "seed": 1})
    s["shapes"] = [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                    "flip_normals": True, "emission": 0.5,
                    "material": {"model": "lambert", "reflectance": 0.8}}]
    s["lights"] = []
    write("furnace.json", s)


# --- Point light over a Lambertian plane (eq. 2.42) ------------------------------------------
def point_plane():
    s = header("A 100 W point light 2 m above an infinite Lambertian plane (rho = 0.5), seen "
               "from above: every pixel is rho/pi * Phi cos(theta) / (4 pi r^2) (Cohen & Wallace "
               "eq. 2.40 and 2.42); the direct integrator computes it exactly.",
               {"position": [0, 5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 60,
                "width": 128, "height": 96},
               {"integrator": "direct", "spp": 1, "max_depth": 1, "seed": 1})
    s["shapes"] = [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0],
                    "material": {"model": "lambert", "reflectance": 0.5}}]
    s["lights"] = [{"type": "point", "position": [0, 2, 0], "power": 100}]
    write("point_plane.json", s)


# --- Material sweep: distribution x roughness x anisotropy -----------------------------------
def material_sweep():
    dists = ["blinn", "beckmann", "ggx"]
    cols = [(0.05, 0.05), (0.15, 0.15), (0.3, 0.3), (0.6, 0.6), (0.05, 0.4), (0.4, 0.05)]
    shapes = [{"type": "plane", "point": [0, -0.5, 0], "normal": [0, 1, 0],
               "material": {"model": "lambert", "reflectance": 0.4}}]
    materials = {}
    for r, dist in enumerate(dists):
        for c, (au, av) in enumerate(cols):
            name = "%s_%d" % (dist, c)
            m = {"model": dist, "fresnel": "conductor"}
            if dist == "blinn":  # Blinn exponent matched to alpha: kappa = 2 / alpha^2 - 2
                ku, kv = (round(2 / a ** 2 - 2, 3) for a in (au, av))
                if au == av:
                    m["exponent"] = ku
                else:
                    m["exponent_u"], m["exponent_v"] = ku, kv
            elif au == av:
                m["alpha"] = au
            else:
                m["alpha_u"], m["alpha_v"] = au, av
            materials[name] = m
            # Local z of the sphere turned to world +y: the tangent (dpdu) runs around the
            # vertical axis, so anisotropic highlights stretch along latitude circles.
            shapes.append({"type": "sphere", "name": name, "center": [0, 0, 0], "radius": 0.45,
                           "material": name,
                           "transform": [{"rotate": {"axis": [1, 0, 0], "angle": -90}},
                                         {"translate": [(c - 2.5) * 1.1, 0, (r - 1) * 1.1]}]})
    shapes.append({"type": "quad", "name": "light", "emission": 12,
                   "vertices": [[-2, 5, -1], [2, 5, -1], [2, 5, 1], [-2, 5, 1]]})
    s = header("Each microfacet distribution (rows: blinn, beckmann, ggx) x roughness "
               "(alpha 0.05, 0.15, 0.3, 0.6) x anisotropy (alpha_u/alpha_v 0.05/0.4 and "
               "0.4/0.05) on exact spheres, conductor Fresnel (aluminium).",
               {"position": [0, 6, 6], "look_at": [0, -0.3, 0], "up": [0, 1, 0], "fov": 45,
                "width": 768, "height": 512},
               {"integrator": "path", "spp": 64, "max_depth": 8, "seed": 1})
    s["materials"] = materials
    s["shapes"] = shapes
    s["lights"] = [{"type": "environment", "radiance": 0.1}]
    write("material_sweep.json", s)


# --- Mirrors and Fresnel -----------------------------------------------------------------------
def mirrors_fresnel():
    materials = {
        "mirror_none": {"model": "mirror"},
        "mirror_glass": {"model": "mirror", "fresnel": "dielectric", "ior": 1.5},
        "mirror_aluminium": {"model": "mirror", "fresnel": "conductor"},
        "mirror_gold": {"model": "mirror", "fresnel": "conductor",
                        "eta": [0.143, 0.374, 1.442], "k": [3.983, 2.385, 1.603]},
        "mirror_schlick": {"model": "mirror", "fresnel": "schlick", "f0": 0.5},
        "plastic": {"model": "composite", "diffuse_reflectance": [0.6, 0.1, 0.1],
                    "glossy_reflectance": 0, "mirror_reflectance": 1,
                    "fresnel": "dielectric", "ior": 1.5},
        "tile_a": {"model": "lambert", "reflectance": 0.8},
        "tile_b": {"model": "lambert", "reflectance": 0.1},
    }
    shapes = []
    # An 8 x 8 checkerboard of quads on the floor, so reflections are easy to read.
    n, size = 8, 1.0
    for i in range(n):
        for j in range(n):
            x0, z0 = (i - n / 2) * size, (j - n / 2) * size
            shapes.append({"type": "quad", "material": "tile_a" if (i + j) % 2 == 0 else "tile_b",
                           "vertices": [[x0, 0, z0], [x0, 0, z0 + size],
                                        [x0 + size, 0, z0 + size], [x0 + size, 0, z0]]})
    names = ["mirror_none", "mirror_glass", "mirror_aluminium", "mirror_gold", "mirror_schlick",
             "plastic"]
    for k, name in enumerate(names):
        shapes.append({"type": "sphere", "name": name, "material": name, "radius": 0.45,
                       "center": [(k - 2.5) * 1.1, 0.45, 0]})
    # A flat mirror standing behind the spheres.
    shapes.append({"type": "quad", "name": "wall mirror", "material": "mirror_aluminium",
                   "vertices": [[-3.5, 0, -2], [3.5, 0, -2], [3.5, 2.5, -2], [-3.5, 2.5, -2]]})
    shapes.append({"type": "disc", "name": "light", "center": [0, 4, 2], "normal": [0, -1, -0.3],
                   "radius": 1, "emission": 10})
    s = header("Perfect mirrors with each Fresnel term (none, dielectric 1.5, aluminium, gold, "
               "Schlick f0 = 0.5) and a plastic (diffuse + Fresnel-weighted mirror) on a "
               "checkerboard, in front of a flat mirror.",
               {"position": [0, 2.2, 6], "look_at": [0, 0.5, 0], "up": [0, 1, 0], "fov": 45,
                "width": 768, "height": 432},
               {"integrator": "path", "spp": 64, "max_depth": 12, "seed": 1})
    s["materials"] = materials
    s["shapes"] = shapes
    s["lights"] = [{"type": "environment", "radiance": [0.15, 0.18, 0.25]}]
    write("mirrors_fresnel.json", s)


# --- >= 1M triangles, procedural -------------------------------------------------------------
def big_mesh():
    s = header("1,002,528 + 81,920 triangles with no mesh file: a 708 x 708 displaced grid "
               "(sin x sin y waves) and a 6-times subdivided icosphere.",
               {"position": [0, 3.5, 6], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 45,
                "width": 640, "height": 480},
               {"integrator": "path", "spp": 16, "max_depth": 6, "seed": 1})
    s["materials"] = {"ground": {"model": "lambert", "reflectance": [0.5, 0.45, 0.4]},
                      "metal": {"model": "ggx", "alpha": 0.2, "fresnel": "conductor"}}
    s["shapes"] = [
        {"type": "grid", "nx": 708, "ny": 708, "amplitude": 0.08, "frequency": 25,
         "material": "ground",
         "transform": [{"rotate": {"axis": [1, 0, 0], "angle": -90}}, {"scale": 5}]},
        {"type": "icosphere", "center": [0, 1, 0], "radius": 1, "subdivisions": 6,
         "material": "metal"},
        {"type": "quad", "name": "light", "emission": 8,
         "vertices": [[-1.5, 5, -1.5], [1.5, 5, -1.5], [1.5, 5, 1.5], [-1.5, 5, 1.5]]},
    ]
    s["lights"] = [{"type": "environment", "radiance": 0.05}]
    write("big_mesh.json", s)


# --- Benchmark scenes of bench/time_error.py: glossy and brushed metal under area lights -------
def _stage(floor, wall):
    """A floor and a back wall as quads (finite, so every renderer has the same geometry)."""
    return [
        {"type": "quad", "name": "floor", "material": floor,
         "vertices": [[-3, 0, 3], [3, 0, 3], [3, 0, -3], [-3, 0, -3]]},
        {"type": "quad", "name": "back wall", "material": wall,
         "vertices": [[-3, 0, -3], [3, 0, -3], [3, 4, -3], [-3, 4, -3]]},
    ]


def glossy():
    s = header("Rough conductors (GGX gold alpha 0.3, Beckmann copper alpha 0.15) and a "
               "dielectric-coated sphere (composite: red Lambert under a GGX alpha 0.1 coat, "
               "IOR 1.5) on a grey floor before a wall, under one area light (time_error "
               "benchmark).",
               {"position": [0, 1.6, 5.5], "look_at": [0, 0.6, 0], "up": [0, 1, 0], "fov": 36,
                "width": 256, "height": 256},
               {"integrator": "path", "spp": 64, "max_depth": 8, "seed": 1})
    s["materials"] = {
        "grey": {"model": "lambert", "reflectance": 0.5},
        "gold": {"model": "ggx", "alpha": 0.3, "fresnel": "conductor",
                 "eta": [0.143, 0.374, 1.442], "k": [3.983, 2.385, 1.603]},
        "copper": {"model": "beckmann", "alpha": 0.15, "fresnel": "conductor",
                   "eta": [0.200, 0.924, 1.102], "k": [3.912, 2.452, 2.142]},
        "coated": {"model": "composite", "diffuse_reflectance": [0.6, 0.08, 0.05],
                   "glossy_reflectance": 1, "distribution": "ggx", "alpha": 0.1,
                   "fresnel": "dielectric", "ior": 1.5},
    }
    s["shapes"] = _stage("grey", "grey") + [
        {"type": "sphere", "name": "gold", "center": [-1.25, 0.55, 0], "radius": 0.55,
         "material": "gold"},
        {"type": "sphere", "name": "coated", "center": [0, 0.55, 0.3], "radius": 0.55,
         "material": "coated"},
        {"type": "sphere", "name": "copper", "center": [1.25, 0.55, 0], "radius": 0.55,
         "material": "copper"},
        {"type": "quad", "name": "light", "emission": 12,
         "vertices": [[-0.6, 3.2, -0.4], [0.6, 3.2, -0.4], [0.6, 3.2, 0.8], [-0.6, 3.2, 0.8]]},
    ]
    s["lights"] = []
    write("glossy.json", s)


def brushed():
    s = header("Brushed metal: an anisotropic GGX aluminium floor (alpha_u 0.05 along x, "
               "alpha_v 0.3) and an anisotropic sphere brushed around its vertical axis "
               "(alpha_u 0.3 along the longitude, alpha_v 0.05) before a Lambert wall, under a "
               "long thin area light and a dim environment (time_error benchmark).",
               {"position": [0, 1.4, 5.0], "look_at": [0, 0.5, 0], "up": [0, 1, 0], "fov": 38,
                "width": 256, "height": 256},
               {"integrator": "path", "spp": 64, "max_depth": 8, "seed": 1})
    s["materials"] = {
        "wall": {"model": "lambert", "reflectance": [0.6, 0.6, 0.55]},
        "brushed floor": {"model": "ggx", "alpha_u": 0.05, "alpha_v": 0.3,
                          "fresnel": "conductor"},
        "brushed sphere": {"model": "ggx", "alpha_u": 0.3, "alpha_v": 0.05,
                           "fresnel": "conductor"},
    }
    s["shapes"] = _stage("brushed floor", "wall") + [
        # Local z turned to world +y: the longitude (the tangent) runs around the vertical.
        {"type": "sphere", "name": "brushed sphere", "center": [0, 0, 0], "radius": 0.6,
         "material": "brushed sphere",
         "transform": [{"rotate": {"axis": [1, 0, 0], "angle": -90}},
                       {"translate": [0.2, 0.6, 0]}]},
        {"type": "quad", "name": "light", "emission": 15,
         "vertices": [[-1.8, 3.0, -1.0], [1.8, 3.0, -1.0], [1.8, 3.0, -0.6], [-1.8, 3.0, -0.6]]},
    ]
    s["lights"] = [{"type": "environment", "radiance": 0.1}]
    write("brushed.json", s)


# --- The README's showcase ----------------------------------------------------------------------
def showcase():
    s = header("Glossy, mirror and diffuse spheres on a plane under an area light: the README's "
               "showcase image.",
               {"position": [0, 1.8, 6.5], "look_at": [0, 0.55, 0], "up": [0, 1, 0], "fov": 36,
                "width": 960, "height": 540},
               {"integrator": "path", "spp": 256, "max_depth": 12, "seed": 7})
    s["materials"] = {
        "floor": {"model": "lambert", "reflectance": 0.45},
        "gold": {"model": "ggx", "alpha": 0.15, "fresnel": "conductor",
                 "eta": [0.143, 0.374, 1.442], "k": [3.983, 2.385, 1.603]},
        "chrome": {"model": "mirror", "fresnel": "conductor",
                   "eta": [3.1, 3.1, 2.3], "k": [3.3, 3.3, 3.1]},
        "clay": {"model": "lambert", "reflectance": [0.7, 0.25, 0.15]},
        "plastic": {"model": "composite", "diffuse_reflectance": [0.1, 0.3, 0.7],
                    "glossy_reflectance": 1, "distribution": "ggx", "alpha": 0.08,
                    "fresnel": "dielectric", "ior": 1.5},
        "brushed": {"model": "ggx", "alpha_u": 0.05, "alpha_v": 0.35, "fresnel": "conductor"},
    }
    s["shapes"] = [
        {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"},
        {"type": "sphere", "name": "clay", "center": [-2.3, 0.5, -0.6], "radius": 0.5,
         "material": "clay"},
        {"type": "sphere", "name": "gold", "center": [-0.9, 0.6, 0.2], "radius": 0.6,
         "material": "gold"},
        {"type": "sphere", "name": "chrome", "center": [0.45, 0.7, -0.4], "radius": 0.7,
         "material": "chrome"},
        {"type": "sphere", "name": "plastic", "center": [1.65, 0.5, 0.3], "radius": 0.5,
         "material": "plastic"},
        # Local z turned to world +y first, then moved: the brushing runs around the vertical.
        {"type": "sphere", "name": "brushed", "center": [0, 0, 0], "radius": 0.45,
         "material": "brushed",
         "transform": [{"rotate": {"axis": [1, 0, 0], "angle": -90}},
                       {"translate": [2.75, 0.45, -0.9]}]},
        {"type": "quad", "name": "softbox", "emission": [9, 8.6, 8],
         "vertices": [[-1.5, 4, -1], [1.5, 4, -1], [1.5, 4, 1.5], [-1.5, 4, 1.5]]},
    ]
    s["lights"] = [{"type": "environment", "radiance": [0.12, 0.15, 0.22]}]
    write("showcase.json", s)


# --- glass: issue 25's glass benchmark (bench/time_error.py) -------------------------------------
def glass():
    s = header("A smooth and a rough (alpha 0.15) glass sphere, ior 1.5, over a checker disc under "
               "Blender's studio HDRI (CC0): issue 25's glass benchmark scene (bench/time_error.py).",
               {"position": [3.2, -4.0, 2.4], "look_at": [0, 0, 0.4], "up": [0, 0, 1], "fov": 35,
                "width": 192, "height": 128},
               {"integrator": "path", "spp": 16, "max_depth": 16, "seed": 1})
    s["materials"] = {
        "floor": {"model": "lambert", "reflectance": {
            "checker": {"colors": [[0.6, 0.6, 0.6], [0.2, 0.2, 0.25]], "scale": 4}}},
        "smooth": {"model": "dielectric", "ior": 1.5},
        "rough": {"model": "dielectric", "ior": 1.5, "alpha": 0.15},
    }
    s["lights"] = [{"type": "environment",
                    "file": "/usr/share/blender/datafiles/studiolights/world/studio.exr",
                    "radiance": 1}]
    s["shapes"] = [
        {"type": "sphere", "center": [-0.8, 0.6, 0.2], "radius": 0.7, "material": "smooth"},
        {"type": "sphere", "center": [0.9, -0.4, 0.2], "radius": 0.7, "material": "rough"},
        {"type": "disc", "center": [0, 0, -0.5], "normal": [0, 0, 1], "radius": 6,
         "material": "floor"},
    ]
    write("glass.json", s)


if __name__ == "__main__":
    cornell()
    furnace()
    point_plane()
    material_sweep()
    mirrors_fresnel()
    big_mesh()
    showcase()
    glossy()
    brushed()
    glass()
