"""State snapshots of objects imported from a Facet JSON scene (export.py: while an object's
Blender state is unchanged, its original description is exported as it was read), and the
export's error."""
import json


class ExportError(Exception):
    pass


def _floats(vals):
    return ",".join(repr(float(v)) for v in vals)


def object_state(obj, matrix=None):
    m = obj.matrix_world if matrix is None else matrix
    parts = [_floats(v for row in m for v in row)]
    if obj.type == 'CAMERA':
        c = obj.data
        parts.append(_floats((c.lens, c.sensor_width, c.sensor_height, c.shift_x, c.shift_y,
                              c.ortho_scale)))
        parts.append(c.sensor_fit + c.type)
        d = c.dof
        parts.append("%s%s" % (d.use_dof, d.focus_object.name if d.focus_object else "")
                     + _floats((d.focus_distance, d.aperture_fstop, d.aperture_blades,
                                d.aperture_rotation, d.aperture_ratio)))
    elif obj.type == 'LIGHT':
        lt = obj.data
        parts.append(lt.type + _floats(list(lt.color) + [lt.energy]))
        if lt.type == 'SPOT':
            parts.append(_floats((lt.spot_size, lt.spot_blend)))
        if lt.type == 'SUN':
            parts.append(_floats((lt.angle,)))
        if lt.type == 'AREA':
            parts.append(lt.shape + _floats((lt.size, lt.size_y)))
    return ";".join(parts)


def render_state(scene):
    r = scene.render
    return "%d,%d,%d,%s,%s" % (r.resolution_x, r.resolution_y, r.resolution_percentage,
                              repr(float(r.pixel_aspect_x)), repr(float(r.pixel_aspect_y)))


def world_state(world):
    parts = [_floats(world.color) + ";%s" % world.use_nodes]
    if world.use_nodes and world.node_tree is not None:
        # An imported sky (importer._sky_world): its Sky Texture's settings and the strengths.
        for n in world.node_tree.nodes:
            if n.bl_idname == 'ShaderNodeTexSky':
                parts.append(n.sky_type + str(n.sun_disc) + _floats((
                    n.sun_size, n.sun_intensity, n.sun_elevation, n.sun_rotation, n.altitude,
                    n.air_density, n.dust_density, n.ozone_density)))
        if len(parts) > 1:
            parts.append(_floats(n.inputs['Strength'].default_value for n in
                                 world.node_tree.nodes if n.bl_idname == 'ShaderNodeBackground'))
    return ";".join(parts)


def _stored(id_block, key, state):
    """The original description stored at import, when the block is unchanged since."""
    if key in id_block and id_block.get("facet_state") == state:
        return json.loads(id_block[key])
    return None


# Object > Visibility > Ray Visibility: Blender's flag -> the shape's "visibility" key
# (FORMAT.md "Ray visibility"; export.ray_visibility, the importer's objects).
RAY_VISIBILITY = {"visible_camera": "camera", "visible_diffuse": "diffuse",
                  "visible_glossy": "glossy", "visible_transmission": "transmission",
                  "visible_volume_scatter": "volume_scatter", "visible_shadow": "shadow"}
