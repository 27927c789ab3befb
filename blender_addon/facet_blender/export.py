"""Blender scene (evaluated depsgraph) -> Facet scene data (native.py's vocabulary).

Meshes go through foreach_get into numpy (never Blender's structs by pointer): the evaluated
mesh (modifiers applied) of every visible object instance, triangulated by Blender's
loop_triangles, split by material slot (one Facet mesh shape per slot used), with split
normals when any face is smooth, in object space with the instance's world matrix as the
shape's transform; the colour attribute its materials' Color Attribute nodes read as the
mesh's vertex colours. A mesh placed several times (instances, linked duplicates) is one
prototype with an instance per placement (export_scene).

Objects imported from a Facet JSON scene carry their original description as custom
properties ("facet_shape", "facet_camera", "facet_light", "facet_environment") with a
snapshot of their Blender state ("facet_state"). While the state is unchanged the original
description is exported as it was read (exact analytic shapes, double-precision transforms,
the exact camera), so a JSON scene renders in Blender exactly as with `facet render`; once the
user moves or edits it, the Blender state is exported instead.
"""
import json

import numpy as np

from . import bake, gaps, hooks, materials, textures, units
# By data type, as Cycles' sync (blender_camera.cpp, blender_mesh.cpp, blender_light.cpp, ...).
from . import sync_camera, sync_hair, sync_motion, sync_volume
from .sync_camera import export_camera
from .sync_light import _light_data
from .sync_mesh import _imported_mesh_arrays, mesh_arrays
from .sync_state import RAY_VISIBILITY, _stored, object_state
from .sync_world import export_environment, export_world_medium

GEOMETRY_TYPES = {'MESH', 'CURVE', 'SURFACE', 'META', 'FONT'}
resolution = sync_camera.resolution  # export.resolution (tests and callers)
DEFAULT_MATERIAL_NAME = "facet_default"


# --- the scene -------------------------------------------------------------------------------


def _matrix_rows(m):
    return [list(row) for row in m]  # a mathutils Matrix's rows as floats


def _is_identity(m):
    return all(m[i][j] == (1.0 if i == j else 0.0) for i in range(4) for j in range(4))


def _placement(m):
    """A placement's transform rows, None for the identity."""
    rows = [list(row) for row in m]
    identity = all(rows[i][j] == (1.0 if i == j else 0.0) for i in range(4) for j in range(4))
    return None if identity else rows


class _Materials:
    """Blender materials -> named Facet materials, each converted once."""

    def __init__(self, problems, users=None):
        self.problems = problems
        self.users = {} if users is None else users  # facet name -> {object names}
        self.by_name = {}  # facet name -> materials.Converted
        self.first_user = {}  # facet name -> the object it was converted for (bakes)
        self.order = []

    def reads_uv(self, mat):
        """Whether material `mat` (or the default, None) reads a UV map."""
        if mat is not None and mat.get("facet_cycles_only"):
            return False
        return bool(self.get(mat)[1].uv_maps)

    def get(self, mat, obj=None):
        name = DEFAULT_MATERIAL_NAME if mat is None else mat.name
        if name not in self.by_name:
            conv = materials.convert(mat, getattr(obj, "original", obj))
            self.problems.extend(conv.problems)
            self.by_name[name] = conv
            self.order.append(name)
            self.first_user[name] = obj.original.name if obj is not None else None
        conv = self.by_name[name]
        if obj is not None:
            self.users.setdefault(name, set()).add(obj.original.name)
        if conv.baked and obj is not None and obj.original.name != self.first_user[name]:
            line = ("material '%s': baked over object '%s''s UVs; object '%s' uses the same "
                    "image over its own UVs" % (name, self.first_user[name], obj.original.name))
            if line not in self.problems:
                self.problems.append(line)
        return name, conv

    def data(self):
        return [(n, self.by_name[n].data) for n in self.order]


class ClipCheck:
    """Whether the scene camera's Clip Start or Clip End cuts an exported object off
    (gaps.CLIP_START, gaps.CLIP_END): add() each placement, lines() after, in one numpy pass.
    Cycles clips at two planes along the view axis, for perspective cameras too
    (kernel/camera/camera.h: the ray starts at depth clip_start and ends at depth clip_end).
    A placement's depths are d(x) = f . (M x + t - p) for x in its local bounding box (centre
    c, half extents h), so with w = M^T f they span w . c + f . (t - p) -+ |w| . h."""

    def __init__(self, cam_obj):
        from mathutils import Vector
        c = cam_obj.data
        m = cam_obj.matrix_world
        self.name = cam_obj.name
        self.fwd = Vector([-m[i][2] for i in range(3)]).normalized()
        self.base = self.fwd.dot(m.translation)
        self.start, self.end = float(c.clip_start), float(c.clip_end)
        self.boxes = {}  # geometry key -> (centre, half extents) of its local bounding box
        self.placed = []  # (geometry key, object name, w, f . t - f . p)

    def add(self, obj, matrix, key):
        """A placement of `obj`'s geometry (`key`: the same for the same geometry). A mesh
        object's box is its bound_box; other types' come from their exported arrays (points()):
        Blender 3.4 leaks the box it allocates for the bound_box of the evaluated mesh a curve,
        surface, metaball or text object becomes."""
        if key not in self.boxes and obj.original.type == 'MESH':
            corners = np.array([tuple(v) for v in obj.bound_box], np.float64)
            self._box(key, corners.min(axis=0), corners.max(axis=0))
        w = self.fwd @ matrix.to_3x3()  # the row vector f^T M = (M^T f)^T
        self.placed.append((key, obj.original.name, tuple(w),
                            self.fwd.dot(matrix.translation) - self.base))

    def points(self, key, arrays):
        """The box of the exported vertices (a MeshArrays or None) of a non-mesh geometry."""
        if key in self.boxes or arrays is None or not len(arrays.positions):
            return
        self._box(key, arrays.positions.min(axis=0), arrays.positions.max(axis=0))

    def _box(self, key, lo, hi):
        lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
        self.boxes[key] = (0.5 * (lo + hi), 0.5 * (hi - lo))

    def lines(self):
        placed = [p for p in self.placed if p[0] in self.boxes]
        if not placed:
            return []
        centre = np.array([self.boxes[p[0]][0] for p in placed])  # (n, 3)
        half = np.array([self.boxes[p[0]][1] for p in placed])
        w = np.array([p[2] for p in placed])
        mid = (w * centre).sum(axis=1) + np.array([p[3] for p in placed])
        reach = (np.abs(w) * half).sum(axis=1)
        far, near = mid + reach, np.maximum(mid - reach, 0.0)
        seen = far > 0.0  # not wholly behind the camera
        out = []
        far = np.where(seen, far, -np.inf)
        i = int(np.argmax(far))
        if far[i] > self.end:
            out.append(self._line(gaps.CLIP_END, self.end, placed[i][1], far[i]))
        near = np.where(seen, near, np.inf)
        i = int(np.argmin(near))
        if self.start > gaps.CLIP_START_FACTORY * (1.0 + 1e-6) and near[i] < self.start:
            out.append(self._line(gaps.CLIP_START, self.start, placed[i][1], near[i]))
        return out

    def _line(self, entry, value, name, reach):
        return ("camera '%s': %s = %.4g: %s (object '%s' reaches %.4g)"
                % (self.name, entry[0], value, entry[1], name, reach))


class _Placed:
    """One mesh (one evaluated geometry with one set of materials) and its placements: the
    shapes of its material slots in object space, and (transform rows, name) per placement."""

    def __init__(self, name, templates, emits):
        self.name = name
        self.templates = templates  # [(suffix, shape dict without transform and name)]
        self.emits = emits
        self.placements = []


def export_scene(depsgraph, camera=None, mesh_cache=None, users=None, instancing=True,
                 frame_set=None):
    """Evaluated depsgraph -> (scene data, [problem lines]). Raises ExportError when the
    scene cannot be rendered at all (no camera, ...). `camera` (scene-data camera) replaces the
    scene's camera (the viewport's view). `mesh_cache` (a dict kept by the caller) reuses the
    arrays of objects converted before (the viewport drops the entries of changed objects).
    `users` (a dict, filled when given): material name -> the names of the objects using it
    (for the grouped report, gaps.grouped).

    Instancing (`instancing`, on by default): a mesh placed more than once (collection
    instances, particles, geometry-nodes instances, linked duplicates: the same evaluated
    geometry with the same materials) is exported once, as a prototype (FORMAT.md,
    "Instances"), with an `instance` shape per placement; a mesh placed once stays a mesh
    shape. Where the core's instancing cannot take a mesh the placements are expanded into
    mesh shapes (exact, one copy each) and reported: an emitting mesh (the core's prototypes
    cannot emit) and Facet shapes imported from JSON (analytic kinds). Blender's nested
    instances arrive as one level already (the depsgraph composes their matrices).

    Motion blur (sync_motion.py): with the scene's Motion Blur on, the render's settings, and
    with `frame_set` (RenderEngine.frame_set: final renders) the camera's and the objects'
    motion over the shutter; the viewport renders without motion blur, as Cycles' does."""
    scene = depsgraph.scene
    problems = []
    bake.PENDING.clear()  # this export's bake requests (facet.bake_inputs bakes them)
    mats = _Materials(problems, users)
    data = {"description": "exported from Blender scene '%s'" % scene.name,
            "camera": camera or export_camera(depsgraph, scene, problems),
            "shapes": [], "lights": []}
    mesh_cache = {} if mesh_cache is None else mesh_cache
    order = []  # in depsgraph order: a shape dict, or a _Placed (one entry per placement)
    placed = {}  # geometry key -> _Placed
    expanded_shapes = set()
    seen = {}  # (object name, geometry, is instance) -> (_Placed, shape name)
    empty = []  # objects whose own mesh is empty (reported unless they place instances)
    instancers = set()
    # Settings and object flags that change Cycles' image and are not converted (gaps.py).
    view_layer = depsgraph.view_layer
    problems.extend(gaps.scene_lines(scene, view_layer))
    flagged = set()  # objects whose flags, type and particle hair were reported
    # Per exported hair shape (by id): what reads its points again at the motion steps
    # (sync_motion.add_motion): ("particle", object, modifier, render) or ("curves", object).
    hair_sources = {}
    volumes = []  # VOLUME objects: (medium name, grid medium, null boundary box) (sync_volume)
    # The scene camera's clipping (the viewport's view has its own, and clips what it shows).
    clip = ClipCheck(scene.camera) if camera is None and scene.camera is not None and \
        scene.camera.type == 'CAMERA' else None
    # Per object placed as itself: how its arrays were read (uv layer, colours) and the arrays,
    # for its deformation motion (sync_motion.add_motion reads it again at each step).
    mesh_sources = {}
    held_out = holdout_objects(view_layer)
    for inst in depsgraph.object_instances:
        obj = inst.object
        matrix = inst.matrix_world.copy()
        if inst.is_instance and inst.parent is not None:
            instancers.add(inst.parent.original.name)
        if obj.original.name not in flagged:
            # The original's settings: an evaluated copy made before a Python property (such
            # as object.cycles') changed keeps the old value until the object is re-evaluated.
            flagged.add(obj.original.name)
            problems.extend(gaps.object_lines(obj.original, view_layer))
        if obj.type != obj.original.type and (obj.original.name, obj.type) not in flagged:
            # A component of another type in an object's evaluated geometry (geometry nodes'
            # Mesh to Points, Mesh to Volume, ...), placed as an instance of that type.
            flagged.add((obj.original.name, obj.type))
            problems.extend(gaps.component_lines(obj, view_layer))
        if obj.type == 'LIGHT':
            orig = obj.original
            stored = None if inst.is_instance else _stored(orig, "facet_light",
                                                           object_state(obj, matrix))
            if stored is not None:
                data["lights"].append(stored)
                continue
            light = _light_data(obj, matrix, problems, scene.facet.lamp_model)
            if light is not None:
                data["lights"].append(light)
            continue
        if obj.type == 'VOLUME':
            if view_layer.use_volumes and (obj.visible_camera or obj.visible_diffuse or
                                           obj.visible_glossy or obj.visible_shadow):
                vol = sync_volume.export_volume(obj, matrix, scene.frame_current, problems,
                                                len(volumes), scene.render.use_motion_blur)
                if vol is not None:
                    volumes.append(vol)
            continue
        visibility = ray_visibility(obj, inst)
        visible = visibility != {key: False for key in RAY_VISIBILITY.values()}
        if obj.type == 'CURVES':  # hair curves (sync_hair.py)
            if view_layer.use_strand and visible:
                got = sync_hair.export_curves_object(obj, matrix, scene, mats.reads_uv, problems)
                if got is not None:
                    order.append(_hair_shape(got[0], got[1], mats, obj, problems, visibility))
                    hair_sources[id(got[0])] = ("curves", obj.original.name)
            continue
        if obj.type not in GEOMETRY_TYPES:
            continue
        if not visible:
            continue
        if obj.type == 'MESH' and view_layer.use_strand and any(
                m.type == 'PARTICLE_SYSTEM' for m in obj.modifiers):
            # Particle hair (sync_hair.py): the object's own placement carries it.
            if not inst.is_instance:
                render = depsgraph.mode == 'RENDER'
                for shape, mat, mod_name in sync_hair.export_particle_hair(
                        obj, scene, mats.reads_uv, problems, render):
                    order.append(_hair_shape(shape, mat, mats, obj, problems, visibility))
                    hair_sources[id(shape)] = ("particle", obj.original.name, mod_name, render)
            elif ("hair", obj.original.name) not in flagged:
                flagged.add(("hair", obj.original.name))
                problems.append("object '%s': the particle hair of its instances is not "
                                "rendered (only the object itself carries its hair)"
                                % obj.original.name)
        orig = obj.original
        data_ptr = obj.data.as_pointer() if obj.type == 'MESH' and obj.data is not None else 0
        clip_key = data_ptr or (orig.name, inst.is_instance)
        if clip is not None:
            clip.add(obj, matrix, clip_key)
        seen_key = (orig.name, data_ptr, inst.is_instance, tuple(sorted(visibility)))
        again = seen.get(seen_key) if data_ptr else None
        if again is not None:
            # Another placement of an object converted above (same object, same geometry:
            # the same materials and the same record): only its matrix is new.
            if again[0].templates:
                again[0].placements.append((_placement(matrix), again[1]))
                order.append(again[0])
            continue
        name = orig.name if not inst.is_instance else "%s (instance)" % orig.name
        if "facet_shape" in orig:
            shape = json.loads(orig["facet_shape"])
            if not inst.is_instance and orig.get("facet_state") == object_state(obj, matrix):
                pass  # unchanged since import: the stored (double precision) transform
            else:
                shape["transform"] = None if _is_identity(matrix) else _matrix_rows(matrix)
            if inst.is_instance and orig.name not in expanded_shapes:
                expanded_shapes.add(orig.name)
                problems.append("object '%s': a Facet %s shape (imported from JSON) placed by "
                                "instances is expanded into a shape per placement (only meshes "
                                "become prototypes)" % (orig.name, shape["type"]))
            if shape["type"] == "mesh" and "file" not in shape:
                arrays = _imported_mesh_arrays(obj)
                if arrays is None:
                    problems.append("object '%s': empty mesh (no faces); skipped" % orig.name)
                    continue
                shape["positions"], shape["indices"], shape["normals"] = arrays
            slot_mat = obj.material_slots[0].material if obj.material_slots else None
            _add_material(shape, slot_mat, mats, obj)
            if _is_holdout(obj, held_out):
                shape["holdout"] = True
            if _is_shadow_catcher(obj):
                shape["shadow_catcher"] = True
            if visibility:
                shape["visibility"] = visibility
            order.append(shape)
            continue
        slots = [s.material for s in obj.material_slots] or [None]
        uv_layer = _uv_layer(obj, slots, mats, problems)
        tangents = uv_layer is not None and any(
            mats.get(m, obj)[1].tangents for m in slots
            if m is None or not m.get("facet_cycles_only"))
        colors = _color_attribute_read(obj, slots, mats, problems)
        # The same evaluated geometry (a pointer compared while this depsgraph lives) with the
        # same materials is one mesh however often it is placed; other kinds: per object.
        holdout = _is_holdout(obj, held_out)
        catcher = _is_shadow_catcher(obj)
        gkey = (data_ptr or orig.name, inst.is_instance if not data_ptr else None,
                tuple(m.name if m is not None else None for m in slots), uv_layer, tangents,
                colors, holdout, catcher, tuple(sorted(visibility.items())))
        rec = placed.get(gkey)
        if rec is None:
            key = (orig.name, inst.is_instance, data_ptr if inst.is_instance else 0, uv_layer,
                   tangents, colors)
            if key not in mesh_cache:
                mesh_cache[key] = mesh_arrays(obj, uv_layer, tangents, colors)
                hooks.export_stats["meshes"] += 1
            rec = placed[gkey] = _placed_mesh(mesh_cache[key], obj, slots, uv_layer, mats,
                                               problems)
            if holdout:  # Object > Visibility > Holdout, or a Holdout collection
                rec.templates = [(s, dict(t, holdout=True)) for s, t in rec.templates]
            if catcher:  # Object > Visibility > Shadow Catcher
                rec.templates = [(s, dict(t, shadow_catcher=True)) for s, t in rec.templates]
            if visibility:  # Object > Visibility > Ray Visibility
                rec.templates = [(s, dict(t, visibility=dict(visibility)))
                                 for s, t in rec.templates]
                line = gaps.emitter_visibility_line(orig.name, visibility) if rec.emits \
                    else None
                if line is not None and line not in problems:
                    problems.append(line)
            if clip is not None and orig.type != 'MESH':
                clip.points(clip_key, mesh_cache[key])
        if not inst.is_instance and rec.templates:
            mesh_sources[orig.name] = (uv_layer, colors, mesh_cache.get(
                (orig.name, False, 0, uv_layer, tangents, colors)))
        if data_ptr:
            seen[seen_key] = (rec, name)
        if not rec.templates:
            if orig.name not in empty:
                empty.append(orig.name)
            continue
        rec.placements.append((_placement(matrix), name))
        order.append(rec)
    if clip is not None:
        problems.extend(clip.lines())
    # An instancer's own geometry may be empty (geometry nodes outputting only instances).
    problems.extend("object '%s': empty mesh (no faces); skipped" % name for name in empty
                    if name not in instancers)
    data["shapes"], prototypes, owners = _place(order, placed, instancing, problems)
    if prototypes:
        data["prototypes"] = prototypes
    env = export_environment(scene, problems)
    if env is not None:
        data["lights"].append(env)
    data["materials"] = mats.data()
    problems.extend(_ray_length_lines(scene, camera, data["materials"]))
    # Media (FORMAT.md "media"): each volume material's, named as the material (its data's
    # "interior"), and the world's Volume as the world medium.
    media = {mats.by_name[n].data["interior"]: mats.by_name[n].medium for n in mats.order
             if mats.by_name[n].medium}
    world_medium, wname = export_world_medium(scene, problems), None
    if world_medium is not None:
        wname = scene.world.name
    elif "facet_world_medium" in scene:  # imported from a JSON scene
        stored = json.loads(scene["facet_world_medium"])
        world_medium, wname = stored["medium"], stored["name"]
    for vname, medium, box in volumes:
        # Each volume's grid medium inside its null box (FORMAT.md "Grids").
        while vname in media or vname in mats.by_name:
            vname += "'"
        media[vname] = medium
        data["materials"].append((vname, {"model": "null", "interior": vname}))
        data["shapes"].append(dict(box, material=vname))
    if world_medium is not None:
        while wname in media:
            wname += " (world)"
        media[wname] = world_medium
        data["world_medium"] = wname
    if media:
        data["media"] = media
        if any(_scatters(m) for m in media.values()):
            line = gaps.volume_bounce_line(scene)
            if line is not None:
                problems.append(line)
    data["render"] = export_render_settings(scene)
    blur = sync_motion.settings(scene, view_layer) if camera is None else None
    if blur is not None:
        data["render"]["motion_blur"] = blur
        if frame_set is not None:
            sync_motion.add_motion(depsgraph, data, frame_set, owners, problems,
                                   mesh_sources, hair_sources)
    return data, problems


def holdout_objects(view_layer):
    """Names of the objects in the view layer's Holdout collections (Outliner's Holdout
    toggle, LayerCollection.holdout), which Cycles holds out as it does Object > Visibility >
    Holdout."""
    names = set()

    def walk(lc):
        for child in lc.children:
            if child.exclude:
                continue
            if child.holdout:
                names.update(o.name for o in child.collection.all_objects)
            walk(child)
    walk(view_layer.layer_collection)
    return names


def _ray_length_lines(scene, camera, materials):
    """Cycles starts camera rays at the camera's Clip Start (kernel/camera/camera.h), so its
    Ray Length of a camera ray is clip_start / cos(angle to the view axis) shorter than Facet's,
    which measures from the camera: a line per material reading Ray Length when Clip Start > 0
    (the F12 camera; the viewport's view has its own clipping)."""
    cam = scene.camera if camera is None else None
    start = float(cam.data.clip_start) if cam is not None and cam.type == 'CAMERA' else 0.0
    if start <= 0.0:
        return []
    return ["material '%s': Light Path Ray Length of camera rays is measured from the camera; "
            "Cycles measures it from Clip Start (%g m nearer along the view axis), so camera "
            "rays read it longer by %g m / cos(angle to the view axis)" % (name, start, start)
            for name, data in materials if textures.reads_ray(data, "ray_length")]


def _is_shadow_catcher(obj):
    """Whether the object is a shadow catcher (FORMAT.md "Shadow catchers")."""
    return bool(getattr(obj.original, "is_shadow_catcher", False))


def ray_visibility(obj, inst=None):
    """The shape's "visibility" (FORMAT.md "Ray visibility"): the flags that are off, each
    False ({} when all are on). An instance's flags are its object's and its instancer's (Cycles
    ands them)."""
    owners = [obj]
    if inst is not None and inst.is_instance and inst.parent is not None:
        owners.append(inst.parent)
    return {key: False for flag, key in RAY_VISIBILITY.items()
            if not all(getattr(o, flag, True) for o in owners)}


def _is_holdout(obj, held_out):
    """Whether the object is a holdout (FORMAT.md "Film transparency and holdouts")."""
    return bool(getattr(obj.original, "is_holdout", False)) or obj.original.name in held_out


def _scatters(medium):
    """Whether a medium dict (FORMAT.md "media", either parametrisation) scatters."""
    if "density" in medium:
        return medium["density"] > 0.0 and max(units.rgb3(medium.get("color", 0.5))) > 0.0
    return max(units.rgb3(medium.get("sigma_s", 0.0))) > 0.0


def _placed_mesh(arrays, obj, slots, uv_layer, mats, problems):
    """A _Placed for the arrays of `obj` (no templates: an empty mesh): one shape per
    material slot used."""
    orig = obj.original
    if arrays is None:
        return _Placed(orig.name, [], False)
    problems.extend(arrays.notes)
    uvs = arrays.uvs
    if uv_layer is not None and uvs is None:
        # Cycles reads a missing UV map as (0, 0): the textures' value at the origin.
        problems.append("object '%s': its textured materials read UV map '%s', which the "
                        "mesh does not have; UV (0, 0) used everywhere, as Cycles does"
                        % (orig.name, uv_layer or "(render)"))
        uvs = np.zeros((len(arrays.positions), 2), np.float32)
    used = np.unique(arrays.material)
    templates = []
    for mi in used:
        mi = int(mi)
        slot_mat = slots[min(mi, len(slots) - 1)] if slots else None
        tris = arrays.indices if len(used) == 1 else arrays.indices[arrays.material == mi]
        shape = {"type": "mesh", "positions": arrays.positions, "indices": tris,
                 "normals": arrays.normals}
        if uvs is not None:
            shape["uvs"] = uvs
        if arrays.tangents is not None:
            shape["tangents"] = arrays.tangents
        if arrays.colors is not None:
            shape["colors"] = arrays.colors
        _add_material(shape, slot_mat, mats, obj)
        if _reads_generated(slot_mat, mats, obj):
            shape["texture_space"] = _texture_space(obj)
        templates.append(("" if len(used) == 1 else " [slot %d]" % mi, shape))
    emits = any(materials.is_texture(t.get("emission")) or any(t.get("emission") or [])
                for _, t in templates)
    return _Placed(orig.name, templates, emits)


def _place(order, placed, instancing, problems):
    """(shapes, prototypes) of the placements in `order`: a mesh placed more than once as a
    prototype and instances (when `instancing`), every other placement as mesh shapes with
    its transform."""
    prototypes = {}
    proto_of = {}  # id(_Placed) -> prototype name
    for rec in placed.values():
        n = len(rec.placements)
        if n < 2 or not instancing:
            continue
        if rec.emits:
            problems.append("object '%s': placed %d times and emits light: expanded into a mesh "
                            "per placement, not instanced (Facet's prototypes cannot emit)"
                            % (rec.name, n))
            continue
        pname, k = rec.name, 1
        while pname in prototypes:
            k += 1
            pname = "%s (%d)" % (rec.name, k)
        prototypes[pname] = [dict(t, name=rec.name + suffix) for suffix, t in rec.templates]
        proto_of[id(rec)] = pname
    shapes = []
    owners = []  # per shape: the object whose own placement it is (None: an instance's)
    next_placement = {}
    for entry in order:
        if not isinstance(entry, _Placed):
            shapes.append(entry)
            owners.append(None)
            continue
        i = next_placement.get(id(entry), 0)
        next_placement[id(entry)] = i + 1
        rows, name = entry.placements[i]
        owner = None if name.endswith(" (instance)") else name
        pname = proto_of.get(id(entry))
        if pname is not None:
            shapes.append({"type": "instance", "of": pname, "transform": rows, "name": name})
            owners.append(owner)
            continue
        for suffix, t in entry.templates:
            shapes.append(dict(t, transform=rows, name=name + suffix))
            owners.append(owner)
    return shapes, prototypes, owners


def _color_attribute_read(obj, slots, mats, problems):
    """The colour attribute the object's materials read through Color Attribute nodes: None
    (none), "" (the default colour attribute) or a name; one per object (the core has one
    set of vertex colours per mesh), the others reported."""
    wanted = []
    for m in slots:
        if m is not None and m.get("facet_cycles_only"):
            continue
        for name in sorted(mats.get(m, obj)[1].color_attributes):
            if name not in wanted:
                wanted.append(name)
    if len(wanted) > 1:
        line = ("object '%s': its materials read several colour attributes (%s); only '%s' is "
                "exported, the others read it too"
                % (obj.original.name, ", ".join("'%s'" % (w or "(default)") for w in wanted),
                   wanted[0] or "(default)"))
        if line not in problems:
            problems.append(line)
    return wanted[0] if wanted else None


def _uv_layer(obj, slots, mats, problems):
    """The UV map the object's textured materials read: None (no texture), "" (the render UV
    map) or a name; one per object, the others reported. A name that is the render UV map's
    (the glTF importer names it on its Normal Map nodes) is that map: ""."""
    layers = getattr(obj.data, "uv_layers", None) or ()
    render = next((u.name for u in layers if u.active_render), None)
    wanted = []
    for m in slots:
        if m is not None and m.get("facet_cycles_only"):
            continue
        for uv in sorted(mats.get(m, obj)[1].uv_maps):
            uv = "" if uv == render else uv
            if uv not in wanted:
                wanted.append(uv)
    if len(wanted) > 1:
        line = ("object '%s': its materials read several UV maps (%s); only '%s' is exported"
                % (obj.original.name, ", ".join("'%s'" % (w or "(render)") for w in wanted),
                   wanted[0] or "(render)"))
        if line not in problems:  # once, however many placements
            problems.append(line)
    return wanted[0] if wanted else None


def _reads_generated(mat, mats, obj):
    """Whether the material's procedural textures read Generated coordinates."""
    if mat is not None and mat.get("facet_cycles_only"):
        return False
    return getattr(mats.get(mat, obj)[1], "generated", False)


def _texture_space(obj):
    """The object's texture space (Cycles' Generated coordinates: its evaluated mesh's
    texspace_location and texspace_size, the automatic one its bounding box), as the shape's
    "texture_space" (FORMAT.md): every material slot's shape shares the object's."""
    data = obj.data
    loc = getattr(data, "texspace_location", None)
    size = getattr(data, "texspace_size", None)
    if loc is None or size is None:
        return {"location": [0.0, 0.0, 0.0], "size": [1.0, 1.0, 1.0]}
    return {"location": [float(x) for x in loc], "size": [float(x) for x in size]}


def _hair_shape(shape, mat, mats, obj, problems, visibility=None):
    """A curves shape (sync_hair.py) with its material and its object's ray visibility; an
    emitting one's emission dropped (reported: curves cannot emit)."""
    _add_material(shape, mat, mats, obj)
    if visibility:
        shape["visibility"] = dict(visibility)
    if shape.pop("emission", None) is not None:
        problems.append("object '%s': hair '%s': its material emits, which curves cannot; "
                        "the emission is not rendered" % (obj.original.name, shape["name"]))
    shape.pop("two_sided", None)
    return shape


def _add_material(shape, mat, mats, obj=None):
    if mat is not None and mat.get("facet_cycles_only"):
        # an emitter's Cycles-only material (tests/support/python/facet_testsupport/cycles_scene.py)
        mat = None
    if mat is None and any(shape.get("emission") or []):
        return  # an emitter without a material reflects nothing (FORMAT.md)
    name, conv = mats.get(mat, obj)
    shape["material"] = name
    if "emission" not in shape or not any(shape.get("emission") or []):
        if conv.emits():
            shape["emission"] = (dict(conv.emission) if materials.is_texture(conv.emission)
                                 else list(conv.emission))
    if "two_sided" not in shape:
        shape["two_sided"] = conv.two_sided
    if conv.light_path:  # Light Path node switches (FORMAT.md "Light Path switches")
        shape["light_path"] = [dict(s) for s in conv.light_path]


def export_render_settings(scene, frame=None):
    fs = scene.facet
    seed = fs.seed + (scene.frame_current if fs.animated_seed else 0)
    out = {"integrator": fs.integrator, "spp": fs.spp, "max_depth": fs.max_depth, "seed": seed}
    if fs.time_budget > 0.0:
        out["time_budget"] = fs.time_budget
    if fs.adaptive_threshold > 0.0:
        out["adaptive_threshold"] = fs.adaptive_threshold
        out["adaptive_min_samples"] = fs.adaptive_min_samples
    if scene.render.film_transparent:  # Film > Transparent: an RGBA image (FORMAT.md)
        out["film_transparent"] = True
    return out
