# Bit-identity of facet-farm against `facet render`: several tile sizes and sample chunks,
# 2 worker processes x 1 thread and 1 in-process worker x 3 threads, stills and animations (per frame and
# per tile), adaptive renders (tiles only), the library entry point and the command (facet-farm,
# python3 -m facet.farm).
import json
import subprocess
import sys

import numpy as np
import pytest

import facet
import facet.farm as farm
from conftest import assert_same, cli_render, farm_cmd, write_scene

W, H, SPP = 96, 64, 12


@pytest.fixture(scope="module")
def still(tmp_path_factory):
    d = tmp_path_factory.mktemp("still")
    scene = write_scene(d / "still.json", W, H, SPP, seed=3)
    return scene, cli_render(scene, d / "ref.exr")


@pytest.fixture(scope="module", params=[(2, 1), (0, 3)], ids=["2procx1", "inprocx3"])
def client(request):
    workers, threads = request.param  # workers 0: one worker in this process (the default)
    cluster = farm.local_cluster(workers, threads)
    c = farm.connect(cluster)
    c.wait_for_workers(max(workers, 1), timeout=60)
    yield c
    c.close()
    cluster.close()


@pytest.mark.parametrize("tile,chunk", [(16, None), (37, 5), (64, 1), (200, 7), (None, None)])
def test_still_bit_identical(still, client, tmp_path, tile, chunk):
    scene, ref = still
    out = tmp_path / "farm.exr"
    stats = {}
    [image] = farm.render_files([str(scene)], [str(out)], client=client, tile_size=tile,
                                sample_chunk=chunk, stats=stats)
    assert stats["slots"] in (2, 3)
    assert_same(image, ref)
    assert_same(facet.read_image(str(out)), ref)


def adaptive_scene(path, threshold=0.05):
    def edit(d):
        d["render"]["adaptive_threshold"] = threshold
    # 72 x 40: the image edge cuts the 16-pixel tile grid.
    return write_scene(path, 72, 40, 64, edit=edit)


@pytest.mark.parametrize("tile", [16, 48, None])
def test_adaptive_bit_identical(client, tmp_path, tile):
    """An adaptive render (render.adaptive_threshold) is split by tiles on the 16-pixel grid,
    each task taking the whole sample range: the CLI's adaptive image bit for bit, and its
    mean samples per pixel (--stats-json) to rounding."""
    scene = adaptive_scene(tmp_path / "adaptive.json")
    ref = cli_render(scene, tmp_path / "ref.exr", "--stats-json", str(tmp_path / "st.json"))
    cli_spp = json.loads((tmp_path / "st.json").read_text())["mean_spp"]
    plain = cli_render(scene, tmp_path / "plain.exr", "--adaptive-threshold", "0")
    assert cli_spp < 64 and not np.array_equal(ref, plain)  # the tiles stopped early
    stats = {}
    [image] = farm.render_files([str(scene)], [str(tmp_path / "o.exr")], client=client,
                                tile_size=tile, stats=stats)
    assert_same(image, ref)
    assert stats["mean_spp"][0] == pytest.approx(cli_spp, rel=1e-12)


def test_adaptive_options_and_errors(client, tmp_path):
    """--adaptive-threshold / --adaptive-min-samples override the scene's, as the CLI's; a
    sample chunk, a tile off the grid, --denoise and bad values are errors naming the option."""
    scene = write_scene(tmp_path / "plain.json", 48, 32, 32)
    ref = cli_render(scene, tmp_path / "ref.exr", "--adaptive-threshold", "0.05",
                     "--adaptive-min-samples", "8")
    [image] = farm.render_files([str(scene)], [str(tmp_path / "o.exr")], client=client,
                                tile_size=32, adaptive_threshold=0.05, adaptive_min_samples=8)
    assert_same(image, ref)
    adaptive = adaptive_scene(tmp_path / "adaptive.json")
    for kw, where in [(dict(sample_chunk=8), "--sample-chunk"), (dict(tile_size=20), "--tile-size"),
                      (dict(denoise=True), "--denoise"),
                      (dict(adaptive_threshold=1.5), "--adaptive-threshold"),
                      (dict(adaptive_threshold=float("nan")), "--adaptive-threshold"),
                      (dict(adaptive_min_samples=-1), "--adaptive-min-samples")]:
        with pytest.raises(farm.FarmError, match=where):
            farm.render_files([str(adaptive)], [str(tmp_path / "e.exr")], client=client, **kw)


def test_seed_and_spp_override(still, client, tmp_path):
    scene, _ = still
    ref = cli_render(scene, tmp_path / "ref.exr", "--spp", "5", "--seed", "11")
    [image] = farm.render_files([str(scene)], [str(tmp_path / "o.exr")], client=client,
                                tile_size=24, sample_chunk=2, spp=5, seed=11)
    assert_same(image, ref)


def test_animation_per_frame_or_per_tile(client, tmp_path):
    frames = [write_scene(tmp_path / f"shot_{k:03d}.json", 48, 32, 6, camera_dx=30 * k)
              for k in range(1, 4)]
    refs = [cli_render(f, tmp_path / f"ref_{k}.exr") for k, f in enumerate(frames)]
    slots = farm._slots(client)
    # 3 frames on 2 slots: one task per frame; 2 frames on 3 slots: tiles of each frame.
    use = frames if slots == 2 else frames[:2]
    farm.render_files([str(f) for f in use], [str(tmp_path / "out" / "frame_####.exr")],
                      client=client)
    for k, f in enumerate(use):
        n = k + 1
        assert_same(facet.read_image(str(tmp_path / "out" / f"frame_{n:04d}.exr")), refs[k])


def test_film_transparent_alpha_bit_identical(client, tmp_path):
    """Film transparency (FORMAT.md "Film transparency and holdouts"): the farm's RGBA image,
    tiles and sample chunks summed with their alpha, is the CLI's bit for bit."""
    def edit(d):
        d["render"]["film_transparent"] = True
        for s in d["shapes"]:
            if s.get("name") == "tall block":  # a holdout: alpha 0 where it is seen
                s["holdout"] = True
    scene = write_scene(tmp_path / "alpha.json", 48, 32, 6, edit=edit)
    ref = cli_render(scene, tmp_path / "ref.exr")
    assert ref.shape == (32, 48, 4) and (ref[:, :, 3] == 0.0).any() and (ref[:, :, 3] == 1).any()
    [image] = farm.render_files([str(scene)], [str(tmp_path / "o.exr")], client=client,
                                tile_size=16, sample_chunk=2)
    assert_same(image, ref)


def test_command_still_exr_and_png(still, tmp_path):
    scene, ref = still
    exr, png = tmp_path / "a.exr", tmp_path / "a.png"
    r = subprocess.run(farm_cmd("render", scene, "-o", exr, "-o", png, "--tile-size", "40",
                                "--sample-chunk", "4"), capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stderr == "" and r.stdout == ""  # quiet when not on a terminal
    assert_same(facet.read_image(str(exr)), ref)
    assert png.stat().st_size > 0


def test_module_animation(tmp_path):
    frames = [write_scene(tmp_path / f"f{k}.json", 40, 24, 4, camera_dx=20 * k)
              for k in range(3)]
    refs = [cli_render(f, tmp_path / f"r{k}.exr") for k, f in enumerate(frames)]
    r = subprocess.run([sys.executable, "-m", "facet.farm", "render", *map(str, frames), "-o",
                        str(tmp_path / "o" / "frame_##.exr"), "--workers", "2", "--threads", "1"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    for k in range(3):  # frame numbers from the file names: f0 f1 f2
        assert_same(facet.read_image(str(tmp_path / "o" / f"frame_{k:02d}.exr")), refs[k])


def test_plan():
    regions, samples = farm.plan_still(1920, 1080, 64, 2)
    assert len(regions) >= 16
    regions, samples = farm.plan_still(100, 50, 10, 1, tile_size=30, sample_chunk=4)
    assert regions[0] == (0, 0, 30, 30) and regions[-1] == (90, 30, 100, 50)
    assert samples == [(0, 4), (4, 8), (8, 10)]
    with pytest.raises(farm.FarmError, match="--tile-size"):
        farm.plan_still(10, 10, 4, 1, tile_size=0)


def test_scene_travels_without_shared_files(client, tmp_path):
    # An inline mesh (arrays travel as numpy buffers) and a mesh file (its bytes travel): the
    # file is deleted before the tasks run, so the workers cannot read it from disk.
    (tmp_path / "wedge.obj").write_text("v 100 0 100\nv 400 0 150\nv 250 300 300\n"
                                        "v 250 0 400\nf 1 2 3\nf 1 3 4\n")

    def edit(d):
        d["shapes"].append({"type": "mesh", "name": "tri", "material": "white",
                            "positions": [300, 50, 200, 500, 50, 250, 400, 250, 300],
                            "indices": [0, 1, 2]})
        d["shapes"].append({"type": "mesh", "name": "wedge", "material": "white",
                            "file": "wedge.obj"})
    scene = write_scene(tmp_path / "meshes.json", 64, 48, 6, edit=edit)
    ref = cli_render(scene, tmp_path / "ref.exr")
    payload = farm.load_payload(str(scene))
    assert payload.meshes and payload.files
    (tmp_path / "wedge.obj").unlink()
    farm._scenes.clear()  # in-process: not the client's validated scene either
    regions, samples = farm.plan_still(64, 48, 6, 2, tile_size=16, sample_chunk=4)
    [image] = farm.run_jobs(client, [farm.Job(payload, regions, samples, [])])
    assert_same(image, ref)
