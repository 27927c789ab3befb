# facet-farm on the scenes of issue 25 §4, CI-sized: an instanced scene (a prototype's mesh file
# placed many times) and a textured scene (an image texture, an HDRI environment map and a
# textured glTF asset). Merged images are bit-identical to `facet render`; the textures are read
# by each worker from the scene's directory (a shared path), never sent through the scheduler.
import json
import pathlib
import pickle
import shutil

import numpy as np
import pytest

import facet
import facet.farm as farm
from conftest import assert_same, cli_render

BOX = pathlib.Path("/usr/share/assimp/models/glTF2/BoxTextured-glTF")  # tools/deps.sh


@pytest.fixture(scope="module", params=[(2, 1), (0, 2)], ids=["2procx1", "inprocx2"])
def client(request):
    workers, threads = request.param
    cluster = farm.local_cluster(workers, threads)
    c = farm.connect(cluster)
    c.wait_for_workers(max(workers, 1), timeout=60)
    yield c
    c.close()
    cluster.close()


def base_scene(width=64, height=48, spp=6):
    return {
        "format": "facet-scene", "version": 1,
        "camera": {"position": [0, -7, 3], "look_at": [0, 0, 0.6], "up": [0, 0, 1], "fov": 45,
                   "width": width, "height": height},
        "render": {"integrator": "path", "spp": spp, "max_depth": 4, "seed": 5},
        "materials": {"ground": {"model": "lambert", "reflectance": 0.5},
                      "leaf": {"model": "lambert", "reflectance": [0.2, 0.5, 0.1]}},
        "shapes": [{"type": "quad", "material": "ground",
                    "vertices": [[-6, -6, 0], [6, -6, 0], [6, 6, 0], [-6, 6, 0]]}],
        "lights": [{"type": "directional", "direction": [0.3, 0.5, -0.8], "irradiance": 2}],
    }


def render(client, payload, tile=16, chunk=4):
    farm._scenes.clear()  # in-process workers: build from the payload, not the client's scene
    regions, samples = farm.plan_still(payload.width, payload.height, payload.spp, 2,
                                       tile_size=tile, sample_chunk=chunk)
    [image] = farm.run_jobs(client, [farm.Job(payload, regions, samples, [])])
    return image


def test_instanced_scene(client, tmp_path):
    # 60 instances of a prototype whose mesh is a file; the file is deleted before the tasks
    # run, so its bytes must travel (once: the payload holds one copy for all instances).
    (tmp_path / "tree.obj").write_text(
        "v -0.3 -0.3 0\nv 0.3 -0.3 0\nv 0 0.3 0\nv 0 0 1.2\n"
        "f 1 2 4\nf 2 3 4\nf 3 1 4\nf 1 3 2\n")
    d = base_scene()
    d["prototypes"] = {"tree": [{"type": "mesh", "file": "tree.obj", "material": "leaf"}]}
    rng = np.random.default_rng(3)
    for k in range(60):
        x, y = (k % 8 - 3.5) * 1.2, (k // 8 - 3.5) * 1.2
        a, s = rng.uniform(0, 6.28), rng.uniform(0.6, 1.4)
        c, si = np.cos(a) * s, np.sin(a) * s
        d["shapes"].append({"type": "instance", "of": "tree", "transform": {"matrix": [
            c, -si, 0, x, si, c, 0, y, 0, 0, s, 0, 0, 0, 0, 1]}})
    scene = tmp_path / "forest.json"
    scene.write_text(json.dumps(d))
    ref = cli_render(scene, tmp_path / "ref.exr")
    payload = farm.load_payload(str(scene))
    assert len(payload.files) == 1  # one copy of tree.obj for the prototype
    (tmp_path / "tree.obj").unlink()
    image = render(client, payload)
    assert_same(image, ref)
    # A wrong variant would show: the same scene without its instances differs.
    assert not np.array_equal(image, cli_render(_without_instances(d, tmp_path), tmp_path / "n.exr"))


def _without_instances(d, tmp_path):
    e = dict(d, shapes=d["shapes"][:1])
    e.pop("prototypes")
    p = tmp_path / "empty.json"
    p.write_text(json.dumps(e))
    return p


def textured_scene(tmp_path):
    """An image texture (a 256 x 256 PNG), an HDRI (a 512 x 256 EXR) and the textured glTF box,
    all relative to the scene file. Returns (scene path, the texture files' total bytes)."""
    u = np.linspace(0, 1, 256, dtype=np.float32)
    tex = np.stack(np.meshgrid(u, u[::-1]), -1)
    tex = np.concatenate([tex, 0.5 * np.ones_like(tex[..., :1])], -1)
    facet.write_image(np.ascontiguousarray(tex), str(tmp_path / "ramp.png"))
    phi = np.linspace(0, 2 * np.pi, 512, dtype=np.float32)
    theta = np.linspace(0, np.pi, 256, dtype=np.float32)[:, None]
    sky = 0.4 + 0.3 * np.cos(theta) * (1 + 0.5 * np.sin(3 * phi))[None, :]
    sky = np.clip(sky, 0.02, None)
    hdri = np.stack([sky, 0.9 * sky, 1.2 * sky], -1).astype(np.float32)
    facet.write_image(np.ascontiguousarray(hdri), str(tmp_path / "sky.exr"))
    for f in ("BoxTextured.gltf", "BoxTextured0.bin", "CesiumLogoFlat.png"):
        shutil.copy(BOX / f, tmp_path)
    d = base_scene()
    d["materials"]["ramp"] = {"model": "lambert", "reflectance": {"texture": "ramp.png"}}
    d["shapes"] += [{"type": "sphere", "center": [-1.2, 0, 0.7], "radius": 0.7, "material": "ramp"},
                    {"type": "gltf", "file": "BoxTextured.gltf",
                     "transform": {"translate": [1.0, 0, 0.5]}}]
    d["lights"].append({"type": "environment", "file": "sky.exr", "radiance": 1})
    scene = tmp_path / "textured.json"
    scene.write_text(json.dumps(d))
    sizes = sum((tmp_path / f).stat().st_size for f in ("ramp.png", "sky.exr", "CesiumLogoFlat.png"))
    return scene, sizes


def test_textured_scene_bit_identical_textures_by_path(client, tmp_path):
    scene, texture_bytes = textured_scene(tmp_path)
    ref = cli_render(scene, tmp_path / "ref.exr")
    payload = farm.load_payload(str(scene))
    # What travels through the scheduler is the pickled payload: texels would make it at least
    # as large as the texture files (here ~0.5 MB: the EXR alone is 512 x 256 x 3 floats before
    # compression); the description alone is ~2 kB. Bound: 16 kB.
    sent = len(pickle.dumps(payload, protocol=5))
    assert texture_bytes > 100_000 and sent < 16_000, (sent, texture_bytes)
    assert not payload.files and str(tmp_path / "sky.exr") in payload.json
    assert_same(render(client, payload), ref)


def test_workers_read_textures_themselves(client, tmp_path):
    # The HDRI is moved away after the client loaded (and validated) the scene: a worker that
    # builds the scene from the payload must fail naming the file. Had the texels travelled in
    # the payload, the render would succeed.
    scene, _ = textured_scene(tmp_path)
    payload = farm.load_payload(str(scene))
    (tmp_path / "sky.exr").rename(tmp_path / "moved.exr")
    with pytest.raises(farm.FarmError, match=r"sky\.exr.*on worker .*share them"):
        render(client, payload)
    # Put back, the same payload renders: workers counted their builds from the payload.
    (tmp_path / "moved.exr").rename(tmp_path / "sky.exr")
    render(client, payload)
    builds = client.run(lambda: farm.worker_scene_builds)
    assert sum(builds.values()) >= 1
