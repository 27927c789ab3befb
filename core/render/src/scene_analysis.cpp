// The scene analysis (SceneFeatures, facet/render/scene.h), made by build_scene once the scene
// is built (scene_builder.h): which lobes, lights, media and motion the scene has, whether an
// emitter may be visible, and SceneFeatures::describe; and Scene::texture_memory.

#include <sstream>

#include "scene_builder.h"

namespace facet::render {

namespace detail {

bool Builder::reflects(const Material& m) {
    if (m.transmissive()) return true;  // a dielectric reflects at least its Fresnel part
    if (const Material::Combination* c = m.combination()) return reflects(*c->a) || reflects(*c->b);
    if (m.oren_nayar()) return max_component(m.oren_nayar()->rho()) > 0.f;
    // Another unit BxDF (velvet, hair's reflection, ...): whatever its lobes are.
    if (m.unit()) return m.unit()->flags() != BxDFFlags::None;
    if (m.diffuse() && max_component(m.diffuse()->rho()) > 0.f) return true;
    if (m.glossy()) return true;
    if (m.principled()) return m.principled()->flags() != BxDFFlags::None;
    if (m.mirror() && max_component(m.mirror()->scale()) > 0.f) return true;
    return false;
}

// Conservative frustum test: false only when the box lies entirely outside one side of the
// camera's view frustum (with a 1% margin).
bool Builder::maybe_visible(const Bounds3& b) const {
    if (b.empty()) return false;
    const Camera& c = m_builder.scene.camera();
    bool all_behind = true, all_left = true, all_right = true, all_below = true, all_above = true;
    float tx = 1.01f * c.tan_half_x, ty = 1.01f * c.tan_half_y;
    const bool persp = c.projection == Projection::Perspective;
    for (int i = 0; i < 8; ++i) {
        Vec3 p(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z);
        Vec3 v = p - c.position;
        float z = glm::dot(v, c.forward), x = glm::dot(v, c.right), y = glm::dot(v, c.true_up);
        // The window at depth z: k (centre +- half-extent), k = z (perspective) or 1
        // (orthographic), widened by a lens of radius R: a lens ray's offset from its
        // lens-centre ray is l (1 - z / focus_distance), at most R (1 + z / focus_distance).
        const float k = persp ? z : 1.f;
        const float m = c.has_lens() ? c.lens_radius * (1.f + z / c.focus_distance) : 0.f;
        all_behind &= z <= 0.f;
        all_left &= x < k * (c.center_x - tx) - m;
        all_right &= x > k * (c.center_x + tx) + m;
        all_below &= y < k * (c.center_y - ty) - m;
        all_above &= y > k * (c.center_y + ty) + m;
    }
    return !(all_behind || all_left || all_right || all_below || all_above);
}

void Builder::analyse() {
    SceneFeatures& f = m_builder.features();
    const Scene& scene = m_builder.scene;
    f = SceneFeatures{};
    f.num_shapes = scene.shapes().size();
    f.num_materials = m_builder.materials().size();
    f.num_lights = scene.lights().size();
    f.lambert_only = !scene.shapes().empty();
    for (std::size_t i = 0; i < scene.shapes().size(); ++i) {
        const ShapeInfo& s = scene.shapes()[i];
        // The shape's own surface, then its parts' (a glTF file's materials).
        auto surface = [&](const ShapeSurface& su) {
            BxDFFlags fl = su.material->flags();
            if (su.textured >= 0) fl = fl | m_builder.textured()[std::size_t(su.textured)].flags;
            f.lobes = f.lobes | fl;
            // The Lambert-only kernel reads the Lambertian lobe itself: Oren-Nayar and
            // combinations of Lambertians are Diffuse too but have no such lobe.
            if (fl != BxDFFlags::None && !(fl == BxDFFlags::Diffuse && su.material->diffuse()))
                f.lambert_only = false;
            if (reflects(*su.material)) f.can_reflect = true;
            if (su.textured >= 0) f.has_textured = true;
            // A material that reads the ray's Light Path state (light_path textures).
            if (su.textured >= 0 && m_builder.textured()[std::size_t(su.textured)].uses_ray)
                f.has_ray_visibility = true;
            // A surface that bounds a medium or lets rays through (an unused one is not).
            if (scene.medium_interface(su.material)) f.has_media = true;
            if (su.material->subsurface()) f.has_subsurface = true;
            if (su.material->has_holdout()) f.has_holdout = true;
            // A Light Path switch's materials, as the shape's own.
            if (su.light_path >= 0) {
                for (const LightPathSwitch::Entry& e :
                     scene.light_paths()[std::size_t(su.light_path)].entries) {
                    f.lobes = f.lobes | e.material->flags();
                    if (reflects(*e.material)) f.can_reflect = true;
                    if (e.material->has_holdout()) f.has_holdout = true;
                    if (e.material->subsurface()) f.has_subsurface = true;
                }
            }
            if (su.light >= 0 && maybe_visible(m_shape_bounds[i])) f.emitter_visible = true;
        };
        if (s.parts.empty()) surface(s);
        for (const ShapeSurface& p : s.parts) surface(p);
        if (s.holdout) f.has_holdout = true;
        if (s.shadow_catcher) f.has_shadow_catcher = true;
        if (s.visibility != kRayAll || s.light_path >= 0) f.has_ray_visibility = true;

        f.num_triangles += s.triangles;
        if (s.kind == ShapeKind::Sphere) ++f.num_spheres;
        if (s.kind == ShapeKind::Plane) ++f.num_planes;
        if (s.kind == ShapeKind::Disc) ++f.num_discs;
    }
    f.has_diffuse = any(f.lobes & BxDFFlags::Diffuse);
    f.has_glossy = any(f.lobes & BxDFFlags::Glossy);
    f.has_specular = any(f.lobes & BxDFFlags::Specular);
    f.has_transmission = is_transmissive(f.lobes);
    for (const Light& l : scene.lights()) {
        l.note(f);
        if (!l.is_delta()) f.any_non_delta_light = true;
        if (l.hittable()) f.any_hittable_light = true;
    }
    f.all_lights_delta = !f.any_non_delta_light;
    if (f.has_ray_visibility) {
        // Each emitting shape's visibility on its lights (light samples: Cycles' exclusions).
        std::vector<std::uint8_t>& lv = m_builder.light_visibility();
        lv.assign(scene.lights().size(), kRayAll);
        for (const ShapeInfo& s : scene.shapes()) {
            if (s.light >= 0) lv[std::size_t(s.light)] = s.visibility;
            for (const ShapeSurface& p : s.parts)
                if (p.light >= 0) lv[std::size_t(p.light)] = s.visibility;
        }
    }
    if (scene.world_medium() >= 0) f.has_media = true;
    if (scene.environment()) f.emitter_visible = true;  // escaping camera rays see it
    f.has_motion = m_camera_moves || m_shapes_move;
    f.needs_alpha = m_desc.render.film_transparent || f.has_holdout || f.has_shadow_catcher;
    if (m_camera_moves) f.emitter_visible = true;  // the frustum test is the still camera's
}

}  // namespace detail

std::string SceneFeatures::describe() const {
    std::ostringstream s;
    auto yn = [](bool b) { return b ? "yes" : "no"; };
    s << "geometry: " << num_shapes << " shapes (" << num_triangles << " triangles, " << num_spheres
      << " exact spheres, " << num_discs << " discs, " << num_planes << " infinite planes), "
      << num_materials << " materials\n";
    s << "lobes: diffuse " << yn(has_diffuse) << ", glossy " << yn(has_glossy) << ", specular "
      << yn(has_specular) << ", transmission " << yn(has_transmission)
      << (lambert_only ? " (Lambert only)" : "") << "; textured materials " << yn(has_textured)
      << "\n";
    s << "lights: " << num_lights << " (point " << yn(has_point) << ", spot " << yn(has_spot)
      << ", directional " << yn(has_directional) << ", area " << yn(has_area) << ", environment "
      << yn(has_environment) << "); all delta: " << yn(all_lights_delta) << "\n";
    s << "emitter visible to the camera: " << yn(emitter_visible)
      << "; surfaces reflect (indirect light possible): " << yn(can_reflect) << "\n";
    if (has_media) s << "media: yes (a world medium or medium boundaries)\n";
    if (has_subsurface) s << "subsurface: yes (random walks inside objects)\n";
    if (has_ray_visibility)
        s << "ray visibility: yes (a shape some kinds of ray do not see, a Light Path switch "
             "or a material reading the ray's Light Path state)\n";
    if (has_motion) s << "motion blur: yes (a moving camera, moving or deforming shapes)\n";
    if (needs_alpha)
        s << "alpha: yes ("
          << (has_shadow_catcher ? "a shadow catcher"
              : has_holdout      ? "a holdout"
                                 : "film transparent")
          << ")\n";
    return s.str();
}

TextureMemoryStats Scene::texture_memory() const {
    TextureMemoryStats s = m_texture_memory;
    if (m_tile_cache) {
        s.hits = s.misses = s.evictions = 0;
        m_tile_cache->stats(s);
    }
    return s;
}

}  // namespace facet::render
