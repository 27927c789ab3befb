# The reflection models from Python: the model table, make_material's errors, and vectorised
# eval / pdf / sample / reflectances against the core's own definitions.
import math

import numpy as np
import pytest

import facet


def random_directions(rng, n):
    # Upper-hemisphere unit vectors.
    v = rng.normal(size=(n, 3))
    v[:, 2] = np.abs(v[:, 2]) + 1e-3
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def test_models_table():
    names = [m.name for m in facet.models()]
    assert names[:3] == ["lambert", "mirror", "ggx"]
    ggx = facet.find_model("ggx")
    assert "alpha" in [p.name for p in ggx.params]
    assert facet.find_model("nope") is None


def test_make_material_errors_name_the_parameter():
    with pytest.raises(ValueError, match="parameter 'alpha' of model 'ggx': must be in"):
        facet.make_material("ggx", alpha=-1.0)
    with pytest.raises(ValueError, match=r"unknown model 'ggz' \(did you mean 'ggx'\?\)"):
        facet.make_material("ggz")
    with pytest.raises(ValueError, match="unknown parameter 'alpah'"):
        facet.make_material("ggx", alpah=0.2)
    with pytest.raises(ValueError, match="reflectance"):
        facet.make_material("lambert", reflectance=(1, 2))
    with pytest.raises(ValueError, match="is NaN"):
        facet.make_material("lambert", reflectance=float("nan"))


def test_lambert_values():
    m = facet.make_material("lambert", reflectance=(0.5, 0.25, 0.125))
    assert m.model == "lambert"
    assert m.params == {"reflectance": (0.5, 0.25, 0.125)}
    rng = np.random.default_rng(1)
    wo, wi = random_directions(rng, 100), random_directions(rng, 100)
    f = m.eval(wo, wi)
    assert f.shape == (100, 3) and f.dtype == np.float32
    np.testing.assert_allclose(f, np.tile([0.5, 0.25, 0.125], (100, 1)) / math.pi, rtol=1e-6)
    # Below the surface: zero.
    assert np.all(m.eval([0, 0, 1], [0, 0, -1]) == 0)
    np.testing.assert_allclose(m.pdf(wo, wi), wi[:, 2] / math.pi, rtol=1e-5)
    r = m.reflectance([0.0, 0.0, 1.0])
    np.testing.assert_allclose(r.value, [0.5, 0.25, 0.125], rtol=1e-6)
    value, error = m.reflectance()  # bihemispherical, unpacks
    np.testing.assert_allclose(value, [0.5, 0.25, 0.125], rtol=1e-6)


@pytest.mark.parametrize("model,params", [
    ("ggx", {"alpha": 0.3}),
    ("beckmann", {"alpha": 0.2, "fresnel": "conductor"}),
    ("blinn", {"exponent": 50.0}),
    ("composite", {"diffuse_reflectance": 0.4, "glossy_reflectance": 0.5,
                   "mirror_reflectance": 0.2, "alpha": 0.25}),
])
def test_vectorised_equals_one_by_one(model, params):
    m = facet.make_material(model, **params)
    rng = np.random.default_rng(2)
    wo, wi = random_directions(rng, 64), random_directions(rng, 64)
    f = m.eval(wo, wi)
    pdf = m.pdf(wo, wi)
    f2, pdf2 = m.eval_pdf(wo, wi)
    np.testing.assert_array_equal(f, f2)
    np.testing.assert_array_equal(pdf, pdf2)
    for i in range(0, 64, 7):
        np.testing.assert_array_equal(m.eval(wo[i], wi[i]), f[i])
        assert m.pdf(wo[i], wi[i]) == pdf[i]
    # One direction broadcasts against many.
    np.testing.assert_array_equal(m.eval(wo[0], wi), m.eval(np.tile(wo[0], (64, 1)), wi))


def test_sample_matches_eval_and_pdf():
    m = facet.make_material("ggx", alpha=0.4)
    rng = np.random.default_rng(3)
    n = 256
    wo = random_directions(rng, n)
    s = m.sample(wo, rng.random(n), rng.random((n, 2)))
    assert s.wi.shape == (n, 3) and s.valid.dtype == np.bool_
    ok = s.valid
    assert ok.sum() > n // 2
    np.testing.assert_allclose(s.f[ok], m.eval(wo[ok], s.wi[ok]), rtol=2e-4, atol=1e-6)
    np.testing.assert_allclose(s.pdf[ok], m.pdf(wo[ok], s.wi[ok]), rtol=2e-4, atol=1e-6)
    assert np.all(s.flags[ok] == int(facet.BxDFFlags.glossy))
    assert np.all(s.pdf[~ok] == 0)


def test_mirror_sample_is_a_delta():
    m = facet.make_material("mirror")
    wo = np.array([0.6, 0.0, 0.8])
    s = m.sample(wo, 0.5, [0.5, 0.5])
    np.testing.assert_allclose(s.wi, [-0.6, 0.0, 0.8], atol=1e-6)
    assert s.pdf == 1.0 and bool(s.valid)
    assert s.flags == int(facet.BxDFFlags.specular)
    assert np.all(m.eval(wo, s.wi) == 0)  # delta lobes: f = pdf = 0


def test_dielectric_transmits_through_python():
    # The registry's glass models reach Python: a smooth interface at normal incidence refracts
    # straight through with probability 1 - R, R = ((1.5 - 1) / (1.5 + 1))^2 = 0.04, and its
    # radiance-mode weight f |cos| / pdf is 1 / 1.5^2 (facet/dielectric.h).
    assert facet.find_model("dielectric") and facet.find_model("thin_dielectric")
    m = facet.make_material("dielectric", ior=1.5)
    s = m.sample(np.array([0.0, 0.0, 1.0]), 0.9, [0.5, 0.5])
    assert bool(s.valid)
    np.testing.assert_allclose(s.wi, [0.0, 0.0, -1.0], atol=1e-6)
    np.testing.assert_allclose(s.pdf, 0.96, rtol=1e-6)
    np.testing.assert_allclose(s.f[0] / s.pdf, 1.0 / 2.25, rtol=1e-5)
    transmission = int(facet.BxDFFlags.transmission)
    assert s.flags == int(facet.BxDFFlags.specular) | transmission
    with pytest.raises(ValueError, match="parameter 'ior' of model 'dielectric'"):
        facet.make_material("dielectric", ior=0.0)


def test_reciprocity_of_reflectances():
    m = facet.make_material("ggx", alpha=0.3)
    w = random_directions(np.random.default_rng(4), 5)
    a = m.hemispherical_directional(w)
    b = m.directional_hemispherical(w)
    assert a.value.shape == (5, 3)
    np.testing.assert_allclose(a.value, b.value, atol=3 * (a.error + b.error).max() + 1e-4)
    c = m.biconical([0, 0, 1], 0.3, [0, 0, 1], 0.3)
    assert c.value.shape == (3,)


def test_bad_direction_arrays():
    m = facet.make_material("lambert")
    with pytest.raises(ValueError, match=r"wo: shape \(4, 2\), expected \(n, 3\)"):
        m.eval(np.zeros((4, 2)), np.zeros((4, 3)))
    with pytest.raises(ValueError, match="wi: row 1 is not finite"):
        m.eval([[0, 0, 1]] * 2, [[0, 0, 1], [np.nan, 0, 1]])
    with pytest.raises(ValueError, match="wo: dtype <U1"):
        m.eval(np.array([["a", "b", "c"]]), [0, 0, 1])
    with pytest.raises(ValueError, match="wi: 3 rows, but wo has 2"):
        m.eval(np.zeros((2, 3)), np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"u: shape \(2,\), expected \(2, 2\)"):
        m.sample([[0, 0, 1]] * 2, [0.1, 0.2], [0.1, 0.2])
    with pytest.raises(ValueError, match=r"uc: element 0 is not in \[0, 1\)"):
        m.sample([0, 0, 1], 1.0, [0.1, 0.2])
    # Non-contiguous and float64/int input is converted, not rejected.
    wo = np.zeros((4, 6))
    wo[:, 4] = 1.0
    np.testing.assert_array_equal(m.eval(wo[:, 2:5], np.array([[0, 0, 1]] * 4)),
                                  m.eval(np.array([[0, 0, 1.0]] * 4), np.array([[0, 0, 1]] * 4)))
