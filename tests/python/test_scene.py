# SceneDescription from Python: JSON read/write round trips, a numpy-built scene against its
# JSON twin (bit for bit), zero-copy meshes kept alive, and clear errors for bad arrays.
import gc
import subprocess
import pickle

import numpy as np
import pytest

import facet
import tiny_scenes as ts


def test_json_round_trip_of_every_scene(scenes_dir):
    for path in sorted(scenes_dir.glob("*.json")):
        d = facet.read_scene_description(str(path))
        text = facet.write_scene_json(d)
        again = facet.parse_scene_description(text, name=path.name, base_dir=d.base_dir)
        assert again == d, path.name
        assert facet.fingerprint(again) == facet.fingerprint(d)


def test_inspect_the_cornell_box(scenes_dir):
    d = facet.read_scene_description(str(scenes_dir / "cornell_box.json"))
    assert (d.camera.width, d.camera.height) == (512, 512)
    assert d.camera.position == pytest.approx((278, 273, -800))
    assert list(d.materials) == ["green", "red", "white"]  # sorted by name
    assert d.materials["white"].model == "lambert"
    assert d.materials["white"].params["reflectance"] == pytest.approx((0.7377, 0.7361, 0.7373))
    assert d.shapes[0].kind == facet.ShapeKind.quad and d.shapes[0].name == "floor"
    assert d.render.spp == 64 and d.render.integrator == "path"
    # Mutating in place changes the description.
    d.shapes[0].name = "ground"
    d.render.spp = 2
    text = d.to_json()
    assert '"ground"' in text and '"spp": 2' in text


def test_numpy_scene_equals_its_json_twin():
    built = ts.numpy_description()
    parsed = facet.parse_scene_description(ts.scene_json(), name="twin")
    assert built == parsed
    assert facet.fingerprint(built) == facet.fingerprint(parsed)
    a = facet.render(facet.build_scene(built, name="numpy"), threads=2)
    b = facet.render(facet.load_scene_from_string(ts.scene_json(), name="twin"), threads=2)
    assert a.shape == (ts.HEIGHT, ts.WIDTH, 3) and a.dtype == np.float32
    assert np.all(np.isfinite(a)) and a.max() > 0
    np.testing.assert_array_equal(a, b)


def test_mesh_is_zero_copy_and_kept_alive():
    positions, indices, normals = ts.mesh_arrays()
    mesh = facet.MeshData(positions, indices, normals)
    assert np.shares_memory(mesh.positions, positions)
    assert np.shares_memory(mesh.indices, indices)
    assert np.shares_memory(mesh.normals, normals)
    assert not mesh.positions.flags.writeable
    assert (mesh.num_vertices, mesh.num_triangles) == (4, 4)
    reference = facet.render(facet.build_scene(ts.numpy_description()), spp=2)
    # Only the description holds the arrays now.
    d = ts.numpy_description()
    d.shapes[2].mesh = mesh
    del positions, indices, normals, mesh
    gc.collect()
    np.testing.assert_array_equal(facet.render(facet.build_scene(d), spp=2), reference)
    # Other dtypes and layouts are converted (a copy), with the same result.
    p, i, n = ts.mesh_arrays()
    wide = np.zeros((4, 6), dtype=np.float64)
    wide[:, ::2] = p
    converted = facet.MeshData(wide[:, ::2], i.astype(np.int64), n.astype(np.float64))
    assert not np.shares_memory(converted.positions, wide)
    assert converted == facet.MeshData(p, i, n)


def test_bad_mesh_arrays_raise_clear_errors():
    p, i, n = ts.mesh_arrays()
    cases = [
        ((p.astype(np.int64), i, None), r"positions: dtype int64, expected float32"),
        ((p[:, :2], i, None), r"positions: shape \(4, 2\), expected \(n, 3\)"),
        ((p.ravel(), i, None), r"positions: shape \(12,\), expected \(n, 3\)"),
        ((np.where(np.arange(12).reshape(4, 3) == 4, np.nan, p).astype(np.float32), i, None),
         r"positions: row 1 is not finite"),
        ((p, i.astype(np.float32), None), r"indices: dtype float32, expected int32"),
        ((p, np.array([[0, 1, -1]], dtype=np.int32), None),
         r"indices: row 0 \(index -1\) is negative"),
        ((p, np.array([[0, 1, 2], [0, 1, 4]], dtype=np.int32), None),
         r"indices: row 1 \(index 4\) is out of range: there are 4 positions"),
        ((p, np.array([[0, 1, 9]], dtype=np.int64), None), r"indices: row 0 \(index 9\)"),
        ((p, i, n[:3]), r"normals: 3 rows, expected one per position \(4\)"),
        ((p, i, np.full((4, 3), np.inf, dtype=np.float32)), r"normals: row 0 is not finite"),
        (("abc", i, None), r"positions: dtype <U3"),
    ]
    for args, message in cases:
        with pytest.raises(ValueError, match=message):
            facet.MeshData(*args)
    with pytest.raises(ValueError, match="give positions and indices together"):
        facet.ShapeDesc(positions=p)


def test_mesh_uvs_from_numpy_match_json():
    """Mesh `uvs` (n, 2) are zero copy and round-trip through JSON; wrong shapes raise naming
    `uvs`."""
    p, i, n = ts.mesh_arrays()
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=np.float32)
    mesh = facet.MeshData(p, i, n, uvs)
    assert np.shares_memory(mesh.uvs, uvs)
    assert facet.MeshData(p, i).uvs is None
    d = ts.numpy_description()
    d.shapes[2].mesh = mesh
    d.shapes[2].material_ref = ""
    d.shapes[2].material = facet.MaterialDesc("lambert")
    twin = facet.parse_scene_description(d.to_json(), name="twin")
    assert twin == d
    assert twin.shapes[2].mesh.uvs.tolist() == uvs.tolist()
    with pytest.raises(ValueError, match=r"uvs: shape \(4, 3\), expected \(n, 2\)"):
        facet.MeshData(p, i, None, np.zeros((4, 3), dtype=np.float32))
    with pytest.raises(ValueError, match=r"uvs: 3 rows, expected one per position \(4\)"):
        facet.MeshData(p, i, None, uvs[:3])
    with pytest.raises(ValueError, match="normals and uvs need positions and indices"):
        facet.ShapeDesc("mesh", uvs=uvs)


def test_texture_parameters_from_python(tmp_path):
    """facet.Texture stands for a parameter value: it round-trips through JSON, renders, and a
    bad texture names its JSON pointer and the file."""
    p, i, n = ts.mesh_arrays()
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=np.float32)
    checker = facet.Texture.checker([0.2, 0.2, 0.2], [0.8, 0.8, 0.8], scale=2)
    d = ts.numpy_description()
    d.shapes[2].mesh = facet.MeshData(p, i, n, uvs)
    d.shapes[2].material_ref = ""
    d.shapes[2].material = facet.MaterialDesc("lambert", reflectance=checker)
    assert d.shapes[2].material.textures["reflectance"] == checker
    assert "reflectance" not in d.shapes[2].material.params
    assert facet.parse_scene_description(d.to_json(), name="twin") == d
    image = facet.render(facet.build_scene(d, name="py"), spp=2)
    assert np.all(np.isfinite(image)) and image.max() > 0
    missing = str(tmp_path / "missing.png")
    d.shapes[2].material = facet.MaterialDesc("lambert", reflectance=facet.Texture(missing))
    with pytest.raises(ValueError, match=r"^py: /shapes/2/material/reflectance/texture: .*missing\.png"):
        facet.build_scene(d, name="py")


def test_build_errors_name_the_place():
    d = ts.numpy_description()
    d.materials["gold"] = facet.MaterialDesc("ggx", alpha=-1.0)
    with pytest.raises(ValueError, match=r"^py: /materials/gold/alpha: .*alpha"):
        facet.build_scene(d, name="py")
    d = ts.numpy_description()
    d.shapes[1].material_ref = "glod"
    with pytest.raises(ValueError, match=r"/shapes/1.*glod.*did you mean 'gold'"):
        facet.build_scene(d)
    d = ts.numpy_description()
    d.lights.clear()
    d.shapes.pop()  # the lamp
    with pytest.raises(ValueError, match="light"):
        facet.build_scene(d)
    d = ts.numpy_description()
    d.shapes.append({"type": "sphere"})
    with pytest.raises(TypeError, match=r"shapes\[4\]: expected a facet.ShapeDesc, got dict"):
        facet.build_scene(d)
    with pytest.raises(TypeError, match="ShapeDesc has no field 'radius_'"):
        facet.ShapeDesc("sphere", radius_=1)
    with pytest.raises(ValueError, match=r"unknown shape kind 'spere' \(did you mean 'sphere'\?\)"):
        facet.ShapeDesc("spere")


def test_degenerate_triangles_are_dropped_with_a_warning():
    d = ts.numpy_description()
    p, i, n = ts.mesh_arrays()
    i = np.vstack([i, [[0, 0, 1]]]).astype(np.int32)  # zero area
    d.shapes[2].mesh = facet.MeshData(p, i, n)
    scene = facet.build_scene(d)
    assert scene.degenerate_triangles == 1
    assert any("tetra" in w for w in scene.warnings), scene.warnings
    reference = facet.render(facet.build_scene(ts.numpy_description()), spp=2)
    np.testing.assert_array_equal(facet.render(scene, spp=2), reference)


def test_description_pickles():
    d = ts.numpy_description()
    again = pickle.loads(pickle.dumps(d))
    assert again == d
    assert isinstance(again.shapes[2].mesh, facet.MeshData)


def test_kind_fields_come_from_the_kind_table(tmp_path):
    # Attributes are the kinds' keys (kinds.h); a key of another kind is refused by name.
    s = facet.ShapeDesc("grid", nx=3, ny=2, amplitude=0.5)
    assert (s.nx, s.ny, s.amplitude) == (3, 2, 0.5)
    with pytest.raises(TypeError, match=r"ShapeDesc has no field 'nx' for kind 'sphere' \(its fields: center, radius\)"):
        facet.ShapeDesc("sphere", nx=2)
    with pytest.raises(TypeError, match=r"LightDesc has no field 'radius' for kind 'point'"):
        facet.LightDesc("point", radius=1)
    assert "kinds: sphere, disc, icosphere" in facet.ShapeDesc.radius.__doc__


def test_export_pov_from_python(tmp_path, scenes_dir, facet_cli):
    # facet.export_pov is the library's exporter: the same SDL as `facet export-pov`.
    src = str(scenes_dir / "cornell_box.json")
    d = facet.read_scene_description(src)
    out = tmp_path / "cornell.pov"
    facet.export_pov(d, str(out), area_grid=2, name="cornell")
    text = out.read_text()
    assert "#version 3.7;" in text and "midpoint cells, grid 2" in text
    cli = tmp_path / "cli.pov"
    subprocess.run([str(facet_cli), "export-pov", src, "-o", str(cli), "--area-grid", "2"], check=True)
    # Identical but for the first comment line, which names the source.
    assert text.splitlines()[1:] == cli.read_text().splitlines()[1:]
    with pytest.raises(ValueError, match="--radiosity"):
        facet.export_pov(d, str(out), radiosity="medum")
    d.lights.append(facet.LightDesc("environment", radiance=0.1))
    with pytest.raises(ValueError, match=r"^cornell: /lights/0: an environment light"):
        facet.export_pov(d, str(out), name="cornell")
