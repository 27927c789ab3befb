"""A Blender lamp -> a Facet light, through the one unit conversion each (units.py; Cycles'
blender_light.cpp)."""
import math

from . import gaps, units


# Blender's area lamp shapes -> Facet's "area" kind's (the importer maps them back).
AREA_SHAPES = {'SQUARE': "square", 'RECTANGLE': "rectangle", 'DISK': "disc", 'ELLIPSE': "ellipse"}


def _light_data(obj, matrix, problems, lamp_model="cycles34"):
    """A Blender lamp -> one light of the scene format (None: not supported, reported).
    `lamp_model` (Scene.facet.lamp_model): "cycles34" gives a Radius and a Sun's Angle Cycles
    3.4's models, "physical" the sphere lamp and the uniform sun cone."""
    lt = obj.data
    cycles34 = lamp_model == "cycles34"
    for label, value, what in gaps.light_gaps(lt, lamp_model):
        problems.append("light '%s': %s light %s = %s: %s" % (obj.name, lt.type.lower(), label,
                                                             value, what))
    m = matrix
    pos = [m[i][3] for i in range(3)]
    axis = [-m[i][2] for i in range(3)]  # Blender lights point along local -Z
    # Sizes as Cycles 3.4 defines them: a point or spot lamp's Radius is the radius of a disc
    # centred on the lamp facing each shaded point, of radiance P / (4 pi) / (pi R^2) (Facet's
    # "radius" with "radius_model": "cycles34_disc"; "physical": the sphere of that radiance),
    # the Sun's Angle its full angular diameter (Facet's "angle", degrees) with Cycles 3.4's
    # sampling ("angle_model": "cycles34"; "physical": the cone keeping the irradiance).
    size = {"radius": float(lt.shadow_soft_size)} if lt.type in ('POINT', 'SPOT') and \
        lt.shadow_soft_size > 0.0 else {}
    if size and cycles34:
        size["radius_model"] = "cycles34_disc"
    if lt.type == 'POINT':
        return {"type": "point", "position": pos, **size,
                 "power": units.point_power_from_blender(lt.color, lt.energy)}
    if lt.type == 'SPOT':
        # Blender's form (FORMAT.md, spot): outer = spot_size / 2, spot_blend as it is, with
        # Cycles 3.4's smoothstep fall-off; the power keeps K = P / (4 pi).
        outer = math.degrees(0.5 * lt.spot_size)
        return {"type": "spot", "position": pos, "direction": axis, "outer_angle": outer,
                 "spot_blend": float(lt.spot_blend), **size,
                 "power": units.spot_blend_power_from_blender(lt.color, lt.energy, outer,
                                                              lt.spot_blend)}
    if lt.type == 'SUN':
        sun = {"angle": math.degrees(lt.angle)} if lt.angle > 0.0 else {}
        if sun and cycles34:
            sun["angle_model"] = "cycles34"
        return {"type": "directional", "direction": axis, **sun,
                 "irradiance": units.sun_irradiance_from_blender(lt.color, lt.energy)}
    if lt.type == 'AREA':
        return _area_light(obj, lt, m, pos, problems)
    problems.append("light '%s': type %s is not supported; skipped" % (obj.name, lt.type))
    return None


def _area_light(obj, lt, m, pos, problems):
    """Blender's area lamp -> the core's `area` kind (square, rectangle, disc, ellipse; power
    P as Blender's): centred on the object, emitting along its local -Z, local +Y up, the
    sizes times the object's scale along X and Y (as Cycles scales them). A shear between the
    lamp's X and Y axes is reported (the sizes along the scaled axes are used)."""
    x = [m[i][0] for i in range(3)]
    y = [m[i][1] for i in range(3)]
    z = [m[i][2] for i in range(3)]
    sx, sy, sz = (math.sqrt(sum(c * c for c in v)) for v in (x, y, z))
    if abs(sum(a * b for a, b in zip(x, y))) > 1e-6 * sx * sy:
        problems.append("light '%s': area lamp sheared by its transform; its X and Y sizes are "
                        "used along perpendicular axes" % obj.name)
    round_shape = lt.shape in ('DISK', 'ELLIPSE')
    size = float(lt.size) * sx
    size_y = (float(lt.size_y) if lt.shape in ('RECTANGLE', 'ELLIPSE') else float(lt.size)) * sy
    out = {"type": "area", "position": pos, "direction": [-c / sz for c in z],
           "up": [c / sy for c in y],
           "size": size, "power": units.area_power_from_blender(lt.color, lt.energy),
           # Blender 3.4 hides a new lamp from camera rays (Object > Visibility > Camera).
           "camera_visible": bool(obj.visible_camera)}
    if abs(size_y - size) > 1e-6 * size:  # float32 matrices: a square stays square
        out["shape"] = "ellipse" if round_shape else "rectangle"
        out["size_y"] = size_y
    else:
        out["shape"] = "disc" if round_shape else "square"
    return out
