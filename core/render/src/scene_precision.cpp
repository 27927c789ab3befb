// The scene builder's checks of float precision (scene_precision.h).
#include "scene_precision.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "facet/render/precision.h"

namespace facet::render {

namespace {

struct Feature {
    double size = std::numeric_limits<double>::infinity();  // the smallest feature
    double coordinate = 0.0;                                // the largest |coordinate|
    const char* what = "";
};

std::string shape_place(const SceneDescription& desc, std::uint32_t index) {
    const std::string& n = index < desc.shapes.size() ? desc.shapes[index].name : std::string();
    return "/shapes/" + std::to_string(index) + (n.empty() ? "" : " ('" + n + "')");
}

Feature mesh_feature(const MeshGeom& g, ShapeKind kind) {
    Feature f;
    const TriangleMesh& m = g.mesh;
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (const Vec3& p : m.positions) {
        const glm::dvec3 d(p);
        lo = glm::min(lo, d);
        hi = glm::max(hi, d);
        f.coordinate = std::max(f.coordinate, largest_magnitude(d));
    }
    if (kind == ShapeKind::Quad || kind == ShapeKind::Box) {
        // Few triangles, each meant: every edge must be representable.
        f.what = "an edge";
        for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            for (int j = 0; j < 3; ++j) {
                const glm::dvec3 a(m.positions[m.indices[t + std::size_t(j)]]);
                const glm::dvec3 b(m.positions[m.indices[t + std::size_t((j + 1) % 3)]]);
                f.size = std::min(f.size, glm::length(b - a));
            }
        }
    } else if (!m.positions.empty()) {
        // Meshes may hold tiny or sliver triangles harmlessly: the shape as a whole must be.
        f.what = "the extent";
        f.size = glm::length(hi - lo);
    }
    return f;
}

Feature prim_feature(const AnalyticPrim& p) {
    Feature f;
    const glm::dmat3 l(p.to_world);
    const bool sphere = p.kind == AnalyticPrim::Kind::Sphere;
    f.what = "the radius";
    for (int i = 0; i < (sphere ? 3 : 2); ++i) f.size = std::min(f.size, glm::length(l[i]));
    const double zr = sphere ? 1.0 : 0.0;
    for (int i = 0; i < 8; ++i) {
        const glm::dvec3 c(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? zr : -zr);
        f.coordinate =
            std::max(f.coordinate, largest_magnitude(glm::dvec3(p.to_world * glm::dvec4(c, 1.0))));
    }
    return f;
}

}  // namespace

void check_precision(Scene::Builder& builder, const SceneDescription& desc,
                     const std::string& name) {
    const Scene::Impl& impl = builder.impl();
    auto check = [&](std::uint32_t shape, const Feature& f) {
        const double spacing = float_spacing(f.coordinate);
        if (f.size >= kMinFeatureUlps * spacing) return;
        std::ostringstream msg;
        msg << name << ": " << shape_place(desc, shape) << ": the shape cannot be represented in "
            << "float where it is: " << f.what << " is " << f.size << ", less than "
            << kMinFeatureUlps << " float spacings (" << spacing << " each) at its coordinates ("
            << f.coordinate << "); enlarge it or move the scene nearer the origin";
        throw SceneError(msg.str());
    };
    for (const MeshGeom& g : impl.meshes)
        check(g.shape, mesh_feature(g, builder.shapes()[g.shape].kind));
    for (const AnalyticPrim& p : impl.prims) check(p.shape, prim_feature(p));

    const Bounds3& b = builder.bounds();
    if (b.empty()) return;
    const double extent = glm::length(glm::dvec3(b.hi) - glm::dvec3(b.lo));
    const double coordinate =
        std::max({largest_magnitude(glm::dvec3(b.lo)), largest_magnitude(glm::dvec3(b.hi)),
                  largest_magnitude(glm::dvec3(builder.camera().position))});
    const double spacing = float_spacing(coordinate);
    if (!(spacing > kSpacingWarnFraction * extent)) return;
    std::ostringstream msg;
    msg << "/: the scene's coordinates reach " << coordinate << ", where float spacing is "
        << spacing << " (" << spacing / extent << " of the scene's extent " << extent
        << "): details smaller than " << spacing << " units may merge; move the scene nearer "
        << "the origin";
    builder.warnings().push_back(msg.str());
}

}  // namespace facet::render
