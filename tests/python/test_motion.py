# Motion blur from Python (scenes/FORMAT.md, "Motion blur"): ShapeDesc.motion, CameraDesc.motion
# (facet.CameraStep) and RenderSettings.motion_blur (facet.MotionBlur) against the same scene
# read from JSON (equal descriptions, bit-identical images), the smear they render, and the
# errors naming the JSON pointer.
import json

import numpy as np
import pytest

import facet
import tiny_scenes as ts

STEPS = [np.eye(4), np.array([[1, 0, 0, 0.4], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], float)]


def scene_dict(blur=True):
    d = ts.scene_dict(spp=4)
    d["shapes"][2]["motion"] = [{"matrix": m.flatten().tolist()} for m in STEPS]
    d["camera"]["motion"] = [
        {"position": d["camera"]["position"], "look_at": d["camera"]["look_at"]},
        {"position": [p + 0.05 for p in d["camera"]["position"]],
         "look_at": d["camera"]["look_at"]}]
    d.setdefault("render", {})["motion_blur"] = {"shutter": 0.5, "position": "start",
                                                 "curve": [1, 2, 1]} if blur else False
    return d


def python_description(blur=True):
    d = ts.numpy_description(spp=4)
    d.shapes[2].motion = [m.copy() for m in STEPS]
    c = d.camera
    d.camera.motion = [facet.CameraStep(position=c.position, look_at=c.look_at, up=c.up),
                       facet.CameraStep(position=[p + 0.05 for p in c.position],
                                        look_at=c.look_at, up=c.up)]
    d.render.motion_blur = facet.MotionBlur(shutter=0.5, position="start", curve=[1, 2, 1]) \
        if blur else facet.MotionBlur(enabled=False)
    return d


def test_motion_from_python_equals_its_json_twin():
    built = python_description()
    parsed = facet.parse_scene_description(json.dumps(scene_dict()), name="twin")
    assert built.render.motion_blur == parsed.render.motion_blur
    assert built.camera.motion == parsed.camera.motion
    np.testing.assert_array_equal(built.shapes[2].motion[1], parsed.shapes[2].motion[1])
    a = facet.render(facet.build_scene(built, name="python"), threads=2)
    b = facet.render(facet.build_scene(parsed, name="twin"), threads=1)
    assert np.all(np.isfinite(a)) and a.max() > 0
    np.testing.assert_array_equal(a, b)
    again = facet.parse_scene_description(built.to_json(), name="again")
    assert again.render.motion_blur.curve == [1, 2, 1]
    assert len(again.shapes[2].motion) == 2


def test_motion_blur_changes_the_image_only_when_on():
    on = facet.render(facet.build_scene(python_description(), name="on"), threads=2)
    off = facet.render(facet.build_scene(python_description(blur=False), name="off"), threads=2)
    d = ts.numpy_description(spp=4)
    still = facet.render(facet.build_scene(d, name="still"), threads=2)
    np.testing.assert_array_equal(off, still)  # the still scene, bit for bit
    assert np.abs(on - still).max() > 0.01


def test_bad_motion_names_the_pointer():
    d = python_description()
    d.shapes[2].motion = [np.eye(4)]
    with pytest.raises(ValueError, match="/shapes/2/motion"):
        facet.build_scene(d, name="bad")
    d = python_description()
    d.render.motion_blur = facet.MotionBlur(shutter=0.0)
    with pytest.raises(ValueError, match="/render/motion_blur/shutter"):
        facet.build_scene(d, name="bad")


def deform_steps():
    """The tetrahedron's positions and normals at two steps: still, then 0.3 along x."""
    p, _, n = ts.mesh_arrays()
    return [p.ravel(), (p + np.float32([0.3, 0, 0])).ravel()], [n.ravel(), n.ravel()]


def deforming(d):
    pos, nrm = deform_steps()
    d.shapes[2].motion_positions = pos
    d.shapes[2].motion_normals = nrm
    d.render.motion_blur = facet.MotionBlur(shutter=0.5)
    return d


def test_deformation_from_python_equals_its_json_twin():
    built = deforming(ts.numpy_description(spp=4))
    j = ts.scene_dict(spp=4)
    pos, nrm = deform_steps()
    j["shapes"][2]["motion_positions"] = [[float(v) for v in st] for st in pos]
    j["shapes"][2]["motion_normals"] = [[float(v) for v in st] for st in nrm]
    j.setdefault("render", {})["motion_blur"] = {"shutter": 0.5}
    parsed = facet.parse_scene_description(json.dumps(j), name="twin")
    assert len(parsed.shapes[2].motion_positions) == 2
    np.testing.assert_array_equal(built.shapes[2].motion_positions[1],
                                  parsed.shapes[2].motion_positions[1])
    np.testing.assert_array_equal(built.shapes[2].motion_normals[0],
                                  parsed.shapes[2].motion_normals[0])
    a = facet.render(facet.build_scene(built, name="python"), threads=2)
    b = facet.render(facet.build_scene(parsed, name="twin"), threads=1)
    np.testing.assert_array_equal(a, b)
    still = facet.render(facet.build_scene(ts.numpy_description(spp=4), name="still"), threads=2)
    assert np.abs(a - still).max() > 0.01  # the tetrahedron smears
    again = facet.parse_scene_description(built.to_json(), name="again")
    assert len(again.shapes[2].motion_positions) == 2


def test_bad_deformation_names_the_pointer():
    d = deforming(ts.numpy_description(spp=4))
    pos = d.shapes[2].motion_positions
    d.shapes[2].motion_positions = [pos[0], pos[1][:-3]]
    with pytest.raises(ValueError, match="/shapes/2/motion_positions/1"):
        facet.build_scene(d, name="bad")
    d = deforming(ts.numpy_description(spp=4))
    bad = d.shapes[2].motion_positions[1].copy()
    bad[0] = np.nan
    d.shapes[2].motion_positions = [d.shapes[2].motion_positions[0], bad]
    with pytest.raises(ValueError, match="/shapes/2/motion_positions/1/0"):
        facet.build_scene(d, name="bad")
    d = deforming(ts.numpy_description(spp=4))
    d.shapes[2].motion_normals = []
    with pytest.raises(ValueError, match="/shapes/2/motion_positions.*motion_normals"):
        facet.build_scene(d, name="bad")
