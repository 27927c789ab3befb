// Private to facet_render: the geometry a Scene holds, shared by the loader (which fills it)
// and embree_scene.cpp (which hands it to Embree). No Embree type here: the backend is opaque.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "facet/render/mesh.h"
#include "facet/render/scene.h"

namespace facet::render {

// A triangle mesh in world space (transform already applied).
struct MeshGeom {
    std::uint32_t shape = 0;
    std::int32_t part = -1;  // index into the shape's ShapeInfo::parts (-1: the shape itself)
    TriangleMesh mesh;       // positions and indices are moved into Embree's buffers by build()
    Vec3 tangent{0.f};       // dpdu hint for every hit (0 = none)
    // Error bound of the hit points along the normal (embree_scene.cpp: triangle_normal_error);
    // SurfaceHit::p_err = rounding_error(p) + normal_err |ng|.
    float normal_err = 0.f;
    // Per triangle: unit geometric normal (xyz) and plane offset w = dot(n, p0). A hit reads one
    // 16-byte record instead of an index triple and three vertices (Embree's BVH leaves hold
    // their own vertex copies, so the mesh arrays are cold when a hit is filled).
    std::vector<glm::vec4> planes;
    // Meshes with vertex normals: the plane and the triangle's three vertex normals in one
    // 64-byte line (`records`, `planes` then empty), so that a hit on a large smooth mesh costs
    // one cache miss instead of four dependent ones (plane, index triple, then three normals):
    // on big_mesh (1.08 M smooth triangles) those misses were a quarter of the render's time.
    struct alignas(64) SmoothRecord {
        glm::vec4 plane;
        Vec3 n[3];
    };
    std::vector<SmoothRecord> records;
    // Texture coordinates, only for shapes that need them (ShapeInfo::needs_uv): per triangle
    // the uv of its three vertices (hit uv = (1 - u - v) uv0 + u uv1 + v uv2 with Embree's
    // barycentrics), or, for the icosphere, from the direction of the hit point in the shape's
    // object space (`spherical`, `to_object`: world -> the unit sphere's frame).
    std::vector<std::array<Vec2, 3>> tri_uvs;
    // With tri_uvs: per triangle dp/du and dp/dv (SurfaceHit::dpdu_uv, dpdv_uv).
    std::vector<std::array<Vec3, 2>> tri_dpduv;
    bool spherical = false;
    // Vertex colours, only for surfaces that read them (ShapeInfo::needs_color): per triangle
    // its corners' linear RGBA (hit colour = (1 - u - v) c0 + u c1 + v c2).
    std::vector<std::array<glm::vec4, 3>> tri_colors;
    Opacity opacity;  // active: cut-outs decided per candidate hit (an Embree filter function)
    glm::dmat4 to_object{1.0};
    // The UV map's tangents, only for shapes that need them (ShapeInfo::needs_tangent): per
    // triangle, its corners' world tangents (xyz) and bitangent signs (w, with the transform's
    // and flip_normals' handedness folded in), interpolated like the uvs; for the icosphere
    // (`spherical`) the analytic dp/du of its UVs, from the hit point, with `tangent_sign`.
    std::vector<std::array<glm::vec4, 3>> tri_tangents;
    float tangent_sign = 0.f;         // icosphere: non-zero when tangents are needed
    glm::dmat3 sphere_to_world{1.0};  // icosphere: linear part of to_object's inverse
    // Deformation motion (ShapeDesc::motion_positions): the vertex positions, and for a smooth
    // mesh the unit vertex normals, at each of >= 2 uniform time steps (motion.h), in the
    // mesh's frame; Embree gets one vertex buffer per step, and `mesh.indices` stay for the
    // hits, which interpolate the triangle at the ray's time (embree_scene.cpp,
    // fill_deformed). `planes` and `records` are the still mesh's. Empty: a still mesh.
    std::vector<std::vector<Vec3>> step_positions;
    std::vector<std::vector<Vec3>> step_normals;
    const glm::vec4& plane(std::size_t tri) const {
        return records.empty() ? planes[tri] : records[tri].plane;
    }
};

// An exact analytic primitive defined in object space: the unit sphere at the origin, or the
// unit disc in the z = 0 plane facing +z. Kept in double: rays are transformed into object
// space and solved there, so the hit is exact to double round-off.
struct AnalyticPrim {
    enum class Kind : std::uint8_t { Sphere, Disc } kind = Kind::Sphere;
    std::uint32_t shape = 0;
    bool flip = false;  // "flip_normals": the geometric normal points inward
    glm::dmat4 to_world{1.0};
    glm::dmat4 to_object{1.0};
    glm::dmat3 normal_to_world{1.0};  // inverse transpose of to_world's linear part
    // Error of the double hit point, added to its rounding in SurfaceHit::p_err (set by build).
    float err_floor = 0.f;
    bool uv = false;  // compute SurfaceHit::uv (ShapeInfo::needs_uv)
    Opacity opacity;  // active: cut-outs decided per root
    // Non-zero (ShapeInfo::needs_tangent): hits get the unit dpdu and this bitangent sign,
    // -1 when flip_normals or a mirroring transform reverses cross(n, dp/du) against dp/dv.
    float tangent_sign = 0.f;
};

// Texture coordinates of a point on the unit sphere (object space): u = longitude / 2 pi
// counter-clockwise about +z from +x, in [0, 1); v = 0 at the -z pole, 1 at the +z pole.
inline Vec2 sphere_uv(const glm::dvec3& p) {
    constexpr double kPi = 3.14159265358979323846;
    double u = std::atan2(p.y, p.x) / (2.0 * kPi);
    if (u < 0.0) u += 1.0;
    const double z = std::clamp(p.z / glm::length(p), -1.0, 1.0);
    return {float(u), float(std::acos(-z) / kPi)};
}

// dp/du and dp/dv (object space) of the map sphere_uv at point p of the unit sphere
// (scene.h: SurfaceHit conventions); at the poles (rho = 0) dp/dv is taken along longitude 0.
inline void sphere_uv_derivatives(const glm::dvec3& p, glm::dvec3& dpdu, glm::dvec3& dpdv) {
    constexpr double kPi = 3.14159265358979323846;
    const double rho = std::sqrt(p.x * p.x + p.y * p.y);
    dpdu = 2.0 * kPi * glm::dvec3(-p.y, p.x, 0.0);
    dpdv = rho > 0.0 ? kPi * glm::dvec3(-p.z * p.x / rho, -p.z * p.y / rho, rho)
                     : kPi * glm::dvec3(-p.z, 0.0, 0.0);
}

// dp/du and dp/dv of a triangle with positions p and texture coordinates uv (pbrt-v4 eq. 6.7),
// or zero vectors when its uvs are degenerate (collinear).
inline std::array<Vec3, 2> triangle_uv_derivatives(const std::array<glm::dvec3, 3>& p,
                                                   const std::array<Vec2, 3>& uv) {
    const glm::dvec2 d02 = glm::dvec2(uv[0]) - glm::dvec2(uv[2]);
    const glm::dvec2 d12 = glm::dvec2(uv[1]) - glm::dvec2(uv[2]);
    const glm::dvec3 dp02 = p[0] - p[2], dp12 = p[1] - p[2];
    const double det = d02.x * d12.y - d02.y * d12.x;
    if (!(std::fabs(det) > 0.0)) return {Vec3(0.f), Vec3(0.f)};
    const glm::dvec3 dpdu = (d12.y * dp02 - d02.y * dp12) / det;
    const glm::dvec3 dpdv = (d02.x * dp12 - d12.x * dp02) / det;
    if (!is_finite(Vec3(dpdu)) || !is_finite(Vec3(dpdv))) return {Vec3(0.f), Vec3(0.f)};
    return {Vec3(dpdu), Vec3(dpdv)};
}

// An infinite plane through `point` with unit normal `normal` (world space).
struct PlaneGeom {
    std::uint32_t shape = 0;
    glm::dvec3 point{0.0};
    glm::dvec3 normal{0.0, 0.0, 1.0};
    Vec3 tangent{1.f, 0.f, 0.f};
    // Texture coordinates (only when `uv`): u = dot(p - point, ex), v = dot(p - point, ey).
    bool uv = false;
    glm::dvec3 ex{1.0, 0.0, 0.0}, ey{0.0, 1.0, 0.0};
    Opacity opacity;           // active: cut-outs decided per hit
    float tangent_sign = 1.f;  // -1 with flip_normals (ey = cross(unflipped normal, ex))
};

// A curves shape (shapes/curves.cpp) as one Embree curve geometry: its strands' segments, in
// world space (a prototype's: in the prototype's frame). A hit (embree_scene.cpp, fill_curve)
// evaluates the segment's basis at Embree's curve parameter in double for the axis point,
// radius and tangent, and reads the strand's data below.
struct CurveGeom {
    enum class Basis : std::uint8_t { Linear, BSpline, CatmullRom };
    std::uint32_t shape = 0;
    Basis basis = Basis::Linear;
    bool flat = false;  // ribbons facing the ray (else round tubes)
    // Control points (xyz) and radii (w), and each segment's first control point, handed to
    // Embree's buffers by build(); hits then read Embree's copies (`vertex`, `segment`).
    std::vector<glm::vec4> vertices;
    std::vector<std::uint32_t> segments;
    const glm::vec4* vertex = nullptr;
    const std::uint32_t* segment = nullptr;
    // Per segment its strand; per strand its first segment (one more: the end).
    std::vector<std::uint32_t> segment_strand;
    std::vector<std::uint32_t> strand_first;
    std::vector<Vec2> root_uvs;  // per strand, only when the surface needs uv
    // Per strand its random value (curve_random), only when the surface's textures read it
    // (ShapeInfo::needs_strand).
    std::vector<float> strand_random;
    // Flat curves: per segment its largest control radius (the self-hit filter:
    // embree_scene.cpp, curve_filter).
    std::vector<float> segment_radius;
    float max_coord = 0.f;  // largest coordinate magnitude of the control points (error bound)
    // Deformation motion (ShapeDesc::motion_positions): the control points and radii at each of
    // >= 2 uniform time steps (motion.h), handed to Embree as one vertex buffer per step (it
    // interpolates them linearly at the ray's time; `vertices` is then unused); hits read
    // Embree's copies (`step_vertex`) at the ray's time. Empty: the curves are still.
    std::vector<std::vector<glm::vec4>> step_vertices;
    std::vector<const glm::vec4*> step_vertex;
};

// A prototype (SceneDescription::prototypes): its triangle meshes in its own object space,
// traced as one Embree scene that every instance of it shares (a two-level BVH).
struct PrototypeGeom {
    std::vector<MeshGeom> meshes;
    std::vector<CurveGeom> curves;
    Bounds3 bounds;  // object-space extent of its meshes
};

// One placement of a prototype. Hits are computed in the prototype's object space with the ray
// brought there (to_object), then taken to world: points by to_world, normals by the inverse
// transpose of its linear part (normal_to_world), tangents and uv derivatives by the linear
// part; the bitangent sign times `handedness` (-1 when to_world mirrors).
struct InstanceGeom {
    std::uint32_t prototype = 0;  // index into Impl::prototypes
    glm::dmat4 to_world{1.0};
    glm::dmat4 to_object{1.0};
    glm::dmat3 normal_to_world{1.0};
    glm::dmat3 abs_linear{1.0};  // |to_world's linear part| per entry (error boxes to world)
    // Infinity norms of the linear parts of to_world and to_object, and the largest magnitudes
    // of their translations (the hit's error box: embree_scene.cpp, fill_instance).
    double linear_norm = 1.0, inverse_norm = 1.0, offset = 0.0, inverse_offset = 0.0;
    float handedness = 1.f;
    // A moving instance (motion.h): its transform per motion step, decomposed (empty: static).
    // The fields above are then those of the first step; a hit recomputes them at its ray's
    // time (placed_at).
    std::vector<DecomposedTransform> motion;
    // Its prototype holds a deforming mesh (MeshGeom::step_positions): hits are filled at the
    // ray's time.
    bool deforms = false;

    // Sets the transform and every field derived from it (M: affine, invertible).
    void place(const glm::dmat4& m) {
        to_world = m;
        to_object = glm::inverse(m);
        const glm::dmat3 lin(m), inv(to_object);
        normal_to_world = glm::transpose(inv);
        handedness = glm::determinant(lin) < 0.0 ? -1.f : 1.f;
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) abs_linear[c][r] = std::fabs(lin[c][r]);
        auto norm = [](const glm::dmat3& a) {  // infinity norm: the largest row sum of |a|
            double best = 0.0;
            for (int r = 0; r < 3; ++r)
                best = std::max(best, std::fabs(a[0][r]) + std::fabs(a[1][r]) + std::fabs(a[2][r]));
            return best;
        };
        linear_norm = norm(lin);
        inverse_norm = norm(inv);
        offset = largest_magnitude(glm::dvec3(m[3]));
        inverse_offset = largest_magnitude(glm::dvec3(to_object[3]));
    }
};

struct EmbreeBackend;  // embree_scene.cpp

struct Scene::Impl {
    Impl();
    ~Impl();
    std::vector<MeshGeom> meshes;
    std::vector<AnalyticPrim> prims;
    std::vector<PlaneGeom> planes;
    std::vector<CurveGeom> curves;
    bool plane_cutouts = false;  // some plane has an opacity (set by build)
    // Some shape's hits compute the object-space point (ShapeInfo::needs_position): the
    // closest-hit path then fills surface extras (set by the scene builder before build).
    bool position_extras = false;
    // Per shape (empty: none): a prototype's shape whose instanced hits keep the shading normal
    // in SurfaceHit::po (ShapeInfo::normal_in_po; set by the scene builder).
    std::vector<std::uint8_t> normal_in_po;
    std::vector<PrototypeGeom> prototypes;
    std::vector<InstanceGeom> instances;
    std::unique_ptr<EmbreeBackend> backend;

    // Builds the Embree scene from meshes and prims. Throws SceneError("<name>: embree: ...").
    void build(const std::string& name);
    // The prototypes' Embree scenes and the instances in the top scene (build's last step).
    void build_instances(const std::string& name);
    // Fills `hit` (except material/emission fields) for a closest hit found by the backend.
    void fill_analytic(const AnalyticPrim& prim, const Ray& ray, float t, SurfaceHit& hit) const;
    // A hit inside instance `inst` (Impl::instances) on its prototype's Embree geometry `geom`.
    template <bool kUv>
    void fill_instance(const InstanceGeom& inst, std::uint32_t geom, std::uint32_t tri,
                       const Ray& ray, float time, float u, float v, float t, SurfaceHit& hit,
                       std::int32_t& part) const;
    // kWorld: `ray` is the world ray (the smooth normal is bent for it: SurfaceHit::ns);
    // false inside an instance, whose caller bends it once in world space.
    template <bool kUv, bool kWorld>
    void fill_triangle(const MeshGeom& mesh, std::uint32_t tri, const Ray& ray, float u, float v,
                       float t, SurfaceHit& hit) const;
};

// The loader's access to a Scene's private members.
struct Scene::Builder {
    Scene scene;
    std::string& name() { return scene.m_name; }
    std::uint64_t& fingerprint() { return scene.m_fingerprint; }
    std::vector<std::string>& warnings() { return scene.m_warnings; }
    Camera& camera() { return scene.m_camera; }
    CameraMotion& camera_motion() { return scene.m_camera_motion; }
    ShutterCurve& shutter() { return scene.m_shutter; }
    RenderSettings& settings() { return scene.m_settings; }
    SceneFeatures& features() { return scene.m_features; }
    std::vector<std::shared_ptr<Material>>& materials() { return scene.m_materials; }
    std::vector<std::unique_ptr<Texture>>& textures() { return scene.m_textures; }
    std::vector<TexturedMaterial>& textured() { return scene.m_textured; }
    TextureMemoryStats& texture_memory() { return scene.m_texture_memory; }
    std::shared_ptr<const TileCache>& tile_cache() { return scene.m_tile_cache; }
    std::vector<ShapeInfo>& shapes() { return scene.m_shapes; }
    std::vector<Light>& lights() { return scene.m_lights; }
    LightDistribution& light_distribution() { return scene.m_light_distribution; }
    LightDistribution& view_light_distribution() { return scene.m_view_light_distribution; }
    std::int32_t& environment() { return scene.m_environment; }
    std::vector<Medium>& media() { return scene.m_media; }
    std::int32_t& world_medium() { return scene.m_world_medium; }
    std::vector<MediumInterface>& interfaces() { return scene.m_interfaces; }
    std::vector<LightPathSwitch>& light_paths() { return scene.m_light_paths; }
    std::vector<std::uint8_t>& light_visibility() { return scene.m_light_visibility; }
    std::vector<std::uint32_t>& camera_lamps() { return scene.m_camera_lamps; }
    Bounds3& bounds() { return scene.m_bounds; }
    Impl& impl() { return *scene.m_impl; }
};

}  // namespace facet::render
