// Warping functions from [0,1)^2 to directions (and to points of the disc and of regular
// polygons, for apertures), with their densities.
//
// Conventions: returned directions are unit vectors in the local frame (z up, facet/frame.h);
// every pdf is per unit solid angle unless its name says otherwise. Inputs u are in [0,1)^2.
#pragma once

#include "facet/types.h"

namespace facet {

// (cos t, sin t) for t in [-pi/4, pi/4] by polynomials in t^2: Chebyshev interpolation of
// cos(t) (degree 4 in t^2) and sin(t) / t (degree 3), truncation error < 2.5e-9, below float
// rounding. The concentric map needs no range reduction, and the libm sincosf call it replaces
// cost ~4% of a Cornell-box render.
inline Vec2 cos_sin_quarter(float t) {
    const float s = t * t;
    const float c =
        0.99999999995f +
        s * (-0.49999999615f + s * (0.041666616693f + s * (-0.0013886618f + s * 2.4379831e-5f)));
    const float n =
        t * (0.99999999692f + s * (-0.16666650674f + s * (0.0083320358f + s * -1.9503904e-4f)));
    return {c, n};
}

// Concentric (Shirley-Chiu) map of the unit square onto the unit disk: area preserving and
// continuous, so stratification survives the warp. theta = pi/4 (b/a) on the sectors around
// the x axis and pi/2 - pi/4 (a/b) around the y axis, whose (cos, sin) is the swapped pair.
inline Vec2 sample_uniform_disk_concentric(Vec2 u) {
    Vec2 o = 2.f * u - Vec2(1.f);
    if (o.x == 0.f && o.y == 0.f) return {0.f, 0.f};
    if (std::fabs(o.x) > std::fabs(o.y)) {
        const Vec2 cs = cos_sin_quarter((kPi / 4.f) * (o.y / o.x));
        return o.x * cs;
    }
    const Vec2 cs = cos_sin_quarter((kPi / 4.f) * (o.x / o.y));
    return o.y * Vec2(cs.y, cs.x);
}

// (cos, sin) of the angle 2 pi u, u in [0, 1): a quarter-turn reduction to [-pi/4, pi/4] and
// cos_sin_quarter, rotated back by the quarter turns (exact swaps and signs).
inline Vec2 cos_sin_turn(float u) {
    const float q = 4.f * u;
    const float k = std::nearbyint(q);
    const Vec2 cs = cos_sin_quarter((kPi / 2.f) * (q - k));
    switch (int(k) & 3) {
        case 0:
            return cs;
        case 1:
            return {-cs.y, cs.x};
        case 2:
            return -cs;
        default:
            return {cs.y, -cs.x};
    }
}

// Polar map of the unit square onto the unit disk: radius sqrt(u.x), angle 2 pi u.y; area
// preserving, smooth in u away from the centre and periodic in u.y (Cycles 3.4's to_unit_disk).
// The cosine lobe's sampler uses it: with Owen-scrambled Sobol points the concentric map's
// kinks along the square's diagonals cost variance where the integrand is peaked (a sun in an
// HDRI; docs/realscenes.md, "Time against error").
inline Vec2 sample_uniform_disk_polar(Vec2 u) {
    return std::sqrt(u.x) * cos_sin_turn(u.y);
}

// Uniform sample of the regular polygon with `corners` >= 3 corners on the unit circle, whose
// edge midpoints lie at angles rotation + 2 pi k / corners (radians, from +x toward +y) and
// corners half-way between (Cycles' polygonal aperture). u.x picks one of the `corners` equal
// triangles (centre, two adjacent corners) and is reused; in the triangle of half-angle
// a = pi / corners around the +x axis, the point s (cos a, sin a (1 - 2 v)) with s = sqrt(u')
// (density proportional to s: the triangle's width grows linearly) is uniform.
inline Vec2 sample_regular_polygon(Vec2 u, int corners, float rotation) {
    const float n = float(corners);
    const float k = std::fmin(std::floor(u.x * n), n - 1.f);
    const float s = std::sqrt(u.x * n - k);
    const float a = kPi / n;
    const Vec2 p(s * std::cos(a), s * std::sin(a) * (1.f - 2.f * u.y));
    const float t = rotation + 2.f * a * k;
    const float c = std::cos(t), sn = std::sin(t);
    return {c * p.x - sn * p.y, sn * p.x + c * p.y};
}

// Cosine-weighted hemisphere (Malley's method on the polar map): pdf = cos(theta) / pi.
inline Vec3 sample_cosine_hemisphere(Vec2 u) {
    Vec2 d = sample_uniform_disk_polar(u);
    float z = std::sqrt(positive_part(1.f - d.x * d.x - d.y * d.y));
    return {d.x, d.y, z};
}
inline float cosine_hemisphere_pdf(float cos_theta) {
    return positive_part(cos_theta) * kInvPi;
}

inline Vec3 sample_uniform_sphere(Vec2 u) {
    float z = 1.f - 2.f * u.x;
    float r = std::sqrt(std::fmax(0.f, 1.f - z * z));
    float phi = 2.f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline constexpr float uniform_sphere_pdf() {
    return kInv4Pi;
}

inline Vec3 sample_uniform_hemisphere(Vec2 u) {
    float z = u.x;
    float r = std::sqrt(std::fmax(0.f, 1.f - z * z));
    float phi = 2.f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline constexpr float uniform_hemisphere_pdf() {
    return kInv2Pi;
}

// Uniform direction inside a cone of half-angle with cosine cos_max around +z.
inline Vec3 sample_uniform_cone(Vec2 u, float cos_max) {
    float z = (1.f - u.x) + u.x * cos_max;
    float r = std::sqrt(std::fmax(0.f, 1.f - z * z));
    float phi = 2.f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniform_cone_pdf(float cos_max) {
    return 1.f / (2.f * kPi * (1.f - cos_max));
}

// Uniform point on a triangle, as barycentrics (b0, b1); b2 = 1 - b0 - b1 (Heitz 2019 warp,
// low distortion so stratification survives).
inline Vec2 sample_uniform_triangle(Vec2 u) {
    float b0, b1;
    if (u.x < u.y) {
        b0 = u.x / 2.f;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2.f;
        b0 = u.x - b1;
    }
    return {b0, b1};
}

// Power heuristic with beta = 2 (Veach 1997, eq. 9.13) for multiple importance sampling.
inline float power_heuristic(float pdf_a, float pdf_b) {
    float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
    if (std::isinf(a)) return 1.f;
    return a + b > 0.f ? a / (a + b) : 0.f;
}

}  // namespace facet
