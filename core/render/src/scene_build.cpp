// build_scene: SceneDescription -> Scene (facet/render/scene_description.h), with every value
// validated, and the scene analysis (SceneFeatures). Every error is a SceneError
// "<name>: <path>: <message>" with the JSON pointer the value would have in a scene file.
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "facet/frame.h"
#include "facet/render/scene_description.h"
#include "scene_checks.h"
#include "scene_impl.h"
#include "scene_precision.h"

namespace facet::render {

using detail::escape_pointer_token;

MeshData MeshData::copy_of(std::vector<float> positions, std::vector<std::uint32_t> indices,
                           std::vector<float> normals) {
    struct Arrays {
        std::vector<float> p;
        std::vector<std::uint32_t> i;
        std::vector<float> n;
    };
    auto a = std::make_shared<Arrays>(
        Arrays{std::move(positions), std::move(indices), std::move(normals)});
    MeshData m;
    m.positions = a->p;
    m.indices = a->i;
    m.normals = a->n;
    m.owner = a;
    return m;
}

bool MeshData::operator==(const MeshData& o) const {
    auto same = [](auto a, auto b) {
        return a.size() == b.size() &&
               (a.empty() || std::memcmp(a.data(), b.data(), a.size_bytes()) == 0);
    };
    return same(positions, o.positions) && same(indices, o.indices) && same(normals, o.normals);
}

bool SceneDescription::operator==(const SceneDescription& o) const {
    return description == o.description && camera == o.camera && materials == o.materials &&
           shapes == o.shapes && lights == o.lights && render.integrator == o.render.integrator &&
           render.spp == o.render.spp && render.time_budget_s == o.render.time_budget_s &&
           render.max_depth == o.render.max_depth && render.seed == o.render.seed;
}

namespace {

// Largest |component| of a vector, in double.
double max_abs(const glm::dvec3& v) {
    return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
}

class Builder {
  public:
    Builder(const SceneDescription& desc, std::string name, const SceneLimits& limits,
            BuildReport* report)
        : m_desc(desc), m_name(std::move(name)), m_limits(limits), m_report(report) {}

    Scene build() {
        const auto t0 = std::chrono::steady_clock::now();
        m_builder.name() = m_name;
        m_builder.fingerprint() = fingerprint(m_desc);
        build_camera();
        build_materials();
        for (std::size_t i = 0; i < m_desc.shapes.size(); ++i) {
            build_shape(m_desc.shapes[i], std::uint32_t(i));
        }
        for (std::size_t i = 0; i < m_desc.lights.size(); ++i) {
            build_light(m_desc.lights[i], "/lights/" + std::to_string(i));
        }
        if (m_builder.lights().empty()) {
            fail("/lights",
                 "the scene has no light source (no entry in \"lights\" and no shape with "
                 "\"emission\")");
        }
        check_precision(m_builder, m_desc, m_name);  // scene_precision.h
        build_render();
        const auto t1 = std::chrono::steady_clock::now();
        m_builder.impl().build(m_name);
        const auto t2 = std::chrono::steady_clock::now();
        analyse();
        m_builder.light_distribution() =
            LightDistribution(m_builder.scene.lights(), m_builder.scene.radius());
        if (m_report) {
            m_report->degenerate_triangles = m_degenerate;
            m_report->warnings = m_builder.warnings();
            m_report->seconds_before_bvh = std::chrono::duration<double>(t1 - t0).count();
            m_report->seconds_bvh = std::chrono::duration<double>(t2 - t1).count();
        }
        return std::move(m_builder.scene);
    }

  private:
    [[noreturn]] void fail(const std::string& pointer, const std::string& message) const {
        throw SceneError(m_name + ": " + (pointer.empty() ? std::string("/") : pointer) + ": " +
                         message);
    }

    // --- value checks --------------------------------------------------------------------------

    void check_finite(const Vec3& v, const std::string& ptr) const {
        for (int i = 0; i < 3; ++i) {
            if (!std::isfinite(v[i]))
                fail(ptr + "/" + std::to_string(i), "must be a finite number");
        }
    }
    void check_finite(double d, const std::string& ptr) const {
        if (!std::isfinite(d)) fail(ptr, "must be a finite number");
    }
    double check_range(double d, const std::string& ptr, double lo, double hi,
                       const char* range_text) const {
        check_finite(d, ptr);
        if (!(d >= lo && d <= hi)) fail(ptr, detail::number_range_message(d, range_text));
        return d;
    }
    std::int64_t check_int(std::int64_t i, const std::string& ptr, std::int64_t lo,
                           std::int64_t hi) const {
        if (i < lo || i > hi) fail(ptr, detail::int_range_message(i, lo, hi));
        return i;
    }
    Vec3 unit_direction(const Vec3& d, const std::string& ptr) const {
        check_finite(d, ptr);
        float len = glm::length(d);
        if (!(len > 0.f) || !std::isfinite(len)) fail(ptr, "must be a non-zero direction");
        return d / len;
    }
    Rgb check_color(const Rgb& c, const std::string& ptr, const char* what) const {
        if (!is_finite(c)) fail(ptr, std::string(what) + " must be finite");
        for (int i = 0; i < 3; ++i) {
            if (c[i] < 0.f) fail(ptr, std::string(what) + " must be >= 0");
        }
        return c;
    }
    // "/shapes/3" or "/shapes/3 ('Suzanne')" for messages about a shape as a whole.
    std::string shape_place(std::uint32_t index) const {
        const std::string& n = m_desc.shapes[index].name;
        return "/shapes/" + std::to_string(index) + (n.empty() ? "" : " ('" + n + "')");
    }

    // --- camera, render ------------------------------------------------------------------------

    void build_camera() {
        const CameraDesc& c = m_desc.camera;
        const std::string ptr = "/camera";
        check_finite(c.position, ptr + "/position");
        check_finite(c.look_at, ptr + "/look_at");
        check_finite(c.up, ptr + "/up");
        double fov = check_range(c.fov, ptr + "/fov", 1e-3, 179.0,
                                 "in [0.001, 179] degrees (full vertical angle)");
        int w = int(check_int(c.width, ptr + "/width", 1, detail::kMaxImageSide));
        int h = int(check_int(c.height, ptr + "/height", 1, detail::kMaxImageSide));
        for (const char* key : {"position", "look_at"}) {
            const Vec3& v = key[0] == 'p' ? c.position : c.look_at;
            if (max_abs(glm::dvec3(v)) > Scene::kMaxCoordinate) {
                std::ostringstream msg;
                msg << "beyond the renderer's coordinate range of +-" << Scene::kMaxCoordinate;
                fail(ptr + "/" + key, msg.str());
            }
        }
        m_max_coordinate = max_abs(glm::dvec3(c.position));
        if (std::int64_t(w) * h > m_limits.max_pixels) {
            fail(ptr, "the image has too many pixels (limit " +
                          std::to_string(m_limits.max_pixels) + ")");
        }
        glm::dvec3 f = glm::dvec3(c.look_at) - glm::dvec3(c.position);
        double flen = glm::length(f);
        if (!(flen > 0.0)) fail(ptr + "/look_at", "must differ from the camera position");
        glm::dvec3 cr = glm::cross(f / flen, glm::dvec3(c.up));
        if (!(glm::length(cr) > 1e-6 * glm::length(glm::dvec3(c.up)))) {
            fail(ptr + "/up", "must not be zero or parallel to the view direction");
        }
        m_builder.camera() = Camera::make(c.position, c.look_at, c.up, float(fov), w, h);
    }

    void build_render() {
        const RenderSettings& r = m_desc.render;
        const std::string ptr = "/render";
        RenderSettings& s = m_builder.settings();
        const std::vector<std::string> known = {"direct", "path"};
        if (std::find(known.begin(), known.end(), r.integrator) == known.end()) {
            std::string msg = "unknown integrator '" + r.integrator + "'";
            std::string g = closest_name(r.integrator, known);
            msg += g.empty() ? " (expected direct or path)" : " (did you mean '" + g + "'?)";
            fail(ptr + "/integrator", msg);
        }
        s.integrator = r.integrator;
        s.spp = int(check_int(r.spp, ptr + "/spp", 1, detail::kMaxSpp));
        s.time_budget_s =
            check_range(r.time_budget_s, ptr + "/time_budget", 0.0, 1e7, "in [0, 1e7] seconds");
        s.max_depth = int(check_int(r.max_depth, ptr + "/max_depth", 0, detail::kMaxDepth));
        s.seed = r.seed;
        s.width = m_builder.camera().width;
        s.height = m_builder.camera().height;
    }

    // --- materials -----------------------------------------------------------------------------

    // Builds a material; parameter errors from the registry name the parameter, which becomes
    // part of the pointer.
    const Material* build_material(const MaterialDesc& m, const std::string& ptr) {
        if (!find_model(m.model)) {
            std::vector<std::string> names;
            for (const auto& mi : model_table()) names.push_back(mi.name);
            std::string msg = "unknown model '" + m.model + "'";
            std::string g = closest_name(m.model, names);
            if (!g.empty()) {
                msg += " (did you mean '" + g + "'?)";
            } else {
                msg += " (expected one of:";
                for (const auto& n : names) msg += " " + n;
                msg += ")";
            }
            fail(ptr + "/model", msg);
        }
        for (const auto& [key, v] : m.params.values()) {
            const std::string p = ptr + "/" + escape_pointer_token(key);
            if (const double* d = std::get_if<double>(&v)) check_finite(*d, p);
            if (const Rgb* c = std::get_if<Rgb>(&v)) check_finite(*c, p);
        }
        try {
            m_builder.materials().push_back(
                std::make_unique<Material>(make_material(m.model, m.params)));
        } catch (const ParamError& e) {
            fail(e.param().empty() ? ptr + "/model" : ptr + "/" + escape_pointer_token(e.param()),
                 e.what());
        }
        return m_builder.materials().back().get();
    }

    void build_materials() {
        for (const auto& [name, m] : m_desc.materials) {
            const std::string ptr = "/materials/" + escape_pointer_token(name);
            if (m_named.count(name)) fail(ptr, "duplicate material name '" + name + "'");
            m_named[name] = build_material(m, ptr);
        }
    }

    const Material* black_material() {
        if (!m_black) {
            m_builder.materials().push_back(
                std::make_unique<Material>(std::nullopt, std::nullopt, std::nullopt));
            m_black = m_builder.materials().back().get();
        }
        return m_black;
    }

    // --- shapes --------------------------------------------------------------------------------

    void build_shape(const ShapeDesc& s, std::uint32_t index) {
        const std::string ptr = "/shapes/" + std::to_string(index);
        const ShapeKind kind = s.kind;
        if (kind > ShapeKind::Grid) fail(ptr + "/type", "unknown shape type");

        ShapeInfo info;
        info.kind = kind;
        info.two_sided = s.two_sided;
        const bool flip_normals = s.flip_normals;
        info.emission = check_color(s.emission, ptr + "/emission", "an emitted radiance");
        const bool emissive = max_component(info.emission) > 0.f;
        if (s.material) {
            if (!s.material_ref.empty()) {
                fail(ptr + "/material",
                     "give either a material name or an inline material, not both");
            }
            info.material = build_material(*s.material, ptr + "/material");
            info.material_name = "<inline>";
        } else if (!s.material_ref.empty()) {
            const std::string& name = s.material_ref;
            auto found = m_named.find(name);
            if (found == m_named.end()) {
                std::vector<std::string> names;
                for (const auto& [n, _] : m_named) names.push_back(n);
                std::string msg = "unknown material '" + name + "'";
                std::string g = closest_name(name, names);
                if (!g.empty()) {
                    msg += " (did you mean '" + g + "'?)";
                } else if (names.empty()) {
                    msg += " (the scene defines no \"materials\")";
                }
                fail(ptr + "/material", msg);
            }
            info.material = found->second;
            info.material_name = name;
        } else if (emissive) {
            info.material = black_material();
            info.material_name = "<black>";
        } else {
            fail(ptr, "missing required key 'material' (only emissive shapes may omit it)");
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
        glm::dmat3 lin(xf);
        glm::dmat3 normal_mat = glm::transpose(glm::inverse(lin));
        auto to_world = [&](const glm::dvec3& p) { return glm::dvec3(xf * glm::dvec4(p, 1.0)); };

        Scene::Impl& impl = m_builder.impl();
        std::vector<Light>& lights = m_builder.lights();
        Bounds3 bounds;
        auto grow = [&](const glm::dvec3& p) {
            bounds.lo = glm::min(bounds.lo, Vec3(p));
            bounds.hi = glm::max(bounds.hi, Vec3(p));
        };
        auto add_prim = [&](AnalyticPrim::Kind k, const glm::dmat4& local) {
            AnalyticPrim prim;
            prim.kind = k;
            prim.shape = index;
            prim.flip = flip_normals;
            prim.to_world = xf * local;
            prim.to_object = glm::inverse(prim.to_world);
            prim.normal_to_world = glm::transpose(glm::inverse(glm::dmat3(prim.to_world)));
            double zr = k == AnalyticPrim::Kind::Sphere ? 1.0 : 0.0;
            for (int i = 0; i < 8; ++i) {
                glm::dvec3 c(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? zr : -zr);
                grow(glm::dvec3(prim.to_world * glm::dvec4(c, 1.0)));
            }
            impl.prims.push_back(prim);
            return impl.prims.back();
        };
        auto check_finite_bounds = [&]() {
            if (!is_finite(bounds.lo) || !is_finite(bounds.hi)) {
                fail(ptr, "the shape's extent overflows float (transform or size too large)");
            }
        };
        auto radius = [&]() {
            double r = check_range(s.radius, ptr + "/radius", 0.0,
                                   std::numeric_limits<float>::max(), "> 0");
            if (!(r > 0.0)) fail(ptr + "/radius", "must be > 0");
            return r;
        };

        TriangleMesh mesh;
        bool is_mesh = false;
        Vec3 tangent(0.f);
        switch (kind) {
            case ShapeKind::Sphere:
            case ShapeKind::Disc: {
                check_finite(s.center, ptr + "/center");
                const Vec3 c = s.center;
                const double r = radius();
                glm::dmat4 local = glm::translate(glm::dmat4(1.0), glm::dvec3(c));
                if (kind == ShapeKind::Disc) {
                    Vec3 n = unit_direction(s.normal, ptr + "/normal");
                    Frame f = Frame::from_z(n);
                    glm::dmat4 rot(1.0);
                    rot[0] = glm::dvec4(glm::dvec3(f.x), 0.0);
                    rot[1] = glm::dvec4(glm::dvec3(f.y), 0.0);
                    rot[2] = glm::dvec4(glm::dvec3(f.z), 0.0);
                    local = local * rot;
                }
                local = glm::scale(local, glm::dvec3(r));
                const AnalyticPrim& prim =
                    add_prim(kind == ShapeKind::Sphere ? AnalyticPrim::Kind::Sphere
                                                       : AnalyticPrim::Kind::Disc,
                             local);
                check_finite_bounds();
                if (emissive) {
                    glm::dmat3 L(prim.to_world);
                    Vec3 center(glm::dvec3(prim.to_world[3]));
                    if (kind == ShapeKind::Disc) {
                        info.light = std::int32_t(lights.size());
                        // cross(L e1, L e2) = det(L) L^-T z: swap the axes when that disagrees
                        // with the hit normal (mirroring transform XOR flip_normals).
                        bool swap = (glm::determinant(L) < 0.0) != flip_normals;
                        Vec3 e1(L[0]), e2(L[1]);
                        if (swap) std::swap(e1, e2);
                        lights.push_back(Light::area_disc(center, e1, e2, info.emission, index));
                    } else {
                        // Light sampling needs a true sphere: the transform must be a similarity.
                        double s2 = glm::dot(L[0], L[0]);
                        glm::dmat3 g = glm::transpose(L) * L;
                        for (int a = 0; a < 3; ++a) {
                            for (int b = 0; b < 3; ++b) {
                                if (std::fabs(g[a][b] - (a == b ? s2 : 0.0)) > 1e-6 * s2) {
                                    fail(ptr + "/emission",
                                         "an emissive sphere cannot be non-uniformly scaled or "
                                         "sheared (use an icosphere for an emissive ellipsoid)");
                                }
                            }
                        }
                        info.light = std::int32_t(lights.size());
                        lights.push_back(Light::area_sphere(center, float(std::sqrt(s2)),
                                                            info.emission, index, flip_normals));
                    }
                }
                break;
            }
            case ShapeKind::Plane: {
                if (emissive) {
                    fail(ptr + "/emission",
                         "an infinite plane cannot emit (infinite power); use "
                         "a quad or a disc");
                }
                check_finite(s.point, ptr + "/point");
                Vec3 n = unit_direction(s.normal, ptr + "/normal");
                PlaneGeom pl;
                pl.shape = index;
                pl.point = to_world(glm::dvec3(s.point));
                pl.normal = glm::normalize(normal_mat * glm::dvec3(n));
                if (flip_normals) pl.normal = -pl.normal;
                pl.tangent = Vec3(glm::normalize(lin * glm::dvec3(Frame::from_z(n).x)));
                if (!is_finite(Vec3(pl.point)) || !is_finite(Vec3(pl.normal))) {
                    fail(ptr, "the transformed plane is not finite");
                }
                check_coordinate_range(max_abs(pl.point), index);
                m_max_coordinate = std::max(m_max_coordinate, max_abs(pl.point));
                impl.planes.push_back(pl);
                break;
            }
            case ShapeKind::Box: {
                check_finite(s.min, ptr + "/min");
                check_finite(s.max, ptr + "/max");
                const Vec3 lo = s.min, hi = s.max;
                if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) {
                    fail(ptr + "/max", "must be greater than \"min\" on every axis");
                }
                mesh = make_box(lo, hi);
                tangent = Vec3(1.f, 0.f, 0.f);
                is_mesh = true;
                break;
            }
            case ShapeKind::Quad: {
                const std::array<Vec3, 4>& p = s.vertices;
                for (std::size_t i = 0; i < 4; ++i) {
                    check_finite(p[i], ptr + "/vertices/" + std::to_string(i));
                }
                mesh = make_quad(p);
                if (glm::length(glm::cross(p[1] - p[0], p[2] - p[0])) == 0.f ||
                    glm::length(glm::cross(p[2] - p[0], p[3] - p[0])) == 0.f) {
                    fail(ptr + "/vertices", "the quad is degenerate (collinear vertices)");
                }
                tangent = p[1] - p[0];
                is_mesh = true;
                break;
            }
            case ShapeKind::Mesh:
                mesh = mesh_of(s, index, ptr);
                reserve_triangles(mesh.num_triangles(), ptr);
                is_mesh = true;
                break;
            case ShapeKind::Icosphere: {
                check_finite(s.center, ptr + "/center");
                const double r = radius();
                int sub = int(check_int(s.subdivisions, ptr + "/subdivisions", 0,
                                        detail::kMaxIcosphereSubdivisions));
                reserve_triangles(20ull << (2 * sub), ptr + "/subdivisions");
                mesh = make_icosphere(sub, s.smooth);
                for (Vec3& p : mesh.positions) p = s.center + float(r) * p;
                is_mesh = true;
                break;
            }
            case ShapeKind::Grid: {
                std::int64_t nx = check_int(s.nx, ptr + "/nx", 1, detail::kMaxGridSide);
                std::int64_t ny = check_int(s.ny, ptr + "/ny", 1, detail::kMaxGridSide);
                if (nx * ny > detail::kMaxGridCells) {
                    fail(ptr, "grid too large: nx * ny must be <= " +
                                  std::to_string(detail::kMaxGridCells));
                }
                double amp =
                    check_range(s.amplitude, ptr + "/amplitude", -1e6, 1e6, "in [-1e6, 1e6]");
                double freq = check_range(s.frequency, ptr + "/frequency", 0.0, 1e6, "in [0, 1e6]");
                reserve_triangles(2ull * std::uint64_t(nx) * std::uint64_t(ny), ptr);
                mesh = make_grid(int(nx), int(ny), float(amp), float(freq));
                tangent = Vec3(1.f, 0.f, 0.f);
                is_mesh = true;
                break;
            }
        }

        if (is_mesh) {
            // A mirroring transform reverses the winding: undo it so the authored front stays
            // the front; "flip_normals" reverses it on purpose.
            bool flip = (glm::determinant(lin) < 0.0) != flip_normals;
            // Also without a transform: the identity leaves positions exact, and normals get
            // their double-precision renormalisation either way.
            for (Vec3& p : mesh.positions) {
                p = Vec3(to_world(glm::dvec3(p)));
                grow(glm::dvec3(p));
            }
            for (Vec3& n : mesh.normals) {
                glm::dvec3 w = normal_mat * glm::dvec3(n);
                double l = glm::length(w);
                n = l > 0.0 ? Vec3(w / l) : Vec3(0.f, 0.f, 1.f);
            }
            if (flip) {
                for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
                    std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
                }
            }
            check_finite_bounds();
            if (std::string err = validate_mesh(mesh); !err.empty()) fail(shape_place(index), err);
            drop_degenerate(mesh, index);
            info.triangles = mesh.num_triangles();
            if (emissive) {
                std::vector<Vec3> tri;
                tri.reserve(mesh.indices.size());
                for (std::uint32_t i : mesh.indices) tri.push_back(mesh.positions[i]);
                Light l = Light::area_triangles(std::move(tri), info.emission, index);
                if (!(l.area() > 0.f)) fail(ptr + "/emission", "the emitting shape has no area");
                info.light = std::int32_t(lights.size());
                lights.push_back(std::move(l));
            }
            MeshGeom g;
            g.shape = index;
            g.mesh = std::move(mesh);
            if (tangent != Vec3(0.f)) g.tangent = Vec3(lin * glm::dvec3(tangent));
            impl.meshes.push_back(std::move(g));
        }
        if (!bounds.empty()) {
            check_coordinate_range(std::max(max_abs(bounds.lo), max_abs(bounds.hi)), index);
            m_builder.bounds().lo = glm::min(m_builder.bounds().lo, bounds.lo);
            m_builder.bounds().hi = glm::max(m_builder.bounds().hi, bounds.hi);
        }
        m_shape_bounds.push_back(bounds);
        m_builder.shapes().push_back(info);
    }

    // Coordinates beyond Scene::kMaxCoordinate break Embree's float triangle test (scene.h).
    void check_coordinate_range(double m, std::uint32_t index) {
        if (m > Scene::kMaxCoordinate) {
            std::ostringstream msg;
            msg << "the shape reaches coordinate " << m << ", beyond the renderer's range of +-"
                << Scene::kMaxCoordinate
                << " (float ray-triangle tests overflow there); scale the scene down or move it "
                   "nearer the origin";
            fail(shape_place(index), msg.str());
        }
        m_max_coordinate = std::max(m_max_coordinate, m);
    }

    // Removes triangles whose world-space edge cross product is exactly zero (repeated or
    // collinear vertices): they have no area, Embree never hits them, and their normal would be
    // NaN. Every other triangle, slivers included, stays.
    void drop_degenerate(TriangleMesh& mesh, std::uint32_t index) {
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

    TriangleMesh mesh_of(const ShapeDesc& s, std::uint32_t index, const std::string& ptr) {
        const MeshData& md = s.mesh;
        if (!s.file.empty()) {
            if (!md.positions.empty() || !md.indices.empty() || !md.normals.empty()) {
                fail(ptr + "/file", "cannot be combined with mesh arrays (give one or the other)");
            }
            if (!m_limits.allow_files) fail(ptr + "/file", "mesh files are disabled here");
            std::filesystem::path p(s.file);
            if (p.is_relative()) p = std::filesystem::path(m_desc.base_dir) / p;
            std::string ext = p.extension().string();
            std::transform(ext.begin(), ext.end(), ext.begin(),
                           [](unsigned char c) { return char(std::tolower(c)); });
            try {
                if (ext == ".obj") return load_obj(p.string());
                if (ext == ".ply") return load_ply(p.string());
            } catch (const std::exception& e) {
                fail(ptr + "/file", e.what());
            }
            fail(ptr + "/file", "unsupported mesh file extension '" + ext + "' (use .obj or .ply)");
        }
        const std::string place = shape_place(index);
        if (md.positions.empty() || md.positions.size() % 3 != 0) {
            fail(ptr + "/positions", "expected a flat array of 3n numbers (x0, y0, z0, x1, ...)");
        }
        if (md.indices.empty() || md.indices.size() % 3 != 0) {
            fail(ptr + "/indices", "expected a flat array of 3n vertex indices");
        }
        TriangleMesh m;
        const std::size_t n = md.num_vertices();
        m.positions.resize(n);
        std::memcpy(m.positions.data(), md.positions.data(), md.positions.size_bytes());
        for (std::size_t i = 0; i < n; ++i) {
            if (!is_finite(m.positions[i])) {
                fail(place, "position " + std::to_string(i) + " is not finite");
            }
        }
        m.indices.assign(md.indices.begin(), md.indices.end());
        for (std::size_t i = 0; i < m.indices.size(); ++i) {
            if (m.indices[i] >= n) {
                fail(ptr + "/indices/" + std::to_string(i),
                     detail::int_range_message(m.indices[i], 0, std::int64_t(n) - 1));
            }
        }
        if (!md.normals.empty()) {
            if (md.normals.size() != md.positions.size()) {
                fail(ptr + "/normals", "expected one normal per position (" + std::to_string(n) +
                                           "), got " + std::to_string(md.normals.size() / 3));
            }
            m.normals.resize(n);
            std::memcpy(m.normals.data(), md.normals.data(), md.normals.size_bytes());
            for (std::size_t i = 0; i < n; ++i) {
                Vec3& v = m.normals[i];
                if (!is_finite(v)) fail(place, "normal " + std::to_string(i) + " is not finite");
                float l = glm::length(v);
                if (!(l > 0.f)) fail(ptr + "/normals", "contains a zero normal");
                v /= l;
            }
        }
        return m;
    }

    // --- lights --------------------------------------------------------------------------------

    void build_light(const LightDesc& l, const std::string& ptr) {
        std::vector<Light>& lights = m_builder.lights();
        switch (l.kind) {
            case LightKind::Point: {
                check_finite(l.position, ptr + "/position");
                Rgb phi = check_color(l.power, ptr + "/power", "a power (W)");
                lights.push_back(Light::point(l.position, phi));
                break;
            }
            case LightKind::Spot: {
                check_finite(l.position, ptr + "/position");
                const Vec3 p = l.position;
                if (l.direction.has_value() == l.look_at.has_value()) {
                    fail(ptr, "give exactly one of \"direction\" and \"look_at\"");
                }
                Vec3 dir;
                if (l.direction) {
                    dir = unit_direction(*l.direction, ptr + "/direction");
                } else {
                    check_finite(*l.look_at, ptr + "/look_at");
                    float len = glm::length(*l.look_at - p);
                    if (!(len > 0.f)) fail(ptr + "/look_at", "must differ from the position");
                    dir = (*l.look_at - p) / len;
                }
                Rgb phi = check_color(l.power, ptr + "/power", "a power (W)");
                double outer = check_range(l.outer_angle, ptr + "/outer_angle", 0.0, 180.0,
                                           "in (0, 180) degrees (half-angle)");
                if (!(outer > 0.0 && outer < 180.0)) {
                    fail(ptr + "/outer_angle", "must be in (0, 180) degrees (half-angle)");
                }
                double inner = l.inner_angle
                                   ? check_range(*l.inner_angle, ptr + "/inner_angle", 0.0, outer,
                                                 "in [0, outer_angle] degrees")
                                   : outer;
                lights.push_back(Light::spot(p, dir, phi, float(inner), float(outer)));
                break;
            }
            case LightKind::Directional: {
                if (!l.direction) fail(ptr, "missing required key 'direction'");
                Vec3 dir = unit_direction(*l.direction, ptr + "/direction");
                Rgb e = check_color(l.irradiance, ptr + "/irradiance", "an irradiance (W/m^2)");
                lights.push_back(Light::directional(dir, e));
                break;
            }
            case LightKind::Environment: {
                if (m_builder.environment() >= 0) {
                    fail(ptr, "only one environment light is allowed");
                }
                Rgb le = check_color(l.radiance, ptr + "/radiance", "a radiance");
                m_builder.environment() = std::int32_t(lights.size());
                lights.push_back(Light::environment(le));
                break;
            }
            default:
                fail(ptr + "/type", "unknown light type");
        }
    }

    // --- analysis ------------------------------------------------------------------------------

    static bool reflects(const Material& m) {
        if (m.diffuse() && max_component(m.diffuse()->rho()) > 0.f) return true;
        if (m.glossy()) return true;
        if (m.mirror() && max_component(m.mirror()->scale()) > 0.f) return true;
        return false;
    }

    // Conservative frustum test: false only when the box lies entirely outside one side of the
    // camera's view frustum (with a 1% margin).
    bool maybe_visible(const Bounds3& b) const {
        if (b.empty()) return false;
        const Camera& c = m_builder.scene.camera();
        bool all_behind = true, all_left = true, all_right = true, all_below = true,
             all_above = true;
        float tx = 1.01f * c.tan_half_x, ty = 1.01f * c.tan_half_y;
        for (int i = 0; i < 8; ++i) {
            Vec3 p(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z);
            Vec3 v = p - c.position;
            float z = glm::dot(v, c.forward), x = glm::dot(v, c.right), y = glm::dot(v, c.true_up);
            all_behind &= z <= 0.f;
            all_left &= x < -z * tx;
            all_right &= x > z * tx;
            all_below &= y < -z * ty;
            all_above &= y > z * ty;
        }
        return !(all_behind || all_left || all_right || all_below || all_above);
    }

    void analyse() {
        SceneFeatures& f = m_builder.features();
        const Scene& scene = m_builder.scene;
        f = SceneFeatures{};
        f.num_shapes = scene.shapes().size();
        f.num_materials = m_builder.materials().size();
        f.num_lights = scene.lights().size();
        f.lambert_only = !scene.shapes().empty();
        for (std::size_t i = 0; i < scene.shapes().size(); ++i) {
            const ShapeInfo& s = scene.shapes()[i];
            BxDFFlags fl = s.material->flags();
            f.lobes = f.lobes | fl;
            if (fl != BxDFFlags::Diffuse && fl != BxDFFlags::None) f.lambert_only = false;
            if (reflects(*s.material)) f.can_reflect = true;
            f.num_triangles += s.triangles;
            if (s.kind == ShapeKind::Sphere) ++f.num_spheres;
            if (s.kind == ShapeKind::Plane) ++f.num_planes;
            if (s.kind == ShapeKind::Disc) ++f.num_discs;
            if (s.light >= 0 && maybe_visible(m_shape_bounds[i])) f.emitter_visible = true;
        }
        f.has_diffuse = any(f.lobes & BxDFFlags::Diffuse);
        f.has_glossy = any(f.lobes & BxDFFlags::Glossy);
        f.has_specular = any(f.lobes & BxDFFlags::Specular);
        for (const Light& l : scene.lights()) {
            switch (l.kind()) {
                case Light::Kind::Point:
                    f.has_point = true;
                    break;
                case Light::Kind::Spot:
                    f.has_spot = true;
                    break;
                case Light::Kind::Directional:
                    f.has_directional = true;
                    break;
                case Light::Kind::Area:
                    f.has_area = true;
                    break;
                case Light::Kind::Environment:
                    f.has_environment = true;
                    f.emitter_visible = true;  // escaping camera rays see it
                    break;
            }
            if (!l.is_delta()) f.any_non_delta_light = true;
        }
        f.all_lights_delta = !f.any_non_delta_light;
    }

    // Counts triangles against the limit before they are generated.
    void reserve_triangles(std::uint64_t n, const std::string& ptr) {
        m_triangles += n;
        if (n > m_limits.max_triangles || m_triangles > m_limits.max_triangles) {
            fail(ptr, "the scene exceeds the limit of " + std::to_string(m_limits.max_triangles) +
                          " triangles");
        }
    }

    const SceneDescription& m_desc;
    std::string m_name;
    SceneLimits m_limits;
    BuildReport* m_report;
    std::uint64_t m_triangles = 0, m_degenerate = 0;
    double m_max_coordinate = 0.0;  // largest |coordinate| of the camera and the shapes
    Scene::Builder m_builder;
    std::map<std::string, const Material*> m_named;
    const Material* m_black = nullptr;
    std::vector<Bounds3> m_shape_bounds;
};

}  // namespace

std::string SceneFeatures::describe() const {
    std::ostringstream s;
    auto yn = [](bool b) { return b ? "yes" : "no"; };
    s << "geometry: " << num_shapes << " shapes (" << num_triangles << " triangles, " << num_spheres
      << " exact spheres, " << num_discs << " discs, " << num_planes << " infinite planes), "
      << num_materials << " materials\n";
    s << "lobes: diffuse " << yn(has_diffuse) << ", glossy " << yn(has_glossy) << ", specular "
      << yn(has_specular) << (lambert_only ? " (Lambert only)" : "") << "\n";
    s << "lights: " << num_lights << " (point " << yn(has_point) << ", spot " << yn(has_spot)
      << ", directional " << yn(has_directional) << ", area " << yn(has_area) << ", environment "
      << yn(has_environment) << "); all delta: " << yn(all_lights_delta) << "\n";
    s << "emitter visible to the camera: " << yn(emitter_visible)
      << "; surfaces reflect (indirect light possible): " << yn(can_reflect) << "\n";
    return s.str();
}

Scene build_scene(const SceneDescription& desc, const std::string& name, const SceneLimits& limits,
                  BuildReport* report) {
    return Builder(desc, name, limits, report).build();
}

}  // namespace facet::render
