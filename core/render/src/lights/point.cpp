// Light kind "point": an isotropic point light of a given power.
#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/light_units.h"

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
