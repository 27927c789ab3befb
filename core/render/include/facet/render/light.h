// Light sources of the renderer, in physical units, and their sampling as seen from a point.
//
// Structure: a Light holds one light TYPE's parameters (a struct of facet/render/lights/<type>.h,
// listed in the table light_types.h, a std::variant) and dispatches to it in Light::visit: the
// one place that goes from a light to its type. Each type's unit under
// core/render/src/lights/ holds its sampling (sample_li, pdf_li), its emission (le,
// le_escape), its power and its factory below (the members every type has: light_sample.h);
// the type's header holds its parameters and the functions small enough to inline (kInline:
// Light::sample_li inlines the type's sample_li into the integrators). Nothing
// else knows a type: the integrators, the light selection (LightDistribution) and the scene
// builder see only Light. The types:
//   point, spot, directional   (lights/point.cpp, spot.cpp, directional.cpp)
//   environment                (lights/environment.cpp: the constant environment)
//   environment_map            (lights/environment_map.cpp)
//   sky_nishita                (lights/sky_nishita.cpp: Blender's Nishita Sky Texture)
//   area_lamp                  (lights/area.cpp: Blender's area lamp, the "area" light kind)
//   emissive_triangles, emissive_parallelogram, emissive_sphere, emissive_disc
//                              (lights/emissive_*.cpp: shapes with an "emission")
//   emissive_moving_triangles  (lights/emissive_moving.cpp: such a triangle shape that moves)
// A type's math (fall-offs, sized lights, the shapes' sampling densities) is documented in its
// unit; light_units.h holds the unit conversions the units and the exporters share.
//
// Conventions:
//  - Units: point and spot lights are given by their radiant power Phi (W, per RGB channel),
//    directional lights by the irradiance E (W/m^2) on a surface facing them, area lights
//    (emissive shapes, area lamps) and the environment by their radiance L (W sr^-1 m^-2).
//  - `sample_li(ctx, u)` picks a direction wi (unit, world space, from ctx.p TOWARD the light)
//    and returns `li` such that the direct-lighting estimate at ctx.p is
//        f(wo, wi) * li * |cos theta_i| / pdf.
//    For lights with extent `li` is the incident radiance and `pdf` is per unit solid angle of
//    wi. For the delta lights (point, spot and directional lights without size) `pdf` = 1,
//    `delta` is true and li is the radiance's equivalent (the unit says which): then
//    li |cos theta_i| is the irradiance the light gives.
//    It returns nullopt when the light cannot contribute (ctx.p behind a spot cone, on the back
//    of a one-sided emitter, zero pdf). `dist` is the distance to the sampled point; shadow rays
//    use Scene::shadow_ray(hit, sample), which ends off the emitter by the sample's error box.
//  - `pdf_li(ctx, wi, p_light, n_light)` is the solid-angle density with which sample_li would
//    have produced wi when the ray p + t wi hits the light at p_light (normal n_light); used for
//    multiple importance sampling of BSDF-sampled rays. 0 for lights no ray can hit.
//  - Time: a moving emitter (emissive_moving_triangles) is sampled, and its pdf taken, where it
//    is at the path's shutter time: sample_li_at and pdf_li_at (the latter with the hit's
//    triangle, SurfaceHit::emitter_prim), which the motion kernels call; the kernels of scenes
//    that do not move call sample_li and pdf_li as before. Every other light is still over the
//    shutter (lamps do not move during the shutter in Cycles 3.4 either: blender/object.cpp
//    syncs lights at the frame only, not at the motion steps).
//  - hittable(): rays can hit the light (emissive shapes, the environment). Only then does MIS
//    weigh its samples against BSDF samples; a sample of any other light (delta lights, lights
//    with size that are not in the traced geometry: a sized point or spot, the sun, an area
//    lamp) is the only estimate of its light and takes weight 1.
//  - Emissive shapes emit only from the FRONT side of their shape (the side the geometric normal
//    of the shape points to, see scene.h); `le(n_light, w)` is the radiance leaving toward w.
//  - `ctx.n` is the (unit) shading normal on the side being lit, used by the constant
//    environment and the inside of sized lights to sample the cosine-weighted hemisphere; pass
//    n = 0 for a point not on a surface (then they sample the sphere uniformly).
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
#include <string_view>
#include <vector>

#include "facet/cdf_search.h"
#include "facet/render/environment_map.h"
#include "facet/render/light_sample.h"
#include "facet/render/light_tree.h"
#include "facet/render/light_types.h"
#include "facet/render/precision.h"
#include "facet/types.h"

namespace facet::render {

class Scene;

class Light {
    template <std::size_t I, class F>
    [[gnu::always_inline]] decltype(auto) visit_from(F& f) const {
        if constexpr (I + 1 == std::variant_size_v<LightTypes>) {
            return f(*std::get_if<I>(&m_state));
        } else {
            if (m_state.index() == I) return f(*std::get_if<I>(&m_state));
            return visit_from<I + 1>(f);
        }
    }

    // The inline part of sample_li: the types with kInline tested in the table's order, every
    // other type through one out-of-line call (cold()).
    template <std::size_t I, class F, class G>
    [[gnu::always_inline]] decltype(auto) visit_inline_from(F& f, G& cold) const {
        if constexpr (I == std::variant_size_v<LightTypes>) {
            return cold();
        } else {
            if constexpr (std::variant_alternative_t<I, LightTypes>::kInline) {
                if (m_state.index() == I) return f(*std::get_if<I>(&m_state));
            }
            return visit_inline_from<I + 1>(f, cold);
        }
    }

  public:
    // f(the type's parameters): the dispatch to the light's type, an inline test of the type
    // index in the table's order (std::visit's own dispatch is an out-of-line call in
    // libstdc++, which costs the hot emissive_parallelogram its inlining).
    template <class F>
    [[gnu::always_inline]] decltype(auto) visit(F&& f) const {
        return visit_from<0>(f);
    }

    // Factories, one per type, each defined in its type's unit (see "Structure"). Arguments
    // are validated by the scene loader (finite, non-negative power, unit directions, 0 <=
    // inner <= outer < 180 degrees...), not here. `radius` > 0 makes a point or spot light a
    // sphere of the same power, or with RadiusModel::Cycles34Disc Cycles 3.4's disc facing the
    // lit point (lights/point.cpp); 0 = a point.
    static Light point(const Vec3& position, const Rgb& power, float radius = 0.f,
                       RadiusModel model = RadiusModel::Sphere);
    // `direction` is the cone axis (unit, the way the light shines); angles are half-angles.
    static Light spot(const Vec3& position, const Vec3& direction, const Rgb& power,
                      float inner_half_angle_deg, float outer_half_angle_deg, float radius = 0.f,
                      RadiusModel model = RadiusModel::Sphere);
    // A spot with Blender's (Cycles 3.4) fall-off: I(theta) = K g(cos theta) with
    // g = cycles_spot_attenuation (light_units.h) for the cone of half-angle outer (<= 90
    // degrees) and blend in [0, 1]; K set so that the total power is Phi (cycles_spot_intensity).
    static Light spot_blend(const Vec3& position, const Vec3& direction, const Rgb& power,
                            float outer_half_angle_deg, float blend, float radius = 0.f,
                            RadiusModel model = RadiusModel::Sphere);
    // `direction` is the way the light TRAVELS (unit); wi = -direction. `angle_deg` in [0, 180)
    // is the full angular diameter of the light's disc of directions (Blender's sun angle);
    // `model` what the sized sun is (lights/directional.cpp).
    static Light directional(const Vec3& direction, const Rgb& irradiance, float angle_deg = 0.f,
                             SunAngleModel model = SunAngleModel::Uniform);
    static Light environment(const Rgb& radiance);
    // Environment map (environment_map.h): le_escape looks the map up, sample_li and pdf_li use
    // its importance density; emission() is its mean radiance.
    static Light environment_map(std::shared_ptr<const EnvironmentMap> map);
    // Blender's Nishita sky (sky_nishita.h): le_escape evaluates it, sample_li and pdf_li use
    // its mixture density (the sky's table and the sun's cone); emission() is its mean radiance.
    static Light sky_nishita(std::shared_ptr<const SkyNishita> sky);
    // Area light over world-space triangles (p0, p1, p2 per triangle, front side by the
    // counter-clockwise winding: n = normalize(cross(p1 - p0, p2 - p0))). Degenerate triangles
    // are dropped; at least one must remain. Two triangles that form a parallelogram make an
    // emissive_parallelogram.
    static Light area_triangles(std::vector<Vec3> triangle_vertices, const Rgb& radiance,
                                std::uint32_t shape);
    // Area light over triangles that move over the shutter (lights/emissive_moving.cpp):
    // `corners` holds the object-space corners (3 per triangle, all kept, in the traced mesh's
    // order) at each of its uniform deformation steps (one: no deformation); the placement is
    // `motion`'s steps (motion.h) or, without them, `place`. Front side as area_triangles', seen
    // through the placement (a mirroring one keeps the object-space front).
    static Light area_moving_triangles(std::vector<std::vector<Vec3>> corners,
                                       std::vector<DecomposedTransform> motion,
                                       const glm::dmat4& place, const Rgb& radiance,
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
    // half-axes; front normal normalize(cross(e1, e2)). Sampled by solid angle (lights/area.cpp).
    // With `camera_visible`, camera rays see it (camera_hit).
    static Light area_lamp(const Vec3& center, const Vec3& e1, const Vec3& e2, const Rgb& radiance,
                           bool ellipse, bool camera_visible = false);

    // What every light has besides its type's parameters (the factories fill it).
    struct Common {
        Rgb emission{0.f};   // Phi, E or L depending on the type (emission())
        Vec3 position{0.f};  // position(): point, spot; a shape light's or lamp's centre
        float area = 0.f;    // area(): emitting surfaces
        bool delta = false;  // is_delta()
        std::uint32_t shape = UINT32_MAX;  // shape()
        bool camera_visible = false;       // camera_visible()
    };
    // For the types' factories: a light of type T (a type of light_types.h).
    template <class T>
    static Light make(T state, const Common& common) {
        return Light(LightTypes(std::in_place_type<T>, std::move(state)), common, T::kHittable,
                     T::kNee);
    }

    // The name of the light's type (its kName: "point", "emissive_parallelogram", ...).
    std::string_view type_name() const;
    // The parameters of type T, or null when the light is of another type.
    template <class T>
    const T* get() const {
        return std::get_if<T>(&m_state);
    }
    // A delta light: sample_li ignores u (point, spot and directional lights without size).
    bool is_delta() const { return m_common.delta; }
    // Whether rays can hit the light (conventions).
    bool hittable() const { return m_hittable; }
    // Whether next-event estimation may sample it (its type's kNee; see nee_samples).
    bool nee_type() const { return m_nee; }
    // An area light whose radiance is a texture (a shape's textured "emission"): next-event
    // estimation does not sample it (nee_samples), BSDF rays find it with MIS weight 1, and
    // the radiance at a hit comes from the texture (SurfaceHit::emitted_radiance); emission()
    // is the texture's largest value, which only sets power() for --explain.
    void set_textured_emission() { m_textured = true; }
    bool textured_emission() const { return m_textured; }
    // The shape index (scene.h, SurfaceHit::shape) of an emissive shape; UINT32_MAX otherwise
    // (also for the area lamp, which is no shape).
    std::uint32_t shape() const { return m_common.shape; }

    // Inline: it runs at every path vertex. Types with kInline (the emissive parallelogram,
    // the usual area light) sample inline, the others through one out-of-line call.
    [[gnu::always_inline]] std::optional<LightLiSample> sample_li(const LightSampleContext& ctx,
                                                                  Vec2 u) const {
        const auto f = [&](const auto& t) __attribute__((always_inline)) {
            return t.sample_li(ctx, u);
        };
        const auto cold = [&] { return sample_li_out_of_line(ctx, u); };
        return visit_inline_from<0>(f, cold);
    }
    std::optional<LightLiSample> sample_li_out_of_line(const LightSampleContext& ctx, Vec2 u) const;
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                 const Vec3& n_light) const;
    // The same at shutter time `time` (light.h "Time"), `prim` the hit's
    // SurfaceHit::emitter_prim: what the motion kernels call. Lights that do not move ignore
    // both; a moving emitter needs them (its pdf_li without them is 0).
    [[gnu::always_inline]] std::optional<LightLiSample> sample_li_at(const LightSampleContext& ctx,
                                                                     Vec2 u, float time) const {
        const auto f = [&](const auto& t) __attribute__((always_inline)) {
            return t.sample_li(ctx, u);
        };
        const auto cold = [&] { return sample_li_at_out_of_line(ctx, u, time); };
        return visit_inline_from<0>(f, cold);
    }
    std::optional<LightLiSample> sample_li_at_out_of_line(const LightSampleContext& ctx, Vec2 u,
                                                          float time) const;
    float pdf_li_at(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                    const Vec3& n_light, std::uint32_t prim, float time) const;
    // Emission: radiance leaving the light's surface at a point of geometric normal n_light
    // toward the unit w (pointing away from the light; 0 on its back side), and radiance
    // arriving along a ray that escapes the scene in direction d. 0 for types without.
    Rgb le(const Vec3& n_light, const Vec3& w) const;
    Rgb le_escape(const Vec3& d) const;
    // le_escape(d), and pdf_li(ctx, d, 0, 0) in `pdf`: an escaping ray's MIS weight (one lookup
    // where the type has le_escape(d, pdf)).
    Rgb le_escape(const Vec3& d, const LightSampleContext& ctx, float& pdf) const;
    // Total emitted power (W per channel) for choosing lights in proportion to power; lights at
    // infinity (directional, environment) use the radius of the scene's bounding sphere.
    Rgb power(float scene_radius) const;
    // Where the light emits (light_sample.h, LightBounds), for the light tree; nullopt for
    // lights at infinity (directional, environment), which the tree samples apart.
    std::optional<LightBounds> bounds() const;
    // Sets the SceneFeatures flags of the light's type.
    void note(SceneFeatures& f) const;

    // The environment's map, or null (a constant environment or another type).
    const EnvironmentMap* map() const;

    // A light that camera rays see ("camera_visible" area lamps): the distance t > 0 along the
    // unit d at which the ray o + t d meets it, or +inf. The radiance seen there is emission().
    bool camera_visible() const { return m_common.camera_visible; }
    float camera_hit(const Vec3& o, const Vec3& d) const;

    // Parameters, for tests and --explain.
    const Vec3& position() const { return m_common.position; }
    const Rgb& emission() const { return m_common.emission; }  // Phi, E or L depending on type
    float area() const { return m_common.area; }               // emitting surfaces: total area

  private:
    Light(LightTypes state, const Common& common, bool hittable, bool nee)
        : m_state(std::move(state)), m_common(common), m_hittable(hittable), m_nee(nee) {}
    LightTypes m_state;
    Common m_common;
    bool m_hittable = false;
    bool m_nee = true;
    bool m_textured = false;
};

// Whether next-event estimation samples this light (its type's kNee, and no textured emission).
// Every light but the constant environment (an environment map is sampled by its importance
// density, combined with the BSDF sample by MIS: a small bright sun is found by the light sample,
// the BSDF sample would rarely hit it). The constant environment's radiance is constant, so the
// BSDF sample that continues a path already draws wi in proportion to f cos L up to visibility (the
// best a light sample could do), while a light sample of it goes cosine-weighted about the normal
// (blind to a glossy lobe: on the brushed scene's near-specular floor almost every such shadow ray
// fell outside the lobe) and takes the shadow ray from the lights that need it (56% of the brushed
// scene's, by power). The path integrator therefore finds the environment by BSDF sampling alone:
// its selection pmf is 0, so the MIS weight of an escaping BSDF ray is 1 (power heuristic with a
// zero light pdf). The `direct` integrator, which has no BSDF rays, still samples it
// (Light::sample_li). A textured emitter is not sampled either (Light::set_textured_emission): its
// light samples would need the texture at the sampled point; BSDF sampling finds it unbiasedly.
inline bool nee_samples(const Light& light) {
    return light.nee_type() && !light.textured_emission();
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
    // The light tree (light_tree.h): the choice depends on the shaded point. With fewer than
    // two candidates, the power distribution (one light is always chosen with probability 1).
    static LightDistribution tree(std::span<const Light> lights, float scene_radius);
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
            i = find_cdf_interval(m_cdf.data(), m_guide.data(), n, u);
        }
        pmf = m_pmf[i];
        return std::uint32_t(i);
    }
    // Probability of choosing light i (what sample() returns for it).
    float pmf(std::size_t i) const { return m_pmf[i]; }
    // The choice for the shaded point ctx (the integrators' calls): the light tree's when
    // there is one, else sample(u, pmf) / pmf(i). With a tree, pmf may be 0: no light chosen.
    [[gnu::always_inline]] std::uint32_t sample(const LightSampleContext& ctx, float u,
                                                float& pmf) const {
        if (m_tree) [[unlikely]]
            return m_tree->sample(ctx.p, ctx.n, u, pmf);
        return sample(u, pmf);
    }
    // The integrators' choice for a shadow ray, with the chosen light's own 2D sample u: without
    // a tree the light is chosen by u.x, and u.x is then rescaled to [0, 1) over the chosen
    // light's interval of the CDF, (u.x - cdf_{i-1}) / pmf_i, and handed on as the light
    // sample's first coordinate (as Cycles 3.4's light_distribution_sample). One 2D point set
    // then both picks the lights and places the samples on them: the pixel's samples that go to
    // light i are the points of its interval of u.x, which a (0, 2)-sequence keeps stratified in
    // 2D, where a choice by a dimension of its own sends light i a random subset of the light
    // sample's points, stratified no better than independent samples. Conditioned on light i,
    // (u.x, u.y) is uniform on [0, 1)^2, so the estimate stays unbiased. The tree chooses by
    // u.x the same way: its traversal rescales u.x over each chosen child's share, and what is
    // left of it is the light sample's first coordinate (LightTree::sample_reusing).
    [[gnu::always_inline]] std::uint32_t sample(const LightSampleContext& ctx, Vec2& u,
                                                float& pmf) const {
        if (m_tree) [[unlikely]]
            return m_tree->sample_reusing(ctx.p, ctx.n, u.x, pmf);
        const std::uint32_t i = sample(u.x, pmf);
        const float lo = i > 0 ? m_cdf[i - 1] : 0.f;
        // lo <= u.x < cdf_i, so the difference is >= 0; round-off may reach 1: clamp.
        if (pmf > 0.f) u.x = std::min((u.x - lo) / pmf, kOneMinusEpsilon);
        return i;
    }
    [[gnu::always_inline]] float pmf(const LightSampleContext& ctx, std::size_t i) const {
        if (m_tree) [[unlikely]]
            return m_tree->pmf(ctx.p, ctx.n, std::uint32_t(i));
        return m_pmf[i];
    }
    // Whether there is a tree.
    bool has_tree() const { return m_tree != nullptr; }

  private:
    // weights[i] < 0 marks a light that is not a candidate (pmf 0 even in the uniform case).
    void build(const std::vector<double>& weights);
    bool m_empty = true;
    std::vector<float> m_cdf;            // running probability, last = 1
    std::vector<float> m_pmf;            // m_cdf[i] - m_cdf[i - 1], exactly as sample() selects
    std::vector<std::uint32_t> m_guide;  // m_cdf's cutpoint table (facet/cdf_search.h)
    std::shared_ptr<const LightTree> m_tree;  // LightSelection::Tree
};

}  // namespace facet::render
