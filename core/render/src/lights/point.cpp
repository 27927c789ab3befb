// Light kind "point": an isotropic point light of a given power.
#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/light_units.h"

namespace facet::render {

namespace {

void build(LightBuild& b) {
    const LightDesc& l = b.light;
    b.check_finite(l.position, b.ptr + "/position");
    b.add_light(Light::point(l.position, b.check_color(l.power, b.ptr + "/power", "a power (W)")));
}

void pov(PovLightOut& o) {
    const LightDesc& l = o.light;
    const glm::dvec3 c = pov_light_colour(point_intensity(glm::dvec3(l.power)));
    o.out() << "light_source { " << pov_vec(glm::dvec3(l.position)) << " " << pov_rgb(c)
            << " physical_falloff }  // " << o.pointer << ": point, power "
            << pov_vec(glm::dvec3(l.power)) << " W\n";
}

}  // namespace

extern const LightKindDef kPointLightKind{
    LightKind::Point,
    "point",
    "isotropic point light of radiant power Φ (W). Irradiance at distance r: "
    "E = Φ cos θ / (4π r²) (Cohen & Wallace eq. 2.40)",
    {{"position", FieldType::Point, true, &LightDesc::position, "-", "position"},
     {"power", FieldType::Color, true, &LightDesc::power, "-", "a power (W)"}},
    {},
    build,
    pov};

}  // namespace facet::render
