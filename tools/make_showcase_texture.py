#!/usr/bin/python3
"""Writes scenes/textures/showcase_tiles.png, the showcase floor's image texture: 4 x 4 square
tiles (so a repeat of the image is 2 x 2 tiles of each tone) in two warm stone tones, each tile
a little lighter or darker by a fixed pseudo-random amount, with a subtle diagonal veining and
dark grout lines 6 texels wide, 512 x 512 sRGB, no alpha. Deterministic (no RNG state, no
dependencies: the PNG is written with zlib), so running it again gives the same bytes.
Usage: tools/make_showcase_texture.py [OUTPUT]"""
import math
import os
import struct
import sys
import zlib

N = 512          # texels per side
TILES = 4        # tiles per side
GROUT = 6        # grout width in texels (half on each side of a tile edge)
LIGHT = (0.80, 0.74, 0.64)  # linear-ish display values in [0, 1] (sRGB encoded as they are)
DARK = (0.56, 0.40, 0.30)
GROUT_RGB = (0.22, 0.20, 0.19)


def tile_shade(i, j):
    """A fixed factor in [0.9, 1.1] per tile (a hash of its indices)."""
    h = (i * 73856093) ^ (j * 19349663) ^ 0x5bd1e995
    h = (h * 2654435761) & 0xFFFFFFFF
    return 0.9 + 0.2 * (h % 1000) / 999.0


def texel(x, y):
    t = N // TILES
    i, j = x // t, y // t
    lx, ly = x % t, y % t
    if min(lx, ly) < GROUT // 2 or max(lx, ly) >= t - GROUT // 2:
        return GROUT_RGB
    base = LIGHT if (i + j) % 2 == 0 else DARK
    s = tile_shade(i, j)
    vein = 1.0 + 0.03 * math.sin(0.05 * (x + 0.6 * y) + 2.0 * math.sin(0.021 * (y - x)) + i + 2 * j)
    return tuple(min(1.0, c * s * vein) for c in base)


def png(path, w, h, rows):
    def chunk(kind, data):
        c = kind + data
        return struct.pack(">I", len(data)) + c + struct.pack(">I", zlib.crc32(c) & 0xFFFFFFFF)
    raw = b"".join(b"\0" + bytes(r) for r in rows)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"sRGB", b"\0") + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "scenes", "textures", "showcase_tiles.png")
    rows = []
    for y in range(N):
        row = []
        for x in range(N):
            row.extend(int(round(255 * c)) for c in texel(x, y))
        rows.append(row)
    png(out, N, N, rows)
    print(f"wrote {out} ({N} x {N})")


if __name__ == "__main__":
    main()
