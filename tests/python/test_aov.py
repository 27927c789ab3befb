"""facet.render_aovs (core/render aov.h): first-hit passes against analytic values.

Scene: a perspective camera 5 above the plane y = 0 (Lambert 0.6) looking straight down, a
sphere (radius 1, centre (1.5, 1, 0), Lambert 0.6) and an emitting quad ((2, 1, 0.5), black
material). Exact expectations (float32 rounding only, hence 1e-5):
- depth on the plane = 5 at every pixel (distance along the view axis; the distance along the
  ray, 5 / cos theta, is up to 1/cos(fov/2) - 1 = 8% larger at the image edge: the check
  fails for it), 1e10 where the camera sees nothing;
- normal on the plane (0, 1, 0); on the sphere the unit (p - c) / r, p reconstructed from the
  depth along the pixel centre's ray (spp 1: pixel centres);
- albedo 0.6 on the Lambertian plane (cosine sampling: every sample's f cos / pdf is 0.6);
- emission (2, 1, 0.5) on the quad, 0 elsewhere;
- deterministic: the same for 1 and 2 threads; passes not asked for are absent.
"""
import json
import math

import numpy as np
import pytest

import facet

W, H, FOV = 48, 36, 40.0


def scene(width=W, height=H, with_sky=False):
    d = {
        "format": "facet-scene", "version": 1,
        "camera": {"position": [0, 5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": FOV,
                   "width": width, "height": height},
        "render": {"spp": 4, "max_depth": 2, "seed": 3},
        "materials": {"grey": {"model": "lambert", "reflectance": 0.6},
                      "black": {"model": "lambert", "reflectance": 0}},
        "shapes": [
            {"type": "disc", "center": [0, 0, 0], "normal": [0, 1, 0], "radius": 3.0,
             "material": "grey"},
            {"type": "sphere", "center": [1.5, 1, 0], "radius": 1.0, "material": "grey"},
            {"type": "quad", "material": "black", "emission": [2, 1, 0.5],
             "vertices": [[-1.5, 0.5, 0.5], [-0.5, 0.5, 0.5], [-0.5, 0.5, -0.5],
                          [-1.5, 0.5, -0.5]]},
        ],
        "lights": [{"type": "point", "position": [0, 4, 0], "power": 10}],
    }
    return facet.load_scene_from_string(json.dumps(d), name="aov")


def pixel_rays():
    """Unit directions of the pixel-centre rays (camera looks down -y, image up = -z)."""
    t = math.tan(math.radians(FOV) / 2.0)
    ys, xs = np.mgrid[0:H, 0:W]
    sx = (2.0 * (xs + 0.5) / W - 1.0) * t * W / H
    sy = (1.0 - 2.0 * (ys + 0.5) / H) * t
    d = np.stack([sx, -np.ones_like(sx), -sy], axis=2)  # right = +x, up = -z
    return d / np.linalg.norm(d, axis=2, keepdims=True)


@pytest.fixture(scope="module")
def passes():
    return facet.render_aovs(scene(), ["albedo", "normal", "depth", "emission"], spp=1)


def test_depth_is_along_the_view_axis(passes):
    depth = passes["depth"][..., 0]
    n = passes["normal"]
    plane = np.abs(n[..., 1] - 1.0) < 1e-6
    plane &= np.all(passes["emission"] == 0, axis=2)
    plane &= np.abs(depth - 5.0) < 0.5  # not the sphere's top
    assert plane.sum() > 0.4 * W * H
    assert np.abs(depth[plane] - 5.0).max() < 1e-5
    # The distance along the ray would differ by up to 8% at the edge: far above 1e-5.
    ray = 5.0 / -pixel_rays()[..., 1]
    assert np.abs(ray[plane] - 5.0).max() > 0.05


def test_sphere_normals_are_analytic(passes):
    depth = passes["depth"][..., 0]
    d = pixel_rays()
    p = np.array([0.0, 5.0, 0.0]) + d * (depth / -d[..., 1])[..., None]
    ref = p - np.array([1.5, 1.0, 0.0])
    on = np.abs(np.linalg.norm(ref, axis=2) - 1.0) < 1e-3
    assert on.sum() > 50
    assert np.abs(passes["normal"][on] - ref[on]).max() < 1e-3


def test_albedo_and_emission(passes):
    em = passes["emission"]
    quad = np.all(np.abs(em - np.array([2.0, 1.0, 0.5])) < 1e-6, axis=2)
    assert quad.sum() > 20
    assert np.all(passes["albedo"][quad] == 0)
    lit = ~quad & (passes["depth"][..., 0] < 1e9)
    assert np.abs(passes["albedo"][lit] - 0.6).max() < 1e-5
    assert np.all(em[~quad] == 0)


def test_misses_and_determinism():
    s = scene(width=W * 2)  # wider: the image edges miss the disc
    a = facet.render_aovs(s, ["depth", "normal", "albedo"], spp=4, seed=5, threads=1)
    b = facet.render_aovs(s, ["depth", "normal", "albedo"], spp=4, seed=5, threads=2)
    assert set(a) == {"depth", "normal", "albedo"}
    for k in a:
        assert np.array_equal(a[k], b[k])
    miss = a["depth"][..., 0] == 1e10
    assert miss.sum() > 100 and np.all(a["normal"][miss] == 0)
    with pytest.raises(ValueError, match="unknown pass 'z'"):
        facet.render_aovs(s, ["z"])
    with pytest.raises(ValueError, match="spp"):
        facet.render_aovs(s, ["depth"], spp=0)
