// Light sources of the renderer, in physical units, and their sampling as seen from a point.
//
// Conventions:
//  - Units: point and spot lights are given by their radiant power Phi (W, per RGB channel),
//    directional lights by the irradiance E (W/m^2) on a surface facing them, area lights
//    (emissive shapes) and the environment by their radiance L (W sr^-1 m^-2).
//  - `sample_li(ctx, u)` picks a direction wi (unit, world space, from ctx.p TOWARD the light)
//    and returns `li` such that the direct-lighting estimate at ctx.p is
//        f(wo, wi) * li * |cos theta_i| / pdf.
//    For area lights and the environment `li` is the incident radiance and `pdf` is per unit
//    solid angle of wi. For the delta lights `pdf` = 1 and `delta` is true, and li is
//      point:       Phi / (4 pi r^2)                 so li |cos| = Phi cos / (4 pi r^2),
//                                                    Cohen & Wallace eq. 2.40;
//      spot:        I(theta) / r^2, I(theta) = I0 * falloff(cos theta), where falloff is 1
//                   inside the inner cone, 0 outside the outer cone and LINEAR IN cos theta
//                   between them, so Phi = 2 pi I0 [(1 - cos_in) + (cos_in - cos_out) / 2]
//                   holds exactly;
//      directional: E (the irradiance on a surface facing the light), dist = +inf.
//  - Lights with size (Blender's lamp radius and sun angle). A point or spot light of radius
//    r > 0 is a SPHERE of uniform radiance L = I0 / (pi r^2) (I0 its on-axis intensity as
//    above: Phi / (4 pi) for a point), so its intensity pi r^2 L = I0 and its power Phi are
//    those of the point light (Cycles 3.4's point lamp: radiance Phi / (4 pi^2 r^2)); a spot
//    sphere's radiance along w (from the sphere toward the receiver) is L falloff(w . axis).
//    From outside, sample_li draws wi uniformly in the cone the sphere subtends (pdf per solid
//    angle 1 / (2 pi (1 - cos theta_max)), sin theta_max = r / d; pbrt-v4's SampleSphere, Cycles'
//    sphere light) and li = L; from inside (d <= r) the point sees L from every direction and
//    wi is cosine-weighted about ctx.n (uniform over the sphere when n = 0). A directional
//    light of angular diameter 2 delta > 0 (the sun) is a cone of directions of uniform
//    radiance L = E / (pi sin^2 delta) about -direction, so that a surface facing it receives
//    E = int_cone L cos = pi L sin^2 delta exactly; wi is uniform in the cone, li = L. These
//    lights are NOT in the ray-traced geometry: no camera or BSDF ray finds them (Blender 3.4
//    shows no lamp to camera rays), so their samples are not delta (a random u is drawn) but
//    take no MIS weight (Light::hittable() is false); pdf_li is 0 for them.
//    It returns nullopt when the light cannot contribute (ctx.p behind a spot cone, on the back
//    of a one-sided emitter, zero pdf). `dist` is the distance to the sampled point; shadow rays
//    use Scene::shadow_ray(hit, sample), which ends off the emitter by the sample's error box.
//  - `pdf_li(ctx, wi, p_light, n_light)` is the solid-angle density with which sample_li would
//    have produced wi when the ray p + t wi hits the light at p_light (normal n_light); used for
//    multiple importance sampling of BSDF-sampled rays. 0 for delta lights.
//  - Area lights emit only from the FRONT side of their shape (the side the geometric normal of
//    the shape points to, see scene.h); `le(n_light, w)` is the radiance leaving toward w.
//  - `ctx.n` is the (unit) shading normal on the side being lit, used by the constant
//    environment to sample the cosine-weighted hemisphere; pass n = 0 for a point not on a
//    surface (then the constant environment is sampled uniformly over the sphere). An
//    environment map ignores ctx and samples its own importance density over the whole sphere
//    (environment_map.h). Spheres are sampled in the cone they
//    subtend (pdf per solid angle), triangles, quads, boxes, meshes and discs uniformly by area
//    (converted to solid angle: pdf = r^2 / (A |cos theta_l|)). A light of exactly two triangles
//    that form a parallelogram (a quad light) maps u straight onto the parallelogram,
//    p = o + u.x e1 + u.y e2: the same density, no triangle search, and u's 2D stratification
//    carries over to the whole light.
//  - Area lamps (Blender's, the "area" kind: Light::area_lamp). A rectangle lamp is sampled
//    uniformly in the solid angle it subtends (Urena, Fajardo & King 2013, "An Area-Preserving
//    Parametrization for Spherical Rectangles"; pdf = 1 / Omega), in double precision. A disc or
//    ellipse lamp is sampled the same way over its bounding rectangle when the point is near
//    (height h above its plane below kLampEllipseNear = 1 times its larger half-axis); a sample
//    that falls outside the ellipse is lost (nullopt), so the density over the ellipse is
//    exactly 1 / Omega_rect, unbiased, with pi/4 of the samples kept far off (more near);
//    farther away the ellipse is sampled uniformly by area, whose solid-angle density is then
//    nearly uniform (see light.cpp for the measured crossover). Either shape falls back to
//    area sampling when Omega < kLampMinSolidAngle (precision: Omega is a sum of four angles
//    minus 2 pi). Lamps emit from the front only: from behind or in the plane, nullopt.
//  - Choosing a light for next-event estimation: LightDistribution, in proportion to power(),
//    or (LightDistribution::view) to each light's contribution measured at the points the
//    camera sees.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "facet/render/environment_map.h"
#include "facet/render/precision.h"
#include "facet/types.h"

namespace facet::render {

class Scene;

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

class Light {
  public:
    enum class Kind : std::uint8_t { Point, Spot, Directional, Area, Environment };

    // Factories. Arguments are validated by the scene loader (finite, non-negative power,
    // unit directions, 0 <= inner <= outer < 180 degrees...), not here.
    // `radius` > 0 makes a sphere light of the same power (see conventions); 0 = a point.
    static Light point(const Vec3& position, const Rgb& power, float radius = 0.f);
    // `direction` is the cone axis (unit, the way the light shines); angles are half-angles.
    static Light spot(const Vec3& position, const Vec3& direction, const Rgb& power,
                      float inner_half_angle_deg, float outer_half_angle_deg, float radius = 0.f);
    // A spot with Blender's (Cycles 3.4) fall-off: I(theta) = K g(cos theta) with
    // g = cycles_spot_attenuation (light_units.h) for the cone of half-angle outer (<= 90
    // degrees) and blend in [0, 1]; K set so that the total power is Phi (cycles_spot_intensity).
    static Light spot_blend(const Vec3& position, const Vec3& direction, const Rgb& power,
                            float outer_half_angle_deg, float blend, float radius = 0.f);
    // `direction` is the way the light TRAVELS (unit); wi = -direction. `angle_deg` in [0, 180)
    // is the full angular diameter of the light's disc of directions (Blender's sun angle).
    static Light directional(const Vec3& direction, const Rgb& irradiance, float angle_deg = 0.f);
    static Light environment(const Rgb& radiance);
    // Environment map (environment_map.h): le_escape looks the map up, sample_li and pdf_li use
    // its importance density; emission() is its mean radiance.
    static Light environment_map(std::shared_ptr<const EnvironmentMap> map);
    // Area light over world-space triangles (p0, p1, p2 per triangle, front side by the
    // counter-clockwise winding: n = normalize(cross(p1 - p0, p2 - p0))). Degenerate triangles
    // are dropped; at least one must remain.
    static Light area_triangles(std::vector<Vec3> triangle_vertices, const Rgb& radiance,
                                std::uint32_t shape);
    // Area light on an exact sphere. Outward normals emit (sampled by the subtended cone from
    // outside); with `inward` the sphere is turned inside out ("flip_normals"): it lights its
    // interior and is sampled uniformly by area from inside.
    static Light area_sphere(const Vec3& center, float radius, const Rgb& radiance,
                             std::uint32_t shape, bool inward = false);
    // Area light on a flat ellipse: points c + cos(a) e1 + sin(a) e2 scaled by r in [0,1],
    // front normal normalize(cross(e1, e2)). A transformed disc is such an ellipse.
    static Light area_disc(const Vec3& center, const Vec3& e1, const Vec3& e2, const Rgb& radiance,
                           std::uint32_t shape);
    // Blender's area lamp (the "area" kind, no shape): a rectangle c + a e1 + b e2 (|a|, |b| <=
    // 1) or, with `ellipse`, the ellipse a^2 + b^2 <= 1, where e1 and e2 are PERPENDICULAR
    // half-axes; front normal normalize(cross(e1, e2)). Sampled by solid angle (see
    // conventions, "Area lamps"). With `camera_visible`, camera rays see it (lamp_hit).
    static Light area_lamp(const Vec3& center, const Vec3& e1, const Vec3& e2, const Rgb& radiance,
                           bool ellipse, bool camera_visible = false);

    Kind kind() const { return m_kind; }
    // A delta light: sample_li ignores u (point, spot and directional lights without size).
    bool is_delta() const { return m_delta; }
    // Whether rays can hit the light (emissive shapes, the environment): only then does MIS
    // weigh its samples against BSDF samples; a sample of any other light (including an
    // "area" lamp, which is no shape) is the only estimate of its light and takes weight 1.
    bool hittable() const {
        return (m_kind == Kind::Area && m_shape != UINT32_MAX) || m_kind == Kind::Environment;
    }
    // An area light whose radiance is a texture (a shape's textured "emission"): next-event
    // estimation does not sample it (nee_samples), BSDF rays find it with MIS weight 1, and
    // the radiance at a hit comes from the texture (SurfaceHit::emitted_radiance); emission()
    // is the texture's largest value, which only sets power() for --explain.
    void set_textured_emission() { m_textured = true; }
    bool textured_emission() const { return m_textured; }
    // The shape index (scene.h, SurfaceHit::shape) of an area light; UINT32_MAX otherwise
    // (also for the "area" light kind, a lamp that is no shape).
    std::uint32_t shape() const { return m_shape; }

    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                 const Vec3& n_light) const;

    // Area light: radiance leaving the light at a point with geometric normal n_light toward
    // direction w (unit, pointing away from the light); 0 on the back side. Other kinds: 0.
    Rgb le(const Vec3& n_light, const Vec3& w) const;
    // Environment: radiance arriving along a ray that escapes the scene in direction d. Others: 0.
    Rgb le_escape(const Vec3& d) const;

    // Total emitted power (W per channel) for choosing lights in proportion to power.
    // Directional and environment lights need the radius of the scene's bounding sphere.
    Rgb power(float scene_radius) const;

    // The environment's map, or null (a constant environment or another kind).
    const EnvironmentMap* map() const { return m_map.get(); }

    // An area lamp that camera rays see ("camera_visible"): the distance t > 0 along the unit
    // d at which the ray o + t d meets the lamp's front side, or +inf (a miss, its back side, or
    // any other light). The radiance seen there is emission().
    bool camera_visible() const { return m_camera_visible; }
    float lamp_hit(const Vec3& o, const Vec3& d) const;

    // Parameters, for exporters, tests and --explain.
    const Vec3& position() const { return m_position; }    // point, spot; sphere/disc centre
    const Vec3& direction() const { return m_direction; }  // spot axis, directional travel dir
    const Rgb& emission() const { return m_emission; }     // Phi, E or L depending on kind
    float cos_inner() const { return m_cos_inner; }
    float cos_outer() const { return m_cos_outer; }
    float area() const { return m_area; }      // area lights: total area
    float radius() const { return m_radius; }  // sphere area lights, point and spot spheres

  private:
    // area_triangles: switch to AreaShape::Parallelogram when the two triangles form one.
    void detect_parallelogram();
    Vec3 sphere_sample_error(const Vec3& p) const;
    // sample_li for every light but the parallelogram (quad) light, which is inline below.
    std::optional<LightLiSample> sample_li_other(const LightSampleContext& ctx, Vec2 u) const;
    // The end of sample_li for lights sampled uniformly by area (triangles, parallelograms,
    // discs): direction, distance and solid-angle pdf of s.p_light (normal s.n_light) from ctx.p.
    std::optional<LightLiSample> finish_area_sample(const LightSampleContext& ctx,
                                                    LightLiSample& s) const;

    // Area lamps (LampRect, LampEllipse): sample_li (see conventions, "Area lamps"), and the
    // solid-angle pdf 1 / Omega of its spherical-rectangle branch from p: 0 from behind, -1
    // when p is sampled by area instead (pdf_li then takes area_to_solid_angle_pdf).
    std::optional<LightLiSample> sample_lamp(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_lamp(const Vec3& p) const;

    // The spot's intensity relative to K (linear or Cycles' form) at cos theta from the axis.
    float spot_falloff(float cos_theta) const;
    // Point and spot factories: radius > 0 (and L = I0 / (pi r^2) finite) makes the sphere.
    void set_sphere(float radius);
    // The sphere of a point or spot light with a radius (conventions): sample_li from p.
    std::optional<LightLiSample> sample_sphere_light(const LightSampleContext& ctx, Vec2 u) const;

    Kind m_kind = Kind::Point;
    bool m_delta = true;
    bool m_textured = false;
    bool m_camera_visible = false;  // area lamps: seen by camera rays (lamp_hit)
    std::uint32_t m_shape = UINT32_MAX;
    Vec3 m_position{0.f};
    Vec3 m_direction{0.f, 0.f, -1.f};
    Rgb m_emission{0.f};   // Phi (point/spot), E (directional), L (area/environment)
    Rgb m_intensity{0.f};  // I0 = radiant intensity on the axis (point, spot)
    float m_cos_inner = 1.f, m_cos_outer = 1.f;
    // Spot with Blender's fall-off (spot_blend): (1 - cos outer) blend; < 0: the linear form.
    float m_spot_smooth = -1.f;
    // Sized point/spot (sphere, radius m_radius) and directional lights: their radiance L, and
    // the sun's 1 - cos delta (delta its half-angle), in double for narrow cones.
    Rgb m_size_radiance{0.f};
    double m_sun_one_minus_cos = 0.0;
    // Area lights.
    enum class AreaShape : std::uint8_t {
        Triangles,
        Parallelogram,  // two triangles forming a parallelogram (a quad)
        Sphere,
        Disc,
        LampRect,    // area lamp rectangle: centre m_position, half-axes m_e1, m_e2
        LampEllipse  // area lamp ellipse: the same frame
    } m_area_shape = AreaShape::Triangles;
    float m_radius = 0.f;   // sphere (area light, or a point/spot light with a radius)
    bool m_inward = false;  // sphere turned inside out
    // Disc: the ellipse's axes; parallelogram: its edges from the corner m_corner.
    Vec3 m_e1{0.f}, m_e2{0.f};
    Vec3 m_normal{0.f};  // disc and parallelogram: unit front normal
    Vec3 m_corner{0.f};  // parallelogram
    // Parallelogram and disc: the error box of every sample (a constant, set by
    // detect_parallelogram and area_disc; light.cpp).
    Vec3 m_sample_err{0.f};
    float m_area = 0.f;
    float m_inv_area = 0.f;
    std::vector<Vec3> m_tri;                      // 3 vertices per triangle
    std::vector<Vec3> m_tri_n;                    // unit front normal per triangle
    std::vector<float> m_tri_cdf;                 // running area fraction, last = 1
    std::shared_ptr<const EnvironmentMap> m_map;  // environment map (shared by copies)
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

[[gnu::always_inline]] inline std::optional<LightLiSample> Light::finish_area_sample(
    const LightSampleContext& ctx, LightLiSample& s) const {
    Vec3 v = s.p_light - ctx.p;
    float d2 = glm::dot(v, v);
    if (!(d2 > 0.f)) return std::nullopt;
    s.dist = std::sqrt(d2);
    s.wi = v / s.dist;
    s.pdf = area_to_solid_angle_pdf(ctx.p, s.wi, s.p_light, s.n_light, m_inv_area);
    if (!(s.pdf > 0.f)) return std::nullopt;
    s.li = m_emission;
    return s;
}

// Inline for quad lights (the usual area light, the Cornell box's): it runs at every path
// vertex. p = corner + u.x e1 + u.y e2, uniform by area.
[[gnu::always_inline]] inline std::optional<LightLiSample> Light::sample_li(
    const LightSampleContext& ctx, Vec2 u) const {
    if (m_kind != Kind::Area || m_area_shape != AreaShape::Parallelogram)
        return sample_li_other(ctx, u);
    LightLiSample s;
    s.p_light = m_corner + u.x * m_e1 + u.y * m_e2;
    s.n_light = m_normal;
    s.p_light_err = m_sample_err;
    return finish_area_sample(ctx, s);
}

// Whether next-event estimation samples this light. Every light but the constant environment
// (an environment map is sampled by its importance density, combined with the BSDF sample by
// MIS: a small bright sun is found by the light sample, the BSDF sample would rarely hit it).
// The constant environment's radiance is constant, so the BSDF sample that continues a path already
// draws wi in proportion to f cos L up to visibility (the best a light sample could do), while a
// light sample of it goes cosine-weighted about the normal (blind to a glossy lobe: on the brushed
// scene's near-specular floor almost every such shadow ray fell outside the lobe) and takes the
// shadow ray from the lights that need it (56% of the brushed scene's, by power). The path
// integrator therefore finds the environment by BSDF sampling alone: its selection pmf is 0, so
// the MIS weight of an escaping BSDF ray is 1 (power heuristic with a zero light pdf). The
// `direct` integrator, which has no BSDF rays, still samples it (Light::sample_li).
// A textured emitter is not sampled either (Light::set_textured_emission): its light samples
// would need the texture at the sampled point; BSDF sampling finds it unbiasedly.
inline bool nee_samples(const Light& light) {
    return (light.kind() != Light::Kind::Environment || light.map() != nullptr) &&
           !light.textured_emission();
}

// The discrete distribution next-event estimation chooses lights from: probability in
// proportion to each light's power (Light::power, averaged over the RGB channels; directional
// lights by their estimate over the scene's bounding sphere), so a strong light gets most
// shadow rays and a weak one few (pbrt-v4's PowerLightSampler). Built once at load time. Only
// lights with nee_samples() are candidates; candidates of zero power are never chosen; if every
// candidate has zero power the choice is uniform over the candidates. `uniform(lights)` builds
// the uniform choice over the candidates (for comparisons and tests). empty(): no candidate
// (e.g. only an environment): next-event estimation is skipped.
class LightDistribution {
  public:
    LightDistribution() = default;
    LightDistribution(std::span<const Light> lights, float scene_radius);
    static LightDistribution uniform(std::span<const Light> lights);
    // In proportion to each light's contribution where it matters: a pilot at load time traces
    // camera rays through a coarse grid of the film (and one diffuse bounce from each hit),
    // and at each hit x takes one light sample per candidate light, adding c_i(x)^2 with
    //     c_i(x) = lum(li) max(0, n . wi) / pdf   when the shadow ray is unblocked, else 0
    // (a one-sample estimate of the light's irradiance at x, no BSDF); bounce hits count half
    // (an average albedo) in c. With C_i = sqrt(sum c_i^2) (the choice that minimises the
    // second moment of the one-sample estimate), the weight of light i is
    // (1 - kViewPowerShare) C_i / sum C +
    // kViewPowerShare P_i / sum P (C_i the pilot's sum, P_i the power weights above): the power
    // share keeps every light of nonzero power choosable (unbiased: a light the pilot never saw
    // lit still gets samples). Falls back to the power weights when there are fewer than 2
    // candidates, when the pilot's budget (kViewBudget light samples) allows fewer than 96
    // receivers (many lights) or when it measured nothing. Deterministic (fixed sample points).
    static LightDistribution view(const Scene& scene);
    static constexpr double kViewPowerShare = 0.2;
    static constexpr std::size_t kViewBudget = std::size_t(1) << 17;

    std::size_t size() const { return m_pmf.size(); }
    bool empty() const { return m_empty; }
    // Index of the light chosen by u in [0,1) (the first i with u < cdf_i), and its probability.
    // Call only when size() > 0.
    std::uint32_t sample(float u, float& pmf) const {
        const std::size_t n = m_cdf.size();
        std::size_t i = 0;
        if (n <= 8) {
            while (i + 1 < n && !(u < m_cdf[i])) ++i;
        } else {
            i = std::size_t(std::upper_bound(m_cdf.begin(), m_cdf.end() - 1, u) - m_cdf.begin());
        }
        pmf = m_pmf[i];
        return std::uint32_t(i);
    }
    // Probability of choosing light i (what sample() returns for it).
    float pmf(std::size_t i) const { return m_pmf[i]; }

  private:
    // weights[i] < 0 marks a light that is not a candidate (pmf 0 even in the uniform case).
    void build(const std::vector<double>& weights);
    bool m_empty = true;
    std::vector<float> m_cdf;  // running probability, last = 1
    std::vector<float> m_pmf;  // m_cdf[i] - m_cdf[i - 1], exactly as sample() selects
};

}  // namespace facet::render
