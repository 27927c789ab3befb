# Small scenes for the Python tests: a JSON scene with analytic shapes, an inline mesh, an
# area light and a point light, and the same scene built from numpy arrays.
import json

import numpy as np

import facet

WIDTH, HEIGHT = 40, 30


def mesh_arrays():
    """A tetrahedron with per-vertex normals (float32 / int32), exactly representable in JSON."""
    positions = np.array([[-0.5, 0.0, -0.25], [0.25, 0.0, -0.5], [0.0, 0.0, 0.25],
                          [-0.125, 0.75, -0.125]], dtype=np.float32)
    indices = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]], dtype=np.int32)
    normals = positions - positions.mean(axis=0)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return positions, indices, normals.astype(np.float32)


def scene_dict(spp=8, width=WIDTH, height=HEIGHT):
    positions, indices, normals = mesh_arrays()
    return {
        "format": "facet-scene",
        "version": 1,
        "description": "python test scene",
        "camera": {"position": [0, 1, 3], "look_at": [0, 0.3, 0], "up": [0, 1, 0], "fov": 45,
                   "width": width, "height": height},
        "render": {"integrator": "path", "spp": spp, "max_depth": 4, "seed": 7},
        "materials": {
            "gold": {"model": "ggx", "alpha": 0.3, "fresnel": "conductor"},
            "white": {"model": "lambert", "reflectance": 0.7},
            "red": {"model": "lambert", "reflectance": [0.6, 0.1, 0.1]},
        },
        "shapes": [
            {"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0],
             "material": "white"},
            {"type": "sphere", "center": [0.7, 0.3, 0], "radius": 0.3, "material": "gold"},
            {"type": "mesh", "name": "tetra", "material": "red",
             "positions": [float(v) for v in positions.ravel()],
             "indices": [int(v) for v in indices.ravel()],
             "normals": [float(v) for v in normals.ravel()]},
            {"type": "quad", "name": "lamp", "emission": 4,
             "vertices": [[-0.5, 2, -0.5], [0.5, 2, -0.5], [0.5, 2, 0.5], [-0.5, 2, 0.5]]},
        ],
        "lights": [{"type": "point", "position": [-1, 1.5, 1], "power": 20}],
    }


def scene_json(spp=8, width=WIDTH, height=HEIGHT):
    return json.dumps(scene_dict(spp, width, height), indent=1)


def numpy_description(spp=8):
    """The scene of scene_dict(), built field by field from Python and numpy arrays."""
    positions, indices, normals = mesh_arrays()
    d = facet.SceneDescription()
    d.description = "python test scene"
    d.camera = facet.CameraDesc(position=(0, 1, 3), look_at=(0, 0.3, 0), up=(0, 1, 0), fov=45,
                                width=WIDTH, height=HEIGHT)
    d.render = facet.RenderSettings(integrator="path", spp=spp, max_depth=4, seed=7)
    # In name order: the JSON reader gives materials sorted (scene_description.h).
    d.materials["gold"] = facet.MaterialDesc("ggx", alpha=0.3, fresnel="conductor")
    d.materials["red"] = facet.MaterialDesc("lambert", reflectance=(0.6, 0.1, 0.1))
    d.materials["white"] = facet.MaterialDesc("lambert", reflectance=0.7)
    d.shapes.append(facet.ShapeDesc("plane", name="floor", point=(0, 0, 0), normal=(0, 1, 0),
                                    material_ref="white"))
    d.shapes.append(facet.ShapeDesc("sphere", center=(0.7, 0.3, 0), radius=0.3,
                                    material_ref="gold"))
    d.shapes.append(facet.ShapeDesc(name="tetra", positions=positions, indices=indices,
                                    normals=normals, material_ref="red"))
    lamp = facet.ShapeDesc("quad", name="lamp", emission=4)
    lamp.vertices = [(-0.5, 2, -0.5), (0.5, 2, -0.5), (0.5, 2, 0.5), (-0.5, 2, 0.5)]
    d.shapes.append(lamp)
    d.lights.append(facet.LightDesc("point", position=(-1, 1.5, 1), power=20))
    return d


def write_scene(tmp_path, spp=8, name="scene.json"):
    path = tmp_path / name
    path.write_text(scene_json(spp))
    return path
