"""A shipped scene (scenes/<name>.json) built at `width` pixels wide, its aspect kept: the
loader of the benchmark scripts that render scenes smaller than they ship (denoise_bench.py,
adaptive_bench.py)."""
import pathlib

import facet

ROOT = pathlib.Path(__file__).resolve().parents[1]


def load(name, width):
    desc = facet.read_scene_description(str(ROOT / "scenes" / f"{name}.json"))
    cam = desc.camera
    height = max(1, round(width * cam.height / cam.width))
    cam.width, cam.height = width, height
    desc.camera = cam
    return facet.build_scene(desc, name=name)
