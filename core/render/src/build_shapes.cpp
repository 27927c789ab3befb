// build_scene's shapes (scene_builder.h): each shape through its kind's builder (kinds.h) with
// the ShapeContext it adds geometry through (meshes, analytic primitives, planes, curves,
// parts, emitters), shape motion and deformation, the prototypes and the instances that place
// them, and the checks on what is added (coordinate range, zero-area triangles, triangle limit).

#include <algorithm>
#include <set>
#include <sstream>

#include "facet/frame.h"
#include "facet/render/kinds.h"
#include "scene_builder.h"
#include "shapes/analytic.h"

namespace facet::render::detail {

// "/shapes/3" or "/shapes/3 ('Suzanne')" (or "/prototypes/tree/0 ...") for messages about a
// shape as a whole (index: in Scene::shapes()).
std::string Builder::shape_place(std::uint32_t index) const {
    return m_places[index];
}

// Whether hits on a surface compute uv: its material, emission or opacity reads a texture
// over UVs (an image or checker; not a vertex colour alone).
bool Builder::needs_uv(const ShapeSurface& s) {
    return (s.textured >= 0 && m_builder.textured()[std::size_t(s.textured)].uses_uv) ||
           (s.emission_texture && s.emission_texture->uses_uv()) || s.opacity.texture != nullptr;
}

// The texture space of shape `s` (ShapeDesc::texture_space; default its object-space box
// `bounds`, as Blender's automatic texture space: centre and half size, a zero half size
// counting as 1 and one below 1e-5 as 1e-5): generated = (po - (centre - half)) / (2 half).
void Builder::set_texture_space(ShapeInfo& info, const ShapeDesc& s, const Bounds3& bounds,
                                const std::string& ptr) {
    Vec3 loc(0.f), size(1.f);
    if (s.texture_space) {
        const std::string tp = ptr + "/texture_space";
        check_finite(s.texture_space->location, tp + "/location");
        check_finite(s.texture_space->size, tp + "/size");
        loc = s.texture_space->location;
        size = s.texture_space->size;
        for (int i = 0; i < 3; ++i)
            if (size[i] == 0.f) fail(tp + "/size/" + std::to_string(i), "must be non-zero");
    } else if (!bounds.empty()) {
        loc = 0.5f * (bounds.lo + bounds.hi);
        size = 0.5f * (bounds.hi - bounds.lo);
        for (int i = 0; i < 3; ++i) {
            if (size[i] == 0.f)
                size[i] = 1.f;
            else if (size[i] > 0.f && size[i] < 1e-5f)
                size[i] = 1e-5f;
        }
    }
    info.texture_lo = loc - size;
    info.texture_inv = 0.5f / size;
}

// Whether hits on a surface compute the object-space point: a procedural texture of its
// material or emission reads object or generated coordinates.
bool Builder::needs_position(const ShapeSurface& s) {
    return (s.textured >= 0 && m_builder.textured()[std::size_t(s.textured)].uses_position) ||
           (s.emission_texture && s.emission_texture->uses_position());
}

// Whether hits on a surface compute the view-dependent coordinates: a procedural texture of
// its material or emission reads normal, reflection, camera or window coordinates.
bool Builder::needs_view(const ShapeSurface& s) {
    return (s.textured >= 0 && m_builder.textured()[std::size_t(s.textured)].uses_view) ||
           (s.emission_texture && s.emission_texture->uses_view());
}

// Whether hits on a surface read the Hair Info values: a texture of its material or emission
// reads them.
bool Builder::needs_strand(const ShapeSurface& s) {
    return (s.textured >= 0 && m_builder.textured()[std::size_t(s.textured)].uses_strand) ||
           (s.emission_texture && s.emission_texture->uses_strand());
}

// Whether hits on a surface interpolate vertex colours: its material or emission reads them.
bool Builder::needs_color(const ShapeSurface& s) {
    return (s.textured >= 0 && m_builder.textured()[std::size_t(s.textured)].uses_color) ||
           (s.emission_texture && s.emission_texture->uses_vertex_color());
}

// What a shape kind's builder adds to the scene (kind_build.h).
class Builder::ShapeContext final : public ShapeBuild {
  public:
    ShapeContext(Builder& b, const ShapeDesc& s, std::uint32_t i, const std::string& p,
                 ShapeInfo& info, std::int32_t proto)
        : ShapeBuild(s, i, p), m_b(b), m_info(info), m_proto(proto) {}
    Bounds3 bounds;         // world extent of what was added
    Bounds3 object_bounds;  // object-space extent of what was added (meshes, spheres, discs)

    [[noreturn]] void fail(const std::string& p, const std::string& m) const override {
        m_b.fail(p, m);
    }
    std::string place() const override { return m_b.shape_place(index); }
    void reserve_triangles(std::uint64_t n, const std::string& p) override {
        m_b.reserve_triangles(n, p);
    }
    bool files_allowed() const override { return m_b.m_limits.allow_files; }
    const std::string& base_dir() const override { return m_b.m_desc.base_dir; }

    const AnalyticPrim& add_prim(AnalyticPrim::Kind k, const glm::dmat4& local) override {
        analytic_in_prototype();
        if (m_info.needs_color) fail_no_colors(m_info.material_name, false);
        AnalyticPrim prim;
        prim.kind = k;
        prim.shape = index;
        prim.flip = shape.flip_normals;
        prim.to_world = xf * local;
        prim.to_object = glm::inverse(prim.to_world);
        prim.normal_to_world = glm::transpose(glm::inverse(glm::dmat3(prim.to_world)));
        prim.uv = m_info.needs_uv;
        prim.opacity = m_info.opacity;
        if (m_info.needs_tangent) prim.tangent_sign = handedness(prim.to_world);
        const double zr = analytic::half_depth(k);
        for (int i = 0; i < 8; ++i) {
            glm::dvec3 c(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? zr : -zr);
            grow(glm::dvec3(prim.to_world * glm::dvec4(c, 1.0)));
            const Vec3 o(glm::dvec3(local * glm::dvec4(c, 1.0)));
            object_bounds.lo = glm::min(object_bounds.lo, o);
            object_bounds.hi = glm::max(object_bounds.hi, o);
        }
        std::vector<AnalyticPrim>& prims = m_b.m_builder.impl().prims;
        prims.push_back(prim);
        return prims.back();
    }

    void add_plane(const glm::dvec3& point, const Vec3& n) override {
        analytic_in_prototype();
        if (m_info.needs_color) fail_no_colors(m_info.material_name, false);
        const glm::dmat3 lin(xf);
        PlaneGeom pl;
        pl.shape = index;
        pl.point = glm::dvec3(xf * glm::dvec4(point, 1.0));
        pl.normal = glm::normalize(glm::transpose(glm::inverse(lin)) * glm::dvec3(n));
        if (shape.flip_normals) pl.normal = -pl.normal;
        const Frame local = Frame::from_z(n);
        pl.tangent = Vec3(glm::normalize(lin * glm::dvec3(local.x)));
        // UV axes: the local frame's x and y through the transform, in world units; y is
        // made orthogonal to x in the plane (the unflipped normal, so flip_normals does not
        // mirror the texture).
        pl.uv = m_info.needs_uv;
        pl.opacity = m_info.opacity;
        pl.tangent_sign = shape.flip_normals ? -1.f : 1.f;
        pl.ex = glm::normalize(lin * glm::dvec3(local.x));
        pl.ey =
            glm::cross(glm::normalize(glm::transpose(glm::inverse(lin)) * glm::dvec3(n)), pl.ex);
        if (!is_finite(Vec3(pl.point)) || !is_finite(Vec3(pl.normal))) {
            fail(ptr, "the transformed plane is not finite");
        }
        m_b.check_coordinate_range(max_abs(pl.point), index);
        m_b.m_builder.impl().planes.push_back(pl);
    }

    void add_triangles(TriangleMesh mesh, const Vec3& tangent, const glm::dmat4* sphere) override {
        add_mesh(std::move(mesh), tangent, -1, emissive, emission, sphere);
    }

    ShapeSurface add_material(const MaterialDesc& m, const std::string& p,
                              const MaterialConversion* conversion) override {
        const BuiltMaterial bm = m_b.build_material(m, p, conversion);
        ShapeSurface surface;
        surface.material = bm.material;
        surface.textured = bm.textured;
        surface.opacity = bm.opacity;
        return surface;
    }

    const Texture* add_texture(const TextureDesc& t, const std::string& p, bool color,
                               bool radiance) override {
        return m_b.build_texture(t, p, color, radiance);
    }

    bool textured_uses_uv(std::int32_t textured) const override {
        return m_b.m_builder.textured()[std::size_t(textured)].uses_uv;
    }

    void add_part(TriangleMesh mesh, ShapeSurface surface) override {
        if (surface.emission_texture) surface.emission = surface.emission_texture->max_value();
        const bool emits = max_component(surface.emission) > 0.f;
        if (emits && m_proto >= 0)
            fail(ptr, "a prototype's shapes cannot emit (" + surface.material_name +
                          " emits; place the emitter as a shape instead)");
        if (emits && surface.opacity.active())
            fail(ptr, "an emitting part cannot have opacity < 1 (" + surface.material_name + ")");
        const Rgb radiance = surface.emission;
        m_info.parts.push_back(std::move(surface));
        add_mesh(std::move(mesh), Vec3(0.f), std::int32_t(m_info.parts.size() - 1), emits, radiance,
                 nullptr);
    }

    void warn(std::string message) override {
        m_b.m_builder.warnings().push_back(std::move(message));
    }

    void add_curves(CurveGeom g, const Bounds3& extent, const Bounds3& object_extent) override {
        if (m_info.needs_color) fail_no_colors(m_info.material_name, false);
        if (m_info.needs_tangent)
            fail(ptr + "/material",
                 "the material has a normal map, which needs a surface's tangent space: "
                 "curves have none");
        if (m_info.opacity.active())
            fail(ptr + "/material", "curves cannot have a material with opacity < 1");
        if (m_info.needs_uv && g.root_uvs.empty())
            fail(ptr + "/root_uvs",
                 "the shape's material or emission is textured but the curves have no "
                 "root_uvs");
        if (!m_info.needs_uv) g.root_uvs = {};
        if (!m_info.needs_strand) {
            g.strand_random = {};
        } else if (g.strand_random.empty()) {
            g.strand_random.resize(g.strand_first.size() - 1);
            for (std::size_t i = 0; i < g.strand_random.size(); ++i)
                g.strand_random[i] = curve_random(std::uint32_t(i));
        }
        object_bounds.lo = glm::min(object_bounds.lo, object_extent.lo);
        object_bounds.hi = glm::max(object_bounds.hi, object_extent.hi);
        grow(glm::dvec3(extent.lo));
        grow(glm::dvec3(extent.hi));
        check_finite_bounds();
        if (m_proto >= 0)
            m_b.m_builder.impl().prototypes[std::size_t(m_proto)].curves.push_back(std::move(g));
        else
            m_b.m_builder.impl().curves.push_back(std::move(g));
    }

    void add_instance(const std::string& of, const std::string& of_ptr) override {
        if (m_proto >= 0)
            fail(of_ptr,
                 "a prototype cannot hold instances (one level of instancing: a prototype "
                 "may not place itself or another prototype)");
        const auto& protos = m_b.m_desc.prototypes;
        for (std::size_t p = 0; p < protos.size(); ++p) {
            if (protos[p].first != of) continue;
            m_b.m_pending.push_back({index, std::uint32_t(p), xf, true});
            return;
        }
        std::string msg = "unknown prototype '" + of + "' (";
        if (protos.empty()) msg += "the scene has no \"prototypes\"";
        for (std::size_t p = 0; p < protos.size(); ++p)
            msg += (p ? ", '" : "known: '") + protos[p].first + "'";
        fail(of_ptr, msg + ")");
    }

    bool can_instance() const override { return m_proto < 0; }
    std::uint32_t add_local_prototype() override {
        std::vector<PrototypeGeom>& protos = m_b.m_builder.impl().prototypes;
        protos.emplace_back();
        return std::uint32_t(protos.size() - 1);
    }
    void add_part_to(std::uint32_t prototype, TriangleMesh mesh, ShapeSurface surface) override {
        // As add_part, with the prototype as destination and no transform (the
        // placements carry it).
        const glm::dmat4 shape_xf = xf;
        xf = glm::dmat4(1.0);
        m_proto = std::int32_t(prototype);
        m_local = true;
        add_part(std::move(mesh), std::move(surface));
        m_local = false;
        m_proto = -1;
        xf = shape_xf;
    }
    void place_prototype(std::uint32_t prototype, const glm::dmat4& local) override {
        m_b.m_pending.push_back({index, prototype, xf * local, false});
    }
    // A moving shape (shape_motion): everything it adds goes to its own prototype, in
    // object space.
    // `motion` (or, without it, the still `place`) places the prototype: its emitting
    // triangles become moving emitters (Light::area_moving_triangles).
    void build_into(std::uint32_t prototype, const std::vector<DecomposedTransform>& motion,
                    const glm::dmat4& place) {
        m_proto = std::int32_t(prototype);
        m_local = true;
        m_moving_proto = m_proto;
        m_motion = motion;
        m_place = place;
    }
    std::int32_t local_prototype() const { return m_proto; }
    // The shape has `motion_positions` (checked against its mesh by add_mesh); `deform`
    // (ShapeBuild): they render (motion blur on; the mesh then goes to its own prototype).
    bool deform_steps = false;

  private:
    // The shape's own triangles (part -1) or one of its parts: transformed, validated,
    // degenerate triangles dropped, an area light when it emits; UVs as add_triangles says.
    void add_mesh(TriangleMesh mesh, const Vec3& tangent, std::int32_t part, bool emits,
                  const Rgb& radiance, const glm::dmat4* sphere) {
        for (const Vec3& p : mesh.positions) {
            object_bounds.lo = glm::min(object_bounds.lo, p);
            object_bounds.hi = glm::max(object_bounds.hi, p);
        }
        const glm::dmat3 lin(xf);
        const glm::dmat3 normal_mat = glm::transpose(glm::inverse(lin));
        // A mirroring transform reverses the winding: undo it so the authored front stays
        // the front; "flip_normals" reverses it on purpose.
        const bool flip = (glm::determinant(lin) < 0.0) != shape.flip_normals;
        // Object-space copies for MikkTSpace (only when a normal map needs tangents).
        std::vector<Vec3> object_positions, object_normals;
        std::vector<std::array<glm::vec4, 3>> tri_tangents;
        if (m_info.needs_tangent && !sphere && mesh.tangents.empty()) {
            object_positions = mesh.positions;
            object_normals = mesh.normals;
        }
        // Also without a transform: the identity leaves positions exact, and normals get
        // their double-precision renormalisation either way.
        for (Vec3& p : mesh.positions) {
            p = Vec3(glm::dvec3(xf * glm::dvec4(glm::dvec3(p), 1.0)));
            grow(glm::dvec3(p));
        }
        for (Vec3& n : mesh.normals) {
            const glm::dvec3 w = normal_mat * glm::dvec3(n);
            const double l = glm::length(w);
            n = l > 0.0 ? Vec3(w / l) : Vec3(0.f, 0.f, 1.f);
        }
        if (flip) {
            for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
                std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
            }
        }
        std::vector<std::vector<Vec3>> step_positions, step_normals;
        if (deform_steps && part < 0)
            deformation_steps(mesh, normal_mat, step_positions, step_normals);
        check_finite_bounds();
        if (std::string err = validate_mesh(mesh); !err.empty()) fail(place(), err);
        // A deforming mesh keeps every triangle: one of zero area at the still time may not
        // be at another (Embree's test misses it while it is degenerate).
        if (step_positions.empty()) m_b.drop_degenerate(mesh, index);
        if (m_info.needs_tangent && !sphere) {
            if (mesh.uvs.empty())
                fail(ptr + (shape.file.empty() ? "/uvs" : "/file"),
                     "the material has a normal map but the mesh has no UVs (its tangent "
                     "space needs them)");
            // MikkTSpace in object space, as Blender computes it: the kept triangles
            // over the untransformed positions and normals.
            TriangleMesh obj;
            if (mesh.tangents.empty()) {
                obj.positions = std::move(object_positions);
                obj.normals = std::move(object_normals);
                obj.uvs = mesh.uvs;
                obj.indices = mesh.indices;
            }
            tri_tangents = corner_tangents(mesh, obj, lin);
        }
        m_info.triangles += mesh.num_triangles();
        if (emits) {
            std::vector<Vec3> tri;
            tri.reserve(mesh.indices.size());
            for (std::uint32_t i : mesh.indices) tri.push_back(mesh.positions[i]);
            Light l = m_proto >= 0 && m_proto == m_moving_proto
                          ? moving_light(std::move(tri), mesh, step_positions, radiance)
                          : Light::area_triangles(std::move(tri), radiance, index);
            if (!(l.area() > 0.f)) fail(ptr + "/emission", "the emitting shape has no area");
            if (part < 0) {
                add_light(std::move(l));
            } else if (!sampled_as_light()) {
                m_info.parts[std::size_t(part)].light = kEmitterNotSampled;
            } else {
                std::vector<Light>& lights = m_b.m_builder.lights();
                if (m_info.parts[std::size_t(part)].emission_texture) l.set_textured_emission();
                m_info.parts[std::size_t(part)].light = std::int32_t(lights.size());
                lights.push_back(std::move(l));
            }
        }
        MeshGeom g;
        g.shape = index;
        g.part = part;
        g.opacity = part < 0 ? m_info.opacity : m_info.parts[std::size_t(part)].opacity;
        const bool uv = part < 0 ? m_info.needs_uv : m_b.needs_uv(m_info.parts[std::size_t(part)]);
        if (uv) {
            if (sphere) {
                g.spherical = true;
                g.to_object = glm::inverse(xf * *sphere);
            } else if (mesh.uvs.empty()) {
                fail(ptr + (shape.file.empty() ? "/uvs" : "/file"),
                     "the shape's material or emission is textured but the mesh has no UVs");
            } else {
                g.tri_uvs.resize(mesh.num_triangles());
                g.tri_dpduv.resize(mesh.num_triangles());
                for (std::size_t t = 0; t < g.tri_uvs.size(); ++t) {
                    std::array<glm::dvec3, 3> p;
                    for (std::size_t j = 0; j < 3; ++j) {
                        g.tri_uvs[t][j] = mesh.uvs[mesh.indices[3 * t + j]];
                        p[j] = glm::dvec3(mesh.positions[mesh.indices[3 * t + j]]);
                    }
                    g.tri_dpduv[t] = triangle_uv_derivatives(p, g.tri_uvs[t]);
                }
            }
        }
        const ShapeSurface& surface = part < 0 ? m_info : m_info.parts[std::size_t(part)];
        if (part < 0 ? m_info.needs_color : m_b.needs_color(surface)) {
            if (mesh.colors.empty()) fail_no_colors(surface.material_name, true);
            g.tri_colors.resize(mesh.num_triangles());
            for (std::size_t t = 0; t < g.tri_colors.size(); ++t)
                for (std::size_t j = 0; j < 3; ++j)
                    g.tri_colors[t][j] = mesh.colors[mesh.indices[3 * t + j]];
        }
        mesh.colors = {};
        if (m_info.needs_tangent && sphere) g.tangent_sign = handedness(xf * *sphere);
        if (m_info.needs_tangent && sphere) g.sphere_to_world = glm::dmat3(xf * *sphere);
        g.tri_tangents = std::move(tri_tangents);
        mesh.uvs = {};
        mesh.tangents = {};
        g.mesh = std::move(mesh);
        g.step_positions = std::move(step_positions);
        g.step_normals = std::move(step_normals);
        if (tangent != Vec3(0.f)) g.tangent = Vec3(lin * glm::dvec3(tangent));
        if (m_proto >= 0) {
            m_b.m_builder.impl().prototypes[std::size_t(m_proto)].meshes.push_back(std::move(g));
        } else {
            m_b.m_builder.impl().meshes.push_back(std::move(g));
        }
    }

    // A moving shape's emitter: its triangles `tri` (object space, the mesh's order), at each
    // deformation step when it deforms, placed by the shape's motion or still placement.
    Light moving_light(std::vector<Vec3> tri, const TriangleMesh& mesh,
                       const std::vector<std::vector<Vec3>>& step_positions,
                       const Rgb& radiance) const {
        std::vector<std::vector<Vec3>> corners;
        if (step_positions.empty()) {
            corners.push_back(std::move(tri));
        } else {
            for (const std::vector<Vec3>& step : step_positions) {
                std::vector<Vec3> c;
                c.reserve(mesh.indices.size());
                for (std::uint32_t i : mesh.indices) c.push_back(step[i]);
                corners.push_back(std::move(c));
            }
        }
        return Light::area_moving_triangles(std::move(corners), m_motion, m_place, radiance, index);
    }

    // The shape's `motion_positions` and `motion_normals` against `mesh` (as given: n
    // vertices, normals or none): every step 3n finite numbers, normals per step exactly
    // when the mesh has normals, none zero. With `deform`, the steps through the shape's
    // transform (positions) and its inverse transpose (normals, normalised), and the
    // shape's extent grown by them; otherwise checked only.
    void deformation_steps(const TriangleMesh& mesh, const glm::dmat3& normal_mat,
                           std::vector<std::vector<Vec3>>& positions,
                           std::vector<std::vector<Vec3>>& normals) {
        const std::size_t n = mesh.positions.size();
        const std::string mp = ptr + "/motion_positions";
        const std::string np = ptr + "/motion_normals";
        auto steps = [&](const std::vector<std::vector<float>>& in, const std::string& p,
                         const char* what, bool unit) {
            std::vector<std::vector<Vec3>> out;
            for (std::size_t k = 0; k < in.size(); ++k) {
                const std::string sp = p + "/" + std::to_string(k);
                if (in[k].size() != 3 * n)
                    fail(sp, "expected " + std::to_string(3 * n) +
                                 " numbers (3 per vertex: " + "the mesh has " + std::to_string(n) +
                                 " vertices), got " + std::to_string(in[k].size()));
                for (std::size_t i = 0; i < in[k].size(); ++i)
                    if (!std::isfinite(in[k][i]))
                        fail(sp + "/" + std::to_string(i), "must be a finite number");
                std::vector<Vec3> v(n);
                for (std::size_t i = 0; i < n; ++i) {
                    v[i] = Vec3(in[k][3 * i], in[k][3 * i + 1], in[k][3 * i + 2]);
                    if (unit && !(glm::length(v[i]) > 0.f))
                        fail(sp + "/" + std::to_string(3 * i),
                             std::string(what) + " " + std::to_string(i) + " is zero");
                }
                out.push_back(std::move(v));
            }
            return out;
        };
        std::vector<std::vector<Vec3>> p = steps(shape.motion_positions, mp, "position", false);
        if (mesh.normals.empty() && !shape.motion_normals.empty())
            fail(np, "the mesh has no normals (give \"normals\" too, or no motion_normals)");
        if (!mesh.normals.empty() && shape.motion_normals.empty())
            fail(mp,
                 "the mesh has normals: give its \"motion_normals\" too (one per vertex "
                 "per step)");
        std::vector<std::vector<Vec3>> nn = steps(shape.motion_normals, np, "normal", true);
        if (!deform) return;
        for (std::vector<Vec3>& step : p)
            for (Vec3& q : step) {
                q = Vec3(glm::dvec3(xf * glm::dvec4(glm::dvec3(q), 1.0)));
                grow(glm::dvec3(q));
            }
        for (std::vector<Vec3>& step : nn)
            for (Vec3& q : step) {
                const glm::dvec3 w = normal_mat * glm::dvec3(q);
                q = Vec3(w / glm::length(w));
            }
        positions = std::move(p);
        normals = std::move(nn);
    }

    // Prototypes hold triangles only: their hits are filled as meshes' are.
    void analytic_in_prototype() const {
        if (m_proto >= 0)
            fail(ptr + "/type",
                 "a prototype holds triangle shapes and curves only (box, quad, mesh, "
                 "icosphere, grid, gltf, curves), not the analytic sphere, disc or plane");
    }

    // A material or emission reads vertex colours the shape does not have: a mesh
    // without "colors" (`mesh`), or a kind that has none.
    [[noreturn]] void fail_no_colors(const std::string& material, bool mesh) const {
        const std::string what = "the material '" + material +
                                 "' or the emission reads vertex colours "
                                 "({\"vertex_color\": true}) but ";
        if (!mesh)
            fail(ptr + "/type", what + "a '" + std::string(shape_kind(shape.kind).name) +
                                    "' has none (only meshes with \"colors\" do)");
        fail(ptr + (shape.kind != ShapeKind::Mesh ? "/type"
                    : shape.file.empty()          ? "/colors"
                                                  : "/file"),
             what + "the mesh has no colours" +
                 (shape.kind == ShapeKind::Mesh ? " (give \"colors\")" : ""));
    }

    // The bitangent sign factor of a placement: -1 when it mirrors (cross(n, t) then
    // points against dp/dv) or when flip_normals reverses n, +1 otherwise (both: +1).
    float handedness(const glm::dmat4& to_world) const {
        const bool mirrored = glm::determinant(glm::dmat3(to_world)) < 0.0;
        return mirrored != shape.flip_normals ? -1.f : 1.f;
    }

    // World tangents per corner of `mesh` (already transformed, degenerate triangles
    // dropped): its own per-position tangents, or MikkTSpace's over `obj` (the same
    // triangles in object space); xyz through the linear part `lin`, w times the
    // handedness.
    std::vector<std::array<glm::vec4, 3>> corner_tangents(const TriangleMesh& mesh,
                                                          const TriangleMesh& obj,
                                                          const glm::dmat3& lin) const {
        const std::size_t nt = mesh.num_triangles();
        std::vector<glm::vec4> c;
        if (mesh.tangents.empty()) {
            c = compute_tangents(obj);
        } else {
            c.resize(3 * nt);
            for (std::size_t i = 0; i < 3 * nt; ++i) c[i] = mesh.tangents[mesh.indices[i]];
        }
        const float hand = handedness(glm::dmat4(lin));
        std::vector<std::array<glm::vec4, 3>> out(nt);
        for (std::size_t t = 0; t < nt; ++t) {
            for (std::size_t j = 0; j < 3; ++j) {
                const glm::vec4& v = c[3 * t + j];
                const glm::dvec3 w = lin * glm::dvec3(Vec3(v));
                const double l = glm::length(w);
                out[t][j] = glm::vec4(l > 0.0 ? Vec3(w / l) : Vec3(0.f), v.w * hand);
            }
        }
        return out;
    }

  public:
    void add_light(Light light) override {
        if (!sampled_as_light()) {
            m_info.light = kEmitterNotSampled;
            return;
        }
        if (m_info.emission_texture) light.set_textured_emission();
        std::vector<Light>& lights = m_b.m_builder.lights();
        m_info.light = std::int32_t(lights.size());
        lights.push_back(std::move(light));
    }

    void check_finite_bounds() override {
        const Bounds3& b = m_local ? local_bounds() : bounds;
        if (!is_finite(b.lo) || !is_finite(b.hi)) {
            fail(ptr, "the shape's extent overflows float (transform or size too large)");
        }
    }

  private:
    // Whether the shape's emission is a light source: as in Cycles 3.4, not when no diffuse,
    // glossy or transmission ray sees it (FORMAT.md, "Ray visibility").
    bool sampled_as_light() const {
        return (m_info.visibility & (kRayDiffuse | kRayGlossy | kRayTransmission)) != 0;
    }
    // The shape's extent, or (add_part_to) its local prototype's.
    void grow(const glm::dvec3& p) {
        Bounds3& b = m_local ? local_bounds() : bounds;
        b.lo = glm::min(b.lo, Vec3(p));
        b.hi = glm::max(b.hi, Vec3(p));
    }
    Bounds3& local_bounds() { return m_b.m_builder.impl().prototypes[std::size_t(m_proto)].bounds; }
    Builder& m_b;
    ShapeInfo& m_info;
    std::int32_t m_proto;  // the prototype being built, or -1
    bool m_local = false;  // building one of the shape's own prototypes (add_part_to)
    // A moving shape's own prototype (build_into), or -1, and what places it.
    std::int32_t m_moving_proto = -1;
    std::vector<DecomposedTransform> m_motion;
    glm::dmat4 m_place{1.0};
};

// Shape `s` as Scene::shapes()[index], at JSON pointer `ptr`: a description shape
// (proto -1) or a shape of prototype `proto` (its geometry then goes to the prototype).
void Builder::build_shape(const ShapeDesc& s, std::uint32_t index, const std::string& ptr,
                          std::int32_t proto) {
    m_places.push_back(ptr + (s.name.empty() ? "" : " ('" + s.name + "')"));
    if (!find_shape_kind(s.kind)) fail(ptr + "/type", "unknown shape type");
    if (proto >= 0 && (s.emission != Rgb(0.f) || s.emission_texture))
        fail(ptr + "/emission",
             "a prototype's shapes cannot emit (light sampling would need each instance as "
             "a light of its own; place an emitter as a shape instead)");
    if (shape_kind(s.kind).places_prototype) {
        // No surface of its own: hits report the prototype's shapes.
        if (s.material || !s.material_ref.empty())
            fail(ptr + "/material",
                 "an instance takes its prototype's materials (give them in the prototype)");
        if (s.emission != Rgb(0.f) || s.emission_texture)
            fail(ptr + "/emission", "an instance cannot emit (its prototype's shapes do not)");
        if (!s.two_sided) fail(ptr + "/two_sided", "give it on the prototype's shapes");
        if (s.flip_normals) fail(ptr + "/flip_normals", "give it on the prototype's shapes");
        if (s.holdout) fail(ptr + "/holdout", "give it on the prototype's shapes");
        if (s.shadow_catcher) fail(ptr + "/shadow_catcher", "give it on the prototype's shapes");
        if (s.visibility != kRayAll) fail(ptr + "/visibility", "give it on the prototype's shapes");
    }

    ShapeInfo info;
    info.kind = s.kind;
    info.two_sided = s.two_sided;
    info.holdout = s.holdout;
    info.shadow_catcher = s.shadow_catcher;
    info.visibility = s.visibility;
    info.emission = check_color(s.emission, ptr + "/emission", "an emitted radiance");
    if (s.emission_texture) {
        if (info.emission != Rgb(0.f))
            fail(ptr + "/emission", "give either a constant or a texture, not both");
        info.emission_texture = build_texture(*s.emission_texture, ptr + "/emission", true, true);
        if (info.emission_texture->uses_ray())
            fail(ptr + "/emission",
                 "an emission cannot read the ray's Light Path state (light sampling reads it "
                 "without a ray): give the shape a `light_path` switch");
        // The largest value makes the shape an emitter and sets its light's power (light.h).
        info.emission = info.emission_texture->max_value();
    }
    const bool emissive = max_component(info.emission) > 0.f;
    if (s.material) {
        if (!s.material_ref.empty()) {
            fail(ptr + "/material", "give either a material name or an inline material, not both");
        }
        const BuiltMaterial bm = build_material(*s.material, ptr + "/material");
        info.material = bm.material;
        info.textured = bm.textured;
        info.opacity = bm.opacity;
        info.material_name = "<inline>";
    } else if (!s.material_ref.empty()) {
        const std::string& name = s.material_ref;
        auto found = m_named.find(name);
        if (found == m_named.end()) fail(ptr + "/material", unknown_material(name));
        info.material = found->second.material;
        info.textured = found->second.textured;
        info.opacity = found->second.opacity;
        info.material_name = name;
    } else if (emissive || shape_kind(s.kind).own_materials ||
               shape_kind(s.kind).places_prototype) {
        // Emitters reflect nothing; kinds with their own materials add them as parts.
        info.material = black_material();
        info.material_name = "<black>";
    } else {
        fail(ptr, "missing required key 'material' (only emissive shapes may omit it)");
    }

    if (!s.light_path.empty()) {
        if (shape_kind(s.kind).places_prototype)
            fail(ptr + "/light_path", "give it on the prototype's shapes");
        if (shape_kind(s.kind).own_materials)
            fail(ptr + "/light_path", "a shape with its own materials (gltf) takes none");
        LightPathSwitch sw;
        for (std::size_t i = 0; i < s.light_path.size(); ++i) {
            const ShapeDesc::LightPathEntry& e = s.light_path[i];
            const std::string ep = ptr + "/light_path/" + std::to_string(i);
            LightPathSwitch::Entry out;
            out.ray = e.ray;
            out.emission = check_color(e.emission, ep + "/emission", "an emitted radiance");
            out.material = black_material();
            if (e.material) {
                const BuiltMaterial bm = e.material->ref.empty()
                                             ? build_material(*e.material, ep + "/material")
                                             : named_material(e.material->ref, ep + "/material");
                // The switch replaces the hit's material after the hit is found: its per-hit
                // data (uv, ...) and Embree's opacity filter are the shape's own material's.
                if (bm.textured >= 0)
                    fail(ep + "/material", "a Light Path switch's material cannot be textured");
                if (bm.opacity.active())
                    fail(ep + "/material",
                         "a Light Path switch's material cannot have opacity < 1 (a fully "
                         "transparent one is the `null` model)");
                if (bm.interior >= 0)
                    fail(ep + "/material",
                         "a Light Path switch's material cannot bound a medium (interior)");
                out.material = bm.material;
            }
            if (max_component(out.emission) > 0.f && info.opacity.active())
                fail(ep + "/emission",
                     "an emitting switch on a shape whose material has opacity < 1");
            sw.entries.push_back(out);
        }
        info.light_path = std::int32_t(m_builder.light_paths().size());
        m_builder.light_paths().push_back(std::move(sw));
    }

    info.needs_uv = needs_uv(info);
    info.needs_color = needs_color(info);
    info.needs_position = needs_position(info);
    info.needs_view = needs_view(info);
    info.needs_strand = needs_strand(info);
    // An invisible boundary cannot emit: rays cross it without a vertex.
    if (emissive) {
        if (const MediumInterface* mi = m_builder.scene.medium_interface(info.material);
            mi && mi->pass_through)
            fail(ptr + "/material", "an emitting shape cannot have a null material");
    }
    // Light sampling would count a cut-out emitter's light in full where rays see it with
    // probability alpha: not supported rather than biased.
    if (emissive && info.opacity.active())
        fail(ptr + "/material", "an emitting shape cannot have a material with opacity < 1");
    if (info.textured >= 0) {
        const TexturedMaterial& tm = m_builder.textured()[std::size_t(info.textured)];
        info.needs_tangent = tm.normal_map != nullptr;
    }
    glm::dmat4 xf(1.0);
    if (s.transform) {
        xf = *s.transform;
        const std::string tp = ptr + "/transform";
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (!std::isfinite(xf[c][r]))
                    fail(tp, "the transform is singular (zero scale?) or not finite");
        if (xf[0][3] != 0.0 || xf[1][3] != 0.0 || xf[2][3] != 0.0 || xf[3][3] != 1.0) {
            fail(tp, "the last row must be [0, 0, 0, 1] (affine transforms only)");
        }
        double det = glm::determinant(glm::dmat3(xf));
        if (!(std::fabs(det) > 1e-300) || !std::isfinite(det)) {
            fail(tp, "the transform is singular (zero scale?) or not finite");
        }
    }
    const std::vector<DecomposedTransform> motion = shape_motion(s, ptr, proto);
    const bool deforms = shape_deformation(s, ptr, proto);
    ShapeContext ctx(*this, s, index, ptr, info, proto);
    ctx.emission = info.emission;
    ctx.emissive = emissive;
    ctx.xf = xf;
    ctx.deform_steps = !s.motion_positions.empty();  // checked by add_mesh, on or off
    const bool places = shape_kind(s.kind).places_prototype;
    if (!motion.empty() || deforms) {
        // A moving shape: an instance moves its placement; a triangle shape goes into a
        // prototype of its own (object space), placed by its motion. A deforming mesh
        // likewise (its steps in object space), placed by its motion or its transform.
        ctx.xf = places ? motion[0].matrix() : glm::dmat4(1.0);
        if (!places) ctx.build_into(ctx.add_local_prototype(), motion, xf);
        ctx.deform = deforms;
    }
    const std::size_t pending = m_pending.size();
    shape_kind(s.kind).build(ctx);
    if (!motion.empty()) {
        if (places) {
            if (m_pending.size() == pending + 1) m_pending.back().motion = motion;
        } else {
            m_pending.push_back(
                {index, std::uint32_t(ctx.local_prototype()), motion[0].matrix(), false, motion});
        }
    } else if (deforms) {
        m_pending.push_back({index, std::uint32_t(ctx.local_prototype()), xf, false});
    }
    for (const ShapeSurface& part : info.parts) {
        info.needs_position = info.needs_position || needs_position(part);
        info.needs_view = info.needs_view || needs_view(part);
    }
    if (info.needs_position || info.needs_view) {
        info.to_object = glm::inverse(xf);
        info.normal_to_object = glm::mat3(glm::transpose(glm::dmat3(xf)));
        m_builder.impl().position_extras = true;
    }
    if (info.needs_view && proto >= 0) {
        // Instanced hits keep the object-space normal in SurfaceHit::po (scene.h).
        if (info.needs_position)
            fail(ptr,
                 "a prototype's shape cannot read normal, reflection, camera or window "
                 "coordinates and object or generated coordinates together");
        info.normal_in_po = true;
        auto& flags = m_builder.impl().normal_in_po;
        flags.resize(m_builder.shapes().size() + 1, 0);
        flags.back() = 1;
    }
    set_texture_space(info, s, ctx.object_bounds, ptr);
    if (proto >= 0) {
        // Object-space extent of the prototype; the scene's grows by its instances.
        Bounds3& pb = m_builder.impl().prototypes[std::size_t(proto)].bounds;
        pb.lo = glm::min(pb.lo, ctx.bounds.lo);
        pb.hi = glm::max(pb.hi, ctx.bounds.hi);
    } else if (!ctx.bounds.empty()) {
        check_coordinate_range(std::max(max_abs(ctx.bounds.lo), max_abs(ctx.bounds.hi)), index);
        m_builder.bounds().lo = glm::min(m_builder.bounds().lo, ctx.bounds.lo);
        m_builder.bounds().hi = glm::max(m_builder.bounds().hi, ctx.bounds.hi);
    }
    m_shape_bounds.push_back(ctx.bounds);
    m_builder.shapes().push_back(info);
}

// A shape's `motion` (scenes/FORMAT.md, "Motion blur"), checked, decomposed (motion.h);
// empty when it has none or motion blur is off (the still `transform` then renders).
std::vector<DecomposedTransform> Builder::shape_motion(const ShapeDesc& s, const std::string& ptr,
                                                       std::int32_t proto) {
    if (s.motion.empty()) return {};
    const std::string mp = ptr + "/motion";
    if (proto >= 0) fail(mp, "a prototype's shapes cannot move (give the instance a motion)");
    if (s.motion.size() < 2)
        fail(mp, "needs at least 2 steps (the transforms at shutter open and close), got " +
                     std::to_string(s.motion.size()));
    if (s.motion.size() > kMaxMotionSteps)
        fail(mp, "at most " + std::to_string(kMaxMotionSteps) + " steps");
    switch (s.kind) {
        case ShapeKind::Box:
        case ShapeKind::Quad:
        case ShapeKind::Mesh:
        case ShapeKind::Icosphere:
        case ShapeKind::Grid:
        case ShapeKind::Curves:
        case ShapeKind::Instance:
            break;
        default:
            fail(mp,
                 "only triangle shapes (box, quad, mesh, icosphere, grid), curves and "
                 "instances can move, not a '" +
                     std::string(shape_kind(s.kind).name) + "'");
    }
    std::vector<DecomposedTransform> out;
    for (std::size_t i = 0; i < s.motion.size(); ++i) {
        const glm::dmat4& m = s.motion[i];
        const std::string tp = mp + "/" + std::to_string(i);
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (!std::isfinite(m[c][r])) fail(tp, "the transform is not finite");
        if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
            fail(tp, "the last row must be [0, 0, 0, 1] (affine transforms only)");
        const double det = glm::determinant(glm::dmat3(m));
        if (!(std::fabs(det) > 1e-300) || !std::isfinite(det))
            fail(tp, "the transform is singular (zero scale?) or not finite");
        out.push_back(DecomposedTransform::decompose(m));
    }
    if (!m_motion_on) return {};
    m_shapes_move = true;
    return out;
}

// A shape's deformation motion (`motion_positions`, `motion_normals`; scenes/FORMAT.md,
// "Motion blur"): its structure checked here (the kind, the step count), its values by
// add_mesh against the mesh. True when it renders (motion blur on).
bool Builder::shape_deformation(const ShapeDesc& s, const std::string& ptr, std::int32_t proto) {
    const std::string mp = ptr + "/motion_positions";
    if (s.motion_positions.empty()) {
        if (!s.motion_normals.empty())
            fail(ptr + "/motion_normals", "given without \"motion_positions\"");
        return false;
    }
    if (s.kind != ShapeKind::Mesh && s.kind != ShapeKind::Curves)
        fail(mp, "only a 'mesh' or 'curves' can deform, not a '" +
                     std::string(shape_kind(s.kind).name) + "'");
    if (s.kind == ShapeKind::Curves && !s.motion_normals.empty())
        fail(ptr + "/motion_normals", "curves have no normals (give motion_positions only)");
    if (proto >= 0) fail(mp, "a prototype's shapes cannot deform");
    if (s.motion_positions.size() < 2)
        fail(mp, "needs at least 2 steps (the positions at shutter open and close), got " +
                     std::to_string(s.motion_positions.size()));
    if (s.motion_positions.size() > kMaxDeformSteps)
        fail(mp, "at most " + std::to_string(kMaxDeformSteps) + " steps");
    if (!s.motion.empty() && s.motion.size() != s.motion_positions.size())
        fail(mp, "has " + std::to_string(s.motion_positions.size()) +
                     " steps but the shape's \"motion\" has " + std::to_string(s.motion.size()) +
                     " (give both the same steps)");
    if (!s.motion_normals.empty() && s.motion_normals.size() != s.motion_positions.size())
        fail(ptr + "/motion_normals", "has " + std::to_string(s.motion_normals.size()) +
                                          " steps but \"motion_positions\" has " +
                                          std::to_string(s.motion_positions.size()));
    if (!m_motion_on) return false;
    m_shapes_move = true;
    return true;
}

// Every prototype's shapes after the description's (Scene::shapes() order), then the
// instances that place them.
void Builder::build_prototypes() {
    std::set<std::string> names;
    // After the shapes' own prototypes (add_local_prototype).
    m_prototype_base = m_builder.impl().prototypes.size();
    for (std::size_t p = 0; p < m_desc.prototypes.size(); ++p) {
        const auto& [pname, shapes] = m_desc.prototypes[p];
        const std::string pp = "/prototypes/" + escape_pointer_token(pname);
        if (!names.insert(pname).second) fail(pp, "duplicate prototype name '" + pname + "'");
        if (shapes.empty()) fail(pp, "a prototype needs at least one shape");
        m_builder.impl().prototypes.emplace_back();
        for (std::size_t k = 0; k < shapes.size(); ++k) {
            build_shape(shapes[k], std::uint32_t(m_builder.shapes().size()),
                        pp + "/" + std::to_string(k), std::int32_t(m_prototype_base + p));
        }
    }
    for (const PendingInstance& pi : m_pending) place_instance(pi);
}

// Instance `pi` (its transforms checked by build_shape: finite, affine, not singular).
void Builder::place_instance(const PendingInstance& pi) {
    InstanceGeom in;
    in.prototype = std::uint32_t(pi.described ? m_prototype_base + pi.prototype : pi.prototype);
    in.place(pi.xf);
    in.motion = pi.motion;
    const PrototypeGeom& proto = m_builder.impl().prototypes[in.prototype];
    in.deforms = std::any_of(proto.meshes.begin(), proto.meshes.end(),
                             [](const MeshGeom& g) { return !g.step_positions.empty(); }) ||
                 std::any_of(proto.curves.begin(), proto.curves.end(),
                             [](const CurveGeom& g) { return !g.step_vertices.empty(); });
    const Bounds3& pb = proto.bounds;
    if (pb.empty()) return;  // a glTF mesh without triangles: nothing to place
    // The world extent of every step's placement; a moving instance's also of its
    // interpolated placements, sampled finely (rotations swing corners outside the steps'
    // boxes). The scene's bounds serve light sampling and precision checks, not tracing
    // (Embree bounds the motion itself).
    Bounds3 wb;
    auto add_corners = [&](const glm::dmat4& m) {
        for (int i = 0; i < 8; ++i) {
            const glm::dvec3 c(i & 1 ? pb.hi.x : pb.lo.x, i & 2 ? pb.hi.y : pb.lo.y,
                               i & 4 ? pb.hi.z : pb.lo.z);
            const Vec3 w(glm::dvec3(m * glm::dvec4(c, 1.0)));
            wb.lo = glm::min(wb.lo, w);
            wb.hi = glm::max(wb.hi, w);
        }
    };
    add_corners(pi.xf);
    if (!in.motion.empty()) {
        constexpr int kBoundSamples = 64;  // per motion segment
        const int n = kBoundSamples * int(in.motion.size() - 1);
        for (int i = 0; i <= n; ++i)
            add_corners(interpolate_motion(in.motion, double(i) / double(n)));
    }
    if (!is_finite(wb.lo) || !is_finite(wb.hi))
        fail(shape_place(pi.shape), "the instance's extent overflows float");
    check_coordinate_range(std::max(max_abs(wb.lo), max_abs(wb.hi)), pi.shape);
    m_builder.bounds().lo = glm::min(m_builder.bounds().lo, wb.lo);
    m_builder.bounds().hi = glm::max(m_builder.bounds().hi, wb.hi);
    Bounds3& sb = m_shape_bounds[pi.shape];
    sb.lo = glm::min(sb.lo, wb.lo);
    sb.hi = glm::max(sb.hi, wb.hi);
    m_builder.impl().instances.push_back(in);
}

// Coordinates beyond Scene::kMaxCoordinate break Embree's float triangle test (scene.h).
void Builder::check_coordinate_range(double m, std::uint32_t index) {
    if (m > Scene::kMaxCoordinate) {
        std::ostringstream msg;
        msg << "the shape reaches coordinate " << m << ", beyond the renderer's range of +-"
            << Scene::kMaxCoordinate
            << " (float ray-triangle tests overflow there); scale the scene down or move it "
               "nearer the origin";
        fail(shape_place(index), msg.str());
    }
}

// Removes triangles whose world-space edge cross product is exactly zero (repeated or
// collinear vertices): they have no area, Embree never hits them, and their normal would be
// NaN. Every other triangle, slivers included, stays.
void Builder::drop_degenerate(TriangleMesh& mesh, std::uint32_t index) {
    std::vector<std::uint32_t>& ix = mesh.indices;
    std::size_t kept = 0;
    for (std::size_t t = 0; t + 2 < ix.size(); t += 3) {
        const Vec3 &a = mesh.positions[ix[t]], &b = mesh.positions[ix[t + 1]],
                   &c = mesh.positions[ix[t + 2]];
        if (glm::cross(b - a, c - a) == Vec3(0.f)) continue;
        ix[kept] = ix[t];
        ix[kept + 1] = ix[t + 1];
        ix[kept + 2] = ix[t + 2];
        kept += 3;
    }
    const std::size_t dropped = (ix.size() - kept) / 3;
    if (dropped == 0) return;
    ix.resize(kept);
    m_degenerate += dropped;
    std::string w = shape_place(index) + ": dropped " + std::to_string(dropped) +
                    " zero-area triangle" + (dropped == 1 ? "" : "s");
    if (kept == 0) fail(shape_place(index), "mesh has no triangles with non-zero area");
    m_builder.warnings().push_back(std::move(w));
}

// Counts triangles against the limit before they are generated.
void Builder::reserve_triangles(std::uint64_t n, const std::string& ptr) {
    m_triangles += n;
    if (n > m_limits.max_triangles || m_triangles > m_limits.max_triangles) {
        fail(ptr, "the scene exceeds the limit of " + std::to_string(m_limits.max_triangles) +
                      " triangles");
    }
}

}  // namespace facet::render::detail
