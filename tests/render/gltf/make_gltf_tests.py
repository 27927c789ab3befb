#!/usr/bin/env python3
"""Writes the glTF files of tests/render/test_gltf.cpp (committed; rerun after changing this):
    /usr/bin/python3 tests/render/gltf/make_gltf_tests.py
The expected values the C++ test checks are stated next to each file here."""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "support", "python"))
from facet_testsupport.gltf_writer import (GltfWriter, TRIANGLE_FAN, TRIANGLE_STRIP, U8, U32,
                                           LINES)


def box():
    """Box [-1, 1] x [-0.5, 0.5] x [-0.25, 0.25] (glTF axes), 24 vertices, u16 indices, one
    material (base 0.8 0.4 0.2, metallic 0.25, roughness 0.5, emissive (1, 0.5, 0) x 3,
    double-sided)."""
    w = GltfWriter()
    hx, hy, hz = 1.0, 0.5, 0.25
    pos, nrm, idx = [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = sign
            u, v = [(a) for a in range(3) if a != axis]
            base = len(pos)
            corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
            for cu, cv in corners:
                p = [0.0, 0.0, 0.0]
                p[axis] = sign
                p[u], p[v] = cu, cv
                pos.append((p[0] * hx, p[1] * hy, p[2] * hz))
                nrm.append(tuple(n))
            # Counter-clockwise seen from outside: (u, v, n) right-handed or not decides.
            un = [0.0] * 3
            un[u] = 1.0
            vn = [0.0] * 3
            vn[v] = 1.0
            cross = (un[1] * vn[2] - un[2] * vn[1], un[2] * vn[0] - un[0] * vn[2],
                     un[0] * vn[1] - un[1] * vn[0])
            if sum(c * d for c, d in zip(cross, n)) > 0:
                idx += [base, base + 1, base + 2, base, base + 2, base + 3]
            else:
                idx += [base, base + 2, base + 1, base, base + 3, base + 2]
    mat = w.material(base=(0.8, 0.4, 0.2, 1.0), metallic=0.25, roughness=0.5,
                     emissive=(1.0, 0.5, 0.0), strength=3.0, double_sided=True)
    m = w.mesh([{"positions": pos, "normals": nrm, "indices": idx, "material": mat}])
    w.node(mesh=m)
    w.write(os.path.join(HERE, "box.gltf"))
    w.write(os.path.join(HERE, "box.glb"))  # the same box as a binary glTF


TRI = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]


def hierarchy():
    """Parent: translation (1, 2, 3), rotation 90 degrees about +y; child: translation
    (0, 0, 1), scale (2, 3, 4); the child's mesh is TRI (u8 indices). A second child under the
    parent with a "matrix" mirroring x (scale -1, 1, 1) holds TRI too (winding flipped back).
    The test composes these itself and checks every vertex."""
    w = GltfWriter()
    m = w.mesh([{"positions": TRI, "indices": [0, 1, 2], "component": U8,
                 "material": w.material(base=(0.5, 0.5, 0.5, 1), metallic=0.0, roughness=0.5)}])
    s = math.sqrt(0.5)
    child = w.node(root=False, translation=[0, 0, 1], scale=[2, 3, 4], mesh=m)
    mirror = w.node(root=False, matrix=[-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], mesh=m)
    w.node(translation=[1, 2, 3], rotation=[0, s, 0, s], children=[child, mirror])
    w.write(os.path.join(HERE, "hierarchy.gltf"))


def shared():
    """One mesh (a 2 x 1 x 0.5 box of 12 triangles with face normals, grey) used by three nodes
    (shared_mesh.gltf: stored once, placed as instances), and the same file with three copies
    of the mesh, one per node (shared_mesh_copies.gltf: flattened). The nodes: a translation;
    a rotation with a non-uniform scale; a mirror. test_instancing.cpp compares the two."""
    def box_geometry():
        pos, nrm, idx = [], [], []
        for axis in range(3):
            for sign in (-1.0, 1.0):
                u, v = [a for a in range(3) if a != axis]
                base = len(pos)
                for cu, cv in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
                    p = [0.0, 0.0, 0.0]
                    p[axis], p[u], p[v] = sign, cu, cv
                    pos.append((p[0], p[1] * 0.5, p[2] * 0.25))
                    n = [0.0, 0.0, 0.0]
                    n[axis] = sign
                    nrm.append(tuple(n))
                outward = (1 if (v - u) % 3 == 1 else -1) * sign > 0
                idx += ([base, base + 1, base + 2, base, base + 2, base + 3] if outward
                        else [base, base + 2, base + 1, base, base + 3, base + 2])
        return pos, nrm, idx

    nodes = [dict(translation=[-2.5, 0, 0]),
             dict(translation=[0, 0.5, 0], rotation=[0, 0.3826834, 0, 0.9238795],
                  scale=[1.2, 0.6, 1.5]),
             dict(matrix=[-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2.5, 0, 0.3, 1])]
    for copies, name in ((False, "shared_mesh.gltf"), (True, "shared_mesh_copies.gltf")):
        w = GltfWriter()
        grey = w.material(base=(0.6, 0.6, 0.6, 1), metallic=0.0, roughness=1.0)
        pos, nrm, idx = box_geometry()
        prim = {"positions": pos, "normals": nrm, "indices": idx, "material": grey}
        m = w.mesh([prim])
        for k, fields in enumerate(nodes):
            w.node(mesh=w.mesh([prim]) if copies and k > 0 else m, **fields)
        w.write(os.path.join(HERE, name))


def modes():
    """A strip of 4 vertices (2 triangles), a fan of 5 (3 triangles), both without indices,
    u32-indexed TRIANGLES (1 triangle), LINES (reported, skipped); two materials (grey,
    red), one primitive without a material (glTF's default, reported)."""
    w = GltfWriter()
    grey = w.material(base=(0.5, 0.5, 0.5, 1), metallic=0.0, roughness=1.0)
    red = w.material(base=(0.9, 0.1, 0.1, 1), metallic=0.0, roughness=1.0)
    strip = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)]
    fan = [(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1), (-1, 1, 1)]
    m = w.mesh([
        {"positions": strip, "indices": None, "mode": TRIANGLE_STRIP, "material": grey},
        {"positions": fan, "indices": None, "mode": TRIANGLE_FAN, "material": red},
        {"positions": TRI, "indices": [0, 1, 2], "component": U32},
        {"positions": TRI, "indices": [0, 1], "mode": LINES, "material": grey},
    ])
    w.node(mesh=m)
    w.write(os.path.join(HERE, "modes.gltf"))


def bad():
    """Broken files: an index out of range, a required extension Facet lacks, an accessor
    beyond its buffer view, a wrong accessor type for POSITION, a NaN position."""
    w = GltfWriter()
    m = w.mesh([{"positions": TRI, "indices": [0, 1, 3]}])
    w.node(mesh=m)
    w.write(os.path.join(HERE, "bad_index.gltf"))

    w = GltfWriter()
    w.use_extension("EXT_made_up", required=True)
    w.node(mesh=w.mesh([{"positions": TRI, "indices": [0, 1, 2]}]))
    w.write(os.path.join(HERE, "bad_required.gltf"))

    w = GltfWriter()
    w.node(mesh=w.mesh([{"positions": TRI, "indices": [0, 1, 2]}]))
    w.doc["accessors"][0]["count"] = 4  # 4 VEC3 floats in a 36-byte view
    w.write(os.path.join(HERE, "bad_bounds.gltf"))

    w = GltfWriter()
    w.node(mesh=w.mesh([{"positions": TRI, "indices": [0, 1, 2]}]))
    w.doc["accessors"][0]["type"] = "VEC2"
    w.write(os.path.join(HERE, "bad_type.gltf"))

    w = GltfWriter()
    w.node(mesh=w.mesh([{"positions": [(0, 0, 0), (1, float("nan"), 0), (0, 1, 0)],
                         "indices": [0, 1, 2]}]))
    w.write(os.path.join(HERE, "bad_nan.gltf"))


if __name__ == "__main__":
    box()
    hierarchy()
    modes()
    bad()
    shared()
