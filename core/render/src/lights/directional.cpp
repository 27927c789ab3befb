// Light kind "directional": parallel light of a given irradiance (a distant sun), and its
// light type.
//
// Sampling (light.h conventions): the delta light gives li = E (the irradiance on a surface
// facing the light), dist = +inf. With an angular diameter 2 delta > 0 (Blender's sun angle) it
// is a cone of directions of uniform radiance L = E / (pi sin^2 delta) about -direction, so that
// a surface facing it receives E = int_cone L cos = pi L sin^2 delta exactly; wi is uniform in
// the cone, li = L. No ray finds the sun (not hittable): pdf_li is 0. Its power for the light
// choice is E times the cross-section pi R^2 of the scene's bounding sphere (pbrt-v4).
#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/light_units.h"
#include "sampling.h"

namespace facet::render {

namespace {

void build(LightBuild& b) {
    const LightDesc& l = b.light;
    if (!l.direction) b.fail(b.ptr, "missing required key 'direction'");
    const Vec3 dir = b.unit_direction(*l.direction, b.ptr + "/direction");
    const Rgb e = b.check_color(l.irradiance, b.ptr + "/irradiance", "an irradiance (W/m^2)");
    double angle = 0.0;
    if (l.angle) {
        const std::string p = b.ptr + "/angle";
        angle = b.check_range(*l.angle, p, 0.0, 180.0, "in [0, 180) degrees");
        if (!(angle < 180.0)) b.fail(p, "must be in [0, 180) degrees (full angle)");
    }
    b.add_light(Light::directional(dir, e, float(angle)));
}

// A parallel light lights only what lies in front of the plane through its location: put it
// far beyond the scene.
void pov(PovLightOut& o) {
    const LightDesc& l = o.light;
    if (l.angle && *l.angle > 0.0)
        o.fail(o.pointer + "/angle",
               "POV-Ray's parallel light has no angular size (its area_light is a grid of point "
               "lights, not a cone of uniform radiance): only angle 0 is exported exactly");
    const glm::dvec3 dir = glm::normalize(glm::dvec3(*l.direction));
    const glm::dvec3 c = pov_parallel_colour(glm::dvec3(l.irradiance));
    o.out() << "light_source { " << pov_vec(-1e9 * dir) << " " << pov_rgb(c)
            << " parallel point_at <0, 0, 0> }"
            << "  // " << o.pointer << ": directional, irradiance "
            << pov_vec(glm::dvec3(l.irradiance)) << " W/m^2\n";
}

}  // namespace

std::optional<LightLiSample> DirectionalLight::sample_li(const LightSampleContext&, Vec2 u) const {
    LightLiSample s;
    if (sized) {
        // Uniform in the cone of half-angle delta about -direction.
        s.wi = Vec3(sample_cone(-direction, one_minus_cos, u));
        s.li = size_radiance;
        s.pdf = float(1.0 / (2.0 * kPiD * one_minus_cos));
        s.dist = kInfinity;
        return s;
    }
    s.wi = -direction;
    s.li = irradiance;
    s.pdf = 1.f;
    s.dist = kInfinity;
    s.delta = true;
    return s;
}

void DirectionalLight::note(SceneFeatures& f) {
    f.has_directional = true;
}

Light Light::directional(const Vec3& direction, const Rgb& irradiance, float angle_deg) {
    DirectionalLight l;
    l.direction = glm::normalize(direction);
    l.irradiance = irradiance;
    // 1 - cos delta = 2 sin^2(delta / 2) and sin^2 delta = omc (2 - omc), delta = angle / 2.
    // Below omc = 1e-30 (angles under ~1e-13 degrees) the cone's pdf and L would overflow a
    // float: such a sun is the parallel light it equals to float precision.
    const double quarter = 0.25 * double(angle_deg) * kPiD / 180.0;
    const double omc = 2.0 * std::sin(quarter) * std::sin(quarter);
    if (omc > 1e-30) {
        l.sized = true;
        l.one_minus_cos = omc;
        l.size_radiance = Rgb(glm::dvec3(irradiance) / (kPiD * omc * (2.0 - omc)));
    }
    return make(l, {.emission = irradiance, .delta = !l.sized});
}

extern const LightKindDef kDirectionalLightKind{
    LightKind::Directional,
    "directional",
    "parallel light travelling along `direction`; `irradiance` is E (W m⁻²) on a surface "
    "facing it. With `angle` 2δ > 0 (Blender's sun angle) it is a disc of directions of "
    "half-angle δ about −`direction` of uniform radiance L = E / (π sin² δ), so the surface "
    "facing it still receives E = π L sin² δ, and a surface tilted by τ ≤ 90° − δ (the cone "
    "above its horizon) receives E cos τ exactly; shadows get penumbras. Directions are "
    "sampled uniformly in the cone; rays never hit the sun",
    {{"direction", FieldType::Direction, true, &LightDesc::direction, "-",
      "direction the light travels"},
     {"irradiance", FieldType::Color, true, &LightDesc::irradiance, "-", "an irradiance (W/m^2)"},
     {"angle", FieldType::Number, false, &LightDesc::angle, "0",
      "full angular diameter 2δ of the light, degrees, in [0, 180)"}},
    {},
    build,
    pov};

}  // namespace facet::render
