// The only file that talks to Embree (docs/architecture.md): RAII owners for the device and the
// scene, the error callback installed right after the device is created, triangle meshes as
// Embree triangle geometry, exact spheres and discs as one Embree user geometry (their geometry,
// solved in double precision, is shapes/analytic.h's), and infinite planes tested analytically
// beside Embree (an infinite plane has no finite bounding box for Embree's BVH).
#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstring>
#include <mutex>

#include "facet/frame.h"
#include "facet/render/sampler.h"
#include "facet/render/shading_normal.h"
#include "scene_impl.h"
#include "shapes/analytic.h"

namespace facet::render {

namespace {

struct DeviceDeleter {
    void operator()(RTCDevice d) const {
        if (d) rtcReleaseDevice(d);
    }
};
struct SceneDeleter {
    void operator()(RTCScene s) const {
        if (s) rtcReleaseScene(s);
    }
};
using DevicePtr = std::unique_ptr<RTCDeviceTy, DeviceDeleter>;
using ScenePtr = std::unique_ptr<RTCSceneTy, SceneDeleter>;

}  // namespace

struct EmbreeBackend {
    DevicePtr device;
    ScenePtr scene;
    // The scene's own curves (not a prototype's), in an Embree scene of their own traced after
    // `scene` (null without curves): built without RTC_SCENE_FLAG_ROBUST, which the triangles'
    // watertightness needs (no ray may slip between two triangles sharing an edge) and curves
    // do not (no two strands share a surface), and which costs their traversal (docs/curves.md,
    // "What a hair sample costs"). The main scene then holds no filter function either (unless
    // a cut-out mesh does), so its triangles take Embree's filterless path. The curves' geometry
    // ids follow the main scene's, so that one geom_to_mesh maps both.
    ScenePtr curve_scene;
    std::vector<std::int32_t> geom_to_mesh;  // Embree geomID -> index in Impl::meshes (-1: user)
    unsigned analytic_geom = RTC_INVALID_GEOMETRY_ID;
    std::mutex error_mutex;
    std::string first_error;  // first Embree error reported through the callback
    // Whether closest-hit packets prefetch the hit records (intersect_packet): only when the
    // per-triangle records outgrow the caches. On the Cornell box (36 triangles) the prefetch
    // loop cost 1.5% of the render for nothing.
    bool prefetch_hit_records = false;
    // Whether some hit needs more than the shape's own surface: a mesh that is a part of its
    // shape (ShapeInfo::parts) or geometry with texture coordinates (which every textured
    // material or emission has). False for most scenes: their hit records then skip the part
    // and UV look-ups and the emission texture test (Scene::complete_hit<false>).
    bool surface_extras = true;
    bool surface_extras_instanced = false;  // some prototype's mesh has parts or uvs
    // Instancing (Impl::prototypes, Impl::instances): one Embree scene per prototype that has
    // instances (null otherwise), its geomID -> index in PrototypeGeom::meshes, and the top
    // scene's geomID -> index in Impl::instances (-1: not an instance).
    std::vector<ScenePtr> prototype_scenes;
    std::vector<std::vector<std::int32_t>> prototype_geom_to_mesh;
    std::vector<std::int32_t> geom_to_instance;
    // Some instance moves (InstanceGeom::motion): rays then hand Embree their time
    // (RayPacket::time, the timed single-ray queries); otherwise Embree gets time 0, as before
    // motion blur existed.
    bool has_motion = false;
};

namespace {

void embree_error(void* user, RTCError code, const char* message) {
    auto* be = static_cast<EmbreeBackend*>(user);
    std::lock_guard<std::mutex> lock(be->error_mutex);
    if (be->first_error.empty()) {
        be->first_error = "error " + std::to_string(int(code)) + ": " + (message ? message : "");
    }
}

// --- texture coordinates (scenes/FORMAT.md, "UV coordinates"), for hits and opacity tests ---

// A triangle's uv at Embree's barycentrics (u, v), or the icosphere's from point p.
Vec2 triangle_uv(const MeshGeom& mg, std::uint32_t tri, float u, float v, const glm::dvec3& p) {
    if (!mg.tri_uvs.empty()) {
        const std::array<Vec2, 3>& t = mg.tri_uvs[tri];
        return (1.f - u - v) * t[0] + u * t[1] + v * t[2];
    }
    return mg.spherical ? sphere_uv(glm::dvec3(mg.to_object * glm::dvec4(p, 1.0))) : Vec2(0.f);
}

// A plane's uv at point p (scene units along its axes). Out of line: inlined into the packet
// query (which GCC decides by the whole file's size) it costs every scene's hits there.
[[gnu::noinline]] Vec2 plane_uv(const PlaneGeom& pl, const glm::dvec3& p) {
    const glm::dvec3 d = p - pl.point;
    return Vec2(float(glm::dot(d, pl.ex)), float(glm::dot(d, pl.ey)));
}

// --- opacity (scene.h, Opacity) ----------------------------------------------------------------

// The random number u in [0, 1) that decides whether a candidate hit of a cut-out surface
// stops the ray (opacity_blocks): a hash of the ray's origin and direction (their float bits)
// and of the primitive (`a`, `b`), as pbrt-v4 hashes the ray for its alpha test
// (GeometricPrimitive::Intersect). No sampler dimension is drawn, so scenes without opacity keep
// their sample sequences, and a ray gets the same answer in a packet or alone, in any tile or
// region. Different rays (jittered film positions, other bounces) get independent numbers.
float hit_uniform(const glm::vec3& o, const glm::vec3& d, std::uint32_t a, std::uint32_t b) {
    std::uint32_t h = hash_combine(hash_u32(a), b);
    for (int i = 0; i < 3; ++i) {
        std::uint32_t bits;
        std::memcpy(&bits, &o[i], sizeof bits);
        h = hash_combine(h, bits);
        std::memcpy(&bits, &d[i], sizeof bits);
        h = hash_combine(h, bits);
    }
    return float(h >> 8) * 0x1p-24f;  // 24 bits: exactly representable, < 1
}

// Tags of the primitive classes in hit_uniform's `a` (triangles use their Embree geomID).
constexpr std::uint32_t kAnalyticTag = 0xA0000000u, kPlaneTag = 0xB0000000u;

// Embree's intersection and occlusion filter on a cut-out triangle mesh (MeshGeom::opacity):
// rejects each candidate hit that its opacity lets through.
void opacity_filter(const RTCFilterFunctionNArguments* args) {
    const auto* mg = static_cast<const MeshGeom*>(args->geometryUserPtr);
    const unsigned n = args->N;
    for (unsigned i = 0; i < n; ++i) {
        if (args->valid[i] != -1) continue;
        const glm::vec3 o(RTCRayN_org_x(args->ray, n, i), RTCRayN_org_y(args->ray, n, i),
                          RTCRayN_org_z(args->ray, n, i));
        const glm::vec3 d(RTCRayN_dir_x(args->ray, n, i), RTCRayN_dir_y(args->ray, n, i),
                          RTCRayN_dir_z(args->ray, n, i));
        const unsigned prim = RTCHitN_primID(args->hit, n, i);
        Vec2 uv(0.f);
        if (mg->opacity.texture) {
            // The candidate's distance is in tfar while the filter runs (Embree 3).
            const glm::dvec3 p =
                glm::dvec3(o) + double(RTCRayN_tfar(args->ray, n, i)) * glm::dvec3(d);
            uv = triangle_uv(*mg, prim, RTCHitN_u(args->hit, n, i), RTCHitN_v(args->hit, n, i), p);
        }
        const std::uint32_t geom = RTCHitN_geomID(args->hit, n, i);
        if (!opacity_blocks(mg->opacity.alpha(uv), hit_uniform(o, d, geom, prim)))
            args->valid[i] = 0;
    }
}

// --- curves (scene_impl.h, CurveGeom) ----------------------------------------------------------

// A curve segment at parameter u: its axis point, the axis' derivative and the radius, in
// double, by the segment's basis (Embree's: uniform cubic B-spline, Catmull-Rom, linear).
struct CurvePoint {
    glm::dvec3 c, dc;
    double r;
};

CurvePoint eval_curve(CurveGeom::Basis basis, const glm::vec4* v, double u) {
    double w[4] = {0.0, 0.0, 0.0, 0.0}, dw[4] = {0.0, 0.0, 0.0, 0.0};
    int n = 4;
    const double u2 = u * u, u3 = u2 * u;
    switch (basis) {
        case CurveGeom::Basis::Linear:
            n = 2;
            w[0] = 1.0 - u;
            w[1] = u;
            dw[0] = -1.0;
            dw[1] = 1.0;
            break;
        case CurveGeom::Basis::BSpline: {
            const double s = 1.0 - u;
            w[0] = s * s * s / 6.0;
            w[1] = (3.0 * u3 - 6.0 * u2 + 4.0) / 6.0;
            w[2] = (-3.0 * u3 + 3.0 * u2 + 3.0 * u + 1.0) / 6.0;
            w[3] = u3 / 6.0;
            dw[0] = -0.5 * s * s;
            dw[1] = 1.5 * u2 - 2.0 * u;
            dw[2] = -1.5 * u2 + u + 0.5;
            dw[3] = 0.5 * u2;
            break;
        }
        case CurveGeom::Basis::CatmullRom:
            w[0] = 0.5 * (-u3 + 2.0 * u2 - u);
            w[1] = 0.5 * (3.0 * u3 - 5.0 * u2 + 2.0);
            w[2] = 0.5 * (-3.0 * u3 + 4.0 * u2 + u);
            w[3] = 0.5 * (u3 - u2);
            dw[0] = 0.5 * (-3.0 * u2 + 4.0 * u - 1.0);
            dw[1] = 0.5 * (9.0 * u2 - 10.0 * u);
            dw[2] = 0.5 * (-9.0 * u2 + 8.0 * u + 1.0);
            dw[3] = 0.5 * (3.0 * u2 - 2.0 * u);
            break;
    }
    CurvePoint p{glm::dvec3(0.0), glm::dvec3(0.0), 0.0};
    for (int i = 0; i < n; ++i) {
        const glm::dvec3 x = glm::dvec3(Vec3(v[i]));
        p.c += w[i] * x;
        p.dc += dw[i] * x;
        p.r += w[i] * double(v[i].w);
    }
    return p;
}

// Embree's intersection and occlusion filter on curves: a strand is seen only from outside, so
// that a ray leaving a hit on it (offset by its error bound to either side) never meets the
// strand it leaves, as Cycles skips the primitive a ray leaves; in particular rays that a hair
// BSDF sends through the fibre pass it.
//  - round: hits where the ray leaves the tube (dot(d, Ng) > 0: Embree's Ng points out of the
//    swept surface) are dropped;
//  - flat: a ribbon faces each ray, so a ray from a ribbon would meet that strand's ribbon for
//    itself at once; hits on a segment whose largest radius (times kFlatSelfReach) reaches the
//    ray's origin are dropped.
constexpr float kFlatSelfReach = 2.f;

void curve_filter(const RTCFilterFunctionNArguments* args) {
    const auto* g = static_cast<const CurveGeom*>(args->geometryUserPtr);
    const unsigned n = args->N;
    for (unsigned i = 0; i < n; ++i) {
        if (args->valid[i] != -1) continue;
        const glm::vec3 d(RTCRayN_dir_x(args->ray, n, i), RTCRayN_dir_y(args->ray, n, i),
                          RTCRayN_dir_z(args->ray, n, i));
        if (!g->flat) {
            const glm::vec3 ng(RTCHitN_Ng_x(args->hit, n, i), RTCHitN_Ng_y(args->hit, n, i),
                               RTCHitN_Ng_z(args->hit, n, i));
            if (glm::dot(d, ng) > 0.f) args->valid[i] = 0;
            continue;
        }
        const float reach = kFlatSelfReach * g->segment_radius[RTCHitN_primID(args->hit, n, i)];
        if (RTCRayN_tfar(args->ray, n, i) * glm::length(d) <= reach) args->valid[i] = 0;
    }
}

// A cut-out primitive's hit, given its nearest root t: the nearest root its opacity keeps (a
// sphere's far root when the near one is let through), or -1. Texture coordinates as
// fill_analytic computes them. Out of line and cold, so that its register spills stay out of
// every opaque sphere's and disc's intersection.
[[gnu::noinline, gnu::cold]] double cutout_root(const AnalyticPrim& prim, std::uint32_t index,
                                                const glm::dvec3& o, const glm::dvec3& d,
                                                const glm::dvec3& o_world,
                                                const glm::dvec3& d_world, double t, double tfar) {
    for (std::uint32_t root = 0; t > 0.0; ++root) {
        const glm::dvec3 po = o + t * d;
        // (A sphere's point is not projected onto it here: uv depends on its direction only.)
        const Vec2 uv = prim.opacity.texture ? analytic::uv(prim.kind, po) : Vec2(0.f);
        if (opacity_blocks(
                prim.opacity.alpha(uv),
                hit_uniform(glm::vec3(o_world), glm::vec3(d_world), kAnalyticTag + root, index)))
            return t;
        t = analytic::intersect(prim.kind, o, d, t, tfar);
    }
    return -1.0;
}

// Nearest hit of primitive `index` (Impl::prims) in (tnear, tfar) that its opacity keeps, or -1.
double intersect_prim(const AnalyticPrim& prim, std::uint32_t index, const glm::dvec3& o_world,
                      const glm::dvec3& d_world, double tnear, double tfar) {
    const glm::dvec3 o = glm::dvec3(prim.to_object * glm::dvec4(o_world, 1.0));
    const glm::dvec3 d = glm::dmat3(prim.to_object) * d_world;
    const double t = analytic::intersect(prim.kind, o, d, tnear, tfar);
    if (!prim.opacity.active()) [[likely]]
        return t;
    return cutout_root(prim, index, o, d, o_world, d_world, t, tfar);
}

void analytic_bounds(const RTCBoundsFunctionArguments* args) {
    const auto* impl = static_cast<const Scene::Impl*>(args->geometryUserPtr);
    const AnalyticPrim& prim = impl->prims[args->primID];
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    const double zr = analytic::half_depth(prim.kind);
    for (int i = 0; i < 8; ++i) {
        glm::dvec3 c(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? zr : -zr);
        glm::dvec3 w = glm::dvec3(prim.to_world * glm::dvec4(c, 1.0));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
    // Pad so that rounding the double box to float can only grow it.
    glm::dvec3 pad = 1e-6 * (glm::abs(lo) + glm::abs(hi)) + 1e-30;
    lo -= pad;
    hi += pad;
    RTCBounds* b = args->bounds_o;
    b->lower_x = float(lo.x);
    b->lower_y = float(lo.y);
    b->lower_z = float(lo.z);
    b->upper_x = float(hi.x);
    b->upper_y = float(hi.y);
    b->upper_z = float(hi.z);
}

void analytic_intersect(const RTCIntersectFunctionNArguments* args) {
    const auto* impl = static_cast<const Scene::Impl*>(args->geometryUserPtr);
    const AnalyticPrim& prim = impl->prims[args->primID];
    RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        glm::dvec3 o(RTCRayN_org_x(rays, args->N, i), RTCRayN_org_y(rays, args->N, i),
                     RTCRayN_org_z(rays, args->N, i));
        glm::dvec3 d(RTCRayN_dir_x(rays, args->N, i), RTCRayN_dir_y(rays, args->N, i),
                     RTCRayN_dir_z(rays, args->N, i));
        float& tfar = RTCRayN_tfar(rays, args->N, i);
        double t = intersect_prim(prim, args->primID, o, d, double(RTCRayN_tnear(rays, args->N, i)),
                                  double(tfar));
        if (!(t > 0.0)) continue;
        float tf = float(t);
        if (!(tf < tfar)) continue;
        tfar = tf;
        RTCHitN_Ng_x(hits, args->N, i) = 0.f;
        RTCHitN_Ng_y(hits, args->N, i) = 0.f;
        RTCHitN_Ng_z(hits, args->N, i) = 1.f;
        RTCHitN_u(hits, args->N, i) = 0.f;
        RTCHitN_v(hits, args->N, i) = 0.f;
        RTCHitN_primID(hits, args->N, i) = args->primID;
        RTCHitN_geomID(hits, args->N, i) = args->geomID;
        RTCHitN_instID(hits, args->N, i, 0) = args->context->instID[0];
    }
}

void analytic_occluded(const RTCOccludedFunctionNArguments* args) {
    const auto* impl = static_cast<const Scene::Impl*>(args->geometryUserPtr);
    const AnalyticPrim& prim = impl->prims[args->primID];
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        glm::dvec3 o(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                     RTCRayN_org_z(args->ray, args->N, i));
        glm::dvec3 d(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                     RTCRayN_dir_z(args->ray, args->N, i));
        float& tfar = RTCRayN_tfar(args->ray, args->N, i);
        double t = intersect_prim(prim, args->primID, o, d,
                                  double(RTCRayN_tnear(args->ray, args->N, i)), double(tfar));
        if (t > 0.0) tfar = -kInfinity;  // Embree's "occluded" mark
    }
}

// Nearest plane hit with t in (0, tmax) in double, or -1; sets `which`. kCutouts: some plane
// has an opacity (Impl::plane_cutouts). Without it the loop has no cut-out call, whose register
// spills would otherwise fall on every opaque plane test.
template <bool kCutouts>
double intersect_planes(const std::vector<PlaneGeom>& planes, const Ray& ray, double tmax,
                        std::size_t& which) {
    double best = -1.0;
    glm::dvec3 o(ray.o), d(ray.d);
    for (std::size_t i = 0; i < planes.size(); ++i) {
        const PlaneGeom& pl = planes[i];
        double dn = glm::dot(d, pl.normal);
        if (dn == 0.0) continue;
        double t = glm::dot(pl.point - o, pl.normal) / dn;
        if (t > 0.0 && t < tmax) {
            if constexpr (kCutouts) {
                // A cut-out plane: the uv of fill (complete_hit) and the hit's random number.
                if (pl.opacity.active() &&
                    !opacity_blocks(pl.opacity.alpha(plane_uv(pl, o + t * d)),
                                    hit_uniform(ray.o, ray.d, kPlaneTag, std::uint32_t(i))))
                    continue;
            }
            tmax = t;
            best = t;
            which = i;
        }
    }
    return best;
}

// (The cut-out loop out of line, so that its spills stay out of the opaque one's caller.)
[[gnu::noinline]] double intersect_cutout_planes(const std::vector<PlaneGeom>& planes,
                                                 const Ray& ray, double tmax, std::size_t& which) {
    return intersect_planes<true>(planes, ray, tmax, which);
}

[[gnu::always_inline]] inline double intersect_planes(const Scene::Impl& impl, const Ray& ray,
                                                      double tmax, std::size_t& which) {
    if (impl.planes.empty()) return -1.0;
    return impl.plane_cutouts ? intersect_cutout_planes(impl.planes, ray, tmax, which)
                              : intersect_planes<false>(impl.planes, ray, tmax, which);
}

// Whether an infinite plane lies on the ray with t in (0, tmax): the part of an occlusion query
// that Embree does not answer.
[[gnu::always_inline]] inline bool plane_blocks(const Scene::Impl& impl, const Ray& r) {
    std::size_t which = 0;
    return intersect_planes(impl, r, double(r.tmax), which) > 0.0;
}

void init_ray(RTCRay& r, const Ray& ray, float tmax) {
    r.org_x = ray.o.x;
    r.org_y = ray.o.y;
    r.org_z = ray.o.z;
    r.tnear = 0.f;
    r.dir_x = ray.d.x;
    r.dir_y = ray.d.y;
    r.dir_z = ray.d.z;
    r.time = 0.f;
    r.tfar = tmax;
    r.mask = 0xFFFFFFFFu;
    r.id = 0;
    r.flags = 0;
}

void init_rayhit(RTCRayHit& rh, const Ray& ray) {
    init_ray(rh.ray, ray, ray.tmax);
    rh.hit.Ng_x = rh.hit.Ng_y = rh.hit.Ng_z = 0.f;
    rh.hit.u = rh.hit.v = 0.f;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

// Curves keep their along/across parameters in SurfaceHit's padding (scene.h, "Curves").
static_assert(sizeof(SurfaceHit) == 168, "SurfaceHit grew: static scenes would pay for it");
static_assert(Scene::kPacketSize == 8, "packet queries are rtcIntersect8 / rtcOccluded8");

// Above this many bytes of per-triangle hit records (a typical L2 cache), closest-hit packets
// prefetch them (EmbreeBackend::prefetch_hit_records).
constexpr std::size_t kPrefetchRecordBytes = std::size_t(1) << 20;
// Embree's mask of the lanes to trace (-1 = active): the first n, where active[k] (all when
// `active` is null).
void packet_valid(int (&valid)[8], std::size_t n, const bool* active) {
    for (std::size_t k = 0; k < 8; ++k) valid[k] = k < n && (!active || active[k]) ? -1 : 0;
}

// Embree's copy of a packet: the rays' arrays, and the fields Facet never varies (tnear 0, time
// 0, every mask bit, no flags); scenes that move then set the time (copy_times). Field by field in
// one loop, which GCC turns into 16-byte moves; a memcpy of the 384 bytes compiles to `rep movsq`,
// whose start-up cost is high at this size (profile in docs/performance.md, "Renderer").
void copy_rays(RTCRay8& r, const RayPacket& rays) {
    for (std::size_t k = 0; k < 8; ++k) {
        r.org_x[k] = rays.ox[k];
        r.org_y[k] = rays.oy[k];
        r.org_z[k] = rays.oz[k];
        r.tnear[k] = 0.f;
        r.dir_x[k] = rays.dx[k];
        r.dir_y[k] = rays.dy[k];
        r.dir_z[k] = rays.dz[k];
        r.time[k] = 0.f;
        r.tfar[k] = rays.tmax[k];
        r.mask[k] = 0xFFFFFFFFu;
        r.id[k] = unsigned(k);
        r.flags[k] = 0u;
    }
}

// The lanes' shutter times, for scenes with moving instances (EmbreeBackend::has_motion).
void copy_times(RTCRay8& r, const RayPacket& rays) {
    for (std::size_t k = 0; k < 8; ++k) r.time[k] = rays.time[k];
}

// The queries of a scene with curves (EmbreeBackend::curve_scene): the main scene, then the
// curves' scene within the nearest hit so far (which a nearer curve replaces), or for the lanes
// nothing blocked yet. Out of line, chosen by one test before the query: scenes without curves
// trace as before.
[[gnu::noinline]] void intersect1_with_curves(const EmbreeBackend& be, RTCIntersectContext& ctx,
                                              RTCRayHit& rh) {
    rtcIntersect1(be.scene.get(), &ctx, &rh);
    rtcIntersect1(be.curve_scene.get(), &ctx, &rh);
}

[[gnu::noinline]] void intersect8_with_curves(const int (&valid)[8], const EmbreeBackend& be,
                                              RTCIntersectContext& ctx, RTCRayHit8& rh) {
    rtcIntersect8(valid, be.scene.get(), &ctx, &rh);
    rtcIntersect8(valid, be.curve_scene.get(), &ctx, &rh);
}

[[gnu::noinline]] void occluded1_with_curves(const EmbreeBackend& be, RTCIntersectContext& ctx,
                                             RTCRay& r) {
    rtcOccluded1(be.scene.get(), &ctx, &r);
    if (!(r.tfar < 0.f)) rtcOccluded1(be.curve_scene.get(), &ctx, &r);
}

[[gnu::noinline]] void occluded8_with_curves(const int (&valid)[8], const EmbreeBackend& be,
                                             RTCIntersectContext& ctx, RTCRay8& r) {
    rtcOccluded8(valid, be.scene.get(), &ctx, &r);
    alignas(32) int open[8];
    bool any = false;
    for (std::size_t k = 0; k < 8; ++k) {
        open[k] = valid[k] && !(r.tfar[k] < 0.f) ? -1 : 0;
        any |= open[k] != 0;
    }
    if (any) rtcOccluded8(open, be.curve_scene.get(), &ctx, &r);
}

// The closest-hit packet of `rays`: the rays as they are, and a hit record that says "no hit
// yet" (geomID and instID invalid), which is all Embree needs in it.
void init_rayhit8(RTCRayHit8& rh, const RayPacket& rays) {
    copy_rays(rh.ray, rays);
    for (int k = 0; k < 8; ++k) {
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
}

// The error bound along the normal of a triangle hit point (MeshGeom::normal_err), from the
// mesh's largest vertex distance from a triangle's float plane (`plane_dev`, measured in double),
// its longest edge and its largest coordinate magnitude:
//  - plane_dev: the projection puts the point on the float plane, this far from the triangle;
//  - gamma(8) of the longest edge: Embree's float test of a ray leaving the triangle works on
//    vertex coordinates relative to the ray origin, rounded to u of the triangle's size, so it
//    can see the triangle that much off its place (pbrt's own intersector bounds its t error
//    instead; Embree's cannot be asked);
//  - kDoubleSlack of the coordinates: the projection's double arithmetic.
float triangle_normal_error(double plane_dev, double max_edge, double max_coord) {
    const double e = plane_dev + double(gamma_bound(8)) * max_edge + kDoubleSlack * max_coord;
    return next_float_up(float(e));
}

// The error of an analytic prim's double hit point before its rounding to float: kDoubleSlack
// of the largest coordinate magnitude of its bounds (solved and projected in object space, then
// transformed: a few dozen double roundings of such magnitudes).
float analytic_error_floor(const AnalyticPrim& prim) {
    double m = 0.0;
    for (int i = 0; i < 8; ++i) {
        glm::dvec3 c(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0);
        m = std::max(m, largest_magnitude(glm::dvec3(prim.to_world * glm::dvec4(c, 1.0))));
    }
    return next_float_up(float(kDoubleSlack * m));
}

// Attaches mesh `m` of `meshes` to `scene` as Embree triangle geometry and fills its hit
// records (planes or smooth records, normal_err); `geom_to_mesh` maps the geometry id to m.
void attach_mesh(RTCDevice device, RTCScene scene, std::vector<MeshGeom>& meshes, std::size_t m,
                 std::vector<std::int32_t>& geom_to_mesh, const std::string& name) {
    MeshGeom& mg = meshes[m];
    const TriangleMesh& mesh = mg.mesh;
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree-owned buffers: Embree pads them as its SIMD loads require. A deforming mesh
    // (MeshGeom::step_positions) has one vertex buffer per uniform time step, which Embree
    // interpolates linearly at the ray's time; a still one has one.
    const std::size_t steps = mg.step_positions.size();
    if (steps >= 2) rtcSetGeometryTimeStepCount(g, unsigned(steps));
    bool buffers = true;
    for (std::size_t k = 0; k < std::max<std::size_t>(steps, 1); ++k) {
        const std::vector<Vec3>& pos = steps >= 2 ? mg.step_positions[k] : mesh.positions;
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX,
                                                              unsigned(k), RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), pos.size()));
        if (!v) {
            buffers = false;
            break;
        }
        for (std::size_t i = 0; i < pos.size(); ++i)
            std::memcpy(v + 3 * i, &pos[i], 3 * sizeof(float));
    }
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.num_triangles()));
    if (buffers && idx) {
        std::memcpy(idx, mesh.indices.data(), mesh.indices.size() * sizeof(unsigned));
        std::vector<glm::vec4> planes(mesh.num_triangles());
        // The hit points' error along the normal (MeshGeom::normal_err): the largest
        // distance of a triangle's vertices from its float plane, and the longest edge.
        double plane_dev = 0.0, max_edge = 0.0, max_coord = 0.0;
        for (std::size_t t = 0; t < planes.size(); ++t) {
            const glm::dvec3 v[3] = {glm::dvec3(mesh.positions[mesh.indices[3 * t]]),
                                     glm::dvec3(mesh.positions[mesh.indices[3 * t + 1]]),
                                     glm::dvec3(mesh.positions[mesh.indices[3 * t + 2]])};
            // In double: the float cross product's squared length overflows for edges
            // beyond ~4e9, which zeroed the walls' normals of a Cornell box scaled by 1e7.
            const glm::dvec3 c = glm::cross(v[1] - v[0], v[2] - v[0]);
            const double len = glm::length(c);
            const Vec3 n = len > 0.0 ? Vec3(c / len) : Vec3(0.f, 0.f, 1.f);
            const glm::dvec3 nd(n);
            const float w = float(glm::dot(nd, v[0]));
            planes[t] = glm::vec4(n, w);
            const double inv_len = 1.0 / glm::length(nd);
            for (int j = 0; j < 3; ++j) {
                plane_dev =
                    std::max(plane_dev, std::fabs(glm::dot(nd, v[j]) - double(w)) * inv_len);
                max_edge = std::max(max_edge, glm::length(v[(j + 1) % 3] - v[j]));
                max_coord = std::max(max_coord, largest_magnitude(v[j]));
            }
        }
        mg.normal_err = triangle_normal_error(plane_dev, max_edge, max_coord);
        if (mesh.normals.empty()) {
            mg.planes = std::move(planes);
        } else {
            std::vector<MeshGeom::SmoothRecord>& rec = mg.records;
            rec.resize(planes.size());
            for (std::size_t t = 0; t < planes.size(); ++t) {
                rec[t].plane = planes[t];
                for (int j = 0; j < 3; ++j)
                    rec[t].n[j] = mesh.normals[mesh.indices[3 * t + std::size_t(j)]];
            }
            mg.mesh.normals = {};
        }
        // Embree holds the data now (the scene keeps the geometry and its buffers alive); a
        // deforming mesh's hits read its indices and steps (fill_deformed).
        mg.mesh.positions = {};
        if (steps < 2) mg.mesh.indices = {};
    }
    if (mg.opacity.active()) {
        // Cut-outs only: every other mesh keeps Embree's filterless path.
        if (!rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED))
            throw SceneError(name +
                             ": embree: built without filter functions, which opacity "
                             "(cut-outs) needs");
        rtcSetGeometryUserData(g, &mg);
        rtcSetGeometryIntersectFilterFunction(g, opacity_filter);
        rtcSetGeometryOccludedFilterFunction(g, opacity_filter);
    }
    rtcCommitGeometry(g);
    unsigned id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    if (geom_to_mesh.size() <= id) geom_to_mesh.resize(id + 1, -1);
    geom_to_mesh[id] = std::int32_t(m);
}

// Attaches curves `c` of `curves` to `scene` as Embree curve geometry (its points and radii,
// its segments' first control points; a round linear strand's segment flags, so that the
// spheres between its segments are not intersected), with the self-hit filter
// (curve_filter); `geom_to_mesh` maps the geometry id to -2 - c. The id is `id` when given
// (EmbreeBackend::curve_scene), Embree's next free one otherwise. Embree holds the arrays then,
// and hits read its copies.
void attach_curves(RTCDevice device, RTCScene scene, std::vector<CurveGeom>& curves, std::size_t c,
                   std::vector<std::int32_t>& geom_to_mesh, const std::string& name,
                   unsigned id = RTC_INVALID_GEOMETRY_ID) {
    CurveGeom& cg = curves[c];
    using B = CurveGeom::Basis;
    RTCGeometryType type = RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE;
    switch (cg.basis) {
        case B::Linear:
            type = cg.flat ? RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE
                           : RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE;
            break;
        case B::BSpline:
            type = cg.flat ? RTC_GEOMETRY_TYPE_FLAT_BSPLINE_CURVE
                           : RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE;
            break;
        case B::CatmullRom:
            type = cg.flat ? RTC_GEOMETRY_TYPE_FLAT_CATMULL_ROM_CURVE
                           : RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE;
            break;
    }
    if (!rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED))
        throw SceneError(name + ": embree: built without filter functions, which curves need");
    RTCGeometry g = rtcNewGeometry(device, type);
    // A deforming one (CurveGeom::step_vertices): one vertex buffer per uniform time step,
    // which Embree interpolates linearly at the ray's time; a still one has one.
    const std::size_t steps = cg.step_vertices.size();
    if (steps >= 2) rtcSetGeometryTimeStepCount(g, unsigned(steps));
    glm::vec4* v = nullptr;
    for (std::size_t k = 0; k < std::max<std::size_t>(steps, 1); ++k) {
        const std::vector<glm::vec4>& src = steps >= 2 ? cg.step_vertices[k] : cg.vertices;
        auto* sv = static_cast<glm::vec4*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX,
                                                                   unsigned(k), RTC_FORMAT_FLOAT4,
                                                                   sizeof(glm::vec4), src.size()));
        if (!sv) {
            v = nullptr;
            break;
        }
        std::memcpy(sv, src.data(), src.size() * sizeof(glm::vec4));
        if (k == 0) v = sv;
        if (steps >= 2) cg.step_vertex.push_back(sv);
    }
    auto* idx = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(std::uint32_t), cg.segments.size()));
    if (v && idx) {
        std::memcpy(idx, cg.segments.data(), cg.segments.size() * sizeof(std::uint32_t));
        cg.vertex = v;
        cg.segment = idx;
        if (cg.basis == B::Linear && !cg.flat) {
            auto* f = static_cast<std::uint8_t*>(
                rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_FLAGS, 0, RTC_FORMAT_UCHAR,
                                        sizeof(std::uint8_t), cg.segments.size()));
            if (f) {
                for (std::size_t k = 0; k + 1 < cg.strand_first.size(); ++k) {
                    const std::uint32_t a = cg.strand_first[k], b = cg.strand_first[k + 1];
                    for (std::uint32_t s = a; s < b; ++s)
                        f[s] = std::uint8_t((s > a ? RTC_CURVE_FLAG_NEIGHBOR_LEFT : 0) |
                                            (s + 1 < b ? RTC_CURVE_FLAG_NEIGHBOR_RIGHT : 0));
                }
            }
        }
        cg.vertices = {};
        cg.step_vertices = {};
        cg.segments = {};
    }
    rtcSetGeometryUserData(g, &cg);
    rtcSetGeometryIntersectFilterFunction(g, curve_filter);
    rtcSetGeometryOccludedFilterFunction(g, curve_filter);
    rtcCommitGeometry(g);
    if (id == RTC_INVALID_GEOMETRY_ID)
        id = rtcAttachGeometry(scene, g);
    else
        rtcAttachGeometryByID(scene, g, id);
    rtcReleaseGeometry(g);
    if (geom_to_mesh.size() <= id) geom_to_mesh.resize(id + 1, -1);
    geom_to_mesh[id] = -2 - std::int32_t(c);
}

}  // namespace

// --- Scene::Impl ------------------------------------------------------------------------------

Scene::Impl::Impl() = default;
Scene::Impl::~Impl() = default;

void Scene::Impl::build(const std::string& name) {
    backend = std::make_unique<EmbreeBackend>();
    EmbreeBackend& be = *backend;
    be.device.reset(rtcNewDevice(nullptr));
    if (!be.device) {
        throw SceneError(name + ": embree: cannot create a device (error " +
                         std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    }
    rtcSetDeviceErrorFunction(be.device.get(), embree_error, &be);
    be.scene.reset(rtcNewScene(be.device.get()));
    // Robust: no accuracy-reducing shortcuts in the triangle test. Without it rays aimed at the
    // Cornell box's edges escape between its walls (test Geometry.CornellBoxIsWatertight); its
    // speed cost is in docs/performance.md, "Renderer". High build quality: static scenes are
    // traced far more than built.
    rtcSetSceneFlags(be.scene.get(), RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(be.scene.get(), RTC_BUILD_QUALITY_HIGH);

    for (std::size_t m = 0; m < meshes.size(); ++m)
        attach_mesh(be.device.get(), be.scene.get(), meshes, m, be.geom_to_mesh, name);
    for (AnalyticPrim& prim : prims) prim.err_floor = analytic_error_floor(prim);
    if (!prims.empty()) {
        RTCGeometry g = rtcNewGeometry(be.device.get(), RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(g, unsigned(prims.size()));
        rtcSetGeometryUserData(g, this);
        rtcSetGeometryBoundsFunction(g, analytic_bounds, this);
        rtcSetGeometryIntersectFunction(g, analytic_intersect);
        rtcSetGeometryOccludedFunction(g, analytic_occluded);
        rtcCommitGeometry(g);
        be.analytic_geom = rtcAttachGeometry(be.scene.get(), g);
        rtcReleaseGeometry(g);
        if (be.geom_to_mesh.size() <= be.analytic_geom) {
            be.geom_to_mesh.resize(be.analytic_geom + 1, -1);
        }
    }
    build_instances(name);
    if (!curves.empty()) {
        // Ids after every one of the main scene's (geom_to_mesh covers them all).
        be.curve_scene.reset(rtcNewScene(be.device.get()));
        rtcSetSceneBuildQuality(be.curve_scene.get(), RTC_BUILD_QUALITY_HIGH);
        const unsigned first = unsigned(be.geom_to_mesh.size());
        for (std::size_t c = 0; c < curves.size(); ++c)
            attach_curves(be.device.get(), be.curve_scene.get(), curves, c, be.geom_to_mesh, name,
                          first + unsigned(c));
        rtcCommitScene(be.curve_scene.get());
    }
    std::size_t record_bytes = 0;
    auto mesh_extras = [](const MeshGeom& mg) {
        return mg.part >= 0 || !mg.tri_uvs.empty() || mg.spherical || !mg.tri_colors.empty();
    };
    for (const MeshGeom& mg : meshes)
        record_bytes += mg.planes.size() * sizeof(glm::vec4) +
                        mg.records.size() * sizeof(MeshGeom::SmoothRecord);
    be.prefetch_hit_records = record_bytes > kPrefetchRecordBytes;
    // (Curves' hits are filled on the extras' path only: scenes without them keep the other.)
    for (const PrototypeGeom& pg : prototypes)
        be.surface_extras_instanced |=
            !pg.curves.empty() || std::any_of(pg.meshes.begin(), pg.meshes.end(), mesh_extras);
    // (Scenes with moving instances take the extras' path too: only it hands fill_instance the
    // lanes' times, so that the other path passes time 0 and loads nothing for it.)
    be.surface_extras =
        be.surface_extras_instanced || be.has_motion || !curves.empty() ||
        std::any_of(meshes.begin(), meshes.end(), mesh_extras) ||
        std::any_of(prims.begin(), prims.end(), [](const AnalyticPrim& p) { return p.uv; }) ||
        std::any_of(planes.begin(), planes.end(), [](const PlaneGeom& p) { return p.uv; }) ||
        position_extras;
    plane_cutouts = std::any_of(planes.begin(), planes.end(),
                                [](const PlaneGeom& p) { return p.opacity.active(); });
    rtcCommitScene(be.scene.get());
    std::lock_guard<std::mutex> lock(be.error_mutex);
    if (!be.first_error.empty()) throw SceneError(name + ": embree: " + be.first_error);
}

void Scene::Impl::build_instances(const std::string& name) {
    if (instances.empty()) return;
    EmbreeBackend& be = *backend;
    be.prototype_scenes.resize(prototypes.size());
    be.prototype_geom_to_mesh.resize(prototypes.size());
    std::vector<bool> used(prototypes.size(), false);
    for (const InstanceGeom& in : instances) used[in.prototype] = true;
    for (std::size_t p = 0; p < prototypes.size(); ++p) {
        if (!used[p]) continue;  // built for its checks only
        ScenePtr ps(rtcNewScene(be.device.get()));
        rtcSetSceneFlags(ps.get(), RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(ps.get(), RTC_BUILD_QUALITY_HIGH);
        for (std::size_t m = 0; m < prototypes[p].meshes.size(); ++m)
            attach_mesh(be.device.get(), ps.get(), prototypes[p].meshes, m,
                        be.prototype_geom_to_mesh[p], name);
        for (std::size_t c = 0; c < prototypes[p].curves.size(); ++c)
            attach_curves(be.device.get(), ps.get(), prototypes[p].curves, c,
                          be.prototype_geom_to_mesh[p], name);
        rtcCommitScene(ps.get());
        be.prototype_scenes[p] = std::move(ps);
    }
    for (std::size_t i = 0; i < instances.size(); ++i) {
        const InstanceGeom& in = instances[i];
        RTCGeometry g = rtcNewGeometry(be.device.get(), RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(g, be.prototype_scenes[in.prototype].get());
        // (A deforming prototype's time steps are its meshes'; the rays then carry a time.)
        if (in.deforms) be.has_motion = true;
        if (in.motion.empty()) {
            rtcSetGeometryTimeStepCount(g, 1);
            float m[12];  // 3x4 column major: the linear part's columns, then the translation
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 3; ++r) m[3 * c + r] = float(in.to_world[c][r]);
            rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m);
        } else {
            // Embree's motion blur: one transform per uniform time step over the ray time
            // [0, 1], given decomposed so that Embree interpolates as motion.h does (T and S
            // linearly, R by slerp) instead of blending matrices.
            be.has_motion = true;
            rtcSetGeometryTimeStepCount(g, unsigned(in.motion.size()));
            for (std::size_t k = 0; k < in.motion.size(); ++k) {
                const DecomposedTransform& d = in.motion[k];
                RTCQuaternionDecomposition qd;
                rtcInitQuaternionDecomposition(&qd);
                rtcQuaternionDecompositionSetScale(&qd, float(d.scale[0][0]), float(d.scale[1][1]),
                                                   float(d.scale[2][2]));
                // S's entries above the diagonal (glm: s[column][row]).
                rtcQuaternionDecompositionSetSkew(&qd, float(d.scale[1][0]), float(d.scale[2][0]),
                                                  float(d.scale[2][1]));
                rtcQuaternionDecompositionSetQuaternion(&qd, float(d.rotation.w),
                                                        float(d.rotation.x), float(d.rotation.y),
                                                        float(d.rotation.z));
                rtcQuaternionDecompositionSetTranslation(
                    &qd, float(d.translation.x), float(d.translation.y), float(d.translation.z));
                rtcSetGeometryTransformQuaternion(g, unsigned(k), &qd);
            }
        }
        rtcCommitGeometry(g);
        const unsigned id = rtcAttachGeometry(be.scene.get(), g);
        rtcReleaseGeometry(g);
        if (be.geom_to_instance.size() <= id) be.geom_to_instance.resize(id + 1, -1);
        be.geom_to_instance[id] = std::int32_t(i);
        if (be.geom_to_mesh.size() <= id) be.geom_to_mesh.resize(id + 1, -1);
    }
}

void Scene::Impl::fill_analytic(const AnalyticPrim& prim, const Ray& ray, float t,
                                SurfaceHit& hit) const {
    // Recompute the hit in double in object space and project it onto the surface, so the
    // returned point lies on the exact surface to float round-off.
    glm::dvec3 o = glm::dvec3(prim.to_object * glm::dvec4(glm::dvec3(ray.o), 1.0));
    glm::dvec3 d = glm::dmat3(prim.to_object) * glm::dvec3(ray.d);
    const analytic::SurfacePoint sp = analytic::project(prim.kind, o + double(t) * d);
    const glm::dvec3& po = sp.p;
    hit.t = t;
    hit.p = Vec3(glm::dvec3(prim.to_world * glm::dvec4(po, 1.0)));
    // The double point lies on the exact surface to kDoubleSlack of the prim's coordinates
    // (err_floor); then one rounding to float.
    hit.p_err = rounding_error(hit.p) + Vec3(prim.err_floor);
    hit.ng = Vec3(glm::normalize(prim.normal_to_world * sp.n));
    if (prim.flip) hit.ng = -hit.ng;
    hit.ns = hit.ng;
    hit.dpdu = Vec3(glm::dmat3(prim.to_world) * sp.tangent);
    hit.shape = prim.shape;
    if (prim.uv) {
        hit.uv = analytic::uv(prim.kind, po);
        // dp/du and dp/dv of the uv map (ray differentials): sphere longitude/latitude, disc
        // bounding square [-1, 1]^2 onto [0, 1]^2.
        const glm::dmat3 lin(prim.to_world);
        glm::dvec3 du, dv;
        analytic::uv_derivatives(prim.kind, po, du, dv);
        hit.dpdu_uv = Vec3(lin * du);
        hit.dpdv_uv = Vec3(lin * dv);
        if (prim.tangent_sign != 0.f) {
            // dp/du of the UVs: along dpdu above; unit (zero at a sphere's poles).
            const float l = glm::length(hit.dpdu);
            hit.dpdu = l > 0.f ? hit.dpdu / l : Vec3(0.f);
            hit.tangent_sign = prim.tangent_sign;
        }
    }
}

// Below this length an interpolated vertex normal (of unit corner normals that nearly cancel)
// is left as ng: the interpolation's rounding, a few 1e-8 per component, is then over 5% of
// the vector, so its direction is noise; and near float's smallest normal numbers its length
// would round too coarsely to normalise it.
constexpr float kMinInterpolatedNormal = 1e-6f;

namespace {

// The shading normal of a hit at barycentrics (u, v) on a smooth triangle (its record's corner
// normals) with geometric normal ng: interpolated, turned into ng's hemisphere and, for a world
// ray (kWorld), bent for it (SurfaceHit::ns). Out of line: the call keeps the closest-hit path
// of flat meshes as short as it was.
template <bool kWorld>
[[gnu::noinline]] Vec3 smooth_normal(const MeshGeom::SmoothRecord& rec, const Ray& ray, float u,
                                     float v, const Vec3& ng) {
    Vec3 ns = (1.f - u - v) * rec.n[0] + u * rec.n[1] + v * rec.n[2];
    const float l = glm::length(ns);
    if (!(l > kMinInterpolatedNormal && std::isfinite(l))) return ng;
    ns /= l;
    ns = glm::dot(ns, ng) < 0.f ? -ns : ns;
    if constexpr (kWorld) ns = ray_side_valid_normal(ng, -ray.d, ns);
    return ns;
}

}  // namespace

// Inline: called once per closest hit, only from Scene::intersect below. kUv: compute the
// texture coordinates of meshes that have them (EmbreeBackend::surface_extras).
template <bool kUv, bool kWorld>
[[gnu::always_inline]] inline void Scene::Impl::fill_triangle(const MeshGeom& mg, std::uint32_t tri,
                                                              const Ray& ray, float u, float v,
                                                              float t, SurfaceHit& hit) const {
    const glm::vec4& plane = mg.plane(tri);
    hit.t = t;
    hit.ng = Vec3(plane);
    // o + t d, then projected onto the triangle's float plane, in double: the error left along
    // the normal is that plane's distance from the triangle (MeshGeom::normal_err) and the
    // rounding to float; the error along the surface (Embree's t) cannot cause
    // self-intersection.
    // No division by |n|^2 (a float-rounded unit vector: 1 within 3u): the projection then
    // misses the plane by at most gamma(3) |s|, added to the bound (a division on every hit's
    // critical path cost more).
    const glm::dvec3 n(hit.ng);
    glm::dvec3 p = glm::dvec3(ray.o) + double(t) * glm::dvec3(ray.d);
    const double s = glm::dot(p, n) - double(plane.w);
    p -= s * n;
    hit.p = Vec3(p);
    // p_err = gamma(1) |p| + (normal_err + gamma(3) |s|) |ng| (rounding_error plus the bound
    // along the normal), four lanes at once: per component it costs as many instructions as
    // the projection itself. The same operations in the same order as the scalar form.
    using F4 = float __attribute__((vector_size(16)));
    using U4 = std::uint32_t __attribute__((vector_size(16)));
    const float k = mg.normal_err + gamma_bound(3) * float(std::fabs(s));
    const F4 p4 = {hit.p.x, hit.p.y, hit.p.z, 0.f};
    F4 n4;  // (ng, w): the plane record; the w lane is not used
    std::memcpy(&n4, &plane, sizeof n4);
    const U4 abs_mask = U4{} + 0x7fffffffu;
    const F4 e = gamma_bound(1) * F4(U4(p4) & abs_mask) + k * F4(U4(n4) & abs_mask);
    hit.p_err = Vec3(e[0], e[1], e[2]);
    hit.ns =
        mg.records.empty() ? hit.ng : smooth_normal<kWorld>(mg.records[tri], ray, u, v, hit.ng);
    hit.dpdu = mg.tangent;
    hit.shape = mg.shape;
    if constexpr (kUv) {
        if (!mg.tri_colors.empty()) {
            const std::array<glm::vec4, 3>& c = mg.tri_colors[tri];
            hit.color = (1.f - u - v) * c[0] + u * c[1] + v * c[2];
        }
        if (!mg.tri_uvs.empty()) {
            hit.uv = triangle_uv(mg, tri, u, v, glm::dvec3(hit.p));
            hit.dpdu_uv = mg.tri_dpduv[tri][0];
            hit.dpdv_uv = mg.tri_dpduv[tri][1];
            if (!mg.tri_tangents.empty()) [[unlikely]] {
                // Interpolated, not normalised (as Cycles' tangent attribute); the sign too.
                const std::array<glm::vec4, 3>& tt = mg.tri_tangents[tri];
                const glm::vec4 tan = (1.f - u - v) * tt[0] + u * tt[1] + v * tt[2];
                hit.dpdu = Vec3(tan);
                hit.tangent_sign = tan.w;
            }
        } else if (mg.spherical) {
            const glm::dvec3 po(mg.to_object * glm::dvec4(glm::dvec3(hit.p), 1.0));
            hit.uv = sphere_uv(po);
            glm::dvec3 du, dv;
            sphere_uv_derivatives(po / glm::length(po), du, dv);
            const glm::dmat3 lin = glm::inverse(glm::dmat3(mg.to_object));
            hit.dpdu_uv = Vec3(lin * du);
            hit.dpdv_uv = Vec3(lin * dv);
            if (mg.tangent_sign != 0.f) [[unlikely]] {
                // dp/du of the sphere's UVs: (-y, x, 0) in its frame, to world; unit.
                const glm::dvec3 w = mg.sphere_to_world * glm::dvec3(-po.y, po.x, 0.0);
                const double l = glm::length(w);
                hit.dpdu = l > 0.0 ? Vec3(w / l) : Vec3(0.f);
                hit.tangent_sign = mg.tangent_sign;
            }
        }
    }
}

// Out of line: only instanced scenes call it. The hit is found in the prototype's object space
// (the ray brought there in double, rounded to float, then fill_triangle as for any mesh) and
// taken to world space (InstanceGeom). Its error box: the object-space box through |linear
// part|, plus the world point's rounding, plus gamma(4) of the magnitudes that Embree's float
// copy of the transform and its float transform of spawned rays work at (the surface Embree
// traces differs from the double placement, and a ray leaving p is moved into object space in
// float: both shift it by a few u of those magnitudes).
// A moving instance (InstanceGeom::motion) is placed at the ray's time by motion.h's
// interpolation, which Embree's float interpolation of the same decomposed steps follows only
// to its own rounding and approximations (which it does not report): the error box then grows
// by kMotionSlack of the magnitudes involved, a safety margin as the triangles' is
// (test Motion.RotatingInstanceHitsLieWithinTheirErrorBox measures the actual difference).
constexpr double kMotionSlack = 1e-4;

namespace {

// A hit on a deforming mesh (MeshGeom::step_positions) at shutter time `time`: the triangle's
// corners, and a smooth mesh's corner normals, interpolated linearly between the two steps
// around the time (as Embree interpolates the vertex buffers), in double; then as fill_triangle
// on that triangle: the point projected onto its plane, the error box from its plane's
// deviation, plus kMotionSlack of its coordinates for Embree's own float interpolation (as a
// moving instance's). UVs and colours are per corner as on a still mesh; dp/du and dp/dv of
// the UVs are the interpolated triangle's; tangents (normal maps) are the still mesh's.
template <bool kUv>
[[gnu::noinline]] void fill_deformed(const MeshGeom& mg, std::uint32_t tri, const Ray& ray,
                                     float time, float u, float v, float t, SurfaceHit& hit) {
    const std::size_t steps = mg.step_positions.size();
    const double x = std::clamp(double(time), 0.0, 1.0) * double(steps - 1);
    const std::size_t i = std::min(std::size_t(x), steps - 2);
    const double f = x - double(i);
    std::uint32_t ix[3];
    for (int j = 0; j < 3; ++j) ix[j] = mg.mesh.indices[3 * std::size_t(tri) + std::size_t(j)];
    const std::vector<Vec3>& a = mg.step_positions[i];
    const std::vector<Vec3>& b = mg.step_positions[i + 1];
    std::array<glm::dvec3, 3> p;
    for (int j = 0; j < 3; ++j)
        p[std::size_t(j)] = (1.0 - f) * glm::dvec3(a[ix[j]]) + f * glm::dvec3(b[ix[j]]);
    const glm::dvec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
    const double len = glm::length(c);
    const Vec3 n = len > 0.0 ? Vec3(c / len) : Vec3(0.f, 0.f, 1.f);
    const glm::dvec3 nd(n);
    const double w = double(float(glm::dot(nd, p[0])));
    double plane_dev = 0.0, max_edge = 0.0, max_coord = 0.0;
    const double inv_len = 1.0 / glm::length(nd);
    for (int j = 0; j < 3; ++j) {
        const std::size_t k = std::size_t(j);
        plane_dev = std::max(plane_dev, std::fabs(glm::dot(nd, p[k]) - w) * inv_len);
        max_edge = std::max(max_edge, glm::length(p[(k + 1) % 3] - p[k]));
        max_coord = std::max(max_coord, largest_magnitude(p[k]));
    }
    hit.t = t;
    hit.ng = n;
    glm::dvec3 pt = glm::dvec3(ray.o) + double(t) * glm::dvec3(ray.d);
    const double s = glm::dot(pt, nd) - w;
    pt -= s * nd;
    hit.p = Vec3(pt);
    const float k = triangle_normal_error(plane_dev, max_edge, max_coord) +
                    float(kMotionSlack * max_coord) + gamma_bound(3) * float(std::fabs(s));
    hit.p_err = rounding_error(hit.p) + k * glm::abs(n);
    hit.ns = hit.ng;
    if (!mg.step_normals.empty()) {
        const std::vector<Vec3>& na = mg.step_normals[i];
        const std::vector<Vec3>& nb = mg.step_normals[i + 1];
        const float ff = float(f);
        auto corner = [&](int j) { return (1.f - ff) * na[ix[j]] + ff * nb[ix[j]]; };
        Vec3 ns = (1.f - u - v) * corner(0) + u * corner(1) + v * corner(2);
        const float l = glm::length(ns);
        if (l > kMinInterpolatedNormal && std::isfinite(l)) {
            ns /= l;
            hit.ns = glm::dot(ns, hit.ng) < 0.f ? -ns : ns;
        }
    }
    hit.dpdu = mg.tangent;
    hit.shape = mg.shape;
    if constexpr (kUv) {
        if (!mg.tri_colors.empty()) {
            const std::array<glm::vec4, 3>& col = mg.tri_colors[tri];
            hit.color = (1.f - u - v) * col[0] + u * col[1] + v * col[2];
        }
        if (!mg.tri_uvs.empty()) {
            hit.uv = triangle_uv(mg, tri, u, v, pt);
            const std::array<Vec3, 2> d = triangle_uv_derivatives(p, mg.tri_uvs[tri]);
            hit.dpdu_uv = d[0];
            hit.dpdv_uv = d[1];
            if (!mg.tri_tangents.empty()) {
                const std::array<glm::vec4, 3>& tt = mg.tri_tangents[tri];
                const glm::vec4 tan = (1.f - u - v) * tt[0] + u * tt[1] + v * tt[2];
                hit.dpdu = Vec3(tan);
                hit.tangent_sign = tan.w;
            }
        }
    }
}

// A hit on segment `seg` of curves `g` at Embree's curve parameter u and distance t (scene.h,
// "Curves"): the axis point, radius and tangent at u in double; round: the normal from the axis
// point to o + t d, and the point put on the tube there; flat: the ribbon's point, and the
// normal of the tube it stands for at its position h across the ribbon. The error box: the
// point's rounding, and Embree's float intersection (its curve parameter and distance) at
// gamma(16) of the coordinates: a ray leaving the hit cannot meet the same strand anyway
// (curve_filter), so the bound only keeps it off neighbouring strands' surfaces no more than
// triangles are. Deforming curves (CurveGeom::step_vertices): the segment's control points
// interpolated linearly between the two steps around the ray's `time` (as Embree interpolates
// the vertex buffers), in double, and the error box grown by kMotionSlack of the coordinates
// for Embree's own float interpolation (as a deforming mesh's).
[[gnu::noinline]] void fill_curve(const CurveGeom& g, std::uint32_t seg, const Ray& ray, float u,
                                  float t, SurfaceHit& hit, float time = 0.f) {
    const glm::vec4* v = g.vertex + g.segment[seg];
    glm::vec4 at_time[4];
    if (!g.step_vertex.empty()) [[unlikely]] {
        const std::size_t steps = g.step_vertex.size();
        const double x = std::clamp(double(time), 0.0, 1.0) * double(steps - 1);
        const std::size_t i = std::min(std::size_t(x), steps - 2);
        const double f = x - double(i);
        const glm::vec4* a = g.step_vertex[i] + g.segment[seg];
        const glm::vec4* b = g.step_vertex[i + 1] + g.segment[seg];
        const int n = g.basis == CurveGeom::Basis::Linear ? 2 : 4;
        for (int q = 0; q < n; ++q)
            at_time[q] = glm::vec4((1.0 - f) * glm::dvec4(a[q]) + f * glm::dvec4(b[q]));
        v = at_time;
    }
    const CurvePoint cp = eval_curve(g.basis, v, double(u));
    glm::dvec3 tangent = cp.dc;
    double tl = glm::length(tangent);
    if (!(tl > 0.0)) {  // coincident control points: the chord of the segment
        const std::uint32_t k = g.basis == CurveGeom::Basis::Linear ? 1 : 3;
        tangent = glm::dvec3(Vec3(v[k])) - glm::dvec3(Vec3(v[0]));
        tl = glm::length(tangent);
    }
    const glm::dvec3 T = tl > 0.0 ? tangent / tl : glm::dvec3(0.0, 0.0, 1.0);
    const glm::dvec3 d(ray.d);
    glm::dvec3 p = glm::dvec3(ray.o) + double(t) * d;
    // w: toward the ray origin, normal to the tangent; b = w x T spans the ribbon.
    glm::dvec3 w = glm::dot(d, T) * T - d;
    const double wl = glm::length(w);
    if (wl > 0.0) {
        w /= wl;
    } else {  // a ray along the tangent
        const Frame f = Frame::from_z(Vec3(T));
        w = glm::dvec3(f.x);
    }
    const glm::dvec3 b = glm::cross(w, T);
    glm::dvec3 n;
    double h;
    if (g.flat) {
        h = std::clamp(glm::dot(p - cp.c, b) / cp.r, -1.0, 1.0);
        n = std::sqrt(std::max(0.0, 1.0 - h * h)) * w + h * b;
    } else {
        const glm::dvec3 r = p - cp.c;
        const double rl = glm::length(r);
        n = rl > 0.0 ? r / rl : w;
        p = cp.c + cp.r * n;
        h = std::clamp(glm::dot(n, b), -1.0, 1.0);
    }
    hit.t = t;
    hit.p = Vec3(p);
    hit.p_err = rounding_error(hit.p) + Vec3(gamma_bound(16) * g.max_coord);
    if (!g.step_vertex.empty()) hit.p_err += Vec3(float(kMotionSlack * g.max_coord));
    hit.ng = Vec3(n);
    hit.ns = hit.ng;
    hit.dpdu = Vec3(T);
    hit.shape = g.shape;
    const std::uint32_t strand = g.segment_strand[seg];
    const std::uint32_t first = g.strand_first[strand];
    hit.strand_v =
        float((double(seg - first) + double(u)) / double(g.strand_first[strand + 1] - first));
    hit.strand_h = std::int16_t(std::lround(h * 32767.0));
    if (!g.strand_random.empty()) [[unlikely]]
        hit.strand_random = g.strand_random[strand];
    if (!g.root_uvs.empty()) {
        hit.uv = g.root_uvs[strand];
        hit.dpdu_uv = Vec3(0.f);
        hit.dpdv_uv = Vec3(0.f);
    }
}

// fill_instance's body for placement `in`; `moving`: `in` is a moving instance's placement at
// the ray's time, whose error box grows by kMotionSlack.
// `timed`: the hit may be on a deforming mesh, filled at the ray's `time` (fill_deformed).
template <bool kUv>
[[gnu::always_inline]] inline void fill_placed(const Scene::Impl& impl, const InstanceGeom& in,
                                               bool moving, bool timed, std::uint32_t geom,
                                               std::uint32_t tri, const Ray& ray, float time,
                                               float u, float v, float t, SurfaceHit& hit,
                                               std::int32_t& part) {
    const PrototypeGeom& pg = impl.prototypes[in.prototype];
    const std::int32_t index = impl.backend->prototype_geom_to_mesh[in.prototype][geom];
    // (A curve's hit: index -2 - its place in PrototypeGeom::curves.)
    // Without kUv (no surface extras) the prototypes hold no curves (surface_extras_instanced).
    const MeshGeom* mg = !kUv || index >= 0 ? &pg.meshes[std::size_t(index)] : nullptr;
    const bool curve = kUv && !mg;
    Ray local;
    local.o = Vec3(glm::dvec3(in.to_object * glm::dvec4(glm::dvec3(ray.o), 1.0)));
    local.d = Vec3(glm::dmat3(in.to_object) * glm::dvec3(ray.d));
    local.tmax = ray.tmax;
    if (curve) [[unlikely]]
        fill_curve(pg.curves[std::size_t(-2 - index)], tri, local, u, t, hit, timed ? time : 0.f);
    else if (timed && !mg->step_positions.empty())
        fill_deformed<kUv>(*mg, tri, local, time, u, v, t, hit);
    else
        impl.fill_triangle<kUv, false>(*mg, tri, local, u, v, t, hit);
    const glm::dmat3 lin(in.to_world);
    const glm::dvec3 po(hit.p);
    // In the prototype's frame (complete_hit takes it to object space): the point, or the
    // normal where the shape keeps it there (set below, after the normal's transform).
    hit.po = hit.p;
    const glm::dvec3 pw = glm::dvec3(in.to_world * glm::dvec4(po, 1.0));
    hit.p = Vec3(pw);
    const double shift =
        double(gamma_bound(4)) * (in.linear_norm * (in.inverse_norm * largest_magnitude(pw) +
                                                    in.inverse_offset + largest_magnitude(po)) +
                                  in.offset) +
        kDoubleSlack * largest_magnitude(pw);
    hit.p_err = Vec3(in.abs_linear * glm::dvec3(hit.p_err) + shift) + rounding_error(hit.p);
    if (moving)
        hit.p_err +=
            Vec3(float(kMotionSlack * (in.linear_norm * largest_magnitude(po) + in.offset)));
    const glm::dvec3 ng = glm::normalize(in.normal_to_world * glm::dvec3(hit.ng));
    glm::dvec3 ns = glm::normalize(in.normal_to_world * glm::dvec3(hit.ns));
    // The normal in the prototype's frame, along the world one (complete_hit takes it to object
    // space where ShapeInfo::normal_in_po).
    const glm::dvec3 n_frame = glm::dot(ns, ng) < 0.0 ? -glm::dvec3(hit.ns) : glm::dvec3(hit.ns);
    if (glm::dot(ns, ng) < 0.0) ns = -ns;
    hit.ng = Vec3(ng);
    hit.ns = Vec3(ns);
    // Bent in world space, where the ray's angles are those the integrators shade with.
    if (!curve && !mg->records.empty()) hit.ns = ray_side_valid_normal(hit.ng, -ray.d, hit.ns);
    hit.dpdu = Vec3(lin * glm::dvec3(hit.dpdu));
    if (curve) hit.dpdu = glm::normalize(hit.dpdu);  // a curve's tangent is unit
    if (!curve) hit.tangent_sign *= in.handedness;   // (a curve's is its strand_random)
    if constexpr (kUv) {
        if (hit.shape < impl.normal_in_po.size() && impl.normal_in_po[hit.shape]) [[unlikely]]
            hit.po = Vec3(n_frame);
        hit.dpdu_uv = Vec3(lin * glm::dvec3(hit.dpdu_uv));
        hit.dpdv_uv = Vec3(lin * glm::dvec3(hit.dpdv_uv));
        part = curve ? -1 : mg->part;
    }
}

// A moving or deforming instance's hit: its placement at the ray's time (motion.h) and its
// deforming meshes' triangles at that time (fill_deformed), then as a still one's. Out of line
// and cold, so that still instances' hits build no placement.
template <bool kUv>
[[gnu::noinline, gnu::cold]] void fill_moving(const Scene::Impl& impl, const InstanceGeom& placed,
                                              std::uint32_t geom, std::uint32_t tri, const Ray& ray,
                                              float time, float u, float v, float t,
                                              SurfaceHit& hit, std::int32_t& part) {
    if (placed.motion.empty()) {
        fill_placed<kUv>(impl, placed, false, true, geom, tri, ray, time, u, v, t, hit, part);
    } else {
        InstanceGeom at_time;
        at_time.prototype = placed.prototype;
        at_time.place(interpolate_motion(placed.motion, double(time)));
        fill_placed<kUv>(impl, at_time, true, true, geom, tri, ray, time, u, v, t, hit, part);
    }
    // A moving emitter's pdf needs its triangle (scene.h; a curve's hit keeps its strand_v).
    if (impl.backend->prototype_geom_to_mesh[placed.prototype][geom] >= 0) hit.emitter_prim = tri;
}

}  // namespace

template <bool kUv>
[[gnu::noinline]] void Scene::Impl::fill_instance(const InstanceGeom& placed, std::uint32_t geom,
                                                  std::uint32_t tri, const Ray& ray, float time,
                                                  float u, float v, float t, SurfaceHit& hit,
                                                  std::int32_t& part) const {
    if (!placed.motion.empty() || placed.deforms) [[unlikely]] {
        fill_moving<kUv>(*this, placed, geom, tri, ray, time, u, v, t, hit, part);
        return;
    }
    fill_placed<kUv>(*this, placed, false, false, geom, tri, ray, time, u, v, t, hit, part);
}

// --- Scene ------------------------------------------------------------------------------------

Scene::Scene() : m_impl(std::make_unique<Impl>()) {}
Scene::~Scene() = default;
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

float Scene::radius() const {
    if (m_bounds.empty()) return 1.f;
    return std::fmax(1.f, 0.5f * glm::length(m_bounds.hi - m_bounds.lo));
}

bool Scene::intersect(const Ray& ray, SurfaceHit& hit) const {
    const Impl& impl = *m_impl;
    if (!impl.backend) return false;  // a default-constructed (empty) scene
    const EmbreeBackend& be = *impl.backend;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    init_rayhit(rh, ray);
    if (be.curve_scene) [[unlikely]]
        intersect1_with_curves(be, ctx, rh);
    else
        rtcIntersect1(be.scene.get(), &ctx, &rh);
    return be.surface_extras
               ? complete_hit<true>(ray, 0.f, rh.hit.instID[0], rh.hit.geomID, rh.hit.primID,
                                    rh.hit.u, rh.hit.v, rh.ray.tfar, hit)
               : complete_hit<false>(ray, 0.f, rh.hit.instID[0], rh.hit.geomID, rh.hit.primID,
                                     rh.hit.u, rh.hit.v, rh.ray.tfar, hit);
}

bool Scene::intersect(const Ray& ray, float time, SurfaceHit& hit) const {
    const Impl& impl = *m_impl;
    if (!impl.backend) return false;
    const EmbreeBackend& be = *impl.backend;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    init_rayhit(rh, ray);
    rh.ray.time = time;
    if (be.curve_scene) [[unlikely]]
        intersect1_with_curves(be, ctx, rh);
    else
        rtcIntersect1(be.scene.get(), &ctx, &rh);
    return be.surface_extras
               ? complete_hit<true>(ray, time, rh.hit.instID[0], rh.hit.geomID, rh.hit.primID,
                                    rh.hit.u, rh.hit.v, rh.ray.tfar, hit)
               : complete_hit<false>(ray, time, rh.hit.instID[0], rh.hit.geomID, rh.hit.primID,
                                     rh.hit.u, rh.hit.v, rh.ray.tfar, hit);
}

// The part of a closest-hit query after Embree: infinite planes (tested here, outside the BVH),
// then the hit record of whatever is nearest. `geom` is Embree's geomID (invalid: no hit).
// kSurfaceExtras (EmbreeBackend::surface_extras): parts, texture coordinates and textured
// emission; without it a hit reads its shape's own surface only.
template <bool kSurfaceExtras>
[[gnu::always_inline]] inline bool Scene::complete_hit(const Ray& ray, float time, unsigned inst,
                                                       unsigned geom, unsigned prim, float u,
                                                       float v, float t, SurfaceHit& hit) const {
    const Impl& impl = *m_impl;
    const EmbreeBackend& be = *impl.backend;
    const float tfar = geom != RTC_INVALID_GEOMETRY_ID ? t : ray.tmax;
    std::size_t plane = 0;
    std::int32_t part = -1;  // the hit mesh's part of its shape (ShapeInfo::parts)
    double tp = intersect_planes(impl, ray, tfar, plane);
    if (tp > 0.0 && float(tp) <= tfar) {
        const PlaneGeom& pl = impl.planes[plane];
        glm::dvec3 p = glm::dvec3(ray.o) + tp * glm::dvec3(ray.d);
        p -= glm::dot(p - pl.point, pl.normal) * pl.normal;  // back onto the plane
        hit.t = float(tp);
        hit.p = Vec3(p);
        // On the double plane to kDoubleSlack of the coordinates, then rounded to float.
        hit.p_err =
            rounding_error(hit.p) +
            Vec3(float(kDoubleSlack * (largest_magnitude(p) + largest_magnitude(pl.point))));
        hit.ng = Vec3(pl.normal);
        hit.ns = hit.ng;
        hit.dpdu = pl.tangent;
        hit.shape = pl.shape;
        if (pl.uv) {
            hit.uv = plane_uv(pl, p);
            hit.dpdu_uv = Vec3(pl.ex);
            hit.dpdv_uv = Vec3(pl.ey);
            hit.tangent_sign = pl.tangent_sign;
        }
    } else if (geom == RTC_INVALID_GEOMETRY_ID) {
        return false;
    } else if (inst != RTC_INVALID_GEOMETRY_ID) [[unlikely]] {
        const InstanceGeom& in = impl.instances[std::size_t(be.geom_to_instance[inst])];
        impl.fill_instance<kSurfaceExtras>(in, geom, prim, ray, time, u, v, t, hit, part);
    } else if (geom == be.analytic_geom) {
        impl.fill_analytic(impl.prims[prim], ray, t, hit);
    } else if (kSurfaceExtras && be.geom_to_mesh[geom] < -1) [[unlikely]] {
        // Curves (geom_to_mesh: -2 - the index), only on the extras' path (surface_extras).
        fill_curve(impl.curves[std::size_t(-2 - be.geom_to_mesh[geom])], prim, ray, u, t, hit);
    } else {
        const MeshGeom& mg = impl.meshes[std::size_t(be.geom_to_mesh[geom])];
        impl.fill_triangle<kSurfaceExtras, true>(mg, prim, ray, u, v, t, hit);
        if constexpr (kSurfaceExtras) part = mg.part;
    }
    const ShapeInfo& shape = m_shapes[hit.shape];
    if constexpr (kSurfaceExtras) {
        if (shape.needs_position) {
            // The object-space point: an instance's hit is in its prototype's frame already.
            const glm::dvec3 p(inst != RTC_INVALID_GEOMETRY_ID && !(tp > 0.0 && float(tp) <= tfar)
                                   ? hit.po
                                   : hit.p);
            hit.po = Vec3(glm::dvec3(shape.to_object * glm::dvec4(p, 1.0)));
        }
        if (shape.normal_in_po) [[unlikely]] {
            // The object-space shading normal (a prototype's shape: hit.po holds it in the
            // prototype's frame), on the ray's side (Cycles' N).
            const Vec3 n = glm::normalize(shape.normal_to_object * hit.po);
            hit.po = glm::dot(hit.ng, ray.d) > 0.f ? -n : n;
        }
    }
    const ShapeSurface& s = part < 0 ? shape : shape.parts[std::size_t(part)];
    hit.material = s.material;
    hit.two_sided = s.two_sided;
    hit.light = s.light;
    hit.textured = s.textured;
    // A textured emission needs uv, which only kSurfaceExtras computes (every textured surface
    // has texture coordinates); its surface is an emitter (light >= 0) like any other.
    hit.emitted_radiance = Rgb(0.f);
    if (s.light != -1 && glm::dot(hit.ng, ray.d) < 0.f) {  // a light or kEmitterNotSampled
        hit.emitted_radiance = s.emission;
        if constexpr (kSurfaceExtras) {
            if (s.emission_texture)
                hit.emitted_radiance = s.emission_texture->eval(
                    texture_point(hit, texture_footprint(hit, nullptr), -ray.d, hit.ns));
        }
    }
    return true;
}

void Scene::intersect_packet(const RayPacket& rays, std::size_t n, SurfaceHit* hits, bool* found,
                             const bool* active) const {
    n = std::min(n, kPacketSize);
    const Impl& impl = *m_impl;
    if (n == 0) return;
    if (!impl.backend) {  // a default-constructed (empty) scene
        for (std::size_t k = 0; k < n; ++k)
            if (!active || active[k]) found[k] = false;
        return;
    }
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    alignas(32) int valid[kPacketSize];
    packet_valid(valid, n, active);
    RTCRayHit8 rh;
    init_rayhit8(rh, rays);
    if (impl.backend->has_motion) [[unlikely]]
        copy_times(rh.ray, rays);
    if (impl.backend->curve_scene) [[unlikely]]
        intersect8_with_curves(valid, *impl.backend, ctx, rh);
    else
        rtcIntersect8(valid, impl.backend->scene.get(), &ctx, &rh);
    // The hit records read per-triangle data that Embree's traversal did not touch (its leaves
    // hold their own vertex copies): on a large mesh these are cache misses. Ask for all lanes'
    // lines first so that the misses overlap instead of queueing one lane at a time.
    for (std::size_t k = 0; k < n && impl.backend->prefetch_hit_records; ++k) {
        const unsigned geom = rh.hit.geomID[k];
        if (!valid[k] || geom == RTC_INVALID_GEOMETRY_ID || geom == impl.backend->analytic_geom ||
            rh.hit.instID[0][k] != RTC_INVALID_GEOMETRY_ID || impl.backend->geom_to_mesh[geom] < 0)
            continue;
        const MeshGeom& mg = impl.meshes[std::size_t(impl.backend->geom_to_mesh[geom])];
        __builtin_prefetch(&mg.plane(rh.hit.primID[k]));
    }
    // The hit records, with the scene's surface extras or without (decided once per packet).
    // (Two plain loops: GCC did not inline complete_hit into a templated lambda.)
    if (impl.backend->surface_extras) {
        for (std::size_t k = 0; k < n; ++k) {
            if (!valid[k]) continue;
            found[k] = complete_hit<true>(rays.get(k), rays.time[k], rh.hit.instID[0][k],
                                          rh.hit.geomID[k], rh.hit.primID[k], rh.hit.u[k],
                                          rh.hit.v[k], rh.ray.tfar[k], hits[k]);
        }
    } else {
        for (std::size_t k = 0; k < n; ++k) {
            if (!valid[k]) continue;
            found[k] = complete_hit<false>(rays.get(k), 0.f, rh.hit.instID[0][k], rh.hit.geomID[k],
                                           rh.hit.primID[k], rh.hit.u[k], rh.hit.v[k],
                                           rh.ray.tfar[k], hits[k]);
        }
    }
}

void Scene::occluded_packet(const RayPacket& rays, std::size_t n, const bool* active,
                            bool* blocked) const {
    n = std::min(n, kPacketSize);
    const Impl& impl = *m_impl;
    // Lanes to trace: active, something to test, not already blocked by an infinite plane
    // (tested outside Embree, as occluded_ray does).
    bool trace[kPacketSize] = {};
    int count = 0;
    for (std::size_t k = 0; k < n; ++k) {
        blocked[k] = false;
        if (!active[k] || !(rays.tmax[k] > 0.f) || !impl.backend) continue;
        // (Planes tested first: the lane's Ray is built only when there are planes.)
        if (!impl.planes.empty() && plane_blocks(impl, rays.get(k))) {
            blocked[k] = true;
            continue;
        }
        trace[k] = true;
        ++count;
    }
    if (count == 0) return;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    alignas(32) int valid[kPacketSize];
    packet_valid(valid, n, trace);
    RTCRay8 r;
    copy_rays(r, rays);
    if (impl.backend->has_motion) [[unlikely]]
        copy_times(r, rays);
    if (impl.backend->curve_scene) [[unlikely]]
        occluded8_with_curves(valid, *impl.backend, ctx, r);
    else
        rtcOccluded8(valid, impl.backend->scene.get(), &ctx, &r);
    for (std::size_t k = 0; k < n; ++k)
        if (trace[k]) blocked[k] = r.tfar[k] < 0.f;  // Embree sets tfar = -inf on a hit
}

bool Scene::occluded(const Vec3& p, const Vec3& ng, const Vec3& wi, float dist) const {
    Ray r = spawn_ray(p, rounding_error(p), ng, wi);
    if (std::isfinite(dist)) {
        const float tmax = dist * (1.f - kShadowEpsilon);
        if (!(tmax > 0.f)) return false;
        r.tmax = tmax;
    }
    return occluded_ray(r);
}

// (init_ray's time is 0: a static scene's shadow ray is the timed one at 0.)
bool Scene::occluded_ray(const Ray& r) const {
    return occluded_ray_at(r, 0.f);
}

bool Scene::occluded_ray_at(const Ray& r, float time) const {
    const Impl& impl = *m_impl;
    if (!impl.backend) return false;
    if (plane_blocks(impl, r)) return true;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay ray;
    init_ray(ray, r, r.tmax);
    ray.time = time;
    if (impl.backend->curve_scene) [[unlikely]]
        occluded1_with_curves(*impl.backend, ctx, ray);
    else
        rtcOccluded1(impl.backend->scene.get(), &ctx, &ray);
    return ray.tfar < 0.f;  // Embree sets tfar = -inf on a hit
}

std::uint64_t Scene::trace_raw_packet(std::span<const Ray> rays, bool shadow) const {
    if (!m_impl->backend) return 0;
    RTCScene scene = m_impl->backend->scene.get();
    RTCScene curves = m_impl->backend->curve_scene.get();
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    std::uint64_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); i += kPacketSize) {
        const std::size_t n = std::min(kPacketSize, rays.size() - i);
        RayPacket packet;
        for (std::size_t k = 0; k < n; ++k) packet.set(k, rays[i + k]);
        alignas(32) int valid[kPacketSize];
        packet_valid(valid, n, nullptr);
        RTCRayHit8 rh;
        init_rayhit8(rh, packet);
        if (shadow) {
            if (curves)
                occluded8_with_curves(valid, *m_impl->backend, ctx, rh.ray);
            else
                rtcOccluded8(valid, scene, &ctx, &rh.ray);
            for (std::size_t k = 0; k < kPacketSize; ++k) hits += valid[k] && rh.ray.tfar[k] < 0.f;
        } else {
            if (curves)
                intersect8_with_curves(valid, *m_impl->backend, ctx, rh);
            else
                rtcIntersect8(valid, scene, &ctx, &rh);
            for (std::size_t k = 0; k < kPacketSize; ++k)
                hits += valid[k] && rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
        }
    }
    return hits;
}

std::uint64_t Scene::trace_raw(std::span<const Ray> rays, bool shadow) const {
    if (!m_impl->backend) return 0;
    RTCScene scene = m_impl->backend->scene.get();
    RTCScene curves = m_impl->backend->curve_scene.get();
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    std::uint64_t hits = 0;
    if (shadow) {
        for (const Ray& r : rays) {
            RTCRay ray;
            init_ray(ray, r, r.tmax);
            if (curves)
                occluded1_with_curves(*m_impl->backend, ctx, ray);
            else
                rtcOccluded1(scene, &ctx, &ray);
            hits += ray.tfar < 0.f;
        }
    } else {
        for (const Ray& r : rays) {
            RTCRayHit rh;
            init_rayhit(rh, r);
            if (curves)
                intersect1_with_curves(*m_impl->backend, ctx, rh);
            else
                rtcIntersect1(scene, &ctx, &rh);
            hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
    }
    return hits;
}

}  // namespace facet::render
