"""The world -> the environment light: a constant radiance, an HDRI map or a Nishita sky
(Cycles' blender_object.cpp's background part)."""
import math

from . import materials, nodegraph, textures, units
from .sync_state import world_state, _stored


def export_environment(scene, problems):
    world = scene.world
    if world is None:
        return None
    stored = _stored(world, "facet_environment", world_state(world))
    if stored is not None:
        return stored
    if world.use_nodes and world.node_tree is not None:
        env = _world_sky(world, problems) or _world_environment_map(world, problems)
        if env is not None:
            return env
        rad = _world_radiance(world, problems)
        if rad is None:
            return None
    else:
        rad = units.emission_from_blender(world.color, 1.0)
    if not any(c > 0.0 for c in rad):
        return None
    return {"type": "environment", "radiance": rad}


def _world_environment_map(world, problems):
    """A world whose output is a Background (or Emission) with its Color fed by an
    Environment Texture (equirectangular), through Mapping nodes of rotations (and a uniform
    scale) from the world's Generated coordinates (the view direction, also when unlinked),
    and a constant Strength -> the core's environment map: file, radiance = Strength, and
    rotate. Cycles looks up l = R d (Mapping Point / Vector: R = Rz Ry Rx; Texture: its
    transpose); Facet looks up l = M^T d, so M = R^T, given as the axis and angle of R^T.
    None when the world is not of this form (the generic conversion then reports it)."""
    walker = nodegraph.Walker(world.node_tree)
    out = nodegraph.active_output(world.node_tree, 'ShaderNodeOutputWorld')
    if out is None:
        return None
    bg = walker.input(out, 'Surface')
    if not isinstance(bg, nodegraph.Out) or bg.convs or bg.node.bl_idname not in (
            'ShaderNodeBackground', 'ShaderNodeEmission'):
        return None
    tex = walker.input(bg.node, 'Color', bg.path)
    strength, _ = walker.fold(walker.input(bg.node, 'Strength', bg.path))
    if not isinstance(tex, nodegraph.Out) or tex.node.bl_idname != 'ShaderNodeTexEnvironment' \
            or tex.socket.identifier != 'Color' or strength is None:
        return None
    what = "world '%s': %s" % (world.name, tex.label())
    node = tex.node
    if node.image is None or node.projection != 'EQUIRECTANGULAR':
        return None
    try:
        path, colorspace, note = textures.image_file(node.image)
    except ValueError:
        return None
    lin = _lookup_rotation(walker, node, tex.path, what, problems)
    if lin is None:
        return None
    if node.image.is_float:
        path, clamped = textures.nonnegative_radiance_file(node.image, path)
        if clamped:
            problems.append("%s: %s" % (what, clamped))
    env = {"type": "environment", "file": path, "radiance": float(strength)}
    _set_rotate(env, lin)
    if note:
        problems.append("%s: %s" % (what, note))
    # The core reads float files as linear and other files sRGB-decoded (FORMAT.md).
    want = "linear" if path.lower().endswith((".exr", ".hdr")) else "srgb"
    if colorspace != want:
        problems.append("%s: colour space '%s': Facet reads this file as %s"
                        % (what, node.image.colorspace_settings.name, want))
    if colorspace == "srgb" and not node.image.is_float:
        problems.append("%s: Cycles interpolates an 8-bit sRGB image before decoding it, "
                        "Facet after" % what)
    if node.interpolation not in ('Linear',):
        problems.append("%s: interpolation %s converted as Linear" % (what, node.interpolation))
    return env


def _lookup_rotation(walker, node, path, what, problems):
    """The rotation R (a 3x3 Matrix) of the Mapping nodes (rotations and a uniform scale) that
    feed the texture `node`'s Vector from the world's Generated coordinates (or nothing), or
    None when anything else feeds it. A Mapping that is not a rotation is reported and read as
    the identity."""
    from mathutils import Matrix
    m = Matrix.Identity(4)
    cur = walker.input(node, 'Vector', path)
    while isinstance(cur, nodegraph.Out):
        n = cur.node
        if n.bl_idname == 'ShaderNodeTexCoord' and cur.socket.identifier == 'Generated':
            break
        if n.bl_idname != 'ShaderNodeMapping':
            return None
        vals = [walker.fold(walker.input(n, name, cur.path))[0]
                for name in ('Location', 'Rotation', 'Scale')]
        mm = textures.mapping_matrix(n.vector_type, *vals) if None not in vals else None
        if mm is None:
            return None
        m = m @ Matrix(mm)
        cur = walker.input(n, 'Vector', cur.path)
    lin = m.to_3x3()
    scale = lin.determinant() ** (1.0 / 3.0) if lin.determinant() > 0.0 else 0.0
    if scale <= 0.0 or m.translation.length > 0.0 or \
            max(abs(v) for row in (lin @ lin.transposed() - Matrix.Identity(3) * scale ** 2)
                for v in row) > 1e-6 * scale ** 2:
        problems.append("%s: its Mapping is not a rotation (with a uniform scale); the map is "
                        "not rotated" % what)
        return Matrix.Identity(3)
    return lin * (1.0 / scale)


def _set_rotate(env, lin):
    """env["rotate"] = M = R^T as an axis and angle (omitted for the identity)."""
    axis, angle = lin.transposed().to_quaternion().to_axis_angle()
    if abs(angle) > 1e-12:
        if max(axis, key=abs) < 0.0:  # the same rotation, read with the axis' main part > 0
            axis, angle = -axis, -angle
        env["rotate"] = {"axis": [float(c) for c in axis], "angle": math.degrees(angle)}


def _world_sky(world, problems):
    """A world whose output is a Background (or Emission) with its Color fed by a Sky Texture of
    type Nishita (through Mapping rotations, as an Environment Texture) and a constant Strength
    -> the core's "sky_nishita" environment (angles in degrees, radiance = Strength). Other sky
    types, and anything else, return None (the generic conversion reports them by name)."""
    walker = nodegraph.Walker(world.node_tree)
    out = nodegraph.active_output(world.node_tree, 'ShaderNodeOutputWorld')
    if out is None:
        return None
    bg = walker.input(out, 'Surface')
    if not isinstance(bg, nodegraph.Out) or bg.convs or bg.node.bl_idname not in (
            'ShaderNodeBackground', 'ShaderNodeEmission'):
        return None
    tex = walker.input(bg.node, 'Color', bg.path)
    strength, _ = walker.fold(walker.input(bg.node, 'Strength', bg.path))
    if not isinstance(tex, nodegraph.Out) or tex.node.bl_idname != 'ShaderNodeTexSky' \
            or tex.socket.identifier != 'Color' or strength is None \
            or tex.node.sky_type != 'NISHITA':
        return None
    node = tex.node
    what = "world '%s': %s" % (world.name, tex.label())
    lin = _lookup_rotation(walker, node, tex.path, what, problems)
    if lin is None:
        return None
    tm = node.texture_mapping
    if tuple(tm.translation) != (0.0, 0.0, 0.0) or tuple(tm.rotation) != (0.0, 0.0, 0.0) \
            or tuple(tm.scale) != (1.0, 1.0, 1.0):
        problems.append("%s: its own texture mapping is not converted (identity used)" % what)
    env = {"type": "sky_nishita", "sun_disc": bool(node.sun_disc),
           "sun_size": math.degrees(node.sun_size),
           "sun_intensity": float(node.sun_intensity),
           "sun_elevation": math.degrees(node.sun_elevation),
           "sun_rotation": math.degrees(node.sun_rotation),
           "altitude": float(node.altitude), "air_density": float(node.air_density),
           "dust_density": float(node.dust_density),
           "ozone_density": float(node.ozone_density), "radiance": float(strength)}
    _set_rotate(env, lin)
    return env


def _world_radiance(world, problems):
    """The world's node tree through the node-graph walker (materials.NodeContext): a
    Background or Emission with constant Color and Strength, a colour linked into the Surface,
    Add Shaders and Mix Shaders of them convert exactly; anything else is reported (gaps.py)
    with what Facet used."""
    ctx = materials.NodeContext("world", world.name, world.node_tree)
    out = nodegraph.active_output(world.node_tree, 'ShaderNodeOutputWorld')
    if out is None:
        return None
    _, rad = ctx.shader(ctx.walker.input(out, 'Surface'), "the World Output's Surface")
    problems.extend(ctx.finish())
    return rad


def export_world_medium(scene, problems):
    """The World Output's Volume -> the world medium (FORMAT.md "media", "world_medium"): the
    same conversion as a material's Volume (materials.NodeContext.volume), or None. Inside it,
    as in Cycles, the environment is not seen where the medium's extinction is > 0 (an infinite
    ray's transmittance is 0) and sun lamps do not reach in."""
    world = scene.world
    if world is None or not world.use_nodes or world.node_tree is None:
        return None
    out = nodegraph.active_output(world.node_tree, 'ShaderNodeOutputWorld')
    if out is None:
        return None
    ctx = materials.NodeContext("world", world.name, world.node_tree)
    vol = ctx.walker.input(out, 'Volume')
    medium = None
    if not (isinstance(vol, nodegraph.Const) and vol.value is None):
        medium = ctx.volume(vol, "the World Output's Volume")
    problems.extend(ctx.finish())
    return medium
