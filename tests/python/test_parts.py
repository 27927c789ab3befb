# Split and merge from Python: regions and sample ranges rendered separately (also on threads,
# through part files and through pickle) merge into exactly the image of one render.
import concurrent.futures
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
