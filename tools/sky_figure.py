#!/usr/bin/python3
"""Draws docs/img/sky_nishita.png: Cycles 3.4 and Facet side by side on the Nishita Sky Texture
scenes of the test blender.cycles_sky (tests/blender/test_cycles_sky.py): the four skies' wide
views, the setting sun's disc and the lit ground and sphere, each pair exposed alike (the row's
Cycles image's 99th luminance percentile maps to 1) and sRGB-encoded.

Run from the repository root after the test (its images are in build/tests/blender/out):
    PYTHONPATH=build/core/python /usr/bin/python3 tools/sky_figure.py build/tests/blender/out
"""
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import facet  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

ROWS = [("default_wide", "default sky"), ("low_wide", "low sun, dust 3, 2 km"),
        ("high_wide", "high sun, air 0.5, ozone 4, 20 km"),
        ("setting_wide", "setting sun (no disc: Mapping)"),
        ("setting_sun", "setting sun's disc, 3° view"), ("lit", "ground and sphere, direct light")]


def srgb(img, scale):
    x = np.clip(img[..., :3] * scale, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def main(out_dir, png):
    fig, axes = plt.subplots(len(ROWS), 2, figsize=(6.4, 2.2 * len(ROWS)), dpi=100)
    for r, (name, title) in enumerate(ROWS):
        cyc = np.asarray(facet.read_image(os.path.join(out_dir, "sky_%s_cycles1.exr" % name)))
        fac = np.asarray(facet.read_image(os.path.join(out_dir, "sky_%s_facet.exr" % name)))
        lum = cyc[..., 0] * 0.2126 + cyc[..., 1] * 0.7152 + cyc[..., 2] * 0.0722
        scale = 1.0 / max(float(np.percentile(lum, 99)), 1e-12)
        for c, (img, who) in enumerate(((cyc, "Cycles 3.4"), (fac, "Facet"))):
            ax = axes[r][c]
            ax.imshow(srgb(img, scale), interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            ax.set_title("%s: %s" % (who, title), fontsize=7)
    fig.tight_layout()
    fig.savefig(png)
    print("wrote", png)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "build/tests/blender/out",
         sys.argv[2] if len(sys.argv) > 2 else "docs/img/sky_nishita.png")
