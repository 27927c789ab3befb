// Light kind "area": Blender's area lamp, a flat one-sided emitter of uniform radiance that is
// not part of the traced geometry (light.h: Light::hittable() is false for it).
//
// Frame (Blender's lamp object): local +z = -direction (the lamp emits along its local -z),
// local +y = `up` made perpendicular to z, local +x = y x z. The lamp spans `size` along x and
// `size_y` (rectangle, ellipse; else `size`) along y, centred on `position`.
#include <cmath>

#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/light_units.h"

namespace facet::render {

namespace {

enum class AreaShape { Square, Rectangle, Disc, Ellipse };

AreaShape parse_shape(const LightBuild& b) {
    const std::string& s = b.light.shape;
    if (s == "square") return AreaShape::Square;
    if (s == "rectangle") return AreaShape::Rectangle;
    if (s == "disc") return AreaShape::Disc;
    if (s == "ellipse") return AreaShape::Ellipse;
    b.fail(b.ptr + "/shape",
           "unknown area light shape '" + s + "' (expected square, rectangle, disc or ellipse)");
    return AreaShape::Square;  // not reached: fail() throws
}

void build(LightBuild& b) {
    const LightDesc& l = b.light;
    b.check_finite(l.position, b.ptr + "/position");
    const glm::dvec3 dir(b.aim(l.position));
    const AreaShape shape = parse_shape(b);
    const bool two_sizes = shape == AreaShape::Rectangle || shape == AreaShape::Ellipse;
    const double sx = b.positive_length(l.size, b.ptr + "/size");
    double sy = sx;
    if (two_sizes) {
        if (!l.size_y) b.fail(b.ptr, "missing required key 'size_y' (shape " + l.shape + ")");
        sy = b.positive_length(*l.size_y, b.ptr + "/size_y");
    } else if (l.size_y) {
        b.fail(b.ptr + "/size_y", "only the rectangle and ellipse shapes take size_y");
    }
    // The lamp's frame (see the top of the file).
    const glm::dvec3 up =
        l.up ? glm::dvec3(b.unit_direction(*l.up, b.ptr + "/up"))
             : (std::fabs(dir.y) < 0.999 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1));
    const glm::dvec3 z = -dir;
    glm::dvec3 y = up - glm::dot(up, z) * z;
    if (!(glm::length(y) > 1e-6)) b.fail(b.ptr + "/up", "must not be parallel to the direction");
    y = glm::normalize(y);
    const glm::dvec3 x = glm::cross(y, z);
    const glm::dvec3 hx = 0.5 * sx * x, hy = 0.5 * sy * y;
    const glm::dvec3 c(l.position);
    // Cycles 3.4: radiance P / (4 A) (light_units.h).
    const bool round = shape == AreaShape::Disc || shape == AreaShape::Ellipse;
    const Rgb power = b.check_color(l.power, b.ptr + "/power", "a power (W)");
    const Rgb radiance(area_lamp_radiance(glm::dvec3(power), area_lamp_area(round, sx, sy)));
    if (!is_finite(radiance))
        b.fail(b.ptr + "/size", "too small for the power: the radiance P / (4 A) overflows");
    // Front side (the side emitting) = dir: cross(e1, e2) must point along -z, so e1 = hy,
    // e2 = hx (cross(y, x) = -z).
    b.add_light(Light::area_lamp(Vec3(c), Vec3(hy), Vec3(hx), radiance, round, l.camera_visible));
}

void pov(PovLightOut& o) {
    o.fail(o.pointer,
           "POV-Ray has no flat emitter of uniform radiance (its area_light is a grid of point "
           "lights); an emissive quad or disc shape of radiance P / (4 A) is exported as "
           "such a grid (--area-grid) and renders the same in Facet, but is also seen by rays");
}

}  // namespace

extern const LightKindDef kAreaLightKind{
    LightKind::Area,
    "area",
    "Blender's area lamp: a flat one-sided emitter of `shape` square (side `size`), rectangle "
    "(`size` × `size_y`), disc (diameter `size`) or ellipse (diameters `size`, `size_y`), "
    "centred on `position`, emitting toward `direction` (its local −z; or toward `look_at`); "
    "its local +y is `up` made perpendicular to the direction, +x = y × z. `power` P is "
    "Blender's (Cycles 3.4): uniform radiance L = P / (4A) with A = size·size_y (square, "
    "rectangle) or π/4·size·size_y (disc, ellipse), so the emitted flux is π L A = π P / 4. "
    "Irradiance on the axis at distance d, facing it: disc of radius R: E = π L R²/(R² + d²); "
    "rectangle of half-sides a, b: E = 2 L [a/√(a²+d²) atan(b/√(a²+d²)) + "
    "b/√(b²+d²) atan(a/√(b²+d²))]. Sampled by solid angle: rectangles exactly (Ureña, Fajardo "
    "& King 2013's spherical rectangle, pdf 1/Ω), discs and ellipses over their bounding "
    "spherical rectangle when near (height < the larger half-axis; samples outside the "
    "ellipse are lost), by area when farther. Camera rays see it only with `camera_visible` "
    "(as Blender 3.4, whose lamps have Object > Visibility > Camera off by default); reflected "
    "and diffuse rays never (only light samples find it): give an emissive quad or disc shape "
    "for an emitter seen in mirrors",
    {{"position", FieldType::Point, true, &LightDesc::position, "-", "centre"},
     {"direction", FieldType::Direction, false, &LightDesc::direction, "-",
      "the way it emits (give this or look_at)"},
     {"look_at", FieldType::Point, false, &LightDesc::look_at, "-",
      "a point on its axis (give this or direction)"},
     {"up", FieldType::Direction, false, &LightDesc::up, "[0, 1, 0]",
      "its local +y, made perpendicular to the direction ([0, 0, 1] by default when the "
      "direction is within 2.6° of ±y)"},
     {"shape", FieldType::Text, false, &LightDesc::shape, "square",
      "square, rectangle, disc or ellipse"},
     {"size", FieldType::Number, true, &LightDesc::size, "-",
      "side (square, rectangle: along x) or diameter (disc, ellipse: along x), > 0"},
     {"size_y", FieldType::Number, false, &LightDesc::size_y, "-",
      "rectangle and ellipse only (required there): the extent along y, > 0"},
     {"power", FieldType::Color, true, &LightDesc::power, "-", "Blender's power P (W)"},
     {"camera_visible", FieldType::Bool, false, &LightDesc::camera_visible, "false",
      "camera rays see its front side, of radiance L (Blender: Object > Visibility > Camera)"}},
    {{"direction", "look_at"}},
    build,
    pov};

}  // namespace facet::render
