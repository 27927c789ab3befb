// What a light's sampling gives and takes (conventions in light.h), shared by the light types'
// headers (facet/render/lights/*.h) and light.h.
#pragma once

#include <cmath>
#include <optional>
#include <string_view>

#include "facet/render/precision.h"
#include "facet/types.h"

namespace facet::render {

struct SceneFeatures;

struct LightSampleContext {
    Vec3 p{0.f};  // the shaded point (world space)
    Vec3 n{0.f};  // unit shading normal on the lit side, or 0 (see conventions)
};

struct LightLiSample {
    Rgb li{0.f};        // see conventions: radiance, or the delta lights' equivalent
    Vec3 wi{0.f};       // unit, from p toward the light
    float pdf = 0.f;    // per unit solid angle; 1 for delta lights
    float dist = 0.f;   // distance from p to the sampled point; +inf for directional/environment
    Vec3 p_light{0.f};  // sampled point on the light (area lights; position for point/spot)
    Vec3 n_light{0.f};  // unit geometric normal there (area lights), else 0
    // Error box of p_light (precision.h): p_light +- p_light_err contains a point of the
    // light's surface as the scene traces it. 0 for point and spot lights (not on a surface).
    Vec3 p_light_err{0.f};
    bool delta = false;  // true for point, spot and directional lights without size
};

// Solid-angle pdf of a point sampled uniformly by area: r^2 / (A cos theta_l) (area-to-solid-
// angle Jacobian, Cohen & Wallace eq. 2.11). 0 on the back side of the one-sided emitter.
[[gnu::always_inline]] inline float area_to_solid_angle_pdf(const Vec3& p, const Vec3& wi,
                                                            const Vec3& p_light,
                                                            const Vec3& n_light, float inv_area) {
    float cos_l = -glm::dot(n_light, wi);
    if (!(cos_l > 0.f)) return 0.f;
    Vec3 v = p_light - p;
    float pdf = glm::dot(v, v) * inv_area / cos_l;
    return std::isfinite(pdf) ? pdf : 0.f;
}

// The end of sample_li for lights sampled uniformly by area (triangles, parallelograms, discs,
// far lamps): direction, distance and solid-angle pdf of s.p_light (normal s.n_light) from
// ctx.p, and the radiance L.
[[gnu::always_inline]] inline std::optional<LightLiSample> finish_area_sample(
    const LightSampleContext& ctx, LightLiSample& s, float inv_area, const Rgb& radiance) {
    Vec3 v = s.p_light - ctx.p;
    float d2 = glm::dot(v, v);
    if (!(d2 > 0.f)) return std::nullopt;
    s.dist = std::sqrt(d2);
    s.wi = v / s.dist;
    s.pdf = area_to_solid_angle_pdf(ctx.p, s.wi, s.p_light, s.n_light, inv_area);
    if (!(s.pdf > 0.f)) return std::nullopt;
    s.li = radiance;
    return s;
}

// What a light with a position emits where, for the light tree (light_tree.h; pbrt-v4's
// LightBounds, after Conty Estevez & Kulla 2018): a box containing the emitter, its power
// `phi` (the luminance of power(): the tree weighs lights by it), and a cone of directions: it
// emits only along directions within theta_o + theta_e of `w` (theta_o bounds the surface
// normals, or a spot's full-intensity cone; theta_e how far beyond that it still emits: pi/2
// for a Lambertian surface). `two_sided`: the cone about -w too. Bounds may be loose, never
// tight: a light must emit nothing where the tree's importance is 0.
struct LightBounds {
    Vec3 lo{0.f}, hi{0.f};
    float phi = 0.f;
    Vec3 w{0.f, 0.f, 1.f};  // unit
    float cos_theta_o = -1.f, cos_theta_e = 0.f;
    bool two_sided = false;
};

// The members every light type T (light.h "Structure") has, in its header
// facet/render/lights/<type>.h; the functions are defined in its unit unless small enough to be
// inline:
//   static constexpr std::string_view kName;    its name (Light::type_name)
//   static constexpr bool kHittable, kNee;      Light::hittable(), Light::nee_type()
//   static constexpr bool kInline;              Light::sample_li inlines its sample_li
//   std::optional<LightLiSample> sample_li(const LightSampleContext&, Vec2 u) const;
//   float pdf_li(const LightSampleContext&, const Vec3& wi, const Vec3& p_light,
//                const Vec3& n_light) const;
//     (a moving emitter has instead sample_li(ctx, u, time) and pdf_li(ctx, wi, p_light,
//     n_light, prim, time): Light::sample_li_at, pdf_li_at)
//   Rgb power(float scene_radius) const;        total emitted power (W per channel)
//   static void note(SceneFeatures&);           the flags a light of this type sets
// and, when it has them (otherwise 0, +inf or null):
//   Rgb le(const Vec3& n_light, const Vec3& w) const;  radiance leaving its surface toward w
//   Rgb le_escape(const Vec3& d) const;                radiance of an escaping ray
//   Rgb le_escape(const Vec3& d, float& pdf) const;    the same with pdf_li's density of d
//   float camera_hit(const Vec3& o, const Vec3& d) const;  a camera ray's hit, not traced
//   const EnvironmentMap* map() const;
//   std::optional<LightBounds> bounds() const;        where it emits (lights with a position;
//                                                     the others are "infinite" to the tree)

}  // namespace facet::render
