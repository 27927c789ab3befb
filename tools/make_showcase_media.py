#!/usr/bin/python3
"""Writes scenes/showcase_media.json, the second showcase: what the first has none of. A jade
Wuson figurine (Debian's assimp-testmodels, `WusonOBJ.obj`) in random-walk subsurface scattering,
a glass of red juice (a dielectric sphere with an absorbing interior), a furry ball (round
Catmull-Rom strands with Cycles' Principled Hair BSDF, melanin and per-strand randomness) under
a spot lamp, on a grey floor under Blender's *studio* HDRI, dimmed. Deterministic (a fixed hash, no RNG state): running it again
gives the same bytes. Usage: tools/make_showcase_media.py [OUTPUT]"""
import json
import math
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STRANDS = 1200       # hairs on the ball
KEYS = 5             # control points per hair (ends repeated for Catmull-Rom: 7)
BALL = (1.55, 0.42, 0.55)
BALL_R = 0.32
HAIR_LEN = 0.16


def unit(i, k):
    """A fixed value in [0, 1) per (i, k) (an integer hash, so no RNG state)."""
    h = (i * 2654435761 + k * 40503 + 0x9E3779B9) & 0xFFFFFFFF
    h ^= h >> 16
    h = (h * 0x45D9F3B) & 0xFFFFFFFF
    h ^= h >> 16
    return h / 2.0 ** 32


def fur():
    """Strands from a Fibonacci lattice of roots on the ball, each curling a little downward."""
    points, counts = [], []
    golden = math.pi * (3.0 - math.sqrt(5.0))
    for i in range(STRANDS):
        y = 1.0 - 2.0 * (i + 0.5) / STRANDS
        r = math.sqrt(1.0 - y * y)
        a = golden * i
        n = (r * math.cos(a), y, r * math.sin(a))
        if n[1] < -0.55:  # none under the ball, where it rests on the floor
            continue
        length = HAIR_LEN * (0.8 + 0.4 * unit(i, 1))
        keys = []
        for k in range(KEYS):
            t = k / (KEYS - 1)
            droop = 0.35 * t * t * length
            wob = 0.02 * math.sin(6.0 * t + 6.28 * unit(i, 2))
            keys.append([BALL[0] + n[0] * (BALL_R + t * length) + wob,
                         BALL[1] + n[1] * (BALL_R + t * length) - droop,
                         BALL[2] + n[2] * (BALL_R + t * length) - wob])
        keys = [keys[0]] + keys + [keys[-1]]  # Catmull-Rom reaches its ends
        points += [round(v, 5) for p in keys for v in p]
        counts.append(len(keys))
    return points, counts


def scene():
    points, counts = fur()
    return {
        "format": "facet-scene",
        "version": 1,
        "description": "The second showcase (tools/make_showcase_media.py): subsurface "
                       "scattering, an absorbing liquid in glass and hair.",
        "camera": {"position": [0.2, 1.35, 5.4], "look_at": [0.15, 0.55, 0], "up": [0, 1, 0],
                   "fov": 36, "width": 640, "height": 360},
        "media": {
            "juice": {"kind": "homogeneous", "sigma_a": [0.4, 3.0, 4.0]},
        },
        "materials": {
            "floor": {"model": "lambert", "reflectance": 0.45},
            "jade": {"model": "principled", "base_color": [0.35, 0.75, 0.45],
                     "subsurface": 1, "subsurface_color": [0.35, 0.8, 0.45],
                     "subsurface_radius": [0.08, 0.25, 0.12], "roughness": 0.25},
            "glass": {"model": "dielectric", "ior": 1.33, "interior": "juice"},
            "fur": {"model": "principled_hair", "parametrization": "melanin", "melanin": 0.35,
                    "roughness": 0.3, "random_color": 0.5, "random_roughness": 0.3,
                    "random": {"hair_info": {}}},
            "ball": {"model": "lambert", "reflectance": [0.5, 0.35, 0.2]},
        },
        "shapes": [
            {"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0],
             "material": "floor"},
            {"type": "mesh", "name": "Wuson", "file": "/usr/share/assimp/models/OBJ/WusonOBJ.obj",
             "material": "jade",
             "transform": [{"rotate": {"axis": [0, 1, 0], "angle": 215}}, {"scale": 0.62},
                           {"translate": [0.05, 0.0005, 0.1]}]},
            {"type": "sphere", "name": "juice", "center": [-0.55, 0.36, 1.0], "radius": 0.36,
             "material": "glass"},
            {"type": "sphere", "name": "ball", "center": list(BALL), "radius": BALL_R,
             "material": "ball"},
            {"type": "curves", "name": "fur", "material": "fur", "basis": "catmull_rom",
             "profile": "round", "points": points, "counts": counts,
             "radius": 0.004},
        ],
        "lights": [
            {"type": "spot", "position": [-1.9, 2.6, -0.8], "look_at": [-1.5, 0.0, -0.4],
             "power": 20, "outer_angle": 30, "inner_angle": 22},
            {"type": "point", "position": [2.5, 3.0, 3.0], "power": 90},
            {"type": "environment",
             "file": "/usr/share/blender/datafiles/studiolights/world/studio.exr",
             "radiance": 0.25},
        ],
        "render": {"integrator": "path", "spp": 128, "max_depth": 12, "seed": 1},
    }


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "scenes",
                                                              "showcase_media.json")
    with open(out, "w") as f:
        json.dump(scene(), f, separators=(",", ":"))
        f.write("\n")


if __name__ == "__main__":
    main()
