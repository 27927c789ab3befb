#!/usr/bin/python3
"""Draws docs/img/envmap_layout.png: the equirectangular layout of an environment map
(scenes/FORMAT.md, "Environment maps"): which image column and row each world direction looks
up with no rotation and up = +Z (Blender's Environment Texture, equirectangular, Z up).

    u = 0.5 - atan2(d.y, d.x) / (2 pi)   from the left edge
    v = theta / pi                       from the top row (theta: angle from +Z)

Run from the repository root: /usr/bin/python3 tools/envmap_figure.py
"""
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def uv(d):
    x, y, z = d
    r = math.sqrt(x * x + y * y + z * z)
    u = 0.5 - math.atan2(y, x) / (2 * math.pi)
    v = math.acos(z / r) / math.pi
    return u, v


def main(out):
    fig, ax = plt.subplots(figsize=(8, 4.4), dpi=100)
    ax.set_xlim(0, 1)
    ax.set_ylim(1, 0)  # v grows downward: row 0 at the top, as the image is stored
    # Sky above the horizon, ground below.
    ax.axhspan(0, 0.5, color="#cfe3f7")
    ax.axhspan(0.5, 1, color="#e8dcc8")
    for u in (0.25, 0.5, 0.75):
        ax.axvline(u, color="#777777", lw=0.8, ls="--")
    ax.axhline(0.5, color="#444444", lw=1.2)
    labels = [((1, 0, 0), "+X\n(centre column)"), ((0, 1, 0), "+Y"), ((0, -1, 0), "\u2212Y"),
              ((-1, 0, 0), "\u2212X\n(seam)")]
    for d, text in labels:
        u, v = uv(d)
        for uu in ([0.0, 1.0] if d[0] < 0 else [u]):
            ax.plot(uu, v, "o", color="#c0392b", ms=8, clip_on=False)
            ax.annotate(text, (uu, v), textcoords="offset points", xytext=(0, 10),
                        ha="center" if 0 < uu < 1 else ("left" if uu == 0 else "right"),
                        fontsize=10)
    ax.annotate("up (+Z): top row", (0.5, 0.0), textcoords="offset points", xytext=(0, -12),
                ha="center", va="top", fontsize=10)
    ax.annotate("down (\u2212Z): bottom row", (0.5, 1.0), textcoords="offset points",
                xytext=(0, 12), ha="center", va="bottom", fontsize=10)
    ax.text(0.99, 0.52, "horizon", ha="right", va="top", fontsize=9, color="#444444")
    ax.set_xticks([0, 0.25, 0.5, 0.75, 1])
    ax.set_yticks([0, 0.25, 0.5, 0.75, 1])
    ax.set_xlabel("u = 0.5 \u2212 atan2(d.y, d.x) / 2\u03c0   (from the image's left edge)")
    ax.set_ylabel("v = \u03b8 / \u03c0   (from the top row)")
    ax.set_title("Environment map layout (no rotation, up = +Z; Blender's equirectangular)")
    fig.tight_layout()
    fig.savefig(out)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/img/envmap_layout.png")
