"""Facet scene data (read by the core's JSON reader) -> Blender objects.

Every shape becomes an object with a display mesh; the exact shape (analytic sphere, plane,
disc, ...; or the mesh arrays) and its transform stay in the object's "facet_shape" property,
and the camera, lights and environment keep their descriptions likewise (see export.py), so
an imported scene renders with Facet in Blender exactly as with `facet render`. Facet
materials become Blender materials of source 'Facet Model'. Quantities are converted to
Blender's units by units.py.
"""
import json
import math

import bmesh
import bpy
import numpy as np
from mathutils import Matrix, Vector

from . import materials, properties, sync_light, sync_state, units

PLANE_DISPLAY_HALF_SIZE = 50.0  # the infinite plane is drawn as a square of this half size
MAX_DISPLAY_SUBDIVISIONS = 4    # icospheres are drawn at most this fine
MAX_DISPLAY_GRID = 128          # grids are drawn with at most this many cells per side
CLIP_START, CLIP_END = 1e-3, 1e7  # the imported camera's clipping (Facet has none)


def _json(value):
    def conv(v):
        if isinstance(v, np.ndarray):
            return v.tolist()
        raise TypeError(type(v))
    return json.dumps(value, default=conv)


def _matrix(rows):
    return Matrix(rows) if rows is not None else Matrix.Identity(4)


def _display_mesh(name, s):
    """A Blender mesh that looks like the shape (in the shape's local space)."""
    me = bpy.data.meshes.new(name)
    kind = s["type"]
    if kind == "mesh" and "file" in s:
        return me  # drawn empty: the file is read by the core at render time
    if kind == "mesh":
        pos = np.asarray(s["positions"], np.float32).reshape(-1, 3)
        idx = np.asarray(s["indices"], np.int32).reshape(-1, 3)
        me.vertices.add(len(pos))
        me.vertices.foreach_set("co", pos.ravel())
        me.loops.add(idx.size)
        me.loops.foreach_set("vertex_index", idx.ravel())
        me.polygons.add(len(idx))
        me.polygons.foreach_set("loop_start", np.arange(0, idx.size, 3, dtype=np.int32))
        me.polygons.foreach_set("loop_total", np.full(len(idx), 3, np.int32))
        me.update(calc_edges=True)
        if s.get("normals") is not None:
            me.polygons.foreach_set("use_smooth", np.ones(len(idx), bool))
            # The exact normals (Blender's custom normals are stored compressed).
            nrm = np.asarray(s["normals"], np.float32).reshape(-1, 3)
            me.attributes.new("facet_normal", 'FLOAT_VECTOR', 'POINT').data.foreach_set(
                "vector", nrm.ravel())
        return me
    bm = bmesh.new()
    try:
        if kind in ("sphere", "icosphere"):
            r, c = float(s["radius"]), Vector(s["center"])
            if kind == "sphere":
                bmesh.ops.create_uvsphere(bm, u_segments=32, v_segments=16, radius=r)
            else:
                bmesh.ops.create_icosphere(
                    bm, subdivisions=min(int(s["subdivisions"]), MAX_DISPLAY_SUBDIVISIONS),
                    radius=r)
            bmesh.ops.translate(bm, vec=c, verts=bm.verts)
        elif kind in ("plane", "disc"):
            n = Vector(s["normal"]).normalized()
            rot = n.to_track_quat('Z', 'Y').to_matrix().to_4x4()
            if kind == "plane":
                bmesh.ops.create_grid(bm, x_segments=1, y_segments=1,
                                      size=PLANE_DISPLAY_HALF_SIZE, matrix=rot)
                bmesh.ops.translate(bm, vec=Vector(s["point"]), verts=bm.verts)
            else:
                bmesh.ops.create_circle(bm, cap_ends=True, segments=48,
                                        radius=float(s["radius"]), matrix=rot)
                bmesh.ops.translate(bm, vec=Vector(s["center"]), verts=bm.verts)
        elif kind == "box":
            lo, hi = Vector(s["min"]), Vector(s["max"])
            bmesh.ops.create_cube(bm, size=1.0)
            for v in bm.verts:
                v.co = Vector([lo[i] + (v.co[i] + 0.5) * (hi[i] - lo[i]) for i in range(3)])
        elif kind == "quad":
            verts = [bm.verts.new(Vector(p)) for p in s["vertices"]]
            bm.faces.new(verts)
        elif kind == "grid":
            nx = min(int(s["nx"]), MAX_DISPLAY_GRID)
            ny = min(int(s["ny"]), MAX_DISPLAY_GRID)
            bmesh.ops.create_grid(bm, x_segments=nx + 1, y_segments=ny + 1, size=1.0)
            a, f = float(s.get("amplitude", 0.0)), float(s.get("frequency", 0.0))
            for v in bm.verts:
                v.co.z = a * math.sin(f * v.co.x) * math.sin(f * v.co.y)
        bm.to_mesh(me)
    finally:
        bm.free()
    return me


def _camera_matrix(position, look_at, up):
    """Blender camera looks down local -Z with local +Y up: columns (r, u, -f)."""
    f, r, u = units.camera_basis(position, look_at, up)
    m = Matrix.Identity(4)
    for i in range(3):
        m[i][0], m[i][1], m[i][2], m[i][3] = r[i], u[i], -f[i], position[i]
    return m


def _direction_matrix(position, direction):
    d = Vector(direction).normalized()
    m = (-d).to_track_quat('Z', 'Y').to_matrix().to_4x4()
    m.translation = Vector(position)
    return m


def _sky_world(world, lt, i, problems):
    """A "sky_nishita" light -> the World: Sky Texture (Nishita, angles in radians) ->
    Background of Strength `radiance` (sync_world._world_sky reads it back). A `rotate` about Z
    by a is the sun's rotation minus a (the same sky); about another axis it is a Mapping node
    rotating the lookup by R = M^T, which Blender honours only without the sun's disc (with it
    the node's Vector input is unavailable): then it is reported."""
    world.use_nodes = True
    nt = world.node_tree
    nt.nodes.clear()
    out = nt.nodes.new('ShaderNodeOutputWorld')
    bg = nt.nodes.new('ShaderNodeBackground')
    sky = nt.nodes.new('ShaderNodeTexSky')
    sky.sky_type = 'NISHITA'
    sky.sun_disc = bool(lt.get("sun_disc", True))
    rotation = lt.get("sun_rotation", 0.0)
    r = lt.get("rotate")
    m = None
    if r is not None:
        axis = Vector(r["axis"]).normalized()
        if abs(axis.x) < 1e-9 and abs(axis.y) < 1e-9:
            rotation -= r["angle"] if axis.z > 0.0 else -r["angle"]
        else:
            m = Matrix.Rotation(math.radians(r["angle"]), 3, axis)
    for key, value in (("sun_size", lt.get("sun_size", 0.545)),
                       ("sun_elevation", lt.get("sun_elevation", 15.0)),
                       ("sun_rotation", rotation)):
        setattr(sky, key, math.radians(value))
    for key, default in (("sun_intensity", 1.0), ("altitude", 0.0), ("air_density", 1.0),
                         ("dust_density", 1.0), ("ozone_density", 1.0)):
        setattr(sky, key, float(lt.get(key, default)))
    rad = lt.get("radiance", 1.0)
    if not isinstance(rad, (int, float)):
        if max(rad) - min(rad) > 0.0:
            problems.append("light %d: sky_nishita: an RGB radiance multiplier is shown in "
                            "Blender's World as its mean (Facet renders it per channel)" % i)
        rad = sum(rad) / 3.0
    bg.inputs['Strength'].default_value = float(rad)
    nt.links.new(sky.outputs['Color'], bg.inputs['Color'])
    nt.links.new(bg.outputs['Background'], out.inputs['Surface'])
    if m is not None:
        tc = nt.nodes.new('ShaderNodeTexCoord')
        mp = nt.nodes.new('ShaderNodeMapping')
        mp.inputs['Rotation'].default_value = m.transposed().to_euler('XYZ')
        nt.links.new(tc.outputs['Generated'], mp.inputs['Vector'])
        nt.links.new(mp.outputs['Vector'], sky.inputs['Vector'])
        if sky.sun_disc:
            problems.append("light %d: sky_nishita: its rotate is not shown in Blender's World "
                            "(Blender ignores a Sky Texture's Vector while its Sun Disc is on); "
                            "Facet renders it" % i)


def _environment_world(world, lt, rad, i, problems):
    """An environment map as Blender's World: Environment Texture (equirectangular, the image
    `file`) -> Background, its Strength the multiplier `radiance` (an RGB multiplier through a
    Multiply node). With no `rotate` and `up` [0, 0, 1] the mapping is exactly Facet's
    (FORMAT.md, "Environment maps": Facet's is defined as Blender's); other orientations are
    reported. Cycles renders this world; the Facet engine renders the stored description."""
    world.use_nodes = True
    nt = world.node_tree
    nt.nodes.clear()
    out = nt.nodes.new('ShaderNodeOutputWorld')
    bg = nt.nodes.new('ShaderNodeBackground')
    tex = nt.nodes.new('ShaderNodeTexEnvironment')
    tex.image = bpy.data.images.load(lt["file"], check_existing=True)
    colour = tex.outputs['Color']
    if isinstance(rad, (int, float)):
        bg.inputs['Strength'].default_value = float(rad)
    else:
        mul = nt.nodes.new('ShaderNodeMixRGB')
        mul.blend_type, mul.inputs['Fac'].default_value = 'MULTIPLY', 1.0
        mul.inputs['Color2'].default_value = list(rad) + [1.0]
        nt.links.new(colour, mul.inputs['Color1'])
        colour = mul.outputs['Color']
        bg.inputs['Strength'].default_value = 1.0
    nt.links.new(colour, bg.inputs['Color'])
    nt.links.new(bg.outputs['Background'], out.inputs['Surface'])
    up = lt.get("up")
    if lt.get("rotate") is not None or (up is not None and list(up) != [0.0, 0.0, 1.0]):
        problems.append("light %d: environment map '%s': its rotate/up is not shown in "
                        "Blender's World (Cycles renders it unrotated); Facet renders it"
                        % (i, lt["file"]))


def _lamp_matrix(position, direction, up):
    """An area lamp's object matrix (FORMAT.md, "area"): local -Z along `direction`, local +Y
    `up` made perpendicular to it ([0, 1, 0], or [0, 0, 1] within 2.6 degrees of +-Y, when
    None), local X = Y x Z."""
    z = -Vector(direction).normalized()
    if up is None:
        up = (0.0, 1.0, 0.0) if abs(z.y) < 0.999 else (0.0, 0.0, 1.0)
    y = Vector(up) - Vector(up).dot(z) * z
    y.normalize()
    x = y.cross(z)
    m = Matrix((x, y, z)).transposed().to_4x4()
    m.translation = Vector(position)
    return m


def _material(name, m):
    mat = bpy.data.materials.new(name)
    properties.set_material_params(mat.facet, m["model"],
                                   {k: v for k, v in m.items() if k != "model"})
    # A viewport colour that resembles the material.
    for key in ("reflectance", "diffuse_reflectance"):
        if key in m and not isinstance(m[key], dict):  # a texture: no constant colour
            v = m[key]
            v = [v] * 3 if isinstance(v, (int, float)) else v
            mat.diffuse_color = (v[0], v[1], v[2], 1.0)
            break
    mat["facet_material"] = _json(m)
    mat["facet_state"] = materials.material_state(mat)
    return mat


def _camera_settings(cd, cam):
    """Blender camera data as Cycles renders the Facet camera `cam` (FORMAT.md "camera")."""
    w, h = cam["width"], cam["height"]
    if cam.get("type", "perspective") == "orthographic":
        # Sensor fit AUTO: Ortho Scale and shift are both of the larger side, as Facet's.
        cd.type, cd.sensor_fit, cd.ortho_scale = 'ORTHO', 'AUTO', cam["scale"]
        to_fitted = 1.0
    else:
        # Sensor fit VERTICAL: the fov is angle_y; shift is in fractions of the height.
        cd.sensor_fit = 'VERTICAL'
        cd.angle_y = math.radians(cam["fov"])
        to_fitted = max(w, h) / h
    cd.shift_x = cam.get("shift_x", 0.0) * to_fitted
    cd.shift_y = cam.get("shift_y", 0.0) * to_fitted
    radius = cam.get("aperture_radius")
    if radius is None and cam.get("fstop") and cam.get("focal_length"):
        radius = cam["focal_length"] * 1e-3 / (2.0 * cam["fstop"])
    if radius:
        # Cycles' radius is lens 1e-3 / (2 fstop) (orthographic: 1 / (2 fstop)) with Blender's
        # own lens, which the fov set: the f-stop that gives Facet's radius.
        cd.dof.use_dof = True
        lens = 1.0 if cd.type == 'ORTHO' else cd.lens * 1e-3
        cd.dof.aperture_fstop = lens / (2.0 * radius)
        cd.dof.focus_distance = cam["focus_distance"]
        cd.dof.aperture_blades = cam.get("blades", 0)
        cd.dof.aperture_rotation = math.radians(cam.get("rotation", 0.0))


def import_scene(context, data, collection=None, problems=None):
    """Creates the scene's objects in `collection` (default: a new one named after the
    description). Returns the collection. What is not imported exactly is appended to
    `problems` (one line each), never dropped silently."""
    problems = [] if problems is None else problems
    scene = context.scene
    coll = collection or bpy.data.collections.new("Facet scene")
    if collection is None:
        scene.collection.children.link(coll)
    mats = {name: _material(name, m) for name, m in data.get("materials", [])}
    # Media (FORMAT.md "media") travel with what names them: a material's interior medium on
    # the material, the world medium on the scene (export.py exports them while unchanged).
    media = data.get("media") or {}
    for mat in mats.values():
        interior = json.loads(mat["facet_material"]).get("interior")
        if interior in media:
            mat["facet_medium"] = _json(media[interior])
    if data.get("world_medium") in media:
        scene["facet_world_medium"] = _json({"name": data["world_medium"],
                                             "medium": media[data["world_medium"]]})
    elif "facet_world_medium" in scene:
        del scene["facet_world_medium"]

    cam = data["camera"]
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = cam["width"], cam["height"], 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    cd = bpy.data.cameras.new("Camera")
    _camera_settings(cd, cam)
    # Facet's camera does not clip; Blender's default clip_end (100) would cut scenes in mm.
    cd.clip_start, cd.clip_end = CLIP_START, CLIP_END
    co = bpy.data.objects.new("Camera", cd)
    co.matrix_world = _camera_matrix(cam["position"], cam["look_at"], cam["up"])
    coll.objects.link(co)
    scene.camera = co
    context.view_layer.update()
    co["facet_camera"] = _json(cam)
    co["facet_state"] = sync_state.object_state(co) + "|" + sync_state.render_state(scene)

    for i, s in enumerate(data.get("shapes", [])):
        name = s.get("name") or "%s %d" % (s["type"], i)
        me = _display_mesh(name, s)
        ob = bpy.data.objects.new(name, me)
        ob.matrix_world = _matrix(s.get("transform"))
        coll.objects.link(ob)
        mat = s.get("material")
        if isinstance(mat, dict):
            bmat = _material("%s (inline)" % name, mat)
        elif mat:
            bmat = mats[mat]
        else:
            bmat = None
        if bmat is not None:
            me.materials.append(bmat)
        # Ray visibility (FORMAT.md): the object's Visibility > Ray Visibility flags, which the
        # export reads back (export.ray_visibility).
        for flag, key in sync_state.RAY_VISIBILITY.items():
            setattr(ob, flag, bool(s.get("visibility", {}).get(key, True)))
        # Mesh arrays stay in the Blender mesh (positions exactly; normals in "facet_normal").
        stored = {k: v for k, v in s.items()
                  if k not in ("material", "positions", "indices", "normals")}
        ob["facet_shape"] = _json(stored)
        context.view_layer.update()
        ob["facet_state"] = sync_state.object_state(ob)

    for i, lt in enumerate(data.get("lights", [])):
        kind = lt["type"]
        if kind == "environment":
            world = scene.world or bpy.data.worlds.new("World")
            scene.world = world
            world.use_nodes = False
            rad = lt.get("radiance")
            rad = 1.0 if rad is None else rad
            world.color = rad if not isinstance(rad, (int, float)) else [rad] * 3
            if lt.get("file"):
                _environment_world(world, lt, rad, i, problems)
            world["facet_environment"] = _json(lt)
            world["facet_state"] = sync_state.world_state(world)
            continue
        if kind == "sky_nishita":
            world = scene.world or bpy.data.worlds.new("World")
            scene.world = world
            _sky_world(world, lt, i, problems)
            world["facet_environment"] = _json(lt)
            world["facet_state"] = sync_state.world_state(world)
            continue
        if kind == "point":
            ld = bpy.data.lights.new("Point %d" % i, 'POINT')
            ld.color, ld.energy = units.point_power_to_blender(lt["power"])
            ld.shadow_soft_size = lt.get("radius") or 0.0
            m = Matrix.Translation(Vector(lt["position"]))
        elif kind == "spot":
            ld = bpy.data.lights.new("Spot %d" % i, 'SPOT')
            outer = lt.get("outer_angle", 45.0)
            if lt.get("spot_blend") is not None:  # Blender's form: its own size and blend
                ld.spot_size, ld.spot_blend = math.radians(2.0 * outer), lt["spot_blend"]
                per_watt = units.spot_blend_power_from_blender([1.0], 1.0, outer,
                                                               lt["spot_blend"])[0]
                ld.color, ld.energy = units.point_power_to_blender(
                    [p / per_watt for p in units.rgb3(lt["power"])])
            else:
                inner = lt.get("inner_angle", outer)
                ld.spot_size, ld.spot_blend = units.spot_cone_to_blender(outer, inner)
                ld.color, ld.energy = units.spot_power_to_blender(lt["power"], outer, inner)
            ld.shadow_soft_size = lt.get("radius") or 0.0
            d = lt.get("direction") or [lt["look_at"][k] - lt["position"][k] for k in range(3)]
            m = _direction_matrix(lt["position"], d)
        elif kind == "area":
            ld = bpy.data.lights.new("Area %d" % i, 'AREA')
            ld.shape = {v: k for k, v in sync_light.AREA_SHAPES.items()}[lt.get("shape", "square")]
            ld.size = lt["size"]
            if "size_y" in lt:
                ld.size_y = lt["size_y"]
            ld.color, ld.energy = units.area_power_to_blender(lt["power"])
            d = lt.get("direction") or [lt["look_at"][k] - lt["position"][k] for k in range(3)]
            m = _lamp_matrix(lt["position"], d, lt.get("up"))
        elif kind == "directional":
            ld = bpy.data.lights.new("Sun %d" % i, 'SUN')
            ld.color, ld.energy = units.sun_irradiance_to_blender(lt["irradiance"])
            ld.angle = math.radians(lt.get("angle") or 0.0)
            m = _direction_matrix([0.0, 0.0, 0.0], lt["direction"])
        else:
            problems.append("light %d: kind '%s' is not imported into Blender yet; skipped"
                            % (i, kind))
            continue
        lo = bpy.data.objects.new(ld.name, ld)
        lo.matrix_world = m
        lo.visible_camera = bool(lt.get("camera_visible", False))
        coll.objects.link(lo)
        context.view_layer.update()
        lo["facet_light"] = _json(lt)
        lo["facet_state"] = sync_state.object_state(lo)

    rs = data.get("render", {})
    fs = scene.facet
    fs.integrator = rs.get("integrator", "path")
    fs.spp = int(rs.get("spp", 16))
    fs.time_budget = float(rs.get("time_budget", 0.0))
    fs.max_depth = int(rs.get("max_depth", 8))
    fs.seed = int(rs.get("seed", 0))
    fs.adaptive_threshold = float(rs.get("adaptive_threshold", 0.0))
    fs.adaptive_min_samples = int(rs.get("adaptive_min_samples", 0))
    fs.animated_seed = False
    return coll
