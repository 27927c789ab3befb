// The scene that `facet render model.glb` renders (facet/render/gltf.h): the file's one shape,
// a white environment, and the file's camera or one framing its bounding box.
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "facet/render/gltf.h"

namespace facet::render {

SceneDescription gltf_scene_description(const std::string& path, int width, int height,
                                        std::vector<std::string>& notes) {
    const GltfImport g = import_gltf(path);
    SceneDescription d;
    d.description = "the glTF file " + path;
    const std::filesystem::path p(path);
    d.base_dir = p.has_parent_path() ? p.parent_path().string() : ".";
    ShapeDesc s;
    s.kind = ShapeKind::Gltf;
    s.name = p.filename().string();
    s.file = p.filename().string();
    d.shapes.push_back(s);
    LightDesc env;
    env.kind = LightKind::Environment;
    env.radiance = Rgb(1.f);
    d.lights.push_back(env);
    notes.push_back("lit by a constant white environment of radiance 1");
    CameraDesc& c = d.camera;
    c.width = width;
    c.height = height;
    if (g.camera) {
        const GltfCamera& gc = *g.camera;
        c.position = Vec3(gc.position);
        c.look_at = Vec3(gc.position + glm::normalize(gc.forward));
        c.up = Vec3(glm::normalize(gc.up));
        c.fov = gc.yfov_deg;
        if (gc.aspect) c.width = std::max(1, int(std::lround(height * *gc.aspect)));
        notes.push_back("using the file's camera " + gc.pointer);
        return d;
    }
    // No camera: look at the bounding sphere of every part from the front-right, above
    // (glTF's +z front is -y after the Z-up turn), at the distance where the sphere fills
    // the smaller field of view.
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const GltfPart& pt : g.parts) {
        for (const Vec3& v : pt.mesh.positions) {
            lo = glm::min(lo, glm::dvec3(v));
            hi = glm::max(hi, glm::dvec3(v));
        }
    }
    if (g.parts.empty()) lo = hi = glm::dvec3(0.0);
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * glm::length(hi - lo), 1e-6);
    c.fov = 40.0;
    const double half = 0.5 * c.fov * M_PI / 180.0 * std::min(1.0, double(width) / height);
    const double dist = 1.1 * radius / std::sin(half);
    const glm::dvec3 dir = glm::normalize(glm::dvec3(0.6, -1.0, 0.5));
    c.position = Vec3(centre + dist * dir);
    c.look_at = Vec3(centre);
    c.up = Vec3(0.f, 0.f, 1.f);
    notes.push_back("the file has no camera: framing its bounding box from the front (fov 40)");
    return d;
}

}  // namespace facet::render
