# facet-farm --denoise: the merged half-buffers denoised after the merge give `facet render
# --denoise`'s image bit for bit, whatever the tiles and sample chunks (chunks never straddle the
# halves), and --denoise-raw the plain render's; the features and their variances rendered per
# tile are the single render's; a render that cannot be denoised is an error.
import subprocess

import pytest

import facet
import facet.farm as farm
from conftest import assert_same, cli_render, farm_cmd, write_scene

W, H, SPP = 80, 56, 12


@pytest.fixture(scope="module")
def refs(tmp_path_factory):
    d = tmp_path_factory.mktemp("denoise")
    scene = write_scene(d / "box.json", W, H, SPP, seed=4)
    den = cli_render(scene, d / "den.exr", "--denoise")
    plain = cli_render(scene, d / "plain.exr")
    return scene, den, plain


@pytest.fixture(scope="module")
def client():
    cluster = farm.local_cluster(0, 2)
    c = farm.connect(cluster)
    yield c
    c.close()
    cluster.close()


@pytest.mark.parametrize("tile,chunk", [(24, 5), (37, 1), (None, None)])
def test_farm_denoise_equals_the_cli(refs, client, tmp_path, tile, chunk):
    scene, den, plain = refs
    [image] = farm.render_files([str(scene)], [str(tmp_path / "o.exr")], client=client,
                                tile_size=tile, sample_chunk=chunk, denoise=True,
                                denoise_raw=[str(tmp_path / "raw.exr")])
    assert_same(image, den)
    assert_same(facet.read_image(str(tmp_path / "o.exr")), den)
    assert_same(facet.read_image(str(tmp_path / "raw.exr")), plain)


def test_tiled_features_and_variances_equal_the_single_render(refs):
    # The features and their variances the workers render per tile (feature_piece), pasted,
    # are the single render's (render_aovs over the whole image, which `facet render
    # --denoise` uses), bit for bit; the Cornell box's edges give non-zero variances.
    scene, _, _ = refs
    payload = farm.load_payload(str(scene))
    job = farm.Job(payload, [], [], [], denoise=True)
    for region in farm.tiles(W, H, 19):
        farm._place_features(job, region, farm.feature_piece(payload, region, 1))
    whole = facet.render_aovs(farm._worker_scene(payload), list(farm.FEATURES), spp=SPP, seed=4,
                              variances=True)
    assert sorted(job.features) == sorted(whole)
    for k, v in whole.items():
        assert_same(job.features[k], v)
    assert (whole["normal_variance"] > 0).any() and (whole["depth_variance"] > 0).any()


def test_command_denoise_and_errors(refs, tmp_path):
    scene, den, _ = refs
    out = tmp_path / "c.exr"
    r = subprocess.run(farm_cmd("render", scene, "-o", out, "--denoise", "--tile-size", "32"),
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert_same(facet.read_image(str(out)), den)
    r = subprocess.run(farm_cmd("render", scene, "-o", out, "--denoise", "--spp", "1"),
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 1 and "--denoise: needs at least 2 samples per pixel" in r.stderr
    r = subprocess.run(farm_cmd("render", scene, "-o", out, "--denoise-raw", tmp_path / "r.exr"),
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 1 and "--denoise-raw: needs --denoise" in r.stderr
