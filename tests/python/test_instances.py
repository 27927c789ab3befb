# Instancing from Python: prototypes (dict name -> [ShapeDesc]) and ShapeDesc("instance"),
# against the same scene read from JSON (equal descriptions, bit-identical images), the
# POV-Ray export's declaration, and the error for an unknown prototype.
import json

import numpy as np
import pytest

import facet
import tiny_scenes as ts

TETRA_AT = [np.array([[1, 0, 0, -0.5], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], float),
            # a rotation of 90 degrees about y, a non-uniform scale, a translation
            np.array([[0, 0, 0.5, 0.6], [0, 1.5, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1]], float)]


def scene_dict():
    d = ts.scene_dict(spp=4)
    tetra = d["shapes"].pop(2)
    d["prototypes"] = {"tetra": [tetra]}
    for m in TETRA_AT:
        d["shapes"].append({"type": "instance", "of": "tetra",
                            "transform": {"matrix": m.flatten().tolist()}})
    return d


def python_description():
    d = ts.numpy_description(spp=4)
    tetra = d.shapes.pop(2)
    d.prototypes["tetra"] = [tetra]
    for m in TETRA_AT:
        d.shapes.append(facet.ShapeDesc("instance", of="tetra", transform=m))
    return d


def test_prototypes_from_python_equal_their_json_twin():
    built = python_description()
    parsed = facet.parse_scene_description(json.dumps(scene_dict()), name="twin")
    assert list(built.prototypes) == ["tetra"]
    assert built == parsed
    assert facet.fingerprint(built) == facet.fingerprint(parsed)
    a = facet.render(facet.build_scene(built, name="python"), threads=2)
    b = facet.render(facet.build_scene(parsed, name="twin"), threads=1)
    assert np.all(np.isfinite(a)) and a.max() > 0
    np.testing.assert_array_equal(a, b)
    # Round trip through the JSON writer keeps the prototypes.
    again = facet.parse_scene_description(built.to_json(), name="again")
    assert again == built and len(again.prototypes["tetra"]) == 1


def test_pov_export_declares_the_prototype(tmp_path):
    path = tmp_path / "inst.pov"
    facet.export_pov(python_description(), str(path))
    pov = path.read_text()
    assert pov.count("#declare FacetPrototype0 = union {") == 1
    assert pov.count("object { FacetPrototype0") == 2


def test_unknown_prototype_names_the_pointer():
    d = python_description()
    d.shapes[-1].of = "tree"
    with pytest.raises(ValueError, match=r"/shapes/4/of: unknown prototype 'tree'"):
        facet.build_scene(d, name="python")
    d.prototypes["tetra"] = [1]
    with pytest.raises(TypeError, match=r"prototypes\['tetra'\]\[0\]"):
        facet.build_scene(d, name="python")
