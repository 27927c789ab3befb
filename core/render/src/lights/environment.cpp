// Light kind "environment": constant radiance from every direction (at most one per scene).
#include "../io/pov_writer.h"
#include "../kind_build.h"

namespace facet::render {

namespace {

void build(LightBuild& b) {
    b.add_environment(
        Light::environment(b.check_color(b.light.radiance, b.ptr + "/radiance", "a radiance")));
}

void pov(PovLightOut& o) {
    if (o.options.environment == "background") {
        o.out() << "background { " << pov_rgb(glm::dvec3(o.light.radiance)) << " }  // "
                << o.pointer
                << ": environment, seen by camera and mirror rays only (approximation: it lights "
                   "no surface)\n";
        return;
    }
    o.fail(o.pointer,
           "an environment light lights every surface from every unoccluded direction, which "
           "POV-Ray cannot express exactly (radiosity only approximates it); --environment "
           "background exports it as the background only");
}

}  // namespace

extern const LightKindDef kEnvironmentLightKind{
    LightKind::Environment,
    "environment",
    "constant radiance arriving from every direction that escapes the scene (at most one)",
    {{"radiance", FieldType::Color, true, &LightDesc::radiance, "-", "a radiance"}},
    {},
    build,
    pov};

}  // namespace facet::render
