// Shape kind "sphere": an exact analytic sphere (ray-traced in double in object space).
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

#include "../io/pov_writer.h"
#include "../kind_build.h"

namespace facet::render {

namespace {

void build(ShapeBuild& b) {
    const ShapeDesc& s = b.shape;
    const AnalyticPrim& prim = b.add_centred_prim(AnalyticPrim::Kind::Sphere);
    if (!b.emissive) return;
    // Light sampling needs a true sphere: the transform must be a similarity.
    const glm::dmat3 L(prim.to_world);
    const Vec3 center(glm::dvec3(prim.to_world[3]));
    const double s2 = glm::dot(L[0], L[0]);
    const glm::dmat3 g = glm::transpose(L) * L;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (std::fabs(g[i][j] - (i == j ? s2 : 0.0)) > 1e-6 * s2) {
                b.fail(b.ptr + "/emission",
                       "an emissive sphere cannot be non-uniformly scaled or sheared (use an "
                       "icosphere for an emissive ellipsoid)");
            }
        }
    }
    b.add_light(
        Light::area_sphere(center, float(std::sqrt(s2)), b.emission, b.index, s.flip_normals));
}

void pov(PovShapeOut& o) {
    if (o.emits)
        o.fail(o.pointer + "/emission",
               "an emissive sphere has no exact POV-Ray light (only quads, meshes and discs are "
               "exported as emitters)");
    const ShapeDesc& s = o.shape;
    if (!o.reads_uv)
        return o.object("sphere { " + pov_vec(glm::dvec3(s.center)) + ", " + pov_num(s.radius),
                        s.flip_normals);
    // Textured: POV-Ray's sphere UVs (Sphere::UVCoord, in the unit sphere's own space) are
    // u = the angle from +x toward +z / 2 pi in [0, 1) and v = 1/2 + asin(y) / pi, the core's
    // u = atan2(y, x) / 2 pi and v = arccos(-z) / pi = 1/2 + asin(z) / pi with y and z
    // exchanged. So a unit sphere whose POV y is the core's local z and POV z the core's y
    // (a mirroring matrix: the sphere is symmetric, only its UVs change), scaled by the radius
    // and moved to the centre, then the shape's transform. uv_mapping patterns are not moved
    // by object transforms.
    const double r = s.radius;
    const glm::dvec3 c(s.center);
    o.object("sphere { 0, 1\n  matrix <" + pov_num(r) + ", 0, 0, 0, 0, " + pov_num(r) + ", 0, " +
                 pov_num(r) + ", 0, " + pov_num(c.x) + ", " + pov_num(c.y) + ", " + pov_num(c.z) +
                 ">",
             s.flip_normals);
}

}  // namespace

extern const ShapeKindDef kSphereKind{
    ShapeKind::Sphere,
    "sphere",
    "**exact** sphere (analytic, solved in double precision; no tessellation)",
    {{"center", FieldType::Point, true, &ShapeDesc::center, "-", "centre"},
     {"radius", FieldType::Number, true, &ShapeDesc::radius, "-", "radius, > 0"}},
    build,
    nullptr,
    pov};

}  // namespace facet::render
