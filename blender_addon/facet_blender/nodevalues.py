"""Blender shader nodes evaluated on constant inputs, each exactly as Cycles 3.4 evaluates it
(its SVM kernel, intern/cycles/kernel/svm/*.h and util/color.h, read in Debian's 3.4.1 copy
under /usr/share/blender/scripts/addons/cycles/source). No bpy import: a node is read only
through its properties (operation, blend_type, ...; a ColorRamp through its own evaluate());
`values` maps input identifiers to floats or 3-tuples.

Cycles computes in float32 from the float32 socket values; these functions compute in double
from the same values, so results agree to float32 rounding (about 1e-7 relative), except where
an operation is discontinuous (floor, compare, ...) at a value within that rounding of its
step. Checked against Cycles renders in tests/blender/test_nodegraph.py.

Formulas (t: factor, a, b: inputs, per colour channel unless stated):
- Math: Cycles' svm_math: safe divide (b = 0 -> 0), safe power (a < 0 with a non-integer b
  -> 0), safe log (a <= 0 or b <= 0 -> 0), sqrt of max(a, 0), inverse sqrt (a <= 0 -> 0),
  round = floor(a + 0.5), modulo = fmod (b = 0 -> 0), wrap, ping-pong, smooth min/max
  (h = max(c - |a - b|, 0)/c; min(a, b) - h^3 c/6), compare (|a - b| <= max(c, FLT_EPSILON)),
  sign (0 -> 0); Clamp ticked: the result clamped to [0, 1].
- Mix RGB (legacy): t clamped to [0, 1], then svm_mix: Mix a + t(b - a), Add a + t b,
  Multiply a + t(ab - a), Subtract a - t b, Screen 1 - (1 - t + t(1 - b))(1 - a), Divide
  (1 - t) a + t a/b (b = 0 channels keep a), Difference a + t(|a - b| - a), Darken/Lighten
  a + t(min/max(a, b) - a), Overlay, Dodge, Burn, Soft Light, Linear Light a + t(2b - 1), and
  Hue/Saturation/Value/Color through HSV; Clamp ticked: the result clamped to [0, 1].
- Mix (3.4): Float and Vector a(1 - t) + b t (Vector: t per component when Non-Uniform);
  Color: svm_mix with t clamped only when Clamp Factor is ticked, the result clamped when
  Clamp Result is.
- Invert: t(1 - c) + (1 - t)c.  Gamma: c^g for c > 0 (other channels unchanged); g = 0 -> 1.
- Hue/Saturation/Value: to HSV; h = fmod(h + hue + 0.5, 1), s = clamp(s sat, 0, 1), v *= val;
  back to RGB; t mix with the input; max(., 0).
- Combine / Separate RGB, XYZ, HSV and Color (RGB, HSV, HSL): the components (Cycles'
  rgb_to_hsv / hsv_to_rgb / rgb_to_hsl / hsl_to_rgb).
- Clamp: Min Max clamp(v, min, max); Range the same with min and max swapped when min > max.
- Map Range (Float and Vector): t = (v - from_min)/(from_max - from_min) (Float: from_max =
  from_min -> 0; Vector: per component, safe divide); Stepped floor(t (steps + 1))/steps;
  Smooth Step (3 - 2t)t^2 and Smoother Step t^3(t(6t - 15) + 10) of t clamped (Float:
  Cycles' smoothstep(from_min, from_max, v), mirrored when from_min > from_max); result
  to_min + t (to_max - to_min), clamped to [to_min, to_max] (either order) when Clamp is ticked.
- Bright/Contrast: max((1 + contrast) c + bright - contrast/2, 0).
- Vector Math: Cycles' svm_vector_math (safe divide, project, reflect about the normalised
  b, refract with the normalised b and Scale as eta, faceforward, snap, wrap, ...); Dot
  Product, Distance and Length on the Value output.
- ColorRamp: Cycles' 256-entry table of the ramp (ColorRamp.evaluate at i/255), read at
  Fac clamped to [0, 1] times 255 with linear interpolation between entries (none for Constant).
- RGB, Value: the output's value.
"""
import math

FLT_EPSILON = 1.1920928955078125e-07


def _interp(a, b, t):
    return a + t * (b - a)


def _sat(x):
    return min(max(x, 0.0), 1.0)


def _fmod(a, b):
    return math.fmod(a, b)


# --- Math ---------------------------------------------------------------------------------------

def _safe_div(a, b):
    return a / b if b != 0.0 else 0.0


def _safe_pow(a, b):
    if a < 0.0 and b != float(int(b)):
        return 0.0
    try:
        return math.pow(a, b)
    except (OverflowError, ZeroDivisionError, ValueError):
        return math.inf if a == 0.0 or abs(a) > 1.0 else 0.0


def _safe_log(a, b):
    if a <= 0.0 or b <= 0.0:
        return 0.0
    return _safe_div(math.log(a), math.log(b))


def _wrap(v, mx, mn):
    r = mx - mn
    return v - r * math.floor((v - mn) / r) if r != 0.0 else mn


def _fract(x):
    return x - math.floor(x)


def _pingpong(a, b):
    return abs(_fract((a - b) / (b * 2.0)) * b * 2.0 - b) if b != 0.0 else 0.0


def _smoothmin(a, b, k):
    if k != 0.0:
        h = max(k - abs(a - b), 0.0) / k
        return min(a, b) - h * h * h * k * (1.0 / 6.0)
    return min(a, b)


def _sign(a):
    return 0.0 if a == 0.0 else (-1.0 if a < 0.0 else 1.0)


def _exp(a):
    try:
        return math.exp(a)
    except OverflowError:
        return math.inf


MATH = {
    'ADD': lambda a, b, c: a + b,
    'SUBTRACT': lambda a, b, c: a - b,
    'MULTIPLY': lambda a, b, c: a * b,
    'DIVIDE': lambda a, b, c: _safe_div(a, b),
    'MULTIPLY_ADD': lambda a, b, c: a * b + c,
    'POWER': lambda a, b, c: _safe_pow(a, b),
    'LOGARITHM': lambda a, b, c: _safe_log(a, b),
    'SQRT': lambda a, b, c: math.sqrt(max(a, 0.0)),
    'INVERSE_SQRT': lambda a, b, c: 1.0 / math.sqrt(a) if a > 0.0 else 0.0,
    'ABSOLUTE': lambda a, b, c: abs(a),
    'EXPONENT': lambda a, b, c: _exp(a),
    'MINIMUM': lambda a, b, c: min(a, b),
    'MAXIMUM': lambda a, b, c: max(a, b),
    'LESS_THAN': lambda a, b, c: 1.0 if a < b else 0.0,
    'GREATER_THAN': lambda a, b, c: 1.0 if a > b else 0.0,
    'SIGN': lambda a, b, c: _sign(a),
    'COMPARE': lambda a, b, c: 1.0 if a == b or abs(a - b) <= max(c, FLT_EPSILON) else 0.0,
    'SMOOTH_MIN': lambda a, b, c: _smoothmin(a, b, c),
    'SMOOTH_MAX': lambda a, b, c: -_smoothmin(-a, -b, c),
    'ROUND': lambda a, b, c: float(math.floor(a + 0.5)),
    'FLOOR': lambda a, b, c: float(math.floor(a)),
    'CEIL': lambda a, b, c: float(math.ceil(a)),
    'TRUNC': lambda a, b, c: float(math.floor(a) if a >= 0.0 else math.ceil(a)),
    'FRACT': lambda a, b, c: _fract(a),
    'MODULO': lambda a, b, c: _fmod(a, b) if b != 0.0 else 0.0,
    'WRAP': lambda a, b, c: _wrap(a, b, c),
    'SNAP': lambda a, b, c: math.floor(_safe_div(a, b)) * b,
    'PINGPONG': lambda a, b, c: _pingpong(a, b),
    'SINE': lambda a, b, c: math.sin(a),
    'COSINE': lambda a, b, c: math.cos(a),
    'TANGENT': lambda a, b, c: math.tan(a),
    'SINH': lambda a, b, c: math.sinh(a),
    'COSH': lambda a, b, c: math.cosh(a),
    'TANH': lambda a, b, c: math.tanh(a),
    'ARCSINE': lambda a, b, c: math.asin(min(max(a, -1.0), 1.0)),
    'ARCCOSINE': lambda a, b, c: math.acos(min(max(a, -1.0), 1.0)),
    'ARCTANGENT': lambda a, b, c: math.atan(a),
    'ARCTAN2': lambda a, b, c: math.atan2(a, b),
    'RADIANS': lambda a, b, c: a * (math.pi / 180.0),
    'DEGREES': lambda a, b, c: a * (180.0 / math.pi),
}


def _math(node, v, out):
    r = MATH[node.operation](v["Value"], v.get("Value_001", 0.0), v.get("Value_002", 0.0))
    return _sat(r) if node.use_clamp else r


def _clamp(node, v, out):
    x, lo, hi = v["Value"], v["Min"], v["Max"]
    if node.clamp_type == 'RANGE' and lo > hi:
        lo, hi = hi, lo
    return min(max(x, lo), hi)


# --- colour -------------------------------------------------------------------------------------

def rgb_to_hsv(rgb):
    r, g, b = rgb
    cmax, cmin = max(r, g, b), min(r, g, b)
    cdelta = cmax - cmin
    v = cmax
    s = cdelta / cmax if cmax != 0.0 else 0.0
    h = 0.0
    if s != 0.0:
        cr, cg, cb = ((cmax - x) / cdelta for x in rgb)
        if r == cmax:
            h = cb - cg
        elif g == cmax:
            h = 2.0 + cr - cb
        else:
            h = 4.0 + cg - cr
        h /= 6.0
        if h < 0.0:
            h += 1.0
    return (h, s, v)


def hsv_to_rgb(hsv):
    h, s, v = hsv
    if s == 0.0:
        return (v, v, v)
    if h == 1.0:
        h = 0.0
    h *= 6.0
    i = math.floor(h)
    f = h - i
    p, q, t = v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f))
    return {0: (v, t, p), 1: (q, v, p), 2: (p, v, t), 3: (p, q, v), 4: (t, p, v)}.get(
        int(i), (v, p, q))


def rgb_to_hsl(rgb):
    r, g, b = rgb
    cmax, cmin = max(r, g, b), min(r, g, b)
    l = min(1.0, (cmax + cmin) / 2.0)
    if cmax == cmin:
        return (0.0, 0.0, l)
    d = cmax - cmin
    s = d / (2.0 - cmax - cmin) if l > 0.5 else d / (cmax + cmin)
    if cmax == r:
        h = (g - b) / d + (6.0 if g < b else 0.0)
    elif cmax == g:
        h = (b - r) / d + 2.0
    else:
        h = (r - g) / d + 4.0
    return (h / 6.0, s, l)


def hsl_to_rgb(hsl):
    h, s, l = hsl
    nr = _sat(abs(h * 6.0 - 3.0) - 1.0)
    ng = _sat(2.0 - abs(h * 6.0 - 2.0))
    nb = _sat(2.0 - abs(h * 6.0 - 4.0))
    chroma = (1.0 - abs(2.0 * l - 1.0)) * s
    return tuple((n - 0.5) * chroma + l for n in (nr, ng, nb))


def _each(f, *cols):
    return tuple(f(*xs) for xs in zip(*cols))


def _overlay(t, a, b):
    tm = 1.0 - t
    return a * (tm + 2.0 * t * b) if a < 0.5 else 1.0 - (tm + 2.0 * t * (1.0 - b)) * (1.0 - a)


def _dodge(t, a, b):
    if a == 0.0:
        return a
    tmp = 1.0 - t * b
    if tmp <= 0.0:
        return 1.0
    return min(a / tmp, 1.0)


def _burn(t, a, b):
    tmp = (1.0 - t) + t * b
    if tmp <= 0.0:
        return 0.0
    return _sat(1.0 - (1.0 - a) / tmp)


def _mix_hue(t, a, b, keep_s):
    hsv2 = rgb_to_hsv(b)
    if hsv2[1] == 0.0:
        return a
    hsv = rgb_to_hsv(a)
    tmp = hsv_to_rgb((hsv2[0], hsv2[1] if keep_s else hsv[1], hsv[2]))
    return _each(lambda x, y: _interp(x, y, t), a, tmp)


def _mix_sat(t, a, b):
    hsv = rgb_to_hsv(a)
    if hsv[1] == 0.0:
        return a
    return hsv_to_rgb((hsv[0], (1.0 - t) * hsv[1] + t * rgb_to_hsv(b)[1], hsv[2]))


def _mix_val(t, a, b):
    hsv = rgb_to_hsv(a)
    return hsv_to_rgb((hsv[0], hsv[1], (1.0 - t) * hsv[2] + t * rgb_to_hsv(b)[2]))


def _mix_soft(t, a, b):
    def f(x, y):
        scr = 1.0 - (1.0 - y) * (1.0 - x)
        return (1.0 - t) * x + t * ((1.0 - x) * y * x + x * scr)
    return _each(f, a, b)


MIX = {
    'MIX': lambda t, a, b: _each(lambda x, y: _interp(x, y, t), a, b),
    'ADD': lambda t, a, b: _each(lambda x, y: _interp(x, x + y, t), a, b),
    'MULTIPLY': lambda t, a, b: _each(lambda x, y: _interp(x, x * y, t), a, b),
    'SUBTRACT': lambda t, a, b: _each(lambda x, y: _interp(x, x - y, t), a, b),
    'SCREEN': lambda t, a, b: _each(lambda x, y: 1.0 - ((1.0 - t) + t * (1.0 - y)) * (1.0 - x),
                                    a, b),
    'DIVIDE': lambda t, a, b: _each(lambda x, y: (1.0 - t) * x + t * x / y if y != 0.0 else x,
                                    a, b),
    'DIFFERENCE': lambda t, a, b: _each(lambda x, y: _interp(x, abs(x - y), t), a, b),
    'DARKEN': lambda t, a, b: _each(lambda x, y: _interp(x, min(x, y), t), a, b),
    'LIGHTEN': lambda t, a, b: _each(lambda x, y: _interp(x, max(x, y), t), a, b),
    'OVERLAY': lambda t, a, b: _each(lambda x, y: _overlay(t, x, y), a, b),
    'DODGE': lambda t, a, b: _each(lambda x, y: _dodge(t, x, y), a, b),
    'BURN': lambda t, a, b: _each(lambda x, y: _burn(t, x, y), a, b),
    'HUE': lambda t, a, b: _mix_hue(t, a, b, False),
    'SATURATION': _mix_sat,
    'VALUE': _mix_val,
    'COLOR': lambda t, a, b: _mix_hue(t, a, b, True),
    'SOFT_LIGHT': _mix_soft,
    'LINEAR_LIGHT': lambda t, a, b: _each(lambda x, y: x + t * (2.0 * y - 1.0), a, b),
}


def _mix_rgb(node, v, out):
    r = MIX[node.blend_type](_sat(v["Fac"]), v["Color1"], v["Color2"])
    return tuple(_sat(c) for c in r) if node.use_clamp else r


def _mix(node, v, out):
    dt = node.data_type
    if dt == 'RGBA':
        t = v["Factor_Float"]
        t = _sat(t) if node.clamp_factor else t
        r = MIX[node.blend_type](t, v["A_Color"], v["B_Color"])
        return tuple(_sat(c) for c in r) if node.clamp_result else r
    if dt == 'FLOAT':
        t = v["Factor_Float"]
        t = _sat(t) if node.clamp_factor else t
        return v["A_Float"] * (1.0 - t) + v["B_Float"] * t
    if dt == 'VECTOR':
        if node.factor_mode == 'NON_UNIFORM':
            t = v["Factor_Vector"]
        else:
            t = (v["Factor_Float"],) * 3
        if node.clamp_factor:
            t = tuple(_sat(x) for x in t)
        return tuple(x * (1.0 - s) + y * s for x, y, s in zip(v["A_Vector"], v["B_Vector"], t))
    raise KeyError(dt)


def _invert(node, v, out):
    t = v["Fac"]
    return tuple(t * (1.0 - c) + (1.0 - t) * c for c in v["Color"])


def _gamma(node, v, out):
    g = v["Gamma"]
    if g == 0.0:
        return (1.0, 1.0, 1.0)
    return tuple(math.pow(c, g) if c > 0.0 else c for c in v["Color"])


def _hsv(node, v, out):
    t, c_in = v["Fac"], v["Color"]
    h, s, val = rgb_to_hsv(c_in)
    h = _fmod(h + v["Hue"] + 0.5, 1.0)
    s = _sat(s * v["Saturation"])
    val *= v["Value"]
    c = hsv_to_rgb((h, s, val))
    return tuple(max(t * x + (1.0 - t) * y, 0.0) for x, y in zip(c, c_in))


_COMBINE = {'RGB': lambda c: c, 'HSV': hsv_to_rgb, 'HSL': hsl_to_rgb}
_SEPARATE = {'RGB': lambda c: c, 'HSV': rgb_to_hsv, 'HSL': rgb_to_hsl}


def _combine(keys, mode=None):
    def f(node, v, out):
        return _COMBINE[mode or node.mode](tuple(v[k] for k in keys))
    return f


def _separate(key, outs, mode=None):
    def f(node, v, out):
        return _SEPARATE[mode or node.mode](v[key])[outs.index(out)]
    return f


def _own_output(node, v, out):
    c = node.outputs[out].default_value
    try:
        return tuple(float(x) for x in c)[:3]
    except TypeError:
        return float(c)


# --- Map Range, Bright/Contrast, Vector Math ----------------------------------------------------

def _smoothstep(e0, e1, x):
    if x < e0:
        return 0.0
    if x >= e1:
        return 1.0
    t = (x - e0) / (e1 - e0)
    return (3.0 - 2.0 * t) * (t * t)


def _smootherstep(e0, e1, x):
    x = _sat(_safe_div(x - e0, e1 - e0))
    return x * x * x * (x * (x * 6.0 - 15.0) + 10.0)


def _map_range_float(node, v):
    x, f0, f1, t0, t1 = (v[k] for k in ("Value", "From Min", "From Max", "To Min", "To Max"))
    if f1 == f0:
        return 0.0
    kind = node.interpolation_type
    if kind == 'STEPPED':
        steps = v.get("Steps", 4.0)
        f = (x - f0) / (f1 - f0)
        f = math.floor(f * (steps + 1.0)) / steps if steps > 0.0 else 0.0
    elif kind == 'SMOOTHSTEP':
        f = 1.0 - _smoothstep(f1, f0, x) if f0 > f1 else _smoothstep(f0, f1, x)
    elif kind == 'SMOOTHERSTEP':
        f = 1.0 - _smootherstep(f1, f0, x) if f0 > f1 else _smootherstep(f0, f1, x)
    else:
        f = (x - f0) / (f1 - f0)
    r = t0 + f * (t1 - t0)
    if node.clamp:  # Cycles adds a Clamp node of type Range (To Min, To Max)
        lo, hi = (t1, t0) if t0 > t1 else (t0, t1)
        r = min(max(r, lo), hi)
    return r


def _map_range_vector(node, v):
    x, f0, f1, t0, t1 = (v[k] for k in ("Vector", "From_Min_FLOAT3", "From_Max_FLOAT3",
                                        "To_Min_FLOAT3", "To_Max_FLOAT3"))
    steps = v.get("Steps_FLOAT3", (4.0, 4.0, 4.0))
    kind = node.interpolation_type
    out = []
    for i in range(3):
        f = _safe_div(x[i] - f0[i], f1[i] - f0[i])
        if kind == 'STEPPED':
            f = math.floor(f * (steps[i] + 1.0)) / steps[i] if steps[i] > 0.0 else 0.0
        elif kind == 'SMOOTHSTEP':
            f = _sat(f)
            f = (3.0 - 2.0 * f) * (f * f)
        elif kind == 'SMOOTHERSTEP':
            f = _sat(f)
            f = f * f * f * (f * (f * 6.0 - 15.0) + 10.0)
        r = t0[i] + f * (t1[i] - t0[i])
        if node.clamp and kind in ('LINEAR', 'STEPPED'):
            lo, hi = (t1[i], t0[i]) if t0[i] > t1[i] else (t0[i], t1[i])
            r = min(max(r, lo), hi)
        out.append(r)
    return tuple(out)


def _map_range(node, v, out):
    if node.data_type == 'FLOAT':
        return _map_range_float(node, v)
    return _map_range_vector(node, v)


def _bright_contrast(node, v, out):
    a = 1.0 + v["Contrast"]
    b = v["Bright"] - v["Contrast"] * 0.5
    return tuple(max(a * c + b, 0.0) for c in v["Color"])


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _scale(a, s):
    return tuple(x * s for x in a)


def _sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def _length(a):
    return math.sqrt(_dot(a, a))


def _normalize(a):
    n = _length(a)
    return _scale(a, 1.0 / n) if n != 0.0 else a


def _refract(i, n, eta):
    d = _dot(n, i)
    k = 1.0 - eta * eta * (1.0 - d * d)
    if k < 0.0:
        return (0.0, 0.0, 0.0)
    return _sub(_scale(i, eta), _scale(n, eta * d + math.sqrt(k)))


def _project(a, b):
    l2 = _dot(b, b)
    return _scale(b, _dot(a, b) / l2) if l2 != 0.0 else (0.0, 0.0, 0.0)


def _reflect(a, b):
    n = _scale(b, 1.0 / _length(b)) if _length(b) != 0.0 else b
    return _sub(a, _scale(n, 2.0 * _dot(a, n)))


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


_VEC = {  # (a, b, c, scale) -> vector; Cycles' svm_vector_math
    'ADD': lambda a, b, c, s: _each(lambda x, y: x + y, a, b),
    'SUBTRACT': lambda a, b, c, s: _sub(a, b),
    'MULTIPLY': lambda a, b, c, s: _each(lambda x, y: x * y, a, b),
    'DIVIDE': lambda a, b, c, s: _each(_safe_div, a, b),
    'CROSS_PRODUCT': lambda a, b, c, s: _cross(a, b),
    'PROJECT': lambda a, b, c, s: _project(a, b),
    'REFLECT': lambda a, b, c, s: _reflect(a, b),
    'REFRACT': lambda a, b, c, s: _refract(a, _normalize(b) if _length(b) != 0.0 else b, s),
    'FACEFORWARD': lambda a, b, c, s: a if _dot(c, b) < 0.0 else _scale(a, -1.0),
    'MULTIPLY_ADD': lambda a, b, c, s: _each(lambda x, y, z: x * y + z, a, b, c),
    'SCALE': lambda a, b, c, s: _scale(a, s),
    'NORMALIZE': lambda a, b, c, s: _normalize(a),
    'SNAP': lambda a, b, c, s: _each(lambda x, y: math.floor(_safe_div(x, y)) * y, a, b),
    'FLOOR': lambda a, b, c, s: tuple(float(math.floor(x)) for x in a),
    'CEIL': lambda a, b, c, s: tuple(float(math.ceil(x)) for x in a),
    'MODULO': lambda a, b, c, s: _each(lambda x, y: _fmod(x, y) if y != 0.0 else 0.0, a, b),
    'WRAP': lambda a, b, c, s: _each(_wrap, a, b, c),
    'FRACTION': lambda a, b, c, s: tuple(_fract(x) for x in a),
    'ABSOLUTE': lambda a, b, c, s: tuple(abs(x) for x in a),
    'MINIMUM': lambda a, b, c, s: _each(min, a, b),
    'MAXIMUM': lambda a, b, c, s: _each(max, a, b),
    'SINE': lambda a, b, c, s: tuple(math.sin(x) for x in a),
    'COSINE': lambda a, b, c, s: tuple(math.cos(x) for x in a),
    'TANGENT': lambda a, b, c, s: tuple(math.tan(x) for x in a),
}
_VEC_VALUE = {  # (a, b) -> value
    'DOT_PRODUCT': lambda a, b: _dot(a, b),
    'DISTANCE': lambda a, b: _length(_sub(a, b)),
    'LENGTH': lambda a, b: _length(a),
}


def _vector_math(node, v, out):
    zero = (0.0, 0.0, 0.0)
    a, b, c = v["Vector"], v.get("Vector_001", zero), v.get("Vector_002", zero)
    op = node.operation
    if op in _VEC_VALUE:
        return _VEC_VALUE[op](a, b) if out == "Value" else zero
    return _VEC[op](a, b, c, v.get("Scale", 1.0)) if out == "Vector" else 0.0


# --- ColorRamp ------------------------------------------------------------------------------

RAMP_TABLE_SIZE = 256  # Cycles' kernel/types.h


def _color_ramp(node, v, out):
    """Cycles samples the ramp into a 256-entry table (Blender's ColorRamp.evaluate at
    i / 255) and interpolates that table linearly (rgb_ramp_lookup; no interpolation when the
    ramp is Constant): the same two table entries, read through the same evaluate()."""
    ramp = node.color_ramp
    n = RAMP_TABLE_SIZE - 1
    f = min(max(v["Fac"], 0.0), 1.0) * n
    i = min(max(int(f), 0), n)
    t = f - i
    c = list(ramp.evaluate(i / n))
    if ramp.interpolation != 'CONSTANT' and t > 0.0:
        c1 = list(ramp.evaluate((i + 1) / n))
        c = [(1.0 - t) * a + t * b for a, b in zip(c, c1)]
    return c[3] if out == "Alpha" else tuple(c[:3])


# bl_idname -> f(node, {input identifier: value}, output identifier) -> value.
EVALUATORS = {
    'ShaderNodeMath': _math,
    'ShaderNodeClamp': _clamp,
    'ShaderNodeMixRGB': _mix_rgb,
    'ShaderNodeMix': _mix,
    'ShaderNodeInvert': _invert,
    'ShaderNodeGamma': _gamma,
    'ShaderNodeHueSaturation': _hsv,
    'ShaderNodeCombineRGB': _combine(("R", "G", "B"), 'RGB'),
    'ShaderNodeSeparateRGB': _separate("Image", ("R", "G", "B"), 'RGB'),
    'ShaderNodeCombineXYZ': _combine(("X", "Y", "Z"), 'RGB'),
    'ShaderNodeSeparateXYZ': _separate("Vector", ("X", "Y", "Z"), 'RGB'),
    'ShaderNodeCombineHSV': _combine(("H", "S", "V"), 'HSV'),
    'ShaderNodeSeparateHSV': _separate("Color", ("H", "S", "V"), 'HSV'),
    'ShaderNodeCombineColor': _combine(("Red", "Green", "Blue")),
    'ShaderNodeSeparateColor': _separate("Color", ("Red", "Green", "Blue")),
    'ShaderNodeMapRange': _map_range,
    'ShaderNodeBrightContrast': _bright_contrast,
    'ShaderNodeVectorMath': _vector_math,
    'ShaderNodeValToRGB': _color_ramp,
    'ShaderNodeRGB': _own_output,
    'ShaderNodeValue': _own_output,
}
