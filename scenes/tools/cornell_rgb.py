#!/usr/bin/env python3
"""Converts the Cornell box's published spectra to the linear RGB values of cornell_box.json.

Data: Cornell University Program of Computer Graphics, "Cornell Box Data"
(https://www.graphics.cornell.edu/online/box/data.html): Lambertian reflectance of the white,
green and red surfaces at 400..700 nm in 4 nm steps, and the light's emission spectrum at
400, 500, 600, 700 nm (linearly interpolated in between).

Method (documented in scenes/FORMAT.md):
 1. XYZ = sum over 1 nm steps of value(lambda) * cmf(lambda), with the CIE 1931 2-degree colour
    matching functions in the multi-lobe Gaussian fit of Wyman, Sloan & Shirley 2013 (JCGT 2(2)),
    values linearly interpolated between the published samples.
 2. Linear sRGB (Rec. 709 primaries) = M_XYZ->sRGB * XYZ.
 3. White balance: divide each channel by the RGB of the equal-energy spectrum (value 1 at every
    wavelength), so that a perfect white reflector is RGB (1, 1, 1) and a flat spectrum of value
    v is (v, v, v). Reflectances and the light's radiance use the same map, so "RGB of the light
    times RGB of a wall" approximates the spectral product.
Run: python3 scenes/tools/cornell_rgb.py
"""
import math

LAMBDA = list(range(400, 701, 4))
WHITE = [0.343, 0.445, 0.551, 0.624, 0.665, 0.687, 0.708, 0.723, 0.715, 0.710, 0.745, 0.758,
         0.739, 0.767, 0.777, 0.765, 0.751, 0.745, 0.748, 0.729, 0.745, 0.757, 0.753, 0.750,
         0.746, 0.747, 0.735, 0.732, 0.739, 0.734, 0.725, 0.721, 0.733, 0.725, 0.732, 0.743,
         0.744, 0.748, 0.728, 0.716, 0.733, 0.726, 0.713, 0.740, 0.754, 0.764, 0.752, 0.736,
         0.734, 0.741, 0.740, 0.732, 0.745, 0.755, 0.751, 0.744, 0.731, 0.733, 0.744, 0.731,
         0.712, 0.708, 0.729, 0.730, 0.727, 0.707, 0.703, 0.729, 0.750, 0.760, 0.751, 0.739,
         0.724, 0.730, 0.740, 0.737]
GREEN = [0.092, 0.096, 0.098, 0.097, 0.098, 0.095, 0.095, 0.097, 0.095, 0.094, 0.097, 0.098,
         0.096, 0.101, 0.103, 0.104, 0.107, 0.109, 0.112, 0.115, 0.125, 0.140, 0.160, 0.187,
         0.229, 0.285, 0.343, 0.390, 0.435, 0.464, 0.472, 0.476, 0.481, 0.462, 0.447, 0.441,
         0.426, 0.406, 0.373, 0.347, 0.337, 0.314, 0.285, 0.277, 0.266, 0.250, 0.230, 0.207,
         0.186, 0.171, 0.160, 0.148, 0.141, 0.136, 0.130, 0.126, 0.123, 0.121, 0.122, 0.119,
         0.114, 0.115, 0.117, 0.117, 0.118, 0.120, 0.122, 0.128, 0.132, 0.139, 0.144, 0.146,
         0.150, 0.152, 0.157, 0.159]
RED = [0.040, 0.046, 0.048, 0.053, 0.049, 0.050, 0.053, 0.055, 0.057, 0.056, 0.059, 0.057,
       0.061, 0.061, 0.060, 0.062, 0.062, 0.062, 0.061, 0.062, 0.060, 0.059, 0.057, 0.058,
       0.058, 0.058, 0.056, 0.055, 0.056, 0.059, 0.057, 0.055, 0.059, 0.059, 0.058, 0.059,
       0.061, 0.061, 0.063, 0.063, 0.067, 0.068, 0.072, 0.080, 0.090, 0.099, 0.124, 0.154,
       0.192, 0.255, 0.287, 0.349, 0.402, 0.443, 0.487, 0.513, 0.558, 0.584, 0.620, 0.606,
       0.609, 0.651, 0.612, 0.610, 0.650, 0.638, 0.627, 0.620, 0.630, 0.628, 0.642, 0.639,
       0.657, 0.639, 0.635, 0.642]
LIGHT_L = [400, 500, 600, 700]
LIGHT = [0.0, 8.0, 15.6, 18.4]


def interp(xs, ys, x):
    for i in range(len(xs) - 1):
        if xs[i] <= x <= xs[i + 1]:
            t = (x - xs[i]) / (xs[i + 1] - xs[i])
            return ys[i] * (1 - t) + ys[i + 1] * t
    return 0.0


def g(x, mu, s1, s2):
    s = s1 if x < mu else s2
    return math.exp(-0.5 * ((x - mu) / s) ** 2)


def cmf(lam):  # Wyman, Sloan & Shirley 2013, multi-lobe fit of CIE 1931 2-degree
    x = 1.056 * g(lam, 599.8, 37.9, 31.0) + 0.362 * g(lam, 442.0, 16.0, 26.7) \
        - 0.065 * g(lam, 501.1, 20.4, 26.2)
    y = 0.821 * g(lam, 568.8, 46.9, 40.5) + 0.286 * g(lam, 530.9, 16.3, 31.1)
    z = 1.217 * g(lam, 437.0, 11.8, 36.0) + 0.681 * g(lam, 459.0, 26.0, 13.8)
    return x, y, z


M = [[3.2404542, -1.5371385, -0.4985314],
     [-0.9692660, 1.8760108, 0.0415560],
     [0.0556434, -0.2040259, 1.0572252]]


def rgb(f):
    xyz = [0.0, 0.0, 0.0]
    for lam in range(400, 701):
        v = f(lam)
        c = cmf(lam)
        for i in range(3):
            xyz[i] += v * c[i]
    return [sum(M[r][k] * xyz[k] for k in range(3)) for r in range(3)]


WB = rgb(lambda lam: 1.0)


def balanced(f):
    return [round(c / w, 4) for c, w in zip(rgb(f), WB)]


if __name__ == "__main__":
    print("white", balanced(lambda l: interp(LAMBDA, WHITE, l)))
    print("green", balanced(lambda l: interp(LAMBDA, GREEN, l)))
    print("red  ", balanced(lambda l: interp(LAMBDA, RED, l)))
    print("light", balanced(lambda l: interp(LIGHT_L, LIGHT, l)))
