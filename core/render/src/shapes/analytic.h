// The geometry of the analytic shapes' primitives in their object space, solved in double: the
// unit sphere |p| = 1 and the unit disc (z = 0, x^2 + y^2 <= 1), which shapes/sphere.cpp and
// shapes/disc.cpp place with a transform (AnalyticPrim, scene_impl.h). embree_scene.cpp hands
// these to Embree as one user geometry; everything a ray needs of the surface itself is here.
//
// Conventions: o, d are the ray's origin and direction in object space (d need not be unit);
// roots are ray parameters t of o + t d; uv as scenes/FORMAT.md, "UV coordinates".
#pragma once

#include <algorithm>
#include <cmath>

#include "../scene_impl.h"

namespace facet::render::analytic {

using Kind = AnalyticPrim::Kind;

// Nearest root t of the unit sphere |o + t d| = 1 in (tnear, tfar), or -1. The discriminant is
// formed as a (1 - |f|^2), f = o - (b/a) d (Ray Tracing Gems ch. 7), which stays accurate for
// distant and tiny spheres; roots by the numerically stable quadratic formula.
inline double intersect_unit_sphere(const glm::dvec3& o, const glm::dvec3& d, double tnear,
                                    double tfar) {
    const double a = glm::dot(d, d);
    const double b = glm::dot(o, d);  // half the linear coefficient
    const glm::dvec3 f = o - (b / a) * d;
    const double disc = a * (1.0 - glm::dot(f, f));
    if (disc < 0.0) return -1.0;
    const double c = glm::dot(o, o) - 1.0;
    const double q = -(b + std::copysign(std::sqrt(disc), b));
    double t0 = q != 0.0 ? c / q : 0.0;
    double t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > tnear && t0 < tfar) return t0;
    if (t1 > tnear && t1 < tfar) return t1;
    return -1.0;
}

// Root t of the unit disc in (tnear, tfar), or -1.
inline double intersect_unit_disc(const glm::dvec3& o, const glm::dvec3& d, double tnear,
                                  double tfar) {
    if (d.z == 0.0) return -1.0;
    const double t = -o.z / d.z;
    if (!(t > tnear && t < tfar)) return -1.0;
    const double x = o.x + t * d.x, y = o.y + t * d.y;
    return x * x + y * y <= 1.0 ? t : -1.0;
}

// The nearest root of the primitive of `kind` in (tnear, tfar), or -1.
[[gnu::always_inline]] inline double intersect(Kind kind, const glm::dvec3& o, const glm::dvec3& d,
                                               double tnear, double tfar) {
    return kind == Kind::Sphere ? intersect_unit_sphere(o, d, tnear, tfar)
                                : intersect_unit_disc(o, d, tnear, tfar);
}

// Half the object-space extent along z: the primitive lies in [-1, 1]^2 x [-z, z].
inline double half_depth(Kind kind) {
    return kind == Kind::Sphere ? 1.0 : 0.0;
}

// Texture coordinates at object-space point po on the surface: the sphere's longitude and
// latitude (sphere_uv), the disc's bounding square [-1, 1]^2 onto [0, 1]^2.
inline Vec2 uv(Kind kind, const glm::dvec3& po) {
    return kind == Kind::Sphere ? sphere_uv(po)
                                : Vec2(float(0.5 * (po.x + 1.0)), float(0.5 * (po.y + 1.0)));
}

// A point near the surface projected onto it, with the outward normal and the tangent (the
// sphere's d p / d longitude about z, the disc's +x), all in object space.
struct SurfacePoint {
    glm::dvec3 p, n, tangent;
};
inline SurfacePoint project(Kind kind, glm::dvec3 po) {
    if (kind == Kind::Sphere) {
        const double len = glm::length(po);
        po = len > 0.0 ? po / len : glm::dvec3(0.0, 0.0, 1.0);
        return {po, po, glm::dvec3(-po.y, po.x, 0.0)};
    }
    po.z = 0.0;
    return {po, glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(1.0, 0.0, 0.0)};
}

// dp/du and dp/dv (object space) of the uv map at surface point po (ray differentials).
inline void uv_derivatives(Kind kind, const glm::dvec3& po, glm::dvec3& dpdu, glm::dvec3& dpdv) {
    if (kind == Kind::Sphere) {
        sphere_uv_derivatives(po, dpdu, dpdv);
    } else {
        dpdu = glm::dvec3(2.0, 0.0, 0.0);
        dpdv = glm::dvec3(0.0, 2.0, 0.0);
    }
}

}  // namespace facet::render::analytic
