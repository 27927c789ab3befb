"""VOLUME objects -> the core's `grid` media (FORMAT.md "Grids"), as Cycles' blender/volume.cpp.

The evaluated volume (the depsgraph's: a file-backed volume, a sequence at the current frame,
Mesh to Volume and Volume Displace results) has its grids written to one OpenVDB file in the
cache directory (Blender's VolumeGrids.save, the grids in object space), read by a `grid`
medium placed by the object's world matrix (and half a voxel, where Cycles centres its
voxels: _cycles_placement); a `null` box around the object's bounding box
(padded by a voxel) with the same matrix is the medium's boundary (its material's
"interior").

The medium is the material's Volume output (materials.NodeContext.volume: the coefficients per
unit of density, Cycles' Density input included) times the grid Cycles multiplies the density
by: Principled Volume's Density Attribute (svm_node_principled_volume). Cycles' volume object
is the region of the grids its shader reads (scene/volume.cpp builds its mesh from them): a
shader that reads no grid (Volume Scatter, Volume Absorption alone, or Density Attribute empty)
renders nothing in Cycles 3.4 (measured: the same image as no volume), and nothing is exported,
with a line. A volume without a material is Cycles' default volume shader, a Principled Volume
with its defaults (scene/shader.cpp). Principled Volume's emission converts as Cycles
computes it (svm_node_principled_volume: not scaled by the density): Emission Strength x
Emission Color as the medium's constant `emission`, and blackbody emission (Blackbody
Intensity, Blackbody Tint, Temperature) with the Temperature Attribute's grid as
`temperature_grid`; an Emission Strength straight from an Attribute node's Fac naming a grid
of the volume as `emission_grid` (the emission Emission Color x the grid). Reported by object,
material and node: what a grid medium cannot hold (a
Color Attribute grid, a volume shader beside the Principled Volume that fills the grids' region
uniformly, blackbody beside another volume shader), a constant emission or temperature (Cycles
fills the volume's active voxels, Facet the density grid's bounding box), a Density Attribute
naming no grid (Cycles renders nothing then), a grid that is not float, velocity (motion blur
of volumes).
"""
import os
import re

import numpy as np

from . import materials, nodegraph, textures, units

# Cycles' default volume shader (scene/shader.cpp add_default: a Principled Volume with its
# node defaults): Density 1, Color 0.5, Absorption Color 0, Anisotropy 0, grid "density".
_DEFAULT_DENSITY, _DEFAULT_COLOR = 1.0, (0.5, 0.5, 0.5)


def _volume_nodes(walker, src, path_nodes):
    """The volume shader nodes (Outs) feeding a Volume socket through Mix / Add Shaders."""
    if not isinstance(src, nodegraph.Out):
        return
    node = src.node
    if node.bl_idname in ('ShaderNodeMixShader', 'ShaderNodeAddShader'):
        for s in node.inputs:
            if s.type == 'SHADER':
                _volume_nodes(walker, walker.input(node, s, src.path), path_nodes)
        return
    path_nodes.append(src)


def _file_name(obj_name, frame, index):
    safe = re.sub(r"[^A-Za-z0-9_.-]", "_", obj_name)[:64]
    return os.path.join(textures.CACHE_DIR, "volume_%s_%d_%d_%d.vdb"
                        % (safe, os.getpid(), frame, index))


def export_volume(obj, matrix, frame, problems, index=0, use_motion_blur=False):
    """An evaluated VOLUME object placed by `matrix` -> (medium name, grid medium dict, null
    boundary shape dict without its material) or None (nothing to render; the reason is in
    `problems`)."""
    orig = obj.original
    subject = "object '%s'" % orig.name
    vol = obj.data
    grids = vol.grids
    try:
        grids.load()
    except Exception:  # noqa: BLE001 - Blender raises for an unreadable file
        pass
    if not len(grids):
        msg = grids.error_message if hasattr(grids, "error_message") else ""
        problems.append("%s: volume has no grids%s; not rendered"
                        % (subject, (" (%s)" % msg) if msg else ""))
        return None
    names = [g.name for g in grids]
    mat = None
    slots = [s.material for s in obj.material_slots if s.material is not None]
    if slots:
        mat = slots[0]
        if len({m.name for m in slots}) > 1:
            problems.append("%s: several materials; only the first ('%s') is converted"
                            % (subject, mat.name))
    medium, grid_name = _medium(mat, subject, names, problems)
    if medium is None:
        return None
    g = grids[names.index(grid_name)]
    if g.data_type != 'FLOAT':  # the core reads float grids (a double one included)
        problems.append("%s: grid '%s' is %s, not a float density (Facet reads float grids); "
                        "not rendered"
                        % (subject, grid_name, g.data_type))
        return None
    tg = medium.get("temperature_grid")
    tg_type = grids[names.index(tg)].data_type if tg is not None else 'FLOAT'
    if tg_type != 'FLOAT':
        problems.append("%s: temperature grid '%s' is %s, not float; blackbody at the constant "
                        "Temperature over the density grid's box" % (subject, tg, tg_type))
        del medium["temperature_grid"]
    if use_motion_blur and any(n in names for n in ('velocity', 'vel', 'v')):
        problems.append("%s: the volume's velocity grid (motion blur of volumes) is not "
                        "converted: rendered without motion" % subject)
    os.makedirs(textures.CACHE_DIR, exist_ok=True)
    path = _file_name(orig.name, frame, index)
    if not grids.save(path):
        problems.append("%s: its grids could not be written to '%s'; not rendered"
                        % (subject, path))
        return None
    medium.update({"kind": "grid", "file": path, "grid": grid_name,
                   "transform": _cycles_placement(matrix, g).tolist()})
    # The evaluated bounding box (Blender 3.4 leaks the 96 bytes it allocates for it when the
    # volume is a geometry-nodes component, an instance of the object: measured, not freed).
    corners = np.array([tuple(v) for v in obj.bound_box], np.float64)
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    pad = _voxel_size(grids, hi - lo)
    lo, hi = lo - pad, hi + pad
    box = {"type": "box", "min": lo.tolist(), "max": hi.tolist(),
           "transform": [list(map(float, row)) for row in matrix],
           "name": "%s (volume)" % orig.name}
    return "%s (volume)" % orig.name, medium, box


def _cycles_placement(matrix, grid):
    """The grid medium's transform: the object's world matrix after half a voxel along each
    index axis. Cycles 3.4 samples a grid as a dense texture whose voxel (i, j, k) is centred
    at index (i + 1/2, j + 1/2, k + 1/2) (image_vdb.cpp's texture-to-index map and the
    texture lookup's half-texel convention), where OpenVDB (and the core) centre it at
    (i, j, k): the shift makes Facet's smoke sit where Cycles draws it (tests/blender/
    test_cycles_smoke.py: without it the block RMSE is 12x the noise floor, with it 1x)."""
    world = np.array([[float(v) for v in row] for row in matrix], np.float64)
    m = getattr(grid, "matrix_object", None)
    if m is None:
        return world
    shift = np.eye(4)
    shift[:3, 3] = 0.5 * np.array([[float(m[r][c]) for c in range(3)] for r in range(3)]).sum(
        axis=1)
    return world @ shift


def _voxel_size(grids, extent):
    """The largest voxel edge of the grids in object space (their index-to-object matrices),
    or 2% of the box when Blender does not expose them: the boundary's padding (trilinear
    interpolation reaches half a voxel past the active voxels' centres)."""
    size = 0.0
    for g in grids:
        m = getattr(g, "matrix_object", None)
        if m is None:
            continue
        size = max(size, max(float(np.linalg.norm([m[r][c] for r in range(3)]))
                             for c in range(3)))
    return size if size > 0.0 else 0.02 * float(max(extent.max(), 1e-6))


def _medium(mat, subject, names, problems):
    """(the grid medium's coefficients (a dict), the density grid's name) of the volume's
    material, or (None, None) when Cycles renders nothing (reported)."""
    if mat is None:
        sa, ss = units.principled_volume_from_blender(_DEFAULT_DENSITY, _DEFAULT_COLOR,
                                                      (0.0, 0.0, 0.0))
        medium, grid = {"sigma_a": sa, "sigma_s": ss}, "density"
        if grid not in names:
            problems.append("%s: no material: Cycles' default volume shader reads grid "
                            "'density', which the volume does not have (its grids: %s); "
                            "Cycles renders nothing, nor does Facet"
                            % (subject, ", ".join(names)))
            return None, None
        return medium, grid
    what = "%s, material '%s'" % (subject, mat.name)
    if not mat.use_nodes or mat.node_tree is None:
        problems.append("%s: no node tree: no volume shader, Cycles renders nothing; not "
                        "rendered" % what)
        return None, None
    out = nodegraph.active_output(mat.node_tree, 'ShaderNodeOutputMaterial')
    if out is None:
        problems.append("%s: no Material Output; not rendered" % what)
        return None, None
    ctx = materials.NodeContext("material", mat.name, mat.node_tree)
    ctx.material = mat
    vol = ctx.walker.input(out, 'Volume')
    surf = ctx.walker.input(out, 'Surface')
    if not (isinstance(surf, nodegraph.Const) and surf.value is None):
        problems.append("%s: the Surface is not rendered on a volume object (in Cycles "
                        "neither)" % what)
    nodes = []
    _volume_nodes(ctx.walker, vol, nodes)
    principled = [o for o in nodes if o.node.bl_idname == 'ShaderNodeVolumePrincipled']
    grid, read_grids = None, set()
    for o in principled:
        node = o.node
        want = node.inputs['Density Attribute'].default_value
        if want:
            read_grids.add(want)
            grid = grid or want
            if want != grid:
                problems.append("%s: %s reads Density Attribute '%s'; one grid per medium: "
                                "'%s' is used" % (what, o.label(), want, grid))
        a = node.inputs['Color Attribute'].default_value
        if a and a in names:
            read_grids.add(a)
            problems.append("%s: %s input 'Color Attribute' = '%s': the grid is not read (a "
                            "grid medium has one density grid); the Color is used"
                            % (what, o.label(), a))
    others = [o for o in nodes if o.node.bl_idname != 'ShaderNodeVolumePrincipled']
    if grid is None:
        problems.append("%s: its Volume (%s) reads no density grid (only Principled Volume's "
                        "Density Attribute does): Cycles renders nothing of the volume "
                        "object, nor does Facet"
                        % (what, ", ".join(o.label() for o in nodes) or "nothing"))
        return None, None
    if grid not in names:
        problems.append("%s: Density Attribute '%s' names no grid of the volume (its grids: "
                        "%s): Cycles renders nothing, nor does Facet"
                        % (what, grid, ", ".join(names)))
        return None, None
    for o in others:
        problems.append("%s: %s is not converted exactly: Cycles fills the grids' region with "
                        "it uniformly, Facet scales it by grid '%s' as the rest of the medium"
                        % (what, o.label(), grid))
    # Blackbody emission (one Principled Volume straight on the output, the only volume
    # shader): its intensity, tint and temperature, and the Temperature Attribute's grid.
    blackbody = None
    if len(nodes) == 1 and principled:
        o = principled[0]
        node = o.node
        b = min(max(float(ctx.value(node, 'Blackbody Intensity', o.path)), 0.0), 1.0)
        if b > 0.0:
            ctx.exact.add((node.name, 'Blackbody Intensity'))
            tint = [max(float(c), 0.0)
                    for c in ctx.value(node, 'Blackbody Tint', o.path)[:3]]
            blackbody = {"blackbody_intensity": b, "blackbody_tint": tint,
                         "temperature": min(max(float(ctx.value(node, 'Temperature', o.path)),
                                                0.0), 1e6)}
            attr = node.inputs['Temperature Attribute'].default_value
            if attr and attr in names:
                blackbody["temperature_grid"] = attr
            else:
                problems.append("%s: %s: blackbody at a constant Temperature (Temperature "
                                "Attribute '%s' names no grid): Cycles emits it over the "
                                "volume's active voxels, Facet over the bounding box of grid "
                                "'%s' (the same where the active voxels fill their box)"
                                % (what, o.label(), attr, grid))
    # Emission Strength straight from an Attribute node's Fac naming a grid of the volume
    # (Cycles reads the grid at each point): the grid is the medium's emission_grid and the
    # strength 1 (the emission is Emission Color x the grid's value).
    emission_grid = None
    if len(nodes) == 1 and principled:
        o = principled[0]
        src = ctx.walker.input(o.node, 'Emission Strength', o.path)
        if isinstance(src, nodegraph.Out) and not src.convs and \
                src.node.bl_idname == 'ShaderNodeAttribute' and \
                src.node.attribute_type == 'GEOMETRY' and src.socket.identifier == 'Fac' and \
                src.node.attribute_name in names:
            emission_grid = src.node.attribute_name
            ctx.given[(o.node.name, 'Emission Strength')] = 1.0
    medium = ctx.volume(vol, "the Material Output's Volume")
    problems.extend(ctx.finish())
    if medium is None and blackbody is not None:
        medium = {"sigma_a": [0.0] * 3, "sigma_s": [0.0] * 3}
    if medium is None:
        problems.append("%s: the volume's coefficients are 0; not rendered" % what)
        return None, None
    out_medium = {"sigma_a": medium["sigma_a"], "sigma_s": medium["sigma_s"]}
    if "g" in medium:
        out_medium["g"] = medium["g"]
    if "emission" in medium and emission_grid is not None:
        out_medium["emission"] = medium["emission"]
        out_medium["emission_grid"] = emission_grid
    elif "emission" in medium:
        # Cycles' Emission Strength x Emission Color, not scaled by the density.
        out_medium["emission"] = medium["emission"]
        problems.append("%s: its constant emission (Emission Strength x Emission Color) is "
                        "converted over the bounding box of grid '%s'; Cycles emits it over "
                        "the volume's active voxels (the same where they fill their box)"
                        % (what, grid))
    if blackbody is not None:
        out_medium.update(blackbody)
    return out_medium, grid



def copy_grids_beside(data, json_path):
    """For a JSON export: each grid medium's file (written to the cache directory) copied
    beside the scene file as "<scene name>_<n>.vdb" and named relative to it, so the exported
    scene renders wherever it is moved with its files."""
    import shutil
    folder = os.path.dirname(os.path.abspath(json_path))
    stem = os.path.splitext(os.path.basename(json_path))[0]
    n = 0
    for medium in (data.get("media") or {}).values():
        if medium.get("kind") != "grid" or not os.path.isabs(medium.get("file", "")):
            continue
        if os.path.dirname(medium["file"]) != textures.CACHE_DIR:
            continue  # not written by this exporter: left where it is
        name = "%s_%d.vdb" % (stem, n)
        n += 1
        shutil.copyfile(medium["file"], os.path.join(folder, name))
        medium["file"] = name
