// Light kind "directional": parallel light of a given irradiance (a distant sun), and its
// light type.
//
// Sampling (light.h conventions): the delta light gives li = E (the irradiance on a surface
// facing the light), dist = +inf. With an angular diameter 2 delta > 0 (Blender's sun angle) it
// is a cone of directions of uniform radiance L = E / (pi sin^2 delta) about -direction, so that
// a surface facing it receives E = int_cone L cos = pi L sin^2 delta exactly; wi is uniform in
// the cone, li = L. No ray finds the sun (not hittable): pdf_li is 0. Its power for the light
// choice is E times the cross-section pi R^2 of the scene's bounding sphere (pbrt-v4).
//
// "angle_model": "cycles34" is Blender 3.4's Cycles sun instead (kernel/light/light.h,
// LIGHT_DISTANT; scene/light.cpp sets radius = tan delta, invarea = 1 / (pi tan^2 delta)): the
// directions toward the points of a disc of radius T = tan delta at distance 1 from the lit
// point, perpendicular to the sun's axis, sampled uniformly over the disc's area; the density per
// solid angle of a direction at theta from the axis is pdf = invarea / cos^3 theta (the disc
// point is at distance 1 / cos theta, seen at cos theta), and Cycles' radiance is
// eval_fac = pdf times the strength E, so every sample gives li / pdf = E. The radiance grows off
// the axis (L(theta) = E / (pi T^2 cos^3 theta)) but the surface facing the sun receives
// E <cos theta> = E 2 (sqrt(1 + T^2) - 1) / T^2 (the mean of cos theta = 1 / sqrt(1 + rho^2)
// over the disc): less than E, 0.982 E at a 30 degree angle, 0.928 E at 60. Not hittable, as
// above (Cycles 3.4 finds the disc with escaping rays, by MIS; the light sample alone has the
// same expectation).
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
    b.add_light(Light::directional(dir, e, float(angle), b.angle_model()));
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
            << " parallel point_at <0, 0, 0>" << o.media_keywords() << " }"
            << "  // " << o.pointer << ": directional, irradiance "
            << pov_vec(glm::dvec3(l.irradiance)) << " W/m^2\n";
}

}  // namespace

std::optional<LightLiSample> DirectionalLight::sample_li(const LightSampleContext&, Vec2 u) const {
    LightLiSample s;
    if (cycles34) {
        // Cycles 3.4: uniform on the disc of radius tan delta at distance 1 along -direction.
        const Vec2 q = sample_uniform_disk_concentric(u);
        const Frame f = Frame::from_z(-direction);
        const glm::dvec3 w = glm::dvec3(f.z) + tan_delta * (glm::dvec3(f.x) * double(q.x) +
                                                            glm::dvec3(f.y) * double(q.y));
        const double len2 = glm::dot(w, w);  // 1 / cos^2 theta
        const double pdf = len2 * std::sqrt(len2) / (kPiD * tan_delta * tan_delta);
        s.wi = Vec3(w / std::sqrt(len2));
        s.pdf = float(pdf);
        s.li = Rgb(glm::dvec3(irradiance) * pdf);
        s.dist = kInfinity;
        if (!(s.pdf > 0.f) || !std::isfinite(s.pdf) || !is_finite(s.li)) return std::nullopt;
        return s;
    }
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

Light Light::directional(const Vec3& direction, const Rgb& irradiance, float angle_deg,
                         SunAngleModel model) {
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
        if (model == SunAngleModel::Cycles34) {
            l.cycles34 = true;
            l.tan_delta = std::tan(0.5 * double(angle_deg) * kPiD / 180.0);
        }
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
      "full angular diameter 2δ of the light, degrees, in [0, 180)"},
     {"angle_model", FieldType::Text, false, &LightDesc::angle_model, "uniform",
      "what a sun with an angle is: `uniform` (the cone of uniform radiance above) or "
      "`cycles34` (Blender 3.4's Cycles: directions through a disc of radius T = tan δ at "
      "distance 1, radiance E / (π T² cos³ θ) at θ from the axis; a facing surface receives "
      "E · 2(√(1 + T²) − 1)/T², 0.982 E at 30°)"}},
    {},
    build,
    pov};

}  // namespace facet::render
