"""Every unit conversion between Blender/Cycles and Facet, one function per quantity.

Facet's units are scenes/FORMAT.md's: point and spot lights by radiant power (W), directional
lights by irradiance (W m^-2), area lights and the environment by radiance (W sr^-1 m^-2),
angles in degrees. Blender's are Cycles' (checked against Cycles 3.4's
intern/cycles/scene/light.cpp and blender/light.cpp):

- point light of Power P: intensity I = P / (4 pi) W/sr in every direction (Cycles divides by
  4 pi, then by the area pi r^2 of its emitting disc). A Facet point light of power Phi has
  I = Phi / (4 pi), so Phi = P. A Radius R keeps P: Cycles 3.4 spreads I over a disc of radius
  R facing the shaded point (radiance P / (4 pi) / (pi R^2)), which the core's
  "radius_model": "cycles34_disc" is (sync_light.py chooses it; the sphere of the same
  radiance with Lamp Model Physical).
- spot light: Cycles gives the cone the point light's intensity P / (4 pi) (no normalisation by
  the cone's solid angle) times cos(angle from the axis) -- measured by render in
  tests/blender/test_cycles_lights.py: Cycles / (P / (4 pi)) = cos to 1e-3 across the cone --
  and fades it with smoothstep over cos theta in [cos(size/2), cos(size/2) + blend
  (1 - cos(size/2))]. Facet's spot is set by its total power, constant inside the inner cone
  and fading *linearly* in cos theta over [cos outer, cos inner]; it has no cos factor. Facet's
  I0 is matched to Cycles' on the axis, P / (4 pi), and the fade range to Cycles'. An
  approximation: off the axis Facet's spot is brighter by 1 / cos (1.07 at 20 degrees, 1.31 at
  40), and linear instead of smoothstep in the blend range.
  The cone integrals (Facet's power for an on-axis intensity, linear or Cycles' fall-off) are
  the core's alone (light_units.h: spot_intensity, cycles_spot_intensity), called through the
  native module; this file only inverts them (they are linear in the power).
- sun of Strength S: irradiance S W/m^2 on a surface facing it when its Angle is 0. With an
  Angle the same S is Cycles 3.4's strength (every light sample carries S: the core's
  "angle_model": "cycles34", whose facing surface receives S 2 (sqrt(1 + T^2) - 1) / T^2,
  T = tan(Angle / 2)); with Lamp Model Physical, the irradiance of a uniform cone.
- area light of Power P: Facet's "area" lamp takes the same P; its radiance L = P / (4 A)
  (Cycles' eval_fac = 0.25 / area; A = size_x size_y, pi/4 of that for round lights) is the
  core's conversion alone (light_units.h: area_lamp_area, area_lamp_radiance), one-sided,
  along the light's local -Z.
- emission shader: radiance = Color x Strength (Cycles' emission closure is radiance).
- world background: radiance = Color x Strength.
"""
import math

from . import native

# --- lights --------------------------------------------------------------------------------


def point_power_from_blender(color, power_w):
    """Blender/Cycles point light (colour, Power in W) -> Facet point light power (W, RGB)."""
    return [float(c) * float(power_w) for c in color]


def point_power_to_blender(power_rgb):
    """Facet point light power (W, RGB) -> (colour, Power in W) for Blender."""
    return _split_colour(power_rgb)


def spot_cone_from_blender(spot_size_rad, spot_blend):
    """Blender spot (full cone angle in radians, blend in [0, 1]) -> Facet (outer_angle,
    inner_angle) half-angles in degrees; the fade range in cos theta is Cycles'."""
    cos_outer = math.cos(0.5 * spot_size_rad)
    cos_inner = min(1.0, cos_outer + float(spot_blend) * (1.0 - cos_outer))
    outer = math.degrees(0.5 * spot_size_rad)
    # acos(cos(x)) can round above x: blend 0 must give inner == outer exactly.
    return outer, min(outer, math.degrees(math.acos(cos_inner)))


def spot_cone_to_blender(outer_deg, inner_deg):
    """Facet (outer_angle, inner_angle) in degrees -> Blender (spot_size in radians, blend)."""
    outer = math.radians(outer_deg)
    cos_outer, cos_inner = math.cos(outer), math.cos(math.radians(inner_deg))
    blend = 0.0 if cos_outer >= 1.0 else (cos_inner - cos_outer) / (1.0 - cos_outer)
    return 2.0 * outer, max(0.0, min(1.0, blend))


def _spot_power_per_intensity(outer_deg, inner_deg):
    """Facet's linear spot: Phi / I0 (sr), from the core's spot_intensity (I0 of 1 W); 0 for a
    cone of zero width."""
    i0 = native.spot_intensity(1.0, inner_deg, outer_deg)[0]
    return 1.0 / i0 if i0 > 0.0 else 0.0


def _blender_intensity(color, power_w):
    """Cycles' spot (and point) intensity of colour x Power P: P / (4 pi) per channel."""
    return [native.point_intensity(float(c) * float(power_w))[0] for c in color]


def spot_power_from_blender(color, power_w, outer_deg, inner_deg):
    """Blender spot (colour, Power) -> Facet spot power: I0 = P / (4 pi) in the cone."""
    factor = _spot_power_per_intensity(outer_deg, inner_deg)
    return [i * factor for i in _blender_intensity(color, power_w)]


def spot_power_to_blender(power_rgb, outer_deg, inner_deg):
    """Facet spot power (W, RGB) -> (colour, Power in W) for Blender."""
    per_watt = _blender_intensity([1.0], 1.0)[0] * _spot_power_per_intensity(outer_deg, inner_deg)
    return _split_colour([p / per_watt for p in power_rgb])


def spot_blend_power_from_blender(color, power_w, outer_deg, blend):
    """Blender spot (colour, Power P, half-angle outer, spot_blend b) -> the power Phi of Facet's
    spot in Blender's form (FORMAT.md, spot) with K = P / (4 pi): the core's
    cycles_spot_intensity gives K for a power, linearly, so Phi = K / K(1 W)."""
    k1 = native.cycles_spot_intensity(1.0, outer_deg, blend)[0]
    k = _blender_intensity(color, power_w)
    return [ki / k1 if k1 > 0.0 else 0.0 for ki in k]


def sun_irradiance_from_blender(color, strength):
    """Blender sun (colour, Strength in W/m^2) -> Facet directional irradiance (W/m^2, RGB)."""
    return [float(c) * float(strength) for c in color]


def sun_irradiance_to_blender(irradiance_rgb):
    return _split_colour(irradiance_rgb)


def area_power_from_blender(color, power_w):
    """Blender area light (colour, Power in W) -> Facet "area" lamp power (W, RGB): the same
    P; the core alone turns it into radiance, L = P / (4 A) (light_units.h,
    area_lamp_radiance)."""
    return point_power_from_blender(color, power_w)


def area_power_to_blender(power_rgb):
    """Facet "area" lamp power (W, RGB) -> (colour, Power in W) for Blender."""
    return _split_colour(power_rgb)


def emission_from_blender(color, strength):
    """Cycles emission shader (or world background) colour x strength -> radiance."""
    return [float(c) * float(strength) for c in color[:3]]


# --- media (volumes) ------------------------------------------------------------------------
# Density is per unit length: Blender's scene unit is the core's (the exporter writes Blender's
# coordinates as they are), so sigma = density per Blender unit with no scale factor. The
# coefficients are the core's conversion (medium.h: cycles_volume) or FORMAT.md's documented
# JSON form; these functions only choose which.


def principled_volume_from_blender(density, color, absorption_color):
    """Cycles' Principled Volume (Density clamped at 0 as Cycles does, Color, Absorption Color)
    -> (sigma_a, sigma_s) per scene unit: the core's cycles_volume."""
    return native.cycles_volume(max(float(density), 0.0), color[:3], absorption_color[:3])


def volume_scatter_from_blender(density, color):
    """Cycles' Volume Scatter (Color, Density) -> (sigma_a, sigma_s): Cycles' extinction is
    Color x Density, all of it scattering (svm_node_closure_volume), which is cycles_volume with
    absorption_color 1 (its absorption term is then 0)."""
    return principled_volume_from_blender(density, color, (1.0, 1.0, 1.0))


def volume_absorption_from_blender(density, color):
    """Cycles' Volume Absorption (Color, Density) -> sigma_a = Density x (1 - Color), Color
    clamped to [0, 1] (FORMAT.md "Cycles' parameters"; svm_node_closure_volume)."""
    d = max(float(density), 0.0)
    return [d * (1.0 - min(max(float(c), 0.0), 1.0)) for c in color[:3]]


def rgb3(v):
    """A colour of the scene format (a number or [r, g, b]) as [r, g, b]."""
    return [float(v)] * 3 if isinstance(v, (int, float)) else [float(c) for c in v]


def _split_colour(rgb):
    """RGB quantity -> (colour with max 1, scalar), as Blender stores lights."""
    m = max(float(v) for v in rgb)
    if m <= 0.0:
        return [1.0, 1.0, 1.0], 0.0
    return [float(v) / m for v in rgb], m


# --- camera --------------------------------------------------------------------------------


def fov_from_projection(projection_11):
    """Full vertical field of view (degrees) from element [1][1] of Blender's camera projection
    matrix (calc_matrix_camera), which is 1 / tan(fov_y / 2) whatever the sensor fit."""
    return math.degrees(2.0 * math.atan(1.0 / float(projection_11)))


def camera_window(projection, orthographic):
    """(h_x, h_y, c_x, c_y): the image window's half-extents and centre (FORMAT.md "camera";
    perspective: on the plane at distance 1, orthographic: in scene units) from Blender's
    camera projection matrix (calc_matrix_camera, rows): a frustum has [0][0] = 2n / (r - l)
    and [0][2] = (r + l) / (r - l), so h_x = 1 / [0][0] and c_x = [0][2] / [0][0]; an
    orthographic box has [0][0] = 2 / (r - l) and [0][3] = -(r + l) / (r - l). Likewise y."""
    p = projection
    hx, hy = 1.0 / float(p[0][0]), 1.0 / float(p[1][1])
    col = 3 if orthographic else 2
    sign = -1.0 if orthographic else 1.0
    return hx, hy, sign * float(p[0][col]) * hx, sign * float(p[1][col]) * hy


def camera_basis(position, look_at, up):
    """FORMAT.md's camera frame: forward f, right r, picture-up u (unit vectors)."""
    f = _normalize([look_at[i] - position[i] for i in range(3)])
    r = _normalize(_cross(f, up))
    u = _cross(r, f)
    return f, r, u


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _normalize(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]
