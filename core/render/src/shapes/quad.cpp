// Shape kind "quad": four points as two triangles (p0 p1 p2), (p0 p2 p3).
#include "../io/pov_writer.h"
#include "../kind_build.h"

namespace facet::render {

namespace {

TriangleMesh triangles(const ShapeDesc& s, const std::string&) {
    return make_quad(s.vertices);
}

void build(ShapeBuild& b) {
    const std::array<Vec3, 4>& p = b.shape.vertices;
    for (std::size_t i = 0; i < 4; ++i)
        b.check_finite(p[i], b.ptr + "/vertices/" + std::to_string(i));
    if (glm::length(glm::cross(p[1] - p[0], p[2] - p[0])) == 0.f ||
        glm::length(glm::cross(p[2] - p[0], p[3] - p[0])) == 0.f) {
        b.fail(b.ptr + "/vertices", "the quad is degenerate (collinear vertices)");
    }
    b.add_triangles(triangles(b.shape, b.base_dir()), p[1] - p[0]);
}

// A flat parallelogram emitter gets one N x N grid of light cells.
void pov(PovShapeOut& o) {
    o.triangles(true);
}

}  // namespace

extern const ShapeKindDef kQuadKind{
    ShapeKind::Quad,
    "quad",
    "4 points, counter-clockwise seen from the front; split into `(p0 p1 p2)`, `(p0 p2 p3)` "
    "(need not be planar)",
    {{"vertices", FieldType::Quad, true, &ShapeDesc::vertices, "-",
      "4 points, counter-clockwise seen from the front"}},
    build,
    triangles,
    pov};

}  // namespace facet::render
