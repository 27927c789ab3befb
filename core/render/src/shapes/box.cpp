// Shape kind "box": an axis-aligned box (before its transform) as 12 flat triangles.
#include "../io/pov_writer.h"
#include "../kind_build.h"

namespace facet::render {

namespace {

TriangleMesh triangles(const ShapeDesc& s, const std::string&) {
    return make_box(s.min, s.max);
}

void build(ShapeBuild& b) {
    const ShapeDesc& s = b.shape;
    b.check_finite(s.min, b.ptr + "/min");
    b.check_finite(s.max, b.ptr + "/max");
    if (!(s.min.x < s.max.x && s.min.y < s.max.y && s.min.z < s.max.z)) {
        b.fail(b.ptr + "/max", "must be greater than \"min\" on every axis");
    }
    b.add_triangles(triangles(s, b.base_dir()), Vec3(1.f, 0.f, 0.f));
}

// POV-Ray's box, except for an emitter (its light cells need the triangles) and a textured box
// (POV-Ray's box UVs unfold the six faces into one image; the core's give each face [0, 1]^2,
// which the triangles carry as uv_vectors).
void pov(PovShapeOut& o) {
    const ShapeDesc& s = o.shape;
    if (o.emits || o.reads_uv) return o.triangles(false);
    o.object("box { " + pov_vec(glm::dvec3(s.min)) + ", " + pov_vec(glm::dvec3(s.max)),
             s.flip_normals);
}

}  // namespace

extern const ShapeKindDef kBoxKind{
    ShapeKind::Box,
    "box",
    "axis-aligned before the transform; 12 triangles, facing outward",
    {{"min", FieldType::Point, true, &ShapeDesc::min, "-", "lowest corner"},
     {"max", FieldType::Point, true, &ShapeDesc::max, "-", "highest corner (> min on every axis)"}},
    build,
    triangles,
    pov};

}  // namespace facet::render
