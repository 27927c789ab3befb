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
    b.add_light(Light::point(l.position, phi, b.light_radius()));
}

void pov(PovLightOut& o) {
    const LightDesc& l = o.light;
    o.check_no_radius();
    const glm::dvec3 c = pov_light_colour(point_intensity(glm::dvec3(l.power)));
    o.out() << "light_source { " << pov_vec(glm::dvec3(l.position)) << " " << pov_rgb(c)
            << " physical_falloff }  // " << o.pointer << ": point, power "
            << pov_vec(glm::dvec3(l.power)) << " W\n";
}

}  // namespace

std::optional<LightLiSample> PointLight::sample_li(const LightSampleContext& ctx, Vec2 u) const {
    if (e.radius > 0.f) return sample_emitter_sphere(e, ctx, u, nullptr);
    return sample_emitter_point(e, ctx, nullptr);
}

void PointLight::note(SceneFeatures& f) {
    f.has_point = true;
}

Light Light::point(const Vec3& position, const Rgb& power, float radius) {
    PointLight l;
    l.e.position = position;
    l.e.power = power;
    l.e.intensity = power * kInv4Pi;  // isotropic: I = Phi / (4 pi)
    const bool sphere = set_emitter_radius(l.e, radius);
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
    "direction. The sphere is not seen by camera or reflected rays (as in Blender 3.4); it "
    "only lights surfaces, sampled uniformly in the cone it subtends",
    {{"position", FieldType::Point, true, &LightDesc::position, "-", "position"},
     {"power", FieldType::Color, true, &LightDesc::power, "-", "a power (W)"},
     kLightRadiusField},
    {},
    build,
    pov};

}  // namespace facet::render
