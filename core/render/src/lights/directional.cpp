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
    b.add_light(Light::directional(dir, e));
}

// A parallel light lights only what lies in front of the plane through its location: put it
// far beyond the scene.
void pov(PovLightOut& o) {
    const LightDesc& l = o.light;
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
    "facing it",
    {{"direction", FieldType::Direction, true, &LightDesc::direction, "-",
      "direction the light travels"},
     {"irradiance", FieldType::Color, true, &LightDesc::irradiance, "-", "an irradiance (W/m^2)"}},
    {},
    build,
    pov};

}  // namespace facet::render
