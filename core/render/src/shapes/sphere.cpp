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
    o.object("sphere { " + pov_vec(glm::dvec3(s.center)) + ", " + pov_num(s.radius),
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
