// Shape kind "disc": an exact analytic disc (one-sided emitter when it emits).
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/frame.h"

namespace facet::render {

namespace {

void build(ShapeBuild& b) {
    const ShapeDesc& s = b.shape;
    const Frame f = Frame::from_z(b.unit_direction(s.normal, b.ptr + "/normal"));
    glm::dmat4 rot(1.0);
    rot[0] = glm::dvec4(glm::dvec3(f.x), 0.0);
    rot[1] = glm::dvec4(glm::dvec3(f.y), 0.0);
    rot[2] = glm::dvec4(glm::dvec3(f.z), 0.0);
    const AnalyticPrim& prim = b.add_centred_prim(AnalyticPrim::Kind::Disc, rot);
    if (!b.emissive) return;
    const glm::dmat3 L(prim.to_world);
    const Vec3 center(glm::dvec3(prim.to_world[3]));
    // cross(L e1, L e2) = det(L) L^-T z: swap the axes when that disagrees with the hit normal
    // (mirroring transform XOR flip_normals).
    const bool swap = (glm::determinant(L) < 0.0) != s.flip_normals;
    Vec3 e1(L[0]), e2(L[1]);
    if (swap) std::swap(e1, e2);
    b.add_light(Light::area_disc(center, e1, e2, b.emission, b.index));
}

// An emitter's light: N equal-area rings x 4N sectors, midpoint cells.
void pov(PovShapeOut& o) {
    const ShapeDesc& s = o.shape;
    if (o.reads_uv) o.fail_uv("POV-Ray's disc has no UV coordinates");
    const double nsign = s.flip_normals ? -1.0 : 1.0;
    const glm::dvec3 nn = glm::normalize(glm::dvec3(s.normal));
    o.object("disc { " + pov_vec(glm::dvec3(s.center)) + ", " + pov_vec(nsign * nn) + ", " +
                 pov_num(s.radius),
             false);
    if (!o.emits) return;
    o.begin_cells();
    const int n = o.area_grid();
    const glm::dmat4 xf = s.transform.value_or(glm::dmat4(1.0));
    const Frame fr = Frame::from_z(Vec3(nn));
    const glm::dvec3 ex(fr.x), ey(fr.y);
    const glm::dmat3 lin(xf);
    const glm::dmat3 nmat = glm::transpose(glm::inverse(lin));
    glm::dvec3 nw = nmat * nn;
    // Area scale of the plane under the transform: |det| |M^-T n|.
    const double area_scale = std::fabs(glm::determinant(lin)) * glm::length(nw);
    nw = glm::normalize(nw) * nsign;
    const int sectors = 4 * n;
    const double cell_area = kPiD * s.radius * s.radius * area_scale / double(n * sectors);
    for (int i = 0; i < n; ++i) {
        const double r = s.radius * std::sqrt((i + 0.5) / n);
        for (int j = 0; j < sectors; ++j) {
            const double phi = 2.0 * kPiD * (j + 0.5) / sectors;
            const glm::dvec3 local =
                glm::dvec3(s.center) + r * (std::cos(phi) * ex + std::sin(phi) * ey);
            o.cell_light(glm::dvec3(xf * glm::dvec4(local, 1.0)), nw, glm::dvec3(s.emission),
                         cell_area);
        }
    }
}

}  // namespace

extern const ShapeKindDef kDiscKind{
    ShapeKind::Disc,
    "disc",
    "exact flat disc",
    {{"center", FieldType::Point, true, &ShapeDesc::center, "-", "centre"},
     {"normal", FieldType::Direction, true, &ShapeDesc::normal, "-", "front side's normal"},
     {"radius", FieldType::Number, true, &ShapeDesc::radius, "-", "radius, > 0"}},
    build,
    nullptr,
    pov};

}  // namespace facet::render
