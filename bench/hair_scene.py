#!/usr/bin/env python3
"""Writes a small hair scene (docs/curves.md, "What scenes without curves pay", and the
per-strand random): a diffuse sphere with N Catmull-Rom strands along its normals, a Principled
Hair material (melanin), a sun, 64 x 48.

    /usr/bin/python3 bench/hair_scene.py out.json [--strands 400] [--random]

--random gives the material random_roughness and random_color 1 with each strand's random
value (a hair_info texture); without it the material has no random inputs."""
import argparse
import json
import math


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--strands", type=int, default=400)
    ap.add_argument("--random", action="store_true")
    a = ap.parse_args()
    points, counts = [], []
    golden = math.pi * (3.0 - math.sqrt(5.0))
    for i in range(a.strands):
        z = 1.0 - 2.0 * (i + 0.5) / a.strands
        r = math.sqrt(1.0 - z * z)
        n = (r * math.cos(golden * i), r * math.sin(golden * i), z)
        keys = [tuple(c * (1.0 + 0.1 * k) + 0.03 * k * k * (0.0, 0.0, -1.0)[j]
                      for j, c in enumerate(n)) for k in range(5)]
        keys = [keys[0]] + keys + [keys[-1]]
        points += [c for p in keys for c in p]
        counts.append(len(keys))
    hair = {"model": "principled_hair", "parametrization": "melanin", "melanin": 0.5,
            "roughness": 0.4, "radial_roughness": 0.4}
    if a.random:
        hair.update({"random_roughness": 1.0, "random_color": 1.0,
                     "random": {"hair_info": {"output": "random"}}})
    scene = {
        "format": "facet-scene", "version": 1,
        "camera": {"position": [0, -4.5, 0.5], "look_at": [0, 0, 0], "up": [0, 0, 1],
                   "fov": 40, "width": 64, "height": 48},
        "render": {"integrator": "path", "spp": 16, "max_depth": 4, "seed": 1},
        "materials": {"hair": hair, "grey": {"model": "lambert", "reflectance": 0.5}},
        "lights": [{"type": "directional", "direction": [-0.3, 0.6, -1], "irradiance": 3}],
        "shapes": [
            {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "grey"},
            {"type": "curves", "material": "hair", "basis": "catmull_rom", "points": points,
             "counts": counts, "radius": 0.02},
        ],
    }
    with open(a.out, "w") as f:
        json.dump(scene, f)


if __name__ == "__main__":
    main()
