// Private to facet_render: sampling pieces several light type units (lights/*.cpp, light.h
// "Structure") share.
#pragma once

#include <cmath>
#include <optional>
#include <type_traits>

#include "facet/frame.h"
#include "facet/render/light.h"
#include "facet/render/scene.h"
#include "facet/sampling.h"

namespace facet::render {

// A point closer than 1e-4 r to an emitting sphere counts as on it. A convex emitter cannot
// light its own surface, but a hit point rounded to just outside the sphere would otherwise see
// a near-hemispherical cone whose samples land at distance ~0 (no shadow ray can block them).
// The excluded shell is 1e-4 r thick: far above float round-off (~1e-7 r), and the light it
// would receive is at grazing angles over a cap of that size.
// Light tree bounds (LightBounds, light_sample.h): the box lo..hi, phi = the mean of the
// power's channels (as the power light selection weighs lights), and the emission cone.
inline LightBounds light_bounds(const Vec3& lo, const Vec3& hi, const Rgb& power, const Vec3& w,
                                float cos_theta_o, float cos_theta_e, bool two_sided = false) {
    LightBounds b;
    b.lo = lo;
    b.hi = hi;
    b.phi = (power.r + power.g + power.b) / 3.f;
    b.w = w;
    b.cos_theta_o = cos_theta_o;
    b.cos_theta_e = cos_theta_e;
    b.two_sided = two_sided;
    return b;
}

// A point's, sphere's or facing disc's box: p +- r in every axis.
inline LightBounds point_bounds(const PointEmitter& e) {
    const Vec3 r(e.radius);
    return light_bounds(e.position - r, e.position + r, e.power, Vec3(0.f, 0.f, 1.f), -1.f, 0.f);
}

// A flat emitter c +- e1 +- e2 (half-axes) facing n: one-sided, Lambertian (theta_o = 0,
// theta_e = pi/2).
inline LightBounds flat_bounds(const Vec3& c, const Vec3& e1, const Vec3& e2, const Vec3& n,
                               const Rgb& power) {
    const Vec3 ext = glm::abs(e1) + glm::abs(e2);
    return light_bounds(c - ext, c + ext, power, n, 1.f, 0.f);
}

inline constexpr double kSphereOutside2 = (1.0 + 1e-4) * (1.0 + 1e-4);

// 1 - cos(theta_max) of the cone subtended by a sphere seen at distance^2 dc2 > r^2, written
// as sin^2 / (1 + cos) so that tiny (distant) spheres lose no precision to cancellation.
inline double sphere_cone_one_minus_cos(double dc2, double r2) {
    double sin2 = r2 / dc2;
    double cos_max = safe_sqrt(1.0 - sin2);
    return sin2 / (1.0 + cos_max);
}

// A direction uniform in solid angle in the cone about the unit `axis` with 1 - cos theta_max =
// omc (pbrt-v4's SampleUniformCone, in double and in the 1 - cos form so that narrow cones keep
// their precision): 1 - cos theta = u.x omc, phi = 2 pi u.y. Density 1 / (2 pi omc).
inline glm::dvec3 sample_cone(const Vec3& axis, double omc, Vec2 u) {
    double one_minus_cos = double(u.x) * omc;
    double cos_t = 1.0 - one_minus_cos;
    double sin_t = safe_sqrt(one_minus_cos * (2.0 - one_minus_cos));
    double phi = 2.0 * kPiD * double(u.y);
    Frame f = Frame::from_z(axis);
    return glm::normalize(glm::dvec3(f.x) * (sin_t * std::cos(phi)) +
                          glm::dvec3(f.y) * (sin_t * std::sin(phi)) + glm::dvec3(f.z) * cos_t);
}

// Distance t along the unit wi from p to the sphere of squared radius r2 whose centre is p +
// to_c: the nearer intersection, or with `far` the farther one (from inside) (Ray Tracing Gems
// ch. 7 form, q = the closest approach). At grazing angles round-off may miss: the distance of
// the closest approach then.
inline double sphere_hit_distance(const glm::dvec3& to_c, const glm::dvec3& wi, double r2,
                                  bool far) {
    double b = glm::dot(to_c, wi);
    glm::dvec3 q = to_c - b * wi;
    double disc = r2 - glm::dot(q, q);
    if (!(disc > 0.0)) return b;
    return far ? b + std::sqrt(disc) : b - std::sqrt(disc);
}

// Error box of a point sampled on a sphere of centre c and radius r: centre and radius are float
// roundings of the traced (double) sphere's, each off by u of its magnitude; the point itself is
// one rounding of a double value (outward samples) or two products and two sums of floats
// (inward samples).
inline Vec3 sphere_sample_error(const Vec3& p, const Vec3& c, float r) {
    return gamma_bound(4) * (glm::abs(p) + glm::abs(c) + Vec3(r));
}

// The point light and the spot (lights/point.cpp, spot.cpp) share PointEmitter (lights/point.h):
// a point of on-axis intensity I0, or with a radius the sphere of radiance L = I0 / (pi r^2)
// that has its intensity and power. The sample functions take `falloff(wi)`, the intensity
// relative to I0 toward the receiver (wi from the receiver to the light), or nullptr for the
// isotropic point light.

// Sets the sphere's (or disc's) radiance for radius r: L = I0 / (pi r^2). Zero when r is so small
// that L overflows a float: the light stays a point. Returns whether the light is a sphere (not
// delta).
inline bool set_emitter_radius(PointEmitter& e, float r, RadiusModel model) {
    e.disc = model == RadiusModel::Cycles34Disc;
    const glm::dvec3 l = glm::dvec3(e.intensity) / (kPiD * double(r) * double(r));
    const Rgb lf(l);
    e.size_radiance = r > 0.f && is_finite(lf) ? lf : Rgb(0.f);
    if (e.size_radiance == Rgb(0.f) && e.intensity != Rgb(0.f)) return false;  // a point to float
    if (!(r > 0.f)) return false;
    e.radius = r;
    return true;
}

// The delta light: li = I(theta) / r^2 (Cohen & Wallace eq. 2.40 once the receiver multiplies
// by cos).
template <class Falloff>
[[gnu::always_inline]] inline std::optional<LightLiSample> sample_emitter_point(
    const PointEmitter& e, const LightSampleContext& ctx, Falloff falloff) {
    LightLiSample s;
    Vec3 v = e.position - ctx.p;
    float r2 = glm::dot(v, v);
    if (!(r2 > 0.f)) return std::nullopt;
    float r = std::sqrt(r2);
    s.wi = v / r;
    Rgb i = e.intensity;
    if constexpr (!std::is_same_v<Falloff, std::nullptr_t>) {
        float f = falloff(s.wi);
        if (f == 0.f) return std::nullopt;
        i *= f;
    }
    s.li = i / r2;
    s.pdf = 1.f;
    s.dist = r;
    s.p_light = e.position;
    s.delta = true;
    return s;
}

// The sphere (lights/point.cpp): from outside uniform in the subtended cone, from inside
// cosine-weighted about ctx.n (uniform over the sphere when n = 0).
template <class Falloff>
std::optional<LightLiSample> sample_emitter_sphere(const PointEmitter& e,
                                                   const LightSampleContext& ctx, Vec2 u,
                                                   Falloff falloff) {
    LightLiSample s;
    const glm::dvec3 p(ctx.p);
    const glm::dvec3 to_c = glm::dvec3(e.position) - p;
    const double dc2 = glm::dot(to_c, to_c);
    const double r2 = double(e.radius) * double(e.radius);
    glm::dvec3 wi;
    double t;
    if (dc2 > r2) {
        // Outside: uniform in the subtended cone, sin theta_max = r / d.
        const double omc = sphere_cone_one_minus_cos(dc2, r2);
        wi = sample_cone(Vec3(to_c / std::sqrt(dc2)), omc, u);
        t = sphere_hit_distance(to_c, wi, r2, false);
        s.pdf = float(1.0 / (2.0 * kPiD * omc));
    } else {
        // Inside (or on) the sphere: radiance L from every direction (Cycles does the same), so
        // the best density is the cosine's; the light point is the far intersection.
        if (ctx.n != Vec3(0.f)) {
            const Vec3 local = sample_cosine_hemisphere(u);
            s.pdf = cosine_hemisphere_pdf(local.z);
            wi = glm::dvec3(Frame::from_z(ctx.n).from_local(local));
        } else {
            wi = glm::dvec3(sample_uniform_sphere(u));
            s.pdf = uniform_sphere_pdf();
        }
        t = sphere_hit_distance(to_c, wi, r2, true);
    }
    s.wi = Vec3(wi);
    s.dist = float(t);
    s.p_light = Vec3(p + t * wi);  // not on traced geometry: no error box, no normal
    s.li = e.size_radiance;
    if constexpr (!std::is_same_v<Falloff, std::nullptr_t>) {
        // The radiance leaving the sphere toward p, along -wi: L falloff(-wi . axis).
        const float f = falloff(s.wi);
        if (f == 0.f) return std::nullopt;
        s.li *= f;
    }
    if (!(s.pdf > 0.f) || !std::isfinite(s.pdf) || !(s.dist > 0.f)) return std::nullopt;
    return s;
}

// Cycles 3.4's point lamp with a radius (RadiusModel::Cycles34Disc, lights/point.cpp): the disc
// of radius r centred on the light whose normal n points to ctx.p, at distance d, sampled
// uniformly over its area (concentric map, density 1 / (pi r^2)). In solid angle about ctx.p
// the density is t^2 / (cos_l pi r^2) with t the distance to the sampled point and cos_l =
// n . (-wi) = d / t (ctx.p lies on n at distance d from the disc's plane): t^3 / (d pi r^2),
// finite and > 0 for every d > 0. li = L (falloff along -wi for the spot).
template <class Falloff>
std::optional<LightLiSample> sample_emitter_disc(const PointEmitter& e,
                                                 const LightSampleContext& ctx, Vec2 u,
                                                 Falloff falloff) {
    const glm::dvec3 p(ctx.p);
    const glm::dvec3 c(e.position);
    const glm::dvec3 from_c = p - c;
    const double d = glm::length(from_c);
    if (!(d > 0.0)) return std::nullopt;
    const Vec2 q = sample_uniform_disk_concentric(u);
    const Frame f = Frame::from_z(Vec3(from_c / d));
    const double r = double(e.radius);
    const glm::dvec3 x = c + r * (glm::dvec3(f.x) * double(q.x) + glm::dvec3(f.y) * double(q.y));
    const glm::dvec3 v = x - p;
    const double t = glm::length(v);
    LightLiSample s;
    s.wi = Vec3(v / t);
    s.dist = float(t);
    s.p_light = Vec3(x);  // not on traced geometry: no error box, no normal
    s.pdf = float(t * t * t / (d * kPiD * r * r));
    s.li = e.size_radiance;
    if constexpr (!std::is_same_v<Falloff, std::nullptr_t>) {
        const float fo = falloff(s.wi);
        if (fo == 0.f) return std::nullopt;
        s.li *= fo;
    }
    if (!(s.pdf > 0.f) || !std::isfinite(s.pdf) || !(s.dist > 0.f)) return std::nullopt;
    return s;
}

}  // namespace facet::render
