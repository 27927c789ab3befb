"""The quadrature twin of a scene's emitters, shared by the POV-Ray cross-check
(tests/povray/crosscheck.py) and the POV-Ray benchmark (bench/povray_bench.py): `facet export-pov
--area-grid N` turns each emitter into lights at the centres of midpoint cells; the twin is the
same scene for Facet's own renderer, with Facet spot lights at those cells.
"""
import json
import math

import numpy as np


def emitters(scene):
    return [s for s in scene["shapes"] if s.get("emission") not in (None, 0, [0, 0, 0])]


def rgb3(v):
    return [float(v)] * 3 if not isinstance(v, list) else [float(c) for c in v]


def transform_matrix(t):
    """FORMAT.md "transform" (one object or a list, applied in order) -> 4x4 (column vectors)."""
    m = np.eye(4)
    for x in (t if isinstance(t, list) else [t]):
        if "matrix" in x:
            step = np.array(x["matrix"], float).reshape(4, 4)
        else:
            sc = x.get("scale", 1.0)
            S = np.diag((sc if isinstance(sc, list) else [sc] * 3) + [1.0])
            R = np.eye(4)
            if "rotate" in x:
                a = np.array(x["rotate"]["axis"], float)
                a /= np.linalg.norm(a)
                th = math.radians(x["rotate"]["angle"])
                K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
                R[:3, :3] = np.eye(3) + math.sin(th) * K + (1 - math.cos(th)) * K @ K
            T = np.eye(4)
            T[:3, 3] = x.get("translate", [0, 0, 0])
            step = T @ R @ S
        m = step @ m
    return m


def emitter_cells(shape, n):
    """The exporter's midpoint cells of an emitter, written here independently of its C++:
    [(centre, unit front normal, cell area)]. Flat parallelogram quads: n x n cells; other quads:
    their two triangles (p0 p1 p2), (p0 p2 p3), n^2 similar sub-triangles each, at their
    centroids; discs: n equal-area rings x 4n sectors, through the shape's transform."""
    m = transform_matrix(shape["transform"]) if "transform" in shape else np.eye(4)
    lin = m[:3, :3]
    world = lambda p: m[:3, :3] @ np.asarray(p, float) + m[:3, 3]
    flip = -1.0 if shape.get("flip_normals") else 1.0
    cells = []
    if shape["type"] == "disc":
        nrm = np.array(shape["normal"], float)
        nrm /= np.linalg.norm(nrm)
        # any orthonormal pair in the disc's plane (the cells' positions are symmetric)
        ex = np.cross(nrm, [1.0, 0, 0] if abs(nrm[0]) < 0.9 else [0, 1.0, 0])
        ex /= np.linalg.norm(ex)
        ey = np.cross(nrm, ex)
        nw = np.linalg.inv(lin).T @ nrm
        area_scale = abs(np.linalg.det(lin)) * np.linalg.norm(nw)
        nw = flip * nw / np.linalg.norm(nw)
        R, sectors = float(shape["radius"]), 4 * n
        cell = math.pi * R * R * area_scale / (n * sectors)
        for i in range(n):
            r = R * math.sqrt((i + 0.5) / n)
            for j in range(sectors):
                phi = 2 * math.pi * (j + 0.5) / sectors
                local = np.array(shape["center"], float) + r * (math.cos(phi) * ex + math.sin(phi) * ey)
                cells.append((world(local), nw, cell))
        return cells
    if shape["type"] != "quad":
        raise RuntimeError("emitter_cells: quads and discs only")
    p = [world(v) for v in shape["vertices"]]
    if (np.linalg.det(lin) < 0) != bool(shape.get("flip_normals")):
        p = [p[0], p[3], p[2], p[1]]  # reversed winding: the other side is the front
    e1, e2 = p[1] - p[0], p[3] - p[0]
    if np.linalg.norm(p[0] + p[2] - p[1] - p[3]) <= 1e-9 * (np.linalg.norm(e1) + np.linalg.norm(e2)):
        nrm = np.cross(p[1] - p[0], p[2] - p[0])
        nrm /= np.linalg.norm(nrm)
        area = np.linalg.norm(np.cross(e1, e2))
        return [(p[0] + (i + 0.5) / n * e1 + (j + 0.5) / n * e2, nrm, area / (n * n))
                for i in range(n) for j in range(n)]
    for a, b, c in ((p[0], p[1], p[2]), (p[0], p[2], p[3])):
        cr = np.cross(b - a, c - a)
        area = 0.5 * np.linalg.norm(cr)
        nrm = cr / (2 * area)
        for i in range(n):
            for j in range(n - i):
                # sub-triangle (i, j): upright centroid (i + 1/3, j + 1/3) / n, inverted (i + 2/3, j + 2/3) / n
                cells.append((a + (i + 1 / 3) / n * (b - a) + (j + 1 / 3) / n * (c - a), nrm, area / n ** 2))
                if i + j + 2 <= n:
                    cells.append((a + (i + 2 / 3) / n * (b - a) + (j + 2 / 3) / n * (c - a), nrm, area / n ** 2))
    return cells


def quadrature_twin(scene, n):
    """The scene with each emitter's light replaced by Facet spot lights at the centres of the
    exporter's midpoint cells: inner angle 0, outer 90 makes Facet's falloff (linear in cos
    between the cones) exactly cos(theta), a Lambertian patch; power Phi = pi I0 with
    I0 = L * cell area (FORMAT.md: Phi = 2 pi I0 [(1 - cos 0) + (cos 0 - cos 90) / 2]). The
    emitter shapes themselves are removed (povray-facet's glowing surface casts no shadow),
    so the pixels that see an emitter are compared separately."""
    twin = json.loads(json.dumps(scene))
    twin["shapes"] = [s for s in twin["shapes"] if s not in emitters(twin)]
    for q in emitters(scene):
        le = rgb3(q["emission"])
        for c, nrm, cell in emitter_cells(q, n):
            twin.setdefault("lights", []).append({
                "type": "spot", "position": c.tolist(), "direction": nrm.tolist(),
                "power": [math.pi * l * cell for l in le], "outer_angle": 90.0, "inner_angle": 0.0})
    return twin
