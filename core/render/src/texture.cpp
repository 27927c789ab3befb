// What every texture kind shares, and textured materials at a hit (conventions in
// facet/render/texture.h; the kinds are units in textures/).
#include "facet/render/texture.h"

#include "facet/render/scene.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace facet::render {

namespace {

constexpr float kPi = 3.14159265358979323846f;

// A combination's sub-materials at p: its textured children built there (into this thread's
// pool: pooled_material, facet/material.h), the constant ones shared.
using Children2 = std::array<std::shared_ptr<const Material>, 2>;
void textured_children(const Scene& scene, const TexturedMaterial& tm, const TexturePoint& p,
                       Children2& children) {
    for (std::size_t k = 0; k < tm.children.size() && k < children.size(); ++k) {
        const TexturedMaterial::Child& c = tm.children[k];
        children[k] = c.textured >= 0
                          ? pooled_material(scene.textured_material(std::size_t(c.textured), p))
                          : c.constant;
    }
}

}  // namespace

Texture::Texture(std::shared_ptr<const TextureSource> source, Rgb min, Rgb max, unsigned inputs,
                 bool tint)
    : m_source(std::move(source)),
      m_min(min),
      m_max(max),
      m_inputs(inputs | (tint ? unsigned(kTextureReadsColor) : 0u)),
      m_tint(tint) {}

void uv_transform(const TextureDesc& d, glm::mat2& a, Vec2& b) {
    const double th = d.uv_rotation * double(kPi) / 180.0;
    const float c = float(std::cos(th)), s = float(std::sin(th));
    // R diag(su, sv); glm matrices are column-major: a[col][row].
    a = glm::mat2(c * d.uv_scale.x, s * d.uv_scale.x, -s * d.uv_scale.y, c * d.uv_scale.y);
    b = d.uv_offset;
}

glm::dmat4 mapping_point_matrix(const glm::dvec3& loc, const glm::dvec3& rot,
                                const glm::dvec3& scale) {
    const double cx = std::cos(rot.x), cy = std::cos(rot.y), cz = std::cos(rot.z);
    const double sx = std::sin(rot.x), sy = std::sin(rot.y), sz = std::sin(rot.z);
    // Rows of R = Rz Ry Rx; glm is column-major: m[col][row].
    const double r[3][3] = {{cy * cz, sy * sx * cz - cx * sz, sy * cx * cz + sx * sz},
                            {cy * sz, sy * sx * sz + cx * cz, sy * cx * sz - sx * cz},
                            {-sy, cy * sx, cy * cx}};
    glm::dmat4 m(1.0);
    for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) m[col][row] = r[row][col] * scale[col];
        m[3][row] = loc[row];
    }
    return m;
}

int wrap_index_outside(int i, int n, TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::Clamp:
            return std::clamp(i, 0, n - 1);
        case TextureWrap::Mirror: {
            const int m = ((i % (2 * n)) + 2 * n) % (2 * n);
            return m < n ? m : 2 * n - 1 - m;
        }
        case TextureWrap::Repeat:
        default:
            return ((i % n) + n) % n;
    }
}

UvFootprint uv_footprint(const PixelFootprint& fp, const Vec3& dpdu, const Vec3& dpdv) {
    // Normal equations of the 3 x 2 system [dpdu dpdv] (du, dv) = dp, solved in double (the
    // determinant of nearly parallel derivatives cancels badly in float).
    const glm::dvec3 a(dpdu), b(dpdv);
    const double aa = glm::dot(a, a), ab = glm::dot(a, b), bb = glm::dot(b, b);
    const double det = aa * bb - ab * ab;
    if (!(det > 0.0) || !std::isfinite(det)) return {};
    auto solve = [&](const Vec3& dp) {
        const glm::dvec3 d(dp);
        const double ra = glm::dot(a, d), rb = glm::dot(b, d);
        const glm::dvec2 r((bb * ra - ab * rb) / det, (aa * rb - ab * ra) / det);
        // A huge (grazing) footprint is clamped far past any pyramid's last level.
        constexpr double kMaxDuv = 1e8;
        return std::isfinite(r.x) && std::isfinite(r.y)
                   ? Vec2(glm::clamp(r, glm::dvec2(-kMaxDuv), glm::dvec2(kMaxDuv)))
                   : Vec2(float(kMaxDuv));
    };
    return {solve(fp.dpdx), solve(fp.dpdy)};
}

UvFootprint Scene::texture_footprint(const SurfaceHit& hit, const Ray* camera_ray) const {
    const PixelFootprint fp = camera_ray
                                  ? m_camera.footprint(camera_ray->o, camera_ray->d, hit.p, hit.ng)
                                  : m_camera.footprint_at(hit.p, hit.ng);
    return uv_footprint(fp, hit.dpdu_uv, hit.dpdv_uv);
}

// Per-hit instantiation of a textured material (scene.h). The values are clamped into the
// textures' [min, max] ranges, which build_scene validated through the registry: bilinear
// weights can round a value one ulp past its neighbours.
Material Scene::material_at(const SurfaceHit& hit, const UvFootprint& fp, const Vec3& wo,
                            const Vec3& ns, const RayState* rs) const {
    TexturePoint p = texture_point(hit, fp, wo, ns);
    p.ray = rs;
    ImageLookupMemo memo;
    p.memo = &memo;
    if (const ShapeInfo& s = m_shapes[hit.shape]; s.needs_strand && s.kind == ShapeKind::Curves) {
        p.strand_random = hit.strand_random;
        p.strand_v = hit.strand_v;
        p.on_strand = 1.f;
    }
    return textured_material(std::size_t(hit.textured), p);
}

// Cycles 3.4's svm_node_tex_coord for a surface hit: N its shading normal turned to the
// viewer's side (shader_setup_from_ray), I = wo.
void Scene::view_coordinates(const SurfaceHit& hit, const Vec3& wo, const Vec3& ns,
                             TexturePoint& p) const {
    const ShapeInfo& s = m_shapes[hit.shape];
    if (s.normal_in_po) {
        p.normal = hit.po;  // a prototype's shape: complete_hit put it there
    } else {
        const Vec3 n = glm::normalize(s.normal_to_object * ns);
        p.normal = glm::dot(hit.ng, wo) < 0.f ? -n : n;
    }
    p.reflection = 2.f * glm::dot(ns, wo) * ns - wo;
    p.camera = m_camera.camera_point(hit.p);
    p.window = m_camera.window_point(p.camera);
}

Material Scene::textured_material(std::size_t index, const TexturePoint& p) const {
    const TexturedMaterial& tm = m_textured[index];
    if (tm.diffuse_base) {
        // A textured diffuse reflectance alone: the base material with its diffuse lobe
        // replaced, the same bits as make_material gives. Composite leaves out a zero diffuse
        // lobe, so a black value takes the general path below.
        const TexturedMaterial::Slot& s = tm.slots[0];
        const Rgb v =
            glm::clamp(s.texture->eval(p), s.texture->min_value(), s.texture->max_value());
        if (tm.diffuse_black_ok || max_component(v) > 0.f)
            return tm.diffuse_base->with_diffuse_reflectance(v);
    }
    // The staged build: the slots' values (through the conversion's sources) set the lobes.
    std::array<DVec3, TexturedMaterial::kMaxStaged> in, out;
    if (tm.convert_values) std::copy(tm.sources.begin(), tm.sources.end(), in.begin());
    for (std::size_t i = 0; i < tm.slots.size(); ++i) {
        const TexturedMaterial::Slot& s = tm.slots[i];
        const Rgb v =
            glm::clamp(s.texture->eval(p), s.texture->min_value(), s.texture->max_value());
        (tm.convert_values ? in[tm.slot_source[i]] : out[i]) =
            s.color ? DVec3(v) : DVec3(double(v.r));
    }
    if (tm.convert_values) tm.convert_values(in.data(), out.data());
    if (tm.children.empty()) return tm.staged->at(std::span(out.data(), tm.num_staged));
    Children2 children;
    textured_children(*this, tm, p, children);
    return tm.staged->at(std::span(out.data(), tm.num_staged),
                         std::span(children.data(), std::min(tm.children.size(), children.size())));
}

}  // namespace facet::render
