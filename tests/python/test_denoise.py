# The denoiser from Python (facet.denoise on arrays, facet.render(denoise=True)) and from the
# CLI (facet render --denoise): the same function as the C++ tests check (denoise.h), so these
# check the bindings: pass-through of a constant, errors naming the argument, and that the
# render option and the CLI give one image that is closer to a high-spp reference than the
# plain render of the same samples.
import subprocess

import numpy as np
import pytest

import facet
import tiny_scenes as ts


def constant(h, w, value):
    return np.full((h, w, 3), value, dtype=np.float32)


def features(h, w):
    return constant(h, w, 0.5), np.dstack([np.zeros((h, w)), np.zeros((h, w)), np.ones((h, w))]).astype(np.float32), constant(h, w, 2.0)


def test_constant_arrays_pass_through():
    albedo, normal, depth = features(12, 17)
    c = constant(12, 17, 0.3)
    out = facet.denoise(c, c, albedo, normal, depth)
    assert out.shape == (12, 17, 3) and out.dtype == np.float32
    # 1e-5 relative: float rounding of normalised weighted sums (denoise.h)
    np.testing.assert_allclose(out, c, rtol=1e-5)


def test_bad_arrays_name_the_argument():
    albedo, normal, depth = features(8, 8)
    c = constant(8, 8, 1.0)
    with pytest.raises(ValueError, match="normal: 4 x 8 pixels, but half_a is 8 x 8"):
        facet.denoise(c, c, albedo, normal[:, :4], depth)
    with pytest.raises(ValueError, match="depth"):
        facet.denoise(c, c, albedo, normal, np.zeros((8, 8)))
    bad = c.copy()
    bad[2, 5, 1] = np.inf
    with pytest.raises(ValueError, match=r"half_b: pixel \(5, 2\) is not finite"):
        facet.denoise(c, bad, albedo, normal, depth)
    with pytest.raises(ValueError, match="radius"):
        facet.denoise(c, c, albedo, normal, depth, radius=0)


def test_render_option_and_cli_agree_and_reduce_the_error(tmp_path, facet_cli):
    scene = facet.load_scene_from_string(ts.scene_json(16, 64, 48), name="tiny")
    reference = facet.render(scene, spp=1024, threads=2, seed=5)
    plain = facet.render(scene, spp=16, threads=2, seed=1)
    den = facet.render(scene, spp=16, threads=2, seed=1, denoise=True)
    assert np.isfinite(den).all()
    mse = lambda x: float(np.mean((x.astype(np.float64) - reference) ** 2))  # noqa: E731
    assert mse(den) < mse(plain) / 2, (mse(den), mse(plain))
    # The CLI writes the same image (EXR is lossless float) and the raw one equals plain.
    path = tmp_path / "tiny.json"
    path.write_text(ts.scene_json(16, 64, 48))
    subprocess.run([str(facet_cli), "render", str(path), "--spp", "16", "--seed", "1",
                    "--threads", "2", "--denoise", "-q", "-o", str(tmp_path / "d.exr"),
                    "--denoise-raw", str(tmp_path / "raw.exr"),
                    "--denoise-features", str(tmp_path / "f")], check=True)
    np.testing.assert_array_equal(facet.read_image(str(tmp_path / "d.exr")), den)
    np.testing.assert_array_equal(facet.read_image(str(tmp_path / "raw.exr")), plain)
    assert (tmp_path / "f.albedo.exr").exists() and (tmp_path / "f.depth.exr").exists()


def test_render_option_and_cli_pass_the_feature_variances(tmp_path, facet_cli):
    # render(denoise=True) is denoise() of its two half-buffers with render_aovs' features AND
    # their variances (aov.h), bit for bit; without the variances the image differs (the tiny
    # scene's edges give non-zero variances); the CLI writes the variances it used.
    scene = facet.load_scene_from_string(ts.scene_json(16, 64, 48), name="tiny")
    den = facet.render(scene, spp=16, threads=2, seed=1, denoise=True)
    a = facet.render(scene, spp=16, samples=(0, 8), threads=2, seed=1)
    b = facet.render(scene, spp=16, samples=(8, 16), threads=2, seed=1)
    f = facet.render_aovs(scene, ["albedo", "normal", "depth"], spp=16, seed=1, variances=True)
    assert sorted(f) == ["albedo", "albedo_variance", "depth", "depth_variance", "normal",
                         "normal_variance"]
    assert (f["normal_variance"] > 0).any() and (f["depth_variance"] >= 0).all()
    kw = {k: f[k] for k in ("albedo_variance", "normal_variance", "depth_variance")}
    np.testing.assert_array_equal(
        facet.denoise(a, b, f["albedo"], f["normal"], f["depth"], **kw), den)
    np.testing.assert_array_equal(facet.denoise_halves(scene, a, b, 16, 1), den)
    none = facet.denoise_halves(scene, a, b, 16, 1, feature_variances=False)
    np.testing.assert_array_equal(none, facet.denoise(a, b, f["albedo"], f["normal"], f["depth"]))
    assert not np.array_equal(none, den)
    path = tmp_path / "tiny.json"
    path.write_text(ts.scene_json(16, 64, 48))
    subprocess.run([str(facet_cli), "render", str(path), "--spp", "16", "--seed", "1",
                    "--threads", "2", "--denoise", "-q", "-o", str(tmp_path / "d.exr"),
                    "--denoise-features", str(tmp_path / "f")], check=True)
    for k in kw:
        np.testing.assert_array_equal(facet.read_image(str(tmp_path / f"f.{k}.exr")), f[k])


def test_render_option_rejects_a_split(tmp_path, facet_cli):
    scene = facet.load_scene_from_string(ts.scene_json(16, 32, 24), name="tiny")
    with pytest.raises(ValueError, match="not split-invariant"):
        facet.render(scene, spp=16, samples=(0, 8), denoise=True)
    path = tmp_path / "tiny.json"
    path.write_text(ts.scene_json(16, 32, 24))
    r = subprocess.run([str(facet_cli), "render", str(path), "--denoise", "--samples", "0:8",
                        "-o", str(tmp_path / "p.fpart")], capture_output=True, text=True)
    assert r.returncode != 0 and "--denoise" in r.stderr, r.stderr


def test_colour_and_variance_and_feature_variances():
    # A flat grey of noise 0.1 / sqrt 2 given as colour and its variance, with a noisy normal
    # (deviation 0.3 per channel, as under depth of field) given with its variance: the MSE
    # against the truth falls tenfold (measured 24x; the C++ tests check the method), and
    # without normal_variance the noisy normal blocks the averaging (measured ~10x worse).
    rng = np.random.default_rng(1)
    h, w = 32, 40
    truth = constant(h, w, 0.4)
    color = (truth + rng.normal(0, 0.1 / np.sqrt(2), truth.shape)).astype(np.float32)
    variance = constant(h, w, 0.005)
    albedo, normal, depth = features(h, w)
    normal = (normal + rng.normal(0, 0.3, normal.shape)).astype(np.float32)
    nv = constant(h, w, 0.09)
    mse = lambda x: float(np.mean((x - truth) ** 2))  # noqa: E731
    out = facet.denoise(albedo=albedo, normal=normal, depth=depth, color=color,
                        variance=variance, normal_variance=nv)
    assert mse(out) < mse(color) / 10, (mse(out), mse(color))
    blocked = facet.denoise(albedo=albedo, normal=normal, depth=depth, color=color,
                            variance=variance)
    assert mse(out) < mse(blocked) / 3, (mse(out), mse(blocked))


def test_colour_errors_name_the_argument():
    albedo, normal, depth = features(8, 8)
    c = constant(8, 8, 1.0)
    with pytest.raises(ValueError, match="variance: missing"):
        facet.denoise(albedo=albedo, normal=normal, depth=depth, color=c)
    with pytest.raises(ValueError, match="color: give either half_a and half_b"):
        facet.denoise(c, c, albedo, normal, depth, color=c, variance=c)
    with pytest.raises(ValueError, match=r"variance: pixel \(0, 0\) is negative"):
        facet.denoise(albedo=albedo, normal=normal, depth=depth, color=c, variance=-c)
    with pytest.raises(ValueError, match="depth_variance: 4 x 8 pixels, but color is 8 x 8"):
        facet.denoise(albedo=albedo, normal=normal, depth=depth, color=c, variance=c,
                      depth_variance=c[:, :4])
