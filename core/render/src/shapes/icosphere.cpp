// Shape kind "icosphere": a subdivided icosahedron (a triangle-mesh sphere).
#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "../scene_checks.h"

namespace facet::render {

namespace {

TriangleMesh triangles(const ShapeDesc& s, const std::string&) {
    TriangleMesh m = make_icosphere(s.subdivisions, s.smooth);
    for (Vec3& p : m.positions) p = s.center + float(s.radius) * p;
    return m;
}

void build(ShapeBuild& b) {
    const ShapeDesc& s = b.shape;
    b.check_finite(s.center, b.ptr + "/center");
    (void)b.positive_length(s.radius, b.ptr + "/radius");
    const auto sub =
        b.check_int(s.subdivisions, b.ptr + "/subdivisions", 0, detail::kMaxIcosphereSubdivisions);
    b.reserve_triangles(20ull << (2 * sub), b.ptr + "/subdivisions");
    // UVs as the analytic sphere's: longitude and latitude of the unit sphere at the centre.
    const glm::dmat4 sphere =
        glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(s.center)), glm::dvec3(s.radius));
    b.add_triangles(triangles(s, b.base_dir()), Vec3(0.f), &sphere);
}

// A mesh2; its UVs are the analytic sphere's at each hit point, which per-vertex uv_vectors
// interpolated over a triangle are not.
void pov(PovShapeOut& o) {
    if (o.reads_uv)
        o.fail_uv(
            "the icosphere's UVs are the sphere's longitude and latitude at each hit point, "
            "which a mesh2's per-vertex uv_vectors only interpolate");
    o.triangles(false);
}

}  // namespace

extern const ShapeKindDef kIcosphereKind{
    ShapeKind::Icosphere,
    "icosphere",
    "icosahedron subdivided n times: 20·4ⁿ triangles, for big procedural meshes",
    {{"center", FieldType::Point, true, &ShapeDesc::center, "-", "centre"},
     {"radius", FieldType::Number, true, &ShapeDesc::radius, "-", "radius, > 0"},
     {"subdivisions", FieldType::Integer, true, &ShapeDesc::subdivisions, "-", "n", 0,
      detail::kMaxIcosphereSubdivisions},
     {"smooth", FieldType::Bool, false, &ShapeDesc::smooth, "true",
      "vertex normals (smooth shading)"}},
    build,
    triangles,
    pov};

}  // namespace facet::render
