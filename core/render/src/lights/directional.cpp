// Light kind "directional": parallel light of a given irradiance (a distant sun).
#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/light_units.h"

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
