# SceneDescription from Python: JSON read/write round trips, a numpy-built scene against its
# JSON twin (bit for bit), zero-copy meshes kept alive, and clear errors for bad arrays.
import gc
import pathlib
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
    with pytest.raises(ValueError, match="normals, uvs, tangents and colors need positions and indices"):
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


def test_mix_and_add_from_python():
    """mix/add take materials=[a, b] (names or MaterialDesc, nested); they round-trip through
    JSON, render, and a cycle names the pointer of the reference."""
    d = ts.numpy_description()
    inner = facet.MaterialDesc("add", materials=[facet.MaterialDesc("oren_nayar", sigma=0.4),
                                                 "white"])
    d.materials["blend"] = facet.MaterialDesc("mix", weight=0.3, materials=["red", inner])
    d.shapes[2].material_ref = "blend"
    blend = d.materials["blend"]
    assert blend.materials[0] == "red"
    assert blend.materials[1].model == "add"
    assert blend.materials[1].materials[1] == "white"
    # (The JSON reader sorts materials by name, so compare the material, not the order.)
    assert facet.parse_scene_description(d.to_json(), name="twin").materials["blend"] == blend
    image = facet.render(facet.build_scene(d, name="py"), spp=2)
    assert np.all(np.isfinite(image)) and image.max() > 0
    d.materials["loop"] = facet.MaterialDesc("mix", materials=["loop", "white"])
    with pytest.raises(ValueError, match=r"/materials/loop/materials/0: material 'loop' refers to itself"):
        facet.build_scene(d, name="py")
    with pytest.raises(ValueError, match="materials"):
        facet.MaterialDesc("mix", materials=[1, 2])


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
    with pytest.raises(TypeError, match=r"LightDesc has no field 'angle' for kind 'point'"):
        facet.LightDesc("point", angle=1)
    # Lights with size (FORMAT.md): the sphere's radius, the sun's angle, the area lamp.
    assert facet.LightDesc("point", radius=0.5).radius == 0.5
    assert facet.LightDesc("directional", angle=0.53).angle == 0.53
    lamp = facet.LightDesc("area", shape="rectangle", size=2, size_y=0.5, power=10,
                           position=[0, 2, 0], direction=[0, -1, 0])
    assert (lamp.shape, lamp.size, lamp.size_y) == ("rectangle", 2, 0.5)
    assert lamp.camera_visible is False  # Blender's default for lamps
    # light_kind_keys(): each kind's keys in the table's order (what the Blender addon copies).
    keys = facet.light_kind_keys()
    assert set(keys) == {"point", "spot", "directional", "environment", "area", "sky_nishita"}
    assert {"sun_elevation", "sun_disc", "altitude", "rotate"} <= set(keys["sky_nishita"])
    sky = facet.LightDesc("sky_nishita", sun_elevation=30.0, sun_disc=False)
    assert (sky.sun_elevation, sky.sun_disc, sky.air_density) == (30.0, False, 1.0)
    assert keys["point"][:2] == ("position", "power") and "radius" in keys["point"]
    assert "camera_visible" in keys["area"] and "radius" not in keys["area"]
    assert {"file", "rotate", "up"} <= set(keys["environment"])
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


def test_camera_lens_and_projection_attributes():
    """The thin-lens, orthographic and shift keys are CameraDesc attributes: None when unset,
    written to JSON when set, and equal after a round trip."""
    d = facet.parse_scene_description(ts.scene_json(), name="twin")
    c = d.camera
    assert c.type == "perspective" and c.scale is None and c.aperture_radius is None
    assert (c.shift_x, c.shift_y, c.blades, c.rotation) == (0, 0, 0, 0)
    c.fstop, c.focal_length, c.focus_distance, c.blades, c.rotation = 2.8, 50, 2.5, 6, 15
    c.shift_x = 0.1
    d.camera = c
    text = facet.write_scene_json(d)
    for key in ('"fstop": 2.8', '"focal_length": 50', '"blades": 6', '"shift_x": 0.1'):
        assert key in text
    again = facet.parse_scene_description(text, name="lens")
    assert again == d and again.camera.focus_distance == pytest.approx(2.5)
    o = facet.CameraDesc(position=(0, 0, 5), look_at=(0, 0, 0), width=8, height=6,
                         type="orthographic", scale=3.0)
    assert o.scale == 3.0 and "orthographic" in repr(o)
    d.camera = o
    assert '"scale": 3' in facet.write_scene_json(d)
    d.camera.scale = -1.0
    with pytest.raises(ValueError, match="/camera/scale"):
        facet.build_scene(d, name="bad")


def test_environment_map_keys_through_the_kind_table(tmp_path):
    # "file", "up" and "rotate" (a dict, as in JSON) are LightDesc keywords of the environment
    # kind only; the map renders: a camera along +X sees the map's centre column (u = 0.5).
    sky = np.zeros((4, 8, 3), np.float32)
    sky[:, :, 0] = np.arange(8, dtype=np.float32)[None, :] + 1.0  # red = column + 1
    sky[:, :, 1] = 0.5
    path = tmp_path / "sky.exr"
    facet.write_image(sky, str(path))
    light = facet.LightDesc("environment", file=str(path), up=(0, 0, 1),
                            rotate={"axis": (0, 0, 1), "angle": 90.0}, radiance=2)
    assert light.rotate == {"axis": (0.0, 0.0, 1.0), "angle": 90.0}
    assert light.file == str(path) and light.up == (0.0, 0.0, 1.0)
    with pytest.raises(TypeError, match=r"LightDesc has no field 'file' for kind 'point'"):
        facet.LightDesc("point", file="sky.exr")
    d = facet.SceneDescription()
    d.camera = facet.CameraDesc(position=(0, 0, 0), look_at=(0, 1, 0), up=(0, 0, 1), fov=1,
                                width=1, height=1)
    d.lights.append(light)
    # Rotated 90 degrees about +Z, the map's +X (u = 0.5: columns 3 and 4, red 4.5) is world +Y.
    img = facet.render(facet.build_scene(d), spp=1)
    np.testing.assert_allclose(img[0, 0], [2 * 4.5, 2 * 0.5, 0.0], rtol=1e-4)
    light.rotate = {"axis": (0, 0, 0), "angle": 1.0}
    d.lights[0] = light
    with pytest.raises(ValueError, match=r"/lights/0/rotate/axis"):
        facet.build_scene(d)


def test_gltf_shape_through_the_kind_table():
    # The gltf kind's keys come from the kind table like every other kind's; its parts keep
    # their own materials, and what is not converted is in Scene.warnings.
    gltf_dir = pathlib.Path(__file__).resolve().parent.parent / "render" / "gltf"
    s = facet.ShapeDesc("gltf", file=str(gltf_dir / "modes.gltf"))
    assert s.file.endswith("modes.gltf")
    with pytest.raises(TypeError, match=r"ShapeDesc has no field 'radius' for kind 'gltf'"):
        facet.ShapeDesc("gltf", radius=1)
    d = ts.numpy_description()
    d.shapes = [s]
    d.lights = [facet.LightDesc("environment", radiance=1.0)]
    scene = facet.build_scene(d)
    assert any("modes.gltf#/meshes/0/primitives/3/mode" in w for w in scene.warnings), \
        scene.warnings
    img = facet.render(scene, spp=1)
    assert np.isfinite(img).all()
    d.shapes = [facet.ShapeDesc("gltf", file=str(gltf_dir / "bad_index.gltf"))]
    with pytest.raises(ValueError, match=r"/shapes/0/file: bad_index.gltf#/accessors/1: index 2"):
        facet.build_scene(d)


def _texel_quad_scene(texture):
    """A 4 x 3 camera whose pixel centres hit the texel centres of a 4 x 3 Lambertian quad under
    a constant environment of radiance 1 (max_depth 1): each pixel is its texel's reflectance
    (as tests/render/test_textures.cpp, LambertQuadRendersEachTexelsLinearReflectance)."""
    d = facet.SceneDescription()
    d.camera = facet.CameraDesc(position=(0, 0, 1.5), look_at=(0, 0, 0), up=(0, 1, 0), fov=90,
                                width=4, height=3)
    d.render = facet.RenderSettings(integrator="path", spp=1, max_depth=1, seed=1)
    quad = facet.ShapeDesc("quad", material=facet.MaterialDesc("lambert", reflectance=texture))
    quad.vertices = [(-2, -1.5, 0), (2, -1.5, 0), (2, 1.5, 0), (-2, 1.5, 0)]
    d.shapes.append(quad)
    d.lights.append(facet.LightDesc("environment", radiance=1))
    return d


def _srgb_decode(codes):
    e = codes.astype(np.float64) / 255.0
    return np.where(e <= 0.04045, e / 12.92, ((e + 0.055) / 1.055) ** 2.4).astype(np.float32)


def test_numpy_textures_render_their_texels():
    """facet.Texture from a numpy array: array[0] is the top row; uint8 is sRGB-decoded by
    default with the exact piecewise curve, float32 is linear. Every path sample returns the
    texel's reflectance (cosine sampling), so the tolerance is float rounding: 2e-7 relative;
    a wrong row order or decoding is off by > 1e-2."""
    codes = (np.arange(36, dtype=np.int64).reshape(3, 4, 3) * 7 + 3).astype(np.uint8)
    cases = [(facet.Texture(codes, filter="closest"), _srgb_decode(codes)),
             (facet.Texture(codes, colorspace="linear", filter="closest"),
              (codes / np.float32(255)).astype(np.float32)),
             (facet.Texture(codes.astype(np.float32) / 300, filter="closest"),
              codes.astype(np.float32) / 300),
             # Grey H x W: one channel, read as grey.
             (facet.Texture(codes[:, :, 0].astype(np.float32) / 300, filter="closest"),
              np.repeat(codes[:, :, :1].astype(np.float32) / 300, 3, axis=2))]
    for texture, want in cases:
        assert texture.shape[:2] == (3, 4)
        image = facet.render(facet.build_scene(_texel_quad_scene(texture)), spp=1)
        np.testing.assert_allclose(image, want, rtol=2e-7, atol=0)
    # Non-contiguous input is copied, not misread.
    flipped = np.ascontiguousarray(codes[::-1])[::-1]
    image = facet.render(facet.build_scene(_texel_quad_scene(
        facet.Texture(flipped, filter="closest"))), spp=1)
    np.testing.assert_allclose(image, _srgb_decode(codes), rtol=2e-7, atol=0)


def test_composite_textures_from_python():
    """Composite kinds (math, vector_math, mix_rgb, color_ramp) from Python: textures as inputs, colours as
    tuples, stops as (position, colour) pairs; they round-trip through JSON, render (a mix of
    constants is its value: 0.2 + 0.25 (0.8 - 0.2), ..., exact to float rounding as the texel
    test above), and a bad operation names its JSON pointer."""
    mix = facet.Texture.procedural('mix_rgb', blend_type='mix', fac=0.25,
                                   color1=(0.2, 0.4, 0.6), color2=(0.8, 0.8, 0.8))
    image = facet.render(facet.build_scene(_texel_quad_scene(mix)), spp=1)
    np.testing.assert_allclose(image, np.broadcast_to([0.35, 0.5, 0.65], image.shape),
                               rtol=2e-7, atol=0)
    noise = facet.Texture.procedural('noise', coordinates='object', scale=4.0)
    ramp = facet.Texture.procedural(
        'color_ramp', fac=facet.Texture.procedural('math', operation='power', a=noise, b=2.0,
                                                   use_clamp=True),
        interpolation='ease', stops=[(0.2, (1.0, 0.0, 0.0)), (0.8, (0.0, 0.0, 1.0, 0.5))])
    d = _texel_quad_scene(ramp)
    assert facet.parse_scene_description(d.to_json(), name="twin") == d
    image = facet.render(facet.build_scene(d), spp=1)
    assert np.all(np.isfinite(image)) and image.max() > 0
    bad = facet.Texture.procedural('math', operation='multiplyy', a=noise)
    with pytest.raises(ValueError, match=r"/shapes/0/material/reflectance/math/operation"):
        facet.build_scene(_texel_quad_scene(bad), name="py")
    # vector_math: a dot product of constants on the Value output (0.1 + 0.1 + 0.3, to float
    # rounding: 1e-6), a scale of a texture round-tripping, the output an operation lacks.
    dot = facet.Texture.procedural('vector_math', operation='dot_product', output='value',
                                   a=(0.2, 0.4, 0.6), b=(0.5, 0.25, 0.5))
    image = facet.render(facet.build_scene(_texel_quad_scene(dot)), spp=1)
    np.testing.assert_allclose(image, np.broadcast_to(0.5, image.shape), rtol=1e-6, atol=0)
    d = _texel_quad_scene(facet.Texture.procedural('vector_math', operation='scale', a=noise,
                                                   scale=0.5))
    assert facet.parse_scene_description(d.to_json(), name="twin") == d
    bad = facet.Texture.procedural('vector_math', operation='length', a=noise)
    with pytest.raises(ValueError, match=r"/shapes/0/material/reflectance/vector_math/output"):
        facet.build_scene(_texel_quad_scene(bad), name="py")


def test_numpy_texture_bad_input_is_a_clear_error():
    good = np.zeros((2, 2, 3), dtype=np.float32)
    bad = [(np.zeros((2, 2, 3), dtype=np.float64), r"dtype float64, expected float32 or uint8"),
           (np.zeros((2, 2, 2), dtype=np.float32), r"shape \(2, 2, 2\), expected"),
           (np.zeros((2, 2, 3, 1), dtype=np.float32), r"shape \(2, 2, 3, 1\), expected"),
           (np.zeros((0, 2, 3), dtype=np.float32), r"is empty"),
           ([[1.0, 2.0]], r"expected a file name \(str\) or a numpy array, got <class .list.>")]
    nan = good.copy()
    nan[1, 0, 2] = np.nan
    bad.append((nan, r"texel \(0, 1\) channel 2 is nan"))
    inf = good.copy()
    inf[0, 1, 0] = -np.inf
    bad.append((inf, r"texel \(1, 0\) channel 0 is -inf"))
    for array, message in bad:
        with pytest.raises((ValueError, TypeError), match=message):
            facet.Texture(array)
    with pytest.raises(ValueError, match=r"colorspace.*'srbg'"):
        facet.Texture(good, colorspace="srbg")
    # A numpy texture cannot be written to a scene file (the fingerprint hashes its texels).
    d = _texel_quad_scene(facet.Texture(good))
    assert d.shapes[0].material.textures["reflectance"].shape == (2, 2, 3)
    with pytest.raises(ValueError, match=r"in-memory \(numpy\) texture cannot be written"):
        d.to_json()
    facet.build_scene(d)


def test_material_desc_normal_map_and_bump(tmp_path):
    """MaterialDesc's normal_map / bump dicts (FORMAT.md keys, defaults filled in), None to
    remove, errors naming the argument; a mix takes names and nested MaterialDesc."""
    tex = facet.Texture.checker((0.5, 0.5, 1.0), (0.6, 0.5, 0.9))
    m = facet.MaterialDesc("lambert", {"normal_map": {"texture": tex, "strength": 0.5},
                                       "bump": {"texture": tex, "distance": 0.1}})
    assert m.normal_map == {"texture": tex, "strength": 0.5, "xy_scale": 1.0}
    assert m.bump == {"texture": tex, "distance": 0.1, "strength": 1.0}
    m.bump = None
    assert m.bump is None
    for bad, msg in (({"texture": tex, "xy_scale": 1}, "unknown key 'xy_scale'"),
                     ({"texture": tex, "distance": "x"}, "expected a number"),
                     ({"distance": 1}, "expected a facet.Texture")):
        with pytest.raises(ValueError, match=msg):
            facet.MaterialDesc("lambert", {"bump": bad})
    mix = facet.MaterialDesc("mix", {"weight": 0.25, "materials": ["a", m]})
    assert mix.materials[0] == "a" and mix.materials[1] == m


def _vertex_colour_triangle_scene(colors, reflectance):
    """The 4 x 3 texel camera over a Lambertian triangle P0 (-2, -1.5), P1 (2, -1.5),
    P2 (-2, 1.5) with vertex colours, under a constant environment of radiance 1, max_depth 1:
    each pixel is the reflectance at its centre (tests/render/test_vertex_colors.cpp)."""
    d = _texel_quad_scene(facet.Texture.checker([0.5] * 3, [0.5] * 3))
    positions = np.array([[-2, -1.5, 0], [2, -1.5, 0], [-2, 1.5, 0]], dtype=np.float32)
    indices = np.array([[0, 1, 2]], dtype=np.int32)
    d.shapes[0] = facet.ShapeDesc(positions=positions, indices=indices, colors=colors,
                                  material=facet.MaterialDesc("lambert", reflectance=reflectance))
    return d


def test_vertex_colours_from_python():
    """MeshData colors (n, 3) or (n, 4) and Texture.vertex_color(): they round-trip through
    JSON, and a pixel centre at barycentrics (b0, b1, b2) renders b0 c0 + b1 c1 + b2 c2 (every
    cosine-weighted sample returns the reflectance: tolerance 2e-6 for Embree's float
    barycentrics); a mesh without colours names the pointer and the material."""
    colors = np.array([[0.9, 0.1, 0.2, 1.0], [0.1, 0.8, 0.3, 0.5], [0.2, 0.3, 0.7, 0.25]],
                      dtype=np.float32)
    d = _vertex_colour_triangle_scene(colors, facet.Texture.vertex_color())
    assert d.shapes[0].mesh.colors.shape == (3, 4)
    np.testing.assert_array_equal(d.shapes[0].mesh.colors, colors)
    tex = d.shapes[0].material.textures["reflectance"]
    assert tex.is_vertex_color and tex.channel == "" and tex.scale == 1.0
    assert facet.parse_scene_description(d.to_json(), name="twin") == d
    image = facet.render(facet.build_scene(d, name="py"), spp=1)
    for y in range(3):
        for x in range(4):
            b1, b2 = (x - 1.5 + 2) / 4, (1 - y + 1.5) / 3
            b0 = 1 - b1 - b2
            if b0 < 0:
                continue
            want = b0 * colors[0, :3] + b1 * colors[1, :3] + b2 * colors[2, :3]
            np.testing.assert_allclose(image[y, x], want, rtol=0, atol=2e-6)
    # RGB colours, one channel as grey.
    d = _vertex_colour_triangle_scene(colors[:, :3].copy(),
                                      facet.Texture.vertex_color(channel="g", scale=0.5))
    assert d.shapes[0].mesh.colors.shape == (3, 3)
    assert facet.parse_scene_description(d.to_json(), name="twin") == d
    facet.build_scene(d, name="py")
    d.shapes[0] = facet.ShapeDesc(positions=d.shapes[0].mesh.positions,
                                  indices=d.shapes[0].mesh.indices,
                                  material=facet.MaterialDesc(
                                      "lambert", reflectance=facet.Texture.vertex_color()))
    with pytest.raises(ValueError, match=r"/shapes/0/colors: the material '<inline>'.*no colours"):
        facet.build_scene(d, name="py")
    with pytest.raises(ValueError, match="colors"):
        facet.MeshData(colors[:, :3], np.array([[0, 1, 2]], dtype=np.int32),
                       colors=colors[:2])


def test_every_model_of_the_table_through_json_python_and_a_render():
    """Each model unit of the core's table (facet.models()) is a MaterialDesc from Python with
    its defaults, round-trips through the JSON writer and reader, builds, and renders finite
    non-negative pixels; combinations take the table's number of sub-materials."""
    names = []
    for info in facet.models():
        d = ts.numpy_description()
        kids = ["red", "white"][:info.children]
        d.materials["m"] = (facet.MaterialDesc(info.name, materials=kids) if kids
                            else facet.MaterialDesc(info.name))
        d.shapes[2].material_ref = "m"
        assert facet.parse_scene_description(d.to_json(), name="twin").materials["m"] == \
            d.materials["m"], info.name
        image = facet.render(facet.build_scene(d, name=info.name), spp=2)
        assert np.all(np.isfinite(image)) and image.min() >= 0.0, info.name
        names.append(info.name)
        # The table's choices are what the builder accepts: each one builds.
        for p in info.params:
            for c in p.choices:
                if not info.children:
                    facet.make_material(info.name, **{p.name: c})
    assert {"translucent", "velvet", "oren_nayar", "principled"} <= set(names)


def test_media_from_python():
    # Media, the world medium and a material's interior, as the JSON format has them
    # (scenes/FORMAT.md, "Media"), with the kind table's fields as attributes.
    d = facet.SceneDescription()
    d.camera = facet.CameraDesc(position=(0, 0, 5), look_at=(0, 0, 0), fov=30, width=8, height=8)
    d.media = {"fog": facet.MediumDesc("homogeneous", sigma_s=(1, 2, 3), g=0.5),
               "smoke": facet.MediumDesc("homogeneous", density=2.0, color=(0.8, 0.5, 0.2))}
    d.world_medium = "fog"
    d.materials = {"b": facet.MaterialDesc("null", interior="smoke")}
    d.shapes = [facet.ShapeDesc("sphere", center=(0, 0, 0), radius=1, material_ref="b")]
    d.lights = [facet.LightDesc("environment", radiance=(1, 1, 1))]
    again = facet.parse_scene_description(d.to_json(), name="media")
    assert again == d
    assert again.media["fog"].g == pytest.approx(0.5)
    assert again.media["smoke"].density == pytest.approx(2.0)
    assert again.world_medium == "fog"
    scene = facet.build_scene(d, name="media")
    assert scene is not None
    with pytest.raises(TypeError, match="no field 'sigma_z'"):
        facet.MediumDesc("homogeneous", sigma_z=1)
    with pytest.raises(ValueError, match="did you mean 'homogeneous'"):
        facet.MediumDesc("homogenous")
    d.media["fog"].g = 2.0
    with pytest.raises(Exception, match="/media/fog/g"):
        facet.build_scene(d, name="media")
    # A grid medium: its file, grid name and placement round-trip; a missing file is an
    # error naming the pointer (the renders from files are the C++ GridMedia tests).
    place = np.array([[2, 0, 0, 1], [0, 2, 0, 0], [0, 0, 2, 0], [0, 0, 0, 1]], dtype=float)
    g = facet.SceneDescription()
    g.camera = d.camera
    g.media = {"smoke": facet.MediumDesc("grid", file="no_such.vdb", grid="flame", density=3.0,
                                         color=(0.9, 0.9, 0.9))}
    g.media["smoke"].transform = place
    g.materials = {"b": facet.MaterialDesc("null", interior="smoke")}
    g.shapes = [facet.ShapeDesc("sphere", center=(0, 0, 0), radius=1, material_ref="b")]
    g.lights = [facet.LightDesc("environment", radiance=(1, 1, 1))]
    back = facet.parse_scene_description(g.to_json(), name="grid")
    assert back == g
    assert back.media["smoke"].grid == "flame"
    assert np.array_equal(np.asarray(back.media["smoke"].transform), place)
    with pytest.raises(Exception, match="/media/smoke/file: .*no_such.vdb.*cannot read"):
        facet.build_scene(g, name="grid")
    # Cycles' Principled Volume, through the core's one conversion.
    sigma_a, sigma_s = facet.cycles_volume(2.0, (0.8, 0.5, 0.2), 0.25)
    assert sigma_s == pytest.approx((1.6, 1.0, 0.4))
    assert sigma_a == pytest.approx((0.2, 0.5, 0.8))


def test_curves_from_python_against_json():
    # A curves shape built from numpy arrays (facet.CurveData) is the JSON shape's twin: equal
    # descriptions and the same image bit for bit; bad arrays are errors naming the key.
    d = facet.parse_scene_description(ts.scene_json(spp=2), name="twin")
    points = np.array([[0, 0, 0], [0.1, 0.3, 0], [0.2, 0.6, 0.1], [0.2, 0.9, 0.2],
                       [-0.5, 0, 0], [-0.5, 0.5, 0]], dtype=np.float32)
    radius = np.array([0.02, 0.02, 0.015, 0.005, 0.03, 0.01], dtype=np.float32)
    hair = facet.ShapeDesc("curves", basis="catmull_rom", profile="round",
                           curves=facet.CurveData(points=points, radius=radius, counts=[4, 2]),
                           material_ref="red")
    # catmull_rom needs 4 points per strand: the second strand is refused by its pointer.
    d.shapes = list(d.shapes) + [hair]
    with pytest.raises(Exception, match=r"/shapes/4/counts/1: a catmull_rom strand needs at "
                                         r"least 4 control points"):
        facet.build_scene(d, name="py")
    hair.basis = "linear"
    d.shapes = list(d.shapes)[:4] + [hair]
    assert hair.curves.num_points == 6
    np.testing.assert_array_equal(hair.curves.points, points)
    np.testing.assert_array_equal(hair.curves.counts, [4, 2])
    assert facet.CurveData(points=points, radius=0.25).radius == 0.25
    text = facet.write_scene_json(d)
    assert '"basis": "linear"' in text
    again = facet.parse_scene_description(text, name="again")
    assert again == d
    a = facet.render(facet.build_scene(d, name="py"), spp=2)
    b = facet.render(facet.build_scene(again, name="json"), spp=2)
    np.testing.assert_array_equal(a, b)


def test_curves_strand_random():
    # Per-strand random values: given as an array (facet.CurveData strand_random) they survive
    # the JSON round trip; facet.curve_random is Cycles' hash of the strand index (the values
    # a shape without them gets; independent lookup3 values of tests/render/test_curves.cpp).
    np.testing.assert_array_equal(facet.curve_random([0, 1, 7]),
                                  np.array([0.8603127598762512, 0.29501262307167053,
                                            0.7391559481620789], np.float32))
    with pytest.raises(ValueError, match=r"indices\[1\]"):
        facet.curve_random([0, -1])
    d = facet.parse_scene_description(ts.scene_json(spp=2), name="random")
    points = np.array([[0, 0, 0], [0, 0.5, 0], [0.5, 0, 0], [0.5, 0.5, 0]], dtype=np.float32)
    c = facet.CurveData(points=points, radius=0.02, counts=[2, 2],
                        strand_random=np.array([0.25, 0.75], np.float32))
    np.testing.assert_array_equal(c.strand_random, [0.25, 0.75])
    assert facet.CurveData(points=points, radius=0.02).strand_random is None
    d.shapes = list(d.shapes) + [facet.ShapeDesc("curves", basis="linear", curves=c,
                                                 material_ref="red")]
    text = facet.write_scene_json(d)
    assert '"strand_random"' in text
    assert facet.parse_scene_description(text, name="again") == d


def test_ray_visibility_and_light_path_switches():
    """ShapeDesc.visibility as a dict of the six ray kinds, ShapeDesc.light_path as a list of
    switch dicts (scenes/FORMAT.md "Ray visibility", "Light Path switches"): set, read back,
    through JSON and back; bad names are clear errors."""
    s = facet.ShapeDesc("sphere", radius=0.5)
    assert s.visibility == {"camera": True, "diffuse": True, "glossy": True,
                            "transmission": True, "volume_scatter": True, "shadow": True}
    s.visibility = {"camera": False, "shadow": False}
    assert [k for k, v in s.visibility.items() if not v] == ["camera", "shadow"]
    with pytest.raises(ValueError, match="camra"):
        s.visibility = {"camra": False}
    with pytest.raises(TypeError, match="shadow"):
        s.visibility = {"shadow": 0}
    s.light_path = [{"ray": "shadow", "material": facet.MaterialDesc("null")},
                    {"ray": "camera", "material": "white", "emission": (0.0, 1.0, 2.0)}]
    got = s.light_path
    assert [e["ray"] for e in got] == ["shadow", "camera"]
    assert got[0]["material"].model == "null" and got[1]["material"] == "white"
    assert tuple(got[1]["emission"]) == pytest.approx((0.0, 1.0, 2.0))
    with pytest.raises(ValueError, match="camra"):
        s.light_path = [{"ray": "camra"}]
    d = facet.parse_scene_description(ts.scene_json())
    d.shapes[0].visibility = {"diffuse": False}
    d.shapes[0].light_path = [{"ray": "camera", "emission": (1.0, 1.0, 1.0)}]
    again = facet.parse_scene_description(facet.write_scene_json(d))
    assert again == d
    assert again.shapes[0].visibility["diffuse"] is False
    assert again.shapes[0].light_path[0]["ray"] == "camera"
