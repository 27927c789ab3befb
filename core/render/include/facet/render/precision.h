// Floating-point error bounds of surface points and the ray origins spawned from them (the
// approach of Pharr, Jakob & Humphreys, "Physically Based Rendering", 4th ed., section 6.8).
//
// Every hit point and every sampled point on a light carries a conservative error box: per
// component a half-width e_i such that the box p +- e contains a point of the exact surface
// (the surface as the scene's float or double data define it). A ray leaving p is started at
// offset_ray_origin(p, e, n, w): p moved along the geometric normal n, to w's side, by
// dot(|n|, e) (the box's extent along n), enlarged to cover the rounding of the move itself and
// a few roundings of |p| more. That origin lies strictly on w's side of the surface's tangent plane
// through any point of the box, so the ray cannot re-hit the surface it leaves through rounding
// error, and the offset is as small as the error itself: a scene whose features the float spacing
// resolves renders the same at any distance from the origin.
//
// The bounds use the unit roundoff u = 2^-24 of float and gamma(n) = n u / (1 - n u), the bound
// of n successive roundings (Higham, "Accuracy and Stability of Numerical Algorithms", 3.1).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "facet/types.h"

namespace facet::render {

inline constexpr float kUnitRoundoff = 0x1p-24f;

// Bound of the relative error of n float roundings: gamma(n) = n u / (1 - n u).
constexpr float gamma_bound(int n) {
    return float(n) * kUnitRoundoff / (1.f - float(n) * kUnitRoundoff);
}

// Relative bound of double-precision arithmetic folded into float error boxes: a few dozen
// double roundings (2^-53 each) with a wide margin. Used for points computed in double
// (spheres, discs, planes, the triangle plane projection) before their rounding to float.
inline constexpr double kDoubleSlack = 0x1p-44;

// The next float above / below v (v finite; +-0 both step to the smallest subnormal).
[[gnu::always_inline]] inline float next_float_up(float v) {
    if (v == 0.f) v = 0.f;  // -0 -> +0
    std::uint32_t b = std::bit_cast<std::uint32_t>(v);
    b = v >= 0.f ? b + 1 : b - 1;
    return std::bit_cast<float>(b);
}
[[gnu::always_inline]] inline float next_float_down(float v) {
    if (v == 0.f) v = -0.f;
    std::uint32_t b = std::bit_cast<std::uint32_t>(v);
    b = v > 0.f ? b - 1 : b + 1;
    return std::bit_cast<float>(b);
}

// The float spacing (ulp) at magnitude m: the gap from float(|m|) to the next float up.
inline double float_spacing(double m) {
    const float f = float(std::fabs(m));
    return double(next_float_up(f)) - double(f);
}

// Largest |component| of a vector.
inline double largest_magnitude(const glm::dvec3& v) {
    return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
}

// |v| per component with std::fabs (one mask instruction each; glm::abs compiles to a compare
// and a conditional negation per component).
[[gnu::always_inline]] inline Vec3 abs_components(const Vec3& v) {
    return {std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)};
}

// Error box of a float p obtained by one rounding of an exact (or double) value: |p_i| gamma(1)
// per component (|fl(x) - x| <= u |x| <= gamma(1) |fl(x)|).
[[gnu::always_inline]] inline Vec3 rounding_error(const Vec3& p) {
    return gamma_bound(1) * abs_components(p);
}

// The origin of a ray leaving surface point p (error box p_err, geometric normal n of either
// orientation, unit within a few u) toward w: see the header comment. Instead of pbrt's step
// of one float per component after the rounding (a dozen instructions a component), the
// offset's length D is enlarged in advance to cover the rounding of D n and of p + D n: with
// offset_i = fl(D n_i) and origin_i = fl(p_i + offset_i), the origin's displacement along n is
// at least D |n|^2 (1 - gamma(2)) - u dot(|n|, |p|), which exceeds the box's extent
// dot(|n|, p_err) when D >= (dot(|n|, p_err) + u dot(|n|, |p|)) / ((1 - gamma(2)) (1 - gamma(4)))
// (|n|^2 >= 1 - gamma(4)). D below is computed with 5 roundings (relative gamma(5)), so factors
// 1 + gamma(12) on p_err and gamma(4) (four times u) on |p| meet that with margin; the |p| term
// makes the inequality strict for every p != 0. With p = 0 and p_err = 0 (an exact point at
// the origin) the origin is p itself.
[[gnu::always_inline]] inline Vec3 offset_ray_origin(const Vec3& p, const Vec3& p_err,
                                                     const Vec3& n, const Vec3& w) {
    constexpr float kErrScale = 1.f + gamma_bound(12);
    constexpr float kPointScale = gamma_bound(4);
    const Vec3 reach = kErrScale * p_err + kPointScale * abs_components(p);
    const float d = glm::dot(abs_components(n), reach);
    return p + (glm::dot(w, n) < 0.f ? -d : d) * n;
}

// Relative amount by which a shadow ray toward a point stops short of it (pbrt's
// ShadowEpsilon): covers the rounding of the segment's length and direction, so the ray ends
// before the offset end point for certain; the part of the segment it skips (1e-4 of it) lies
// within the offset end's neighbourhood on the light.
inline constexpr float kShadowEpsilon = 1e-4f;

}  // namespace facet::render
