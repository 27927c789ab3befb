// Shape kind "plane": an infinite plane (cannot emit: its power would be infinite).
#include "../io/pov_writer.h"
#include "../kind_build.h"

namespace facet::render {

namespace {

void build(ShapeBuild& b) {
    const ShapeDesc& s = b.shape;
    if (b.emissive) {
        b.fail(b.ptr + "/emission",
               "an infinite plane cannot emit (infinite power); use a quad or a disc");
    }
    b.check_finite(s.point, b.ptr + "/point");
    b.add_plane(glm::dvec3(s.point), b.unit_direction(s.normal, b.ptr + "/normal"));
}

void pov(PovShapeOut& o) {
    const ShapeDesc& s = o.shape;
    if (o.reads_uv) o.fail_uv("POV-Ray's plane has no UV coordinates");
    const glm::dvec3 n = (s.flip_normals ? -1.0 : 1.0) * glm::normalize(glm::dvec3(s.normal));
    o.object("plane { " + pov_vec(n) + ", " + pov_num(glm::dot(n, glm::dvec3(s.point))), false);
}

}  // namespace

extern const ShapeKindDef kPlaneKind{
    ShapeKind::Plane,
    "plane",
    "**infinite** exact plane; cannot emit (infinite power)",
    {{"point", FieldType::Point, true, &ShapeDesc::point, "-", "a point on the plane"},
     {"normal", FieldType::Direction, true, &ShapeDesc::normal, "-", "front side's normal"}},
    build,
    nullptr,
    pov};

}  // namespace facet::render
