#!/usr/bin/python3
"""Pictures of each analytic shape's UV convention (scenes/FORMAT.md, "UV coordinates").

    /usr/bin/python3 tools/uv_pictures.py [--facet build/core/cli/facet] [--out docs/figures]

Writes uv_grid.png (the texture: red grows with u, green with v, a line every 1/8, a white
square at uv (0, 0) and an "F" in the first cell, which reads mirrored if the convention were
mirrored) and uv_<kind>.png for quad, box, grid (uv_grid_shape.png), sphere, icosphere, disc
and plane: each shape with the texture as the reflectance of a Lambertian material under a
constant environment of radiance 1 (max_depth 1: each pixel is the texture's value, no shading),
rendered through `facet render`. The camera looks at the
flat shapes from the +z side, x to the right, y up; the box from (2.2, 1.6, 3), so that three
faces show. The spheres are turned so that their local +z pole points up (world +y; local +y
becomes world -z) and seen from (2.6, 1, -2.6), longitude 45 degrees: v grows upward, u grows
counter-clockwise seen from above the +z pole, from the seam at the local +x meridian (left of
the centre) toward local +y.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image, ImageDraw

SIZE = 512  # texture side in texels


def uv_grid_image():
    """The UV grid texture as 8-bit sRGB (row 0 the top: v = 1)."""
    n = SIZE
    u = (np.arange(n) + 0.5) / n
    v = 1 - (np.arange(n) + 0.5) / n
    img = np.zeros((n, n, 3), dtype=np.float64)
    img[:, :, 0] = 0.15 + 0.85 * u[None, :]
    img[:, :, 1] = 0.15 + 0.85 * v[:, None]
    img[:, :, 2] = 0.25
    rgb = (np.clip(img, 0, 1) * 255).astype(np.uint8)
    pic = Image.fromarray(rgb, "RGB")
    d = ImageDraw.Draw(pic)
    for k in range(9):  # grid lines every 1/8
        x = min(n - 1, k * n // 8)
        d.line([(x, 0), (x, n - 1)], fill=(20, 20, 20), width=3)
        d.line([(0, x), (n - 1, x)], fill=(20, 20, 20), width=3)
    # The origin corner (u = 0, v = 0 is the bottom-left of the picture): a white square, and
    # an "F" in the first cell, drawn with lines (no font needed).
    d.rectangle([0, n - 24, 24, n - 1], fill=(255, 255, 255))
    c = n // 8
    x0, y0 = int(0.35 * c), n - int(0.2 * c)  # bottom of the F's stem
    d.line([(x0, y0), (x0, y0 - int(0.6 * c))], fill=(255, 255, 255), width=7)
    d.line([(x0, y0 - int(0.6 * c)), (x0 + int(0.4 * c), y0 - int(0.6 * c))],
           fill=(255, 255, 255), width=7)
    d.line([(x0, y0 - int(0.3 * c)), (x0 + int(0.3 * c), y0 - int(0.3 * c))],
           fill=(255, 255, 255), width=7)
    return pic


def shapes():
    """(name, shape JSON without material/emission, camera JSON)."""
    front = {"position": [0, 0, 4], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 40,
             "width": 256, "height": 256}
    oblique = {"position": [2.2, 1.6, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 40,
               "width": 256, "height": 256}
    # The spheres from longitude 45 degrees (u = 0.125, half-way between local +x and local +y)
    # and a little above the equator: the seam u = 0 (local +x) is left of the centre.
    globe = dict(oblique, position=[2.6, 1.0, -2.6])
    return [
        ("quad", {"type": "quad", "vertices": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]},
         front),
        ("box", {"type": "box", "min": [-0.8, -0.8, -0.8], "max": [0.8, 0.8, 0.8]}, oblique),
        ("grid", {"type": "grid", "nx": 16, "ny": 16}, front),
        ("sphere", {"type": "sphere", "center": [0, 0, 0], "radius": 1.1,
                    "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}}, globe),
        ("icosphere", {"type": "icosphere", "center": [0, 0, 0], "radius": 1.1,
                       "subdivisions": 4,
                       "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}}, globe),
        ("disc", {"type": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.2},
         front),
        ("plane", {"type": "plane", "point": [-1, -1, 0], "normal": [0, 0, 1]}, front),
    ]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--facet", default="build/core/cli/facet")
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--spp", type=int, default=16)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    grid = uv_grid_image()
    grid.save(os.path.join(args.out, "uv_grid.png"))
    with tempfile.TemporaryDirectory() as tmp:
        grid.save(os.path.join(tmp, "uv_grid.png"))
        for name, shape, camera in shapes():
            shape = dict(shape)
            # The plane's uv is in scene units: one texture repeat per 2 units.
            tex = {"texture": "uv_grid.png"}
            if name == "plane":
                tex["uv_scale"] = [0.5, 0.5]
            # A Lambertian reflectance texture under a constant environment of radiance 1 with
            # max_depth 1: every sample returns the texel's reflectance (cosine sampling), so
            # the picture is the texture as the shape maps it, without shading.
            shape["material"] = {"model": "lambert", "reflectance": tex}
            scene = {"format": "facet-scene", "version": 1, "camera": camera,
                     "shapes": [shape], "lights": [{"type": "environment", "radiance": 1}],
                     "render": {"max_depth": 1, "spp": args.spp, "integrator": "path"}}
            path = os.path.join(tmp, name + ".json")
            with open(path, "w") as f:
                json.dump(scene, f)
            # "uv_grid.png" is the texture itself: the grid shape is uv_grid_shape.png.
            out = os.path.join(args.out,
                               "uv_grid_shape.png" if name == "grid" else f"uv_{name}.png")
            subprocess.run([args.facet, "render", path, "--quiet", "-o", out], check=True)
            print(out)


if __name__ == "__main__":
    sys.exit(main())
