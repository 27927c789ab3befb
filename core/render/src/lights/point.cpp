// Light kind "point": an isotropic point light of a given power, and its light type.
//
// Sampling (light.h conventions): the delta light gives li = Phi / (4 pi r^2), so li |cos| =
// Phi cos / (4 pi r^2) (Cohen & Wallace eq. 2.40). With a radius r > 0 (Blender's lamp radius)
// it is a SPHERE of uniform radiance L = I0 / (pi r^2), I0 = Phi / (4 pi) its intensity, so its
// intensity pi r^2 L = I0 and its power Phi are those of the point light (Cycles 3.4's point
// lamp: radiance Phi / (4 pi^2 r^2)). From outside, sample_li draws wi uniformly in the cone the
// sphere subtends (pdf per solid angle 1 / (2 pi (1 - cos theta_max)), sin theta_max = r / d;
// pbrt-v4's SampleSphere, Cycles' sphere light) and li = L; from inside (d <= r) the point sees
// L from every direction and wi is cosine-weighted about ctx.n (uniform over the sphere when
// n = 0). The sphere is NOT in the ray-traced geometry: no camera or BSDF ray finds it (Blender
// 3.4 shows no lamp to camera rays), so its samples are not delta (a random u is drawn) but take
// no MIS weight (not hittable); pdf_li is 0.
//
// "radius_model": "cycles34_disc" is Blender 3.4's Cycles instead (kernel/light/light.h,
// light_sample for LIGHT_POINT: the lamp's radiance strength / (4 pi) / (pi r^2), eval_fac =
// invarea / (4 pi), on a disc of radius r through the centre whose normal points to the lit
// point): the same L on a DISC facing each lit point (its intensity toward the point, pi r^2 L,
// is I0), so that a surface facing the centre at distance d receives
// E = pi L r^2 / (d^2 + r^2) = I0 / (d^2 + r^2) instead of the sphere's I0 / d^2 (the disc
// fills the cone of half-angle atan(r / d), the sphere the narrower asin(r / d)). Sampled
// uniformly over the disc's area (sampling.h, sample_emitter_disc; Cycles does the same), pdf
// per solid angle t^3 / (d pi r^2). Cycles 3.4 lets BSDF rays hit that disc (facing the ray's
// origin, so the same disc) and weighs them by MIS against the light sample; the ray then goes
// on through the lamp. Facet leaves it out of the traced geometry, like the sphere: a disc whose
// orientation depends on the ray's origin is no Embree geometry, and since the lamp blocks no
// ray, the light sample alone has the same expectation (weight 1, as for every non-hittable
// light); what differs is only the noise of BSDF-sampled glossy reflections of the lamp.
#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/light_units.h"
#include "sampling.h"

namespace facet::render {

namespace {

void build(LightBuild& b) {
    const LightDesc& l = b.light;
    b.check_finite(l.position, b.ptr + "/position");
    const Rgb phi = b.check_color(l.power, b.ptr + "/power", "a power (W)");
    b.add_light(Light::point(l.position, phi, b.light_radius(), b.radius_model()));
}

void pov(PovLightOut& o) {
    const LightDesc& l = o.light;
    o.check_no_radius();
    const glm::dvec3 c = pov_light_colour(point_intensity(glm::dvec3(l.power)));
    o.out() << "light_source { " << pov_vec(glm::dvec3(l.position)) << " " << pov_rgb(c)
            << " physical_falloff" << o.media_keywords() << " }  // " << o.pointer
            << ": point, power " << pov_vec(glm::dvec3(l.power)) << " W\n";
}

}  // namespace

std::optional<LightLiSample> PointLight::sample_li(const LightSampleContext& ctx, Vec2 u) const {
    if (e.radius > 0.f) {
        if (e.disc) return sample_emitter_disc(e, ctx, u, nullptr);
        return sample_emitter_sphere(e, ctx, u, nullptr);
    }
    return sample_emitter_point(e, ctx, nullptr);
}

void PointLight::note(SceneFeatures& f) {
    f.has_point = true;
}

Light Light::point(const Vec3& position, const Rgb& power, float radius, RadiusModel model) {
    PointLight l;
    l.e.position = position;
    l.e.power = power;
    l.e.intensity = power * kInv4Pi;  // isotropic: I = Phi / (4 pi)
    const bool sphere = set_emitter_radius(l.e, radius, model);
    return make(l, {.emission = power, .position = position, .delta = !sphere});
}

extern const LightKindDef kPointLightKind{
    LightKind::Point,
    "point",
    "isotropic point light of radiant power Φ (W). Irradiance at distance r: "
    "E = Φ cos θ / (4π r²) (Cohen & Wallace eq. 2.40). With `radius` R > 0 it is a sphere "
    "(Blender's point lamp radius) of uniform radiance L = Φ / (4π² R²), the same power and "
    "far field (irradiance on a facing surface at distance d from the centre: "
    "E = π L R²/d² = Φ / (4π d²) exactly); a point inside the sphere sees L from every "
    "direction; sampled uniformly in the cone it subtends. With `radius_model` "
    "`cycles34_disc` it is Blender 3.4's Cycles lamp instead: a disc of radius R centred on "
    "`position` facing each lit point, of the same radiance L, so a facing surface at distance "
    "d receives E = π L R²/(d² + R²) = Φ / (4π (d² + R²)); sampled uniformly over the disc. "
    "Neither is seen by camera or reflected rays; they only light surfaces (Cycles 3.4 also "
    "finds its disc with reflected rays, weighted by MIS: the same expectation, less noise in "
    "glossy reflections of the lamp)",
    {{"position", FieldType::Point, true, &LightDesc::position, "-", "position"},
     {"power", FieldType::Color, true, &LightDesc::power, "-", "a power (W)"},
     kLightRadiusField,
     kLightRadiusModelField},
    {},
    build,
    pov};

std::optional<LightBounds> PointLight::bounds() const {
    return point_bounds(e);
}

}  // namespace facet::render
