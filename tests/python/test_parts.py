# Split and merge from Python: regions and sample ranges rendered separately (also on threads,
# through part files and through pickle) merge into exactly the image of one render.
import concurrent.futures
import json
import pickle

import numpy as np
import pytest

import facet
import tiny_scenes as ts

SPP = 6


@pytest.fixture(scope="module")
def scene():
    return facet.load_scene_from_string(ts.scene_json(SPP), name="tiny")


@pytest.fixture(scope="module")
def whole(scene):
    return facet.render(scene)


def part(scene, **options):
    session = facet.RenderSession(scene, **options)
    assert session.render() is True
    return session.part()


def test_regions_merge_bit_for_bit(scene, whole):
    w, h = ts.WIDTH, ts.HEIGHT
    # Uneven cuts, not on the tile grid or the 8-pixel packet grid.
    regions = [(0, 0, 13, 11), (13, 0, w, 11), (0, 11, 29, h), (29, 11, w, h)]
    parts = [part(scene, region=r) for r in regions]
    assert parts[1].region == (13, 0, w, 11)
    assert parts[1].image().shape == (11, w - 13, 3)
    np.testing.assert_array_equal(parts[1].image(), whole[0:11, 13:w])
    np.testing.assert_array_equal(facet.merge_parts(parts), whole)
    # Arrival order does not matter.
    np.testing.assert_array_equal(facet.merge_parts(parts[::-1]), whole)


def test_sample_ranges_merge_bit_for_bit(scene, whole):
    parts = [part(scene, samples=s) for s in [(0, 1), (1, 4), (4, SPP)]]
    assert parts[1].samples == (1, 4)
    np.testing.assert_array_equal(facet.merge_parts(parts), whole)


def test_split_across_threads_files_and_pickle(scene, whole, tmp_path):
    jobs = [dict(region=(0, 0, ts.WIDTH, 16), samples=(0, 2)),
            dict(region=(0, 0, ts.WIDTH, 16), samples=(2, SPP)),
            dict(region=(0, 16, ts.WIDTH, ts.HEIGHT), samples=(0, SPP))]
    with concurrent.futures.ThreadPoolExecutor(3) as pool:
        parts = list(pool.map(lambda o: part(scene, threads=1, **o), jobs))
    paths = []
    for k, p in enumerate(parts):
        paths.append(str(tmp_path / f"p{k}.fpart"))
        p.write(paths[-1])
    from_files = [facet.read_part(p) for p in paths]
    assert from_files[0].name == paths[0]
    np.testing.assert_array_equal(facet.merge_parts(from_files), whole)
    pickled = [pickle.loads(pickle.dumps(p)) for p in parts]
    assert pickled[2].region == parts[2].region and pickled[2].seed == parts[2].seed
    np.testing.assert_array_equal(facet.merge_parts(pickled), whole)


def test_bad_merges_name_the_part(scene):
    a = part(scene, region=(0, 0, ts.WIDTH, 16))
    b = part(scene, region=(0, 10, ts.WIDTH, ts.HEIGHT))
    a.name, b.name = "top", "bottom"
    with pytest.raises(RuntimeError, match="bottom|top"):
        facet.merge_parts([a, b])  # overlap
    with pytest.raises(RuntimeError):
        facet.merge_parts([a])  # missing pixels
    other = facet.load_scene_from_string(ts.scene_json(SPP).replace('"seed": 7', '"seed": 8'),
                                         name="other")
    c = part(other, region=(0, 16, ts.WIDTH, ts.HEIGHT))
    c.name = "other seed"
    with pytest.raises(RuntimeError, match="other seed"):
        facet.merge_parts([a, c])
    with pytest.raises(ValueError, match="names: expected one name per part"):
        facet.merge_parts([a, c], names=["x"])


def test_film_transparent_is_rgba_and_merges(tmp_path):
    """Film > Transparent (FORMAT.md "Film transparency and holdouts"): RGBA arrays, colour
    premultiplied; parts with alpha merge (files, pickle) into the single render's RGBA; a
    holdout shape is alpha 0 and black."""
    d = ts.scene_dict(SPP)
    d["render"]["film_transparent"] = True
    d["shapes"][1]["holdout"] = True  # the gold sphere
    sc = facet.load_scene_from_string(json.dumps(d), name="tiny alpha")
    whole = facet.render(sc)
    assert whole.shape == (ts.HEIGHT, ts.WIDTH, 4)
    a = whole[:, :, 3]
    assert a.min() >= 0.0 and a.max() <= 1.0
    # Some pixels see the sky (the camera looks over the floor) or the holdout: alpha 0, black.
    holes = a == 0.0
    assert holes.any() and (a == 1.0).any()
    assert np.all(whole[holes][:, :3] == 0.0)
    parts = [part(sc, samples=s) for s in [(0, 2), (2, SPP)]]
    np.testing.assert_array_equal(facet.merge_parts(parts), whole)
    parts[0].write(str(tmp_path / "a.fpart"))
    again = [facet.read_part(str(tmp_path / "a.fpart")), pickle.loads(pickle.dumps(parts[1]))]
    np.testing.assert_array_equal(facet.merge_parts(again), whole)
    # The description's attributes.
    desc = facet.read_scene_description(str(ts.write_scene(tmp_path)))
    assert desc.render.film_transparent is False and desc.shapes[0].holdout is False
    desc.render.film_transparent = True
    assert facet.render(facet.build_scene(desc, name="t")).shape[2] == 4


def test_shadow_catcher_keeps_the_shadows_as_alpha(tmp_path):
    """A shadow catcher (FORMAT.md "Shadow catchers"): over a transparent film the floor loses
    its colour and keeps its shadows as alpha; parts of it (regions and sample ranges, through
    a part file and pickle) merge bit for bit into the whole render's image, its Combined with
    the Shadow Catcher pass and that pass; the description's attribute."""
    d = ts.scene_dict(SPP)
    d["render"]["film_transparent"] = True
    # Only the point light: an emitting shape that is no catcher does not light the catcher's
    # unshadowed run (as in Cycles), so its shadows would not be caught.
    d["shapes"] = [s for s in d["shapes"] if "emission" not in s]
    plain = facet.render(facet.load_scene_from_string(json.dumps(d), name="tiny alpha"))
    d["shapes"][0]["shadow_catcher"] = True  # the floor
    sc = facet.load_scene_from_string(json.dumps(d), name="tiny catcher")
    img = facet.render(sc)
    assert img.shape == (ts.HEIGHT, ts.WIDTH, 4)
    # The floor: opaque and lit without the flag, colourless with it.
    floor = (plain[:, :, 3] == 1.0) & (plain[:, :, :3].max(axis=2) > 0.0) & \
        (img[:, :, :3].max(axis=2) == 0.0)
    assert floor.sum() > 0.2 * floor.size
    a = img[:, :, 3][floor]
    assert np.median(a) < 0.5 and a.max() > 0.5  # mostly lit, with shadows
    # The Shadow Catcher pass: the light the floor kept, 1 where no catcher is seen; with it
    # the image is the matte (the floor colourless and transparent).
    image, sc_pass = facet.render(sc, shadow_catcher_pass=True)
    assert sc_pass.shape == (ts.HEIGHT, ts.WIDTH, 3)
    np.testing.assert_array_equal(image[:, :, :3], img[:, :, :3])  # the matte's colour
    assert np.all(image[:, :, 3] <= img[:, :, 3])  # the shadows leave the alpha
    assert np.mean(image[:, :, 3][floor] == 0.0) > 0.9
    # Where the camera sees the floor only (the matte's alpha 0) the approximation's alpha is
    # 1 - the pass's mean, clamped (film.h), to float rounding.
    pure = floor & (image[:, :, 3] == 0.0)
    assert (img[:, :, 3][pure] > 0.5).sum() >= 3
    np.testing.assert_allclose(img[:, :, 3][pure],
                               1.0 - np.clip(sc_pass[pure].mean(axis=1), 0.0, 1.0), atol=1e-6)
    assert np.all(sc_pass[(plain[:, :, 3] == 0.0)] == 1.0)  # no catcher seen
    # Parts: two regions, one of them in two sample ranges, via a file and pickle.
    w, h = ts.WIDTH, ts.HEIGHT
    parts = [part(sc, region=(0, 0, w, 9)), part(sc, region=(0, 9, w, h), samples=(0, 2)),
             part(sc, region=(0, 9, w, h), samples=(2, SPP))]
    parts[0].write(str(tmp_path / "c.fpart"))
    parts[0] = facet.read_part(str(tmp_path / "c.fpart"))
    parts[1] = pickle.loads(pickle.dumps(parts[1]))
    np.testing.assert_array_equal(facet.merge_parts(parts), img)
    merged, merged_pass = facet.merge_parts(parts, shadow_catcher_pass=True)
    np.testing.assert_array_equal(merged, image)
    np.testing.assert_array_equal(merged_pass, sc_pass)
    desc = facet.read_scene_description(str(ts.write_scene(tmp_path)))
    assert desc.shapes[0].shadow_catcher is False
    desc.shapes[0].shadow_catcher = True
    assert "a shadow catcher" in facet.build_scene(desc, name="t").explain()
