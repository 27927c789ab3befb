#!/usr/bin/python3
"""Renders a scene twice and writes the two images side by side.

  povray_patch/side_by_side.py POVRAY_FACET OUT.png [WIDTH HEIGHT]
      scenes/pov/showcase.pov with stock POV-Ray finishes by /usr/bin/povray
      (Declare=Classic=1), and with `brdf` finishes by povray-facet
  povray_patch/side_by_side.py POVRAY_FACET OUT.png WIDTH HEIGHT --convert SCENE.pov
      a stock scene by povray-facet as written, and with `brdf_convert_classic on` injected by
      +HI (docs/povray.md, "Classic finishes")

Also writes OUT's stem + _stock.png and _brdf.png (the left and right images).
"""
import os
import struct
import subprocess
import sys
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "support", "python"))
from facet_testsupport.png import read_png  # noqa: E402

SCENE = os.path.join(HERE, "..", "scenes", "pov", "showcase.pov")


def write_png(path, width, height, rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body
                + struct.pack(">I", zlib.crc32(kind + body) & 0xffffffff))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def render(binary, out, w, h, extra, scene=SCENE):
    tmp = os.path.dirname(out)
    # +L: the scene's image files are relative to its directory.
    cmd = [binary, f"+I{os.path.abspath(scene)}", f"+L{os.path.dirname(os.path.abspath(scene))}",
           f"+O{out}", f"+W{w}", f"+H{h}", "-D", "-V",
           "-GA", "+GF", "+FN8", "+A0.05", "+AM2", "+R2"] + extra
    p = subprocess.run(cmd, cwd=tmp, env=dict(os.environ, HOME=tmp),
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    if p.returncode != 0:
        sys.exit(f"{binary} failed:\n{p.stderr.decode()[-2000:]}")


def main():
    facet, out = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    w, h = (int(sys.argv[3]), int(sys.argv[4])) if len(sys.argv) > 4 else (480, 270)
    convert = sys.argv[6] if len(sys.argv) > 6 and sys.argv[5] == "--convert" else None
    stem = os.path.splitext(out)[0]
    with tempfile.TemporaryDirectory() as tmp:
        a, b = os.path.join(tmp, "stock.png"), os.path.join(tmp, "brdf.png")
        if convert:
            header = os.path.join(tmp, "convert.inc")
            with open(header, "w") as f:
                f.write("global_settings { brdf_convert_classic on }\n")
            render(facet, a, w, h, [], convert)
            render(facet, b, w, h, [f"+HI{header}"], convert)
        else:
            render("/usr/bin/povray", a, w, h, ["Declare=Classic=1"])
            render(facet, b, w, h, [])
        ia, ib = read_png(a), read_png(b)
        for img, name in ((ia, "_stock.png"), (ib, "_brdf.png")):
            ch = img[2]
            write_png(stem + name, w, h, [[r[x * ch + c] for x in range(w) for c in range(3)]
                                          for r in img[4]])
        gap = [255] * (3 * 4)
        rows = []
        for ra, rb in zip(ia[4], ib[4]):
            ca, cb = ia[2], ib[2]
            rows.append([ra[x * ca + c] for x in range(w) for c in range(3)] + gap
                        + [rb[x * cb + c] for x in range(w) for c in range(3)])
        write_png(out, 2 * w + 4, h, rows)
    print(f"wrote {out}, {stem}_stock.png, {stem}_brdf.png")


if __name__ == "__main__":
    main()
