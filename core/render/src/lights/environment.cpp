// Light kind "environment": radiance arriving from every direction that escapes the scene (at
// most one per scene): a constant, or an equirectangular image (environment_map.h) oriented by
// "up" and "rotate".
#include <glm/gtc/matrix_transform.hpp>

#include <filesystem>

#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/environment_map.h"
#include "facet/render/texel_image.h"

namespace facet::render {

namespace {

// R_up (environment_map.h): the smallest rotation taking +Z to the unit vector `up`.
glm::dmat3 up_rotation(const glm::dvec3& up) {
    const glm::dvec3 z(0.0, 0.0, 1.0);
    const double c = glm::dot(z, up);
    const glm::dvec3 axis = glm::cross(z, up);
    const double s = glm::length(axis);
    if (!(s > 1e-12)) {
        // +Z: the identity; -Z: a half turn about X (keeps +X, flips Y and Z).
        return c > 0.0
                   ? glm::dmat3(1.0)
                   : glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, -1));
    }
    return glm::dmat3(glm::rotate(glm::dmat4(1.0), std::atan2(s, c), axis / s));
}

void build(LightBuild& b) {
    const LightDesc& l = b.light;
    const std::string& ptr = b.ptr;
    if (l.file.empty()) {
        for (const auto& [given, key] :
             {std::pair{l.rotate.has_value(), "rotate"}, std::pair{l.up.has_value(), "up"}}) {
            if (given)
                b.fail(ptr + "/" + key,
                       "orients an environment map: give \"file\" (a constant environment "
                       "looks the same from every direction)");
        }
        if (!l.radiance) b.fail(ptr + "/radiance", "is required (or give a map as \"file\")");
        b.add_environment(
            Light::environment(b.check_color(*l.radiance, ptr + "/radiance", "a radiance")));
        return;
    }
    const Rgb multiplier =
        l.radiance ? b.check_color(*l.radiance, ptr + "/radiance", "a radiance multiplier")
                   : Rgb(1.f);
    glm::dmat3 frame(1.0);
    if (l.up) frame = up_rotation(glm::dvec3(b.unit_direction(*l.up, ptr + "/up")));
    if (l.rotate) {
        const Vec3 axis = b.unit_direction(l.rotate->axis, ptr + "/rotate/axis");
        b.check_finite(l.rotate->angle, ptr + "/rotate/angle");
        frame = glm::dmat3(
                    glm::rotate(glm::dmat4(1.0), glm::radians(l.rotate->angle), glm::dvec3(axis))) *
                frame;
    }
    if (!b.files_allowed()) b.fail(ptr + "/file", "image files are disabled here");
    std::filesystem::path path(l.file);
    if (path.is_relative()) path = std::filesystem::path(b.base_dir()) / path;
    TexelImage image;
    const std::string where = ptr + "/file";
    try {
        // Auto colour space: float files linear, 8/16-bit files sRGB-decoded (texel_image.h).
        image = load_texel_image(path.string(), {ColorSpace::Auto, true}, where);
    } catch (const TexelImageError& e) {
        // "<where>: <file>: <what>"; fail() names the pointer itself.
        std::string m = e.what();
        if (m.rfind(where + ": ", 0) == 0) m.erase(0, where.size() + 2);
        b.fail(where, m);
    }
    b.add_environment(Light::environment_map(
        std::make_shared<const EnvironmentMap>(image, multiplier, glm::mat3(frame))));
}

void pov(PovLightOut& o) {
    if (!o.light.file.empty())
        o.fail(o.pointer + "/file",
               "an environment map is not exported to POV-Ray yet (its sky_sphere image_map "
               "orientation is not derived); remove the map or render with facet");
    const Rgb radiance = o.light.radiance.value_or(Rgb(0.f));
    if (o.options.environment == "background") {
        o.out() << "background { " << pov_rgb(glm::dvec3(radiance)) << " }  // " << o.pointer
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
    "radiance arriving from every direction that escapes the scene (at most one): a constant, "
    "or an equirectangular map (see [Environment maps](#environment-maps))",
    {{"radiance", FieldType::Color, false, &LightDesc::radiance, "- without `file`; 1 with `file`",
      "the radiance L (W sr^-1 m^-2), required without `file`; with `file`, the multiplier of "
      "the map's texels"},
     {"file", FieldType::Path, false, &LightDesc::file, "-",
      "an equirectangular image (EXR, HDR, PNG sRGB-decoded, ... relative to the scene file); "
      "direction d looks up u = 0.5 - atan2(d.y, d.x) / 2pi from the left edge, v = theta / pi "
      "from the top row (Blender's Environment Texture, Z up)"},
     {"up", FieldType::Direction, false, &LightDesc::up, "[0, 0, 1]",
      "the world direction of the map's top row (smallest rotation from +Z); `file` only"},
     {"rotate", FieldType::Rotation, false, &LightDesc::rotate, "none",
      "rotates the map (after `up`) by `angle` degrees about `axis`, right-handed, in world "
      "space; `file` only"}},
    {},
    build,
    pov};

}  // namespace facet::render
