"""The lobe and albedo plot of the material panel, from the core's own evaluation (the values
`facet brdf plot` draws): top, the lobe f(wo, wi) cos(theta_o) in the plane of incidence for
light from theta_i = 45 degrees (polar, scaled to its peak); bottom, the albedo
rho(wo -> 2pi)(theta_o) for theta_o in [0, 90) degrees on a 0..1 axis. Colour materials draw one
curve per channel, grey ones one black curve. Delta lobes (mirror) have f = 0 and show only in
the albedo."""
import math

import numpy as np

from . import native

SIZE = 256
THETA_I = 45.0
_BG, _GRID, _BLACK = (1.0, 1.0, 1.0), (0.72, 0.72, 0.72), (0.0, 0.0, 0.0)
_CHANNELS = ((0.82, 0.16, 0.16), (0.16, 0.63, 0.24), (0.16, 0.31, 0.86))


def _line(img, x0, y0, x1, y1, colour):
    n = int(max(abs(x1 - x0), abs(y1 - y0)) * 2) + 1
    xs = np.linspace(x0, x1, n)
    ys = np.linspace(y0, y1, n)
    for dx in (0, 1):
        for dy in (0, 1):
            xi = np.clip((xs + dx - 0.5).astype(int), 0, SIZE - 1)
            yi = np.clip((ys + dy - 0.5).astype(int), 0, SIZE - 1)
            img[yi, xi, :3] = colour


def _polyline(img, xs, ys, colour):
    for k in range(len(xs) - 1):
        _line(img, xs[k], ys[k], xs[k + 1], ys[k + 1], colour)


def lobe_image(material_data):
    """Material (FORMAT.md dict) -> RGBA float32 (SIZE, SIZE, 4), row 0 at the top."""
    mat = native.facet.make_material(material_data["model"],
                                     **{k: v for k, v in material_data.items() if k != "model"})
    img = np.ones((SIZE, SIZE, 4), np.float32)
    img[..., :3] = _BG
    cx, cy, r = SIZE / 2, 150.0, 115.0
    # Lobe: wo over the plane of incidence, light from +x at THETA_I.
    t = np.radians(np.linspace(-90.0, 90.0, 361))
    wo = np.stack([np.sin(t), np.zeros_like(t), np.cos(t)], axis=1).astype(np.float32)
    ti = math.radians(THETA_I)
    wi = np.array([math.sin(ti), 0.0, math.cos(ti)], np.float32)
    f = np.asarray(mat.eval(wo, np.tile(wi, (len(t), 1))), np.float64) * np.maximum(
        wo[:, 2:3], 0.0)
    for a in range(-90, 91, 30):  # angle grid
        ar = math.radians(a)
        _line(img, cx, cy, cx + r * math.sin(ar), cy - r * math.cos(ar), _GRID)
    _line(img, cx - r, cy, cx + r, cy, _BLACK)
    _line(img, cx, cy, cx + r * math.sin(ti), cy - r * math.cos(ti), (0.95, 0.6, 0.1))
    peak = f.max()
    grey = np.allclose(f[:, 0], f[:, 1]) and np.allclose(f[:, 1], f[:, 2])
    if peak > 0.0:
        for ch in ([0] if grey else [0, 1, 2]):
            rr = r * f[:, ch] / peak
            _polyline(img, cx + rr * np.sin(t), cy - rr * np.cos(t),
                      _BLACK if grey else _CHANNELS[ch])
    # Albedo strip.
    x0, x1, y0, y1 = 20.0, SIZE - 20.0, SIZE - 12.0, 172.0
    _line(img, x0, y0, x1, y0, _BLACK)
    _line(img, x0, y0, x0, y1, _BLACK)
    _line(img, x0, y1, x1, y1, _GRID)
    th = np.radians(np.linspace(0.0, 89.0, 46))
    wo = np.stack([np.sin(th), np.zeros_like(th), np.cos(th)], axis=1).astype(np.float32)
    rho = np.asarray(mat.reflectance(wo).value, np.float64)
    xs = x0 + (x1 - x0) * th / math.radians(90.0)
    grey = np.allclose(rho[:, 0], rho[:, 1]) and np.allclose(rho[:, 1], rho[:, 2])
    for ch in ([0] if grey else [0, 1, 2]):
        _polyline(img, xs, y0 - (y0 - y1) * np.clip(rho[:, ch], 0.0, 1.0),
                  _BLACK if grey else _CHANNELS[ch])
    return img


class PanelPlot:
    """The panel's preview icon, redrawn when the material's parameters change."""

    def __init__(self):
        import bpy.utils.previews
        self.previews = bpy.utils.previews.new()
        self.keys = {}
        self.errors = {}

    def icon(self, mat_name, data):
        key = repr(sorted(data.items()))
        p = self.previews.get(mat_name) or self.previews.new(mat_name)
        if self.keys.get(mat_name) != key:
            self.keys[mat_name] = key
            try:
                img = lobe_image(data)
                self.errors.pop(mat_name, None)
            except Exception as e:  # an invalid parameter: the panel shows the core's message
                self.errors[mat_name] = str(e)
                img = np.ones((SIZE, SIZE, 4), np.float32)
            p.image_size = (SIZE, SIZE)
            p.image_pixels_float = img[::-1].ravel()  # previews store rows bottom to top
        return p.icon_id, self.errors.get(mat_name)

    def close(self):
        import bpy.utils.previews
        bpy.utils.previews.remove(self.previews)
