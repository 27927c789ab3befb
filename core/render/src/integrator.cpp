// The `direct` and `path` integrators as templates on compile-time scene features, and the
// choice among their instantiations (facet/render/integrator.h).
#include "facet/render/integrator.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <utility>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <pcg_random.hpp>

#include "facet/frame.h"
#include "facet/registry.h"
#include "facet/render/aov.h"
#include "facet/render/sampler.h"
#include "facet/sampling.h"
#include "light_path.h"

namespace facet::render {

namespace {

// Lane k's shutter time in the motion kernels, 0 in the others (which never read it).
template <std::uint32_t F>
[[gnu::always_inline]] inline float lane_time(const RayPacket& rays, std::size_t k) {
    if constexpr ((F & kFeatMotion) != 0)
        return rays.time[k];
    else
        return 0.f;
}

// The light sample and the pdf of a BSDF ray's hit on a light, at the path's shutter time in
// the motion kernels (moving emitters, light.h "Time"); the other kernels make the calls they
// made before motion blur existed.
template <std::uint32_t F>
[[gnu::always_inline]] inline std::optional<LightLiSample> sample_light(
    const Light& light, const LightSampleContext& ctx, Vec2 u, [[maybe_unused]] float time) {
    if constexpr ((F & kFeatMotion) != 0)
        return light.sample_li_at(ctx, u, time);
    else
        return light.sample_li(ctx, u);
}
template <std::uint32_t F>
[[gnu::always_inline]] inline float hit_light_pdf(const Light& light, const LightSampleContext& ctx,
                                                  const Vec3& wi, const SurfaceHit& hit,
                                                  [[maybe_unused]] float time) {
    if constexpr ((F & kFeatMotion) != 0)
        return light.pdf_li_at(ctx, wi, hit.p, hit.ng, hit.emitter_prim, time);
    else
        return light.pdf_li(ctx, wi, hit.p, hit.ng);
}

// The closest hit of `ray` at its path's shutter time `time` in the motion kernels; the other
// kernels trace at time 0, exactly as before motion blur existed.
template <std::uint32_t F>
[[gnu::always_inline]] inline bool trace(const Scene& scene, const Ray& ray,
                                         [[maybe_unused]] float time, SurfaceHit& hit) {
    if constexpr ((F & kFeatMotion) != 0)
        return scene.intersect(ray, time, hit);
    else
        return scene.intersect(ray, hit);
}

// ---- alpha (kFeatAlpha; integrator.h conventions, "Alpha") ----

// The holdout weight of a see-through hit: 1 on a holdout shape, else its material's.
[[gnu::noinline]] float holdout_at(const Scene& scene, const SurfaceHit& hit, const Vec3& ray_d) {
    if (scene.shapes()[hit.shape].holdout) return 1.f;
    const Material& m = *hit.material;
    if (!m.has_holdout()) return 0.f;
    const Vec3 wo_w = -ray_d;
    const Vec3 n = glm::dot(hit.ng, wo_w) >= 0.f ? hit.ns : -hit.ns;
    return m.holdout_weight(Frame::from_z(n).to_local(wo_w));
}

// The transparency a path's throughput beta carries (Cycles: the average over channels).
inline float mean3(const Rgb& c) {
    return (c.r + c.g + c.b) * (1.f / 3.f);
}

// ---- ray visibility and Light Path switches (integrator.h, "Ray visibility") ----

// The entry of switch `index` that a ray with Light Path outputs `lp` sees, or null when none
// matches (the shape's own material).
inline const LightPathSwitch::Entry* light_path_entry(const Scene& scene, std::int32_t index,
                                                      std::uint8_t lp) {
    for (const LightPathSwitch::Entry& e : scene.light_paths()[std::size_t(index)].entries)
        if ((e.ray & lp) != 0) return &e;
    return nullptr;
}

// Whether a light sample of light i reaches a material of lobes `lobes` (Cycles 3.4's
// SHADER_EXCLUDE_* of a mesh light, from its object's ray visibility): not when every lobe is
// of a kind whose rays do not see the emitter (diffuse; glossy and mirror). Transmissive
// materials are lit whatever the flags (Cycles 3.4 excludes no glass closure), and a material
// with lobes of both kinds keeps the whole light sample (Cycles would drop the excluded
// lobes' share: FORMAT.md "Ray visibility").
inline bool light_reaches(const Scene& scene, std::uint32_t i, BxDFFlags lobes) {
    const std::uint8_t v = scene.light_visibility()[i];
    if (v == kRayAll || is_transmissive(lobes)) return true;
    BxDFFlags seen = BxDFFlags::None;
    if ((v & kRayDiffuse) != 0) seen = seen | BxDFFlags::Diffuse;
    if ((v & kRayGlossy) != 0) seen = seen | BxDFFlags::Glossy | BxDFFlags::Specular;
    return any(lobes & seen) ||
           !any(lobes & (BxDFFlags::Diffuse | BxDFFlags::Glossy | BxDFFlags::Specular));
}

// Whether a BSDF sample is a straight pass-through (a transparent surface, `null`).
inline bool passes_straight(const BSDFSample& bs, const Vec3& wo) {
    return bs.is_specular() && bs.wi == -wo;
}

// ---- shadow catcher (alpha media kernel; integrator.h conventions, "Shadow catcher") ----

// A camera sample's run of media_path_li in a scene with a shadow catcher: `catchers_only`
// makes it the catcher-only run; the rest is what the run found.
struct CatcherPath {
    bool catchers_only = false;  // in: after the split, rays see shadow catchers only
    bool split = false;          // the path met a catcher while see-through
    Rgb matte{0.f};              // the radiance gathered before the split (full run)
    // The environment seen by the see-through path: where it escapes, or straight behind the
    // catcher at the split (times the throughput), as Cycles' background pass.
    Rgb background{0.f};
    float split_t = 0.f;  // the throughput's mean at the split (the matte's transparency)
};

// Whether a hit's shape is a shadow catcher.
inline bool is_catcher(const Scene& scene, const SurfaceHit& hit) {
    return scene.shapes()[hit.shape].shadow_catcher;
}

// Whether light `l` lights a run (`only_catchers`: the catcher-only run after its split). As in
// Cycles, an emitting shape lights the catcher-only run only if it is a catcher itself (its
// other surfaces are absent there); lamps and the environment light every run.
inline bool lights_run(const Scene& scene, const Light& l, bool only_catchers) {
    return !only_catchers || l.shape() == UINT32_MAX || scene.shapes()[l.shape()].shadow_catcher;
}

// The closest hit of `ray` among the shadow catchers: other shapes are passed as if absent
// (hit.t stays the distance from ray.o).
template <std::uint32_t F>
[[gnu::noinline]] bool trace_catchers(const Scene& scene, const Ray& ray, float time,
                                      SurfaceHit& hit, KernelCounters& c);

// ---- BSDF access: the Material, or its single Lambertian lobe in the Lambert-only kernel ----

template <std::uint32_t F>
Rgb bsdf_f(const Material& m, const Vec3& wo, const Vec3& wi) {
    if constexpr ((F & kFeatLambertOnly) != 0)
        return m.diffuse()->f(wo, wi);
    else
        return m.f(wo, wi);
}

// f and pdf together (next-event estimation with MIS): one pass over the glossy lobe's D and
// Lambda; equal to f() and pdf() bit for bit (Material::eval).
template <std::uint32_t F>
[[gnu::always_inline]] inline BSDFEval bsdf_eval(const Material& m, const Vec3& wo,
                                                 const Vec3& wi) {
    if constexpr ((F & kFeatLambertOnly) != 0)
        return {m.diffuse()->f(wo, wi), m.diffuse()->pdf(wo, wi)};
    else
        return m.eval(wo, wi);
}

template <std::uint32_t F>
std::optional<BSDFSample> bsdf_sample(const Material& m, const Vec3& wo, float uc, Vec2 u) {
    if constexpr ((F & kFeatLambertOnly) != 0)
        return m.diffuse()->sample_f(wo, uc, u);
    else
        return m.sample_f(wo, uc, u);
}

// Whether the material has a non-delta lobe. In the Lambert-only kernel every material is
// either one Lambertian lobe or black (no lobe at all, e.g. an emitter's default material);
// the BSDF functions above are only called after this returned true.
template <std::uint32_t F>
bool has_non_specular(const Material& m) {
    if constexpr ((F & kFeatLambertOnly) != 0)
        return m.diffuse().has_value();
    else
        return is_non_specular(m.flags());
}

// Largest channel without a libm call (std::fmax is not inlined without -ffinite-math-only);
// a NaN channel may be ignored, which is harmless: callers test `> 0` and NaN estimates are
// dropped per sample by the tile loop.
inline float max3(const Rgb& c) {
    const float m = c.r > c.g ? c.r : c.g;
    return m > c.b ? m : c.b;
}

// Shading geometry at a hit, oriented toward the viewer (scene.h sidedness rules).
struct Shading {
    Frame frame;
    Vec3 ng, ns, wo;  // world ng/ns on the viewer's side; wo in the local frame
};

// Whether the material reads the tangent direction: only an anisotropic microfacet lobe does.
// Lambertian, mirror and isotropic microfacet lobes are invariant under rotation about the
// normal, so for them the frame's tangent is arbitrary and Frame::from_z(ns) replaces the
// Gram-Schmidt of from_z_x (every kernel makes the same choice, so their images still agree).
template <std::uint32_t F>
bool needs_tangent(const Material& m) {
    if constexpr ((F & kFeatLambertOnly) != 0) {
        return false;
    } else {
        return m.anisotropic();  // an anisotropic glossy lobe, here or in a mix's child
    }
}

// False when the surface is seen from the back and is one-sided (it reflects nothing).
template <std::uint32_t F>
[[gnu::always_inline]] inline bool make_shading(const SurfaceHit& hit, const Material& m,
                                                const Vec3& ray_d, Shading& sh) {
    const Vec3 wo_w = -ray_d;
    const bool front = glm::dot(hit.ng, wo_w) > 0.f;
    if (!front && !hit.two_sided) return false;
    sh.ng = front ? hit.ng : -hit.ng;
    sh.ns = front ? hit.ns : -hit.ns;
    sh.frame = needs_tangent<F>(m) ? Frame::from_z_x(sh.ns, hit.dpdu) : Frame::from_z(sh.ns);
    sh.wo = sh.frame.to_local(wo_w);
    return true;
}

// Shading geometry of a transmissive material (facet/dielectric.h): the frame's z is the
// shape's own shading normal, NOT turned toward the viewer, because the side it points to is
// the outside of the dielectric; wo may then lie below the frame (a ray inside the glass).
// Two-sidedness does not apply: both sides of an interface transmit and reflect.
[[gnu::always_inline]] inline void make_transmissive_shading(const SurfaceHit& hit,
                                                             const Material& m, const Vec3& ray_d,
                                                             Shading& sh) {
    sh.ng = hit.ng;
    sh.ns = hit.ns;
    sh.frame = m.anisotropic() ? Frame::from_z_x(sh.ns, hit.dpdu) : Frame::from_z(sh.ns);
    sh.wo = sh.frame.to_local(-ray_d);
}

// Whether world direction w (local z = w_local_z) leaves the surface on a side where the
// material can send it: for reflection models the viewer's side of the geometric normal (sh.ng
// is turned toward the viewer), for transmissive ones either side, but the geometric and the
// shading normal must agree on which (otherwise a shading normal would leak light through).
[[gnu::always_inline]] inline bool valid_side(const Shading& sh, bool transmissive, const Vec3& w,
                                              float w_local_z) {
    const float g = glm::dot(w, sh.ng);
    return transmissive ? g * w_local_z > 0.f : g > 0.f;
}

// ---- path: rendering equation by path tracing, NEE + MIS (power heuristic) ----

constexpr std::size_t kLanes = Scene::kPacketSize;

// One path of a packet (path_packet): what a path keeps from one vertex to the next. The ray to
// the current vertex and its hit live in the packet's arrays, next to the other lanes'.
struct PathState {
    Rgb L{0.f}, beta{1.f};
    bool specular_bounce = false;
    float prev_bsdf_pdf = 0.f;
    LightSampleContext prev_ctx;
    // Next-event estimation at the current vertex: what L gains when the shadow ray (traced
    // with the other lanes' after every lane has shaded its vertex) is not blocked.
    Rgb nee{0.f};
    // Alpha kernels: whether the path is still see-through, and its transparency T.
    bool see_through = true;
    float transparent = 0.f;
};

// The sample values one path vertex may use (integrator.h: the dimensions of a vertex), drawn
// for the 8 paths of a packet together (VertexSampleLanes).
struct VertexSamples {
    // (base + 0, the light choice's dimension, is read by none: LightDistribution::sample)
    Vec2 light;      // base + 1
    float lobe;      // base + 3 (not in the Lambert-only kernel)
    Vec2 bsdf;       // base + 4
    float roulette;  // base + 6 (only from kRouletteDepth on)
};

// The samples of one depth for every lane of a packet: each dimension of the vertex block is
// drawn for all lanes at once (sample_*_lanes, vectorised), and only the dimensions the kernel
// can read at this depth. Lane k gets exactly the values its own Sampler would give.
struct VertexSampleLanes {
    alignas(32) float light_x[kSamplerLanes], light_y[kSamplerLanes], lobe[kSamplerLanes],
        bsdf_x[kSamplerLanes], bsdf_y[kSamplerLanes], roulette[kSamplerLanes];

    template <std::uint32_t F>
    void draw(const std::uint32_t* seeds, std::uint32_t index, int depth) {
        const std::uint32_t base = 1u + std::uint32_t(kDimsPerVertex * depth);
        sample_2d_lanes(seeds, index, base + 1u, light_x, light_y);
        if constexpr ((F & kFeatLambertOnly) == 0) sample_1d_lanes(seeds, index, base + 3u, lobe);
        sample_2d_lanes(seeds, index, base + 4u, bsdf_x, bsdf_y);
        if (depth + 1 >= kRouletteDepth) sample_1d_lanes(seeds, index, base + 6u, roulette);
    }
    // Lane k's values (the entries that draw() skipped are never read).
    VertexSamples lane(std::size_t k) const {
        return {{light_x[k], light_y[k]}, lobe[k], {bsdf_x[k], bsdf_y[k]}, roulette[k]};
    }
};

// The rest of path_vertex once the hit's material `m` is known: light sample and BSDF sample.
template <std::uint32_t F>
[[gnu::always_inline]] inline bool path_scatter(const Scene& scene,
                                                const LightDistribution& light_dist, PathState& p,
                                                RayPacket& rays, std::size_t k,
                                                const SurfaceHit& hit, const VertexSamples& s,
                                                bool& has_shadow, RayPacket& shadow, int depth,
                                                int max_depth, KernelCounters& c, const Vec3& ray_d,
                                                const Material& m) {
    constexpr bool kMis = (F & kFeatMis) != 0;
    constexpr bool kSpecular = (F & kFeatSpecular) != 0;
    constexpr bool kTransmission = (F & kFeatTransmission) != 0;
    const std::span<const Light> lights = scene.lights();
    const int num_lights = int(lights.size());
    Shading sh;
    // Transmissive materials exist only in the transmission kernel (kFeatTransmission).
    bool transmissive = false;
    if constexpr (kTransmission) transmissive = m.transmissive();
    if (transmissive)
        make_transmissive_shading(hit, m, ray_d, sh);
    else if (!make_shading<F>(hit, m, ray_d, sh))
        return false;
    // A transmissive surface is lit from both sides: no hemisphere for the environment's
    // cosine sampling (light.h, ctx.n = 0).
    const LightSampleContext ctx{hit.p, transmissive ? Vec3(0.f) : sh.ns};
    // The origin of both rays that leave this vertex, the shadow ray and the continuation:
    // both go to the viewer's side of a reflecting surface (checked below), so one offset
    // serves both. Rays leaving a transmissive surface start on their own side (origin_to).
    const Vec3 origin = offset_ray_origin(hit.p, hit.p_err, sh.ng, sh.ng);
    auto origin_to = [&](const Vec3& w) {
        return transmissive ? offset_ray_origin(hit.p, hit.p_err, sh.ng, w) : origin;
    };

    // Next-event estimation: one light, chosen in proportion to power among the lights it
    // samples (light.h: not the environment, which the BSDF sample below finds).
    if (!light_dist.empty() && has_non_specular<F>(m)) {
        // The light choice needs a sample only when there is a choice; every draw has a fixed
        // dimension, so skipping one does not shift the others.
        float select_pmf = 1.f;
        std::uint32_t light_index = 0;
        Vec2 u_light = s.light;
        if (num_lights > 1) light_index = light_dist.sample(ctx, u_light, select_pmf);
        const Light& light = lights[light_index];
        // (select_pmf is 0 only when the light tree finds no light that can reach ctx.)
        if (auto ls = select_pmf > 0.f ? sample_light<F>(light, ctx, u_light, lane_time<F>(rays, k))
                                       : std::nullopt) {
            // Reflection: the light must be on the viewer's side of the surface; transmission:
            // on either side (valid_side).
            const Vec3 wi = sh.frame.to_local(ls->wi);
            if (valid_side(sh, transmissive, ls->wi, wi.z) && ls->pdf > 0.f) {
                // With MIS the BSDF pdf is needed too: one evaluation for both.
                BSDFEval e;
                if constexpr (kMis)
                    e = bsdf_eval<F>(m, sh.wo, wi);
                else
                    e.f = bsdf_f<F>(m, sh.wo, wi);
                const Rgb contrib = e.f * std::fabs(wi.z) * ls->li;
                if (max3(contrib) > 0.f) {
                    ++c.shadow_rays;
                    has_shadow = true;
                    shadow.set(k, Scene::shadow_ray_from(origin_to(ls->wi), *ls));
                    const float lp = select_pmf * ls->pdf;
                    float w = 1.f;
                    if constexpr (kMis) {
                        // Only lights that rays can hit compete with BSDF samples (a delta
                        // light never is one: light.h).
                        if (light.hittable()) w = power_heuristic(lp, e.pdf);
                    }
                    p.nee = p.beta * contrib * (w / lp);
                }
            }
        }
    }
    // The last vertex needs a BSDF sample only to find emitters (MIS) or through a mirror.
    if constexpr (!kMis) {
        if (depth + 1 >= max_depth) return false;
    }

    // BSDF sampling for the next vertex.
    if constexpr ((F & kFeatLambertOnly) != 0) {
        if (!m.diffuse()) return false;  // black
    }
    // Lobe choice: a Lambertian lobe ignores uc (facet/lambert.h), so the Lambert-only kernel
    // does not draw it; the general kernel passes a value the single lobe ignores.
    const float uc = (F & kFeatLambertOnly) != 0 ? 0.f : s.lobe;
    const std::optional<BSDFSample> bs = bsdf_sample<F>(m, sh.wo, uc, s.bsdf);
    if (!bs || !(bs->pdf > 0.f)) return false;
    const Vec3 wi_w = sh.frame.from_local(bs->wi);
    // Below the geometric surface (reflection), or on the side the shading frame disagrees with.
    if (!valid_side(sh, transmissive, wi_w, bs->wi.z)) return false;
    p.beta *= bs->f * (std::fabs(bs->wi.z) / bs->pdf);
    if (!(max3(p.beta) > 0.f)) return false;
    if constexpr ((F & kFeatAlpha) != 0)
        p.see_through = p.see_through && passes_straight(*bs, sh.wo);
    if constexpr (kSpecular) p.specular_bounce = bs->is_specular();
    p.prev_bsdf_pdf = bs->pdf;
    p.prev_ctx = ctx;

    // Russian roulette (unbiased): survive with probability sqrt(max(beta)) (integrator.h),
    // reweight survivors.
    if (depth + 1 >= kRouletteDepth) {
        const float q = std::max(0.f, 1.f - std::sqrt(max3(p.beta)));
        if (q > 0.f) {
            if (s.roulette < q) return false;
            p.beta /= 1.f - q;
        }
    }
    rays.set(k, Ray{origin_to(wi_w), wi_w, kInfinity});
    ++c.rays;
    return true;
}

// A hit on a textured material: the material built for it (Scene::bsdf_at), out of line so
// that the untextured path keeps its code and its stack frame as before.
template <std::uint32_t F>
[[gnu::noinline]] bool path_scatter_textured(const Scene& scene,
                                             const LightDistribution& light_dist, PathState& p,
                                             RayPacket& rays, std::size_t k, const SurfaceHit& hit,
                                             const VertexSamples& s, bool& has_shadow,
                                             RayPacket& shadow, int depth, int max_depth,
                                             KernelCounters& c, const Ray& ray) {
    SurfaceHit h = hit;
    std::optional<Material> textured;
    const Material& m = scene.bsdf_at(h, ray, depth == 0, textured);
    const Vec3& ray_d = ray.d;
    return path_scatter<F>(scene, light_dist, p, rays, k, h, s, has_shadow, shadow, depth,
                           max_depth, c, ray_d, m);
}

// The vertex at `depth` of path `p`, lane k of the packets: reached by the ray rays[k] (closest
// hit `hit` when `found`), with the vertex's samples `s`: emission found by the ray, the light
// sample (shadow ray shadow[k] and p.nee, `has_shadow` set), and the BSDF sample that continues
// the path (rays[k] becomes the next ray). False when the path ends here.
template <std::uint32_t F>
bool path_vertex(const Scene& scene, const LightDistribution& light_dist, PathState& p,
                 RayPacket& rays, std::size_t k, bool found, const SurfaceHit& hit,
                 const VertexSamples& s, bool& has_shadow, RayPacket& shadow, int depth,
                 int max_depth, KernelCounters& c) {
    const Vec3 ray_d = rays.direction(k);
    constexpr bool kMis = (F & kFeatMis) != 0;
    constexpr bool kSpecular = (F & kFeatSpecular) != 0;
    constexpr bool kEmission = (F & kFeatEmission) != 0;
    constexpr bool kIndirect = (F & kFeatIndirect) != 0;
    constexpr bool kTextured = (F & kFeatTextured) != 0;
    const std::span<const Light> lights = scene.lights();

    // Area lamps that camera rays see (transparent: the path goes on behind them).
    if (depth == 0 && scene.has_camera_lamps()) [[unlikely]]
        p.L += scene.camera_lamps(rays.origin(k), ray_d, found ? hit.t : kInfinity);

    // Alpha: the background or a holdout seen through nothing but transparent surfaces.
    if constexpr ((F & kFeatAlpha) != 0) {
        if (p.see_through) {
            if (!found) {
                if (scene.settings().film_transparent) {
                    p.transparent += mean3(p.beta);
                    return false;
                }
            } else if (const float h = holdout_at(scene, hit, ray_d); h > 0.f) {
                p.transparent += h * mean3(p.beta);
                if (h >= 1.f) return false;
            }
        }
    }

    // Emission reached by this ray: full weight from the camera or after a delta lobe (light
    // sampling cannot produce those paths); MIS-weighted against NEE otherwise.
    if constexpr (kMis) {
        if (depth > 0 || kEmission) {
            if (!found) {
                if (const Light* env = scene.environment()) {
                    if (depth == 0 || p.specular_bounce) {
                        p.L += p.beta * env->le_escape(ray_d);
                    } else {
                        float pdf;
                        const Rgb le = env->le_escape(ray_d, p.prev_ctx, pdf);
                        const float lp =
                            light_dist.pmf(p.prev_ctx, std::size_t(env - lights.data())) * pdf;
                        p.L += p.beta * le * power_heuristic(p.prev_bsdf_pdf, lp);
                    }
                }
            } else if (hit.light >= 0 && max3(hit.emitted_radiance) > 0.f) {
                if (depth == 0 || p.specular_bounce) {
                    p.L += p.beta * hit.emitted_radiance;
                } else {
                    const std::size_t li = std::size_t(hit.light);
                    const float lp =
                        light_dist.pmf(p.prev_ctx, li) *
                        hit_light_pdf<F>(lights[li], p.prev_ctx, ray_d, hit, lane_time<F>(rays, k));
                    p.L += p.beta * hit.emitted_radiance * power_heuristic(p.prev_bsdf_pdf, lp);
                }
            }
        }
    }
    if (!found || depth >= max_depth) return false;
    if constexpr (!kIndirect && !kSpecular) {
        if (depth >= 1) return false;
    }
    if constexpr (kTextured) {
        if (hit.textured >= 0)
            return path_scatter_textured<F>(scene, light_dist, p, rays, k, hit, s, has_shadow,
                                            shadow, depth, max_depth, c, rays.get(k));
    }
    return path_scatter<F>(scene, light_dist, p, rays, k, hit, s, has_shadow, shadow, depth,
                           max_depth, c, ray_d, *hit.material);
}

// Fewer live paths than this trace their closest-hit rays one by one: a packet query costs
// nearly as much with few active lanes as with eight (thresholds 2, 3 and 5 time alike:
// docs/performance.md, "Renderer").
constexpr int kMinPacketLanes = 3;

// The paths of n <= kLanes camera rays `rays` (closest hits `hits` / `found`, traced by the
// caller), pixel seeds `seeds` (kLanes of them; the first n are used), sample index `index`,
// traced together depth by depth: the closest-hit rays of a depth go to Embree as one packet
// (one by one when only a few paths are left), then the shadow rays of that depth as one packet.
// Each path performs exactly the shading operations, in the same order, that it would alone; only
// Embree's packet and single-ray kernels may disagree on a ray that grazes an edge (measured:
// material_sweep within 7.5e-7 relative of single-ray tracing, the other scenes bit-identical).
// Radiance estimates are left in L[k].
template <std::uint32_t F>
void path_packet(const Scene& scene, const LightDistribution& light_dist, std::size_t n,
                 RayPacket& rays, std::array<SurfaceHit, kLanes>& hits,
                 std::array<bool, kLanes>& found, const std::uint32_t* seeds, std::uint32_t index,
                 int max_depth, KernelCounters& c, Rgb* L, float* T) {
    static_assert(kLanes == kSamplerLanes);
    constexpr bool kIndirect = (F & kFeatIndirect) != 0;
    constexpr bool kSpecular = (F & kFeatSpecular) != 0;
    std::array<PathState, kLanes> paths;
    VertexSampleLanes samples;
    std::array<bool, kLanes> alive, has_shadow, blocked;
    RayPacket shadow;
    // Shadow rays at their paths' times (set() keeps a lane's time).
    if constexpr ((F & kFeatMotion) != 0)
        std::copy(std::begin(rays.time), std::end(rays.time), std::begin(shadow.time));
    alive.fill(false);
    std::fill(alive.begin(), alive.begin() + std::ptrdiff_t(n), true);
    for (int depth = 0;; ++depth) {
        if (depth > 0) {
            int live = 0;
            for (std::size_t k = 0; k < n; ++k) live += alive[k];
            if (live == 0) break;
            if (live < kMinPacketLanes) {
                for (std::size_t k = 0; k < n; ++k)
                    if (alive[k])
                        found[k] = trace<F>(scene, rays.get(k), lane_time<F>(rays, k), hits[k]);
            } else {
                scene.intersect_packet(rays, n, hits.data(), found.data(), alive.data());
            }
        }
        // Dimension 0 was the film position; a vertex that shades draws from its own block.
        // Past max_depth (and past the first bounce without indirect light or mirrors) a
        // vertex only looks for emission.
        if (depth < max_depth && (kIndirect || kSpecular || depth < 1))
            samples.draw<F>(seeds, index, depth);
        bool any_shadow = false;
        for (std::size_t k = 0; k < n; ++k) {
            has_shadow[k] = false;
            if (!alive[k]) continue;
            alive[k] = path_vertex<F>(scene, light_dist, paths[k], rays, k, found[k], hits[k],
                                      samples.lane(k), has_shadow[k], shadow, depth, max_depth, c);
            any_shadow |= has_shadow[k];
        }
        if (any_shadow) {
            scene.occluded_packet(shadow, n, has_shadow.data(), blocked.data());
            for (std::size_t k = 0; k < n; ++k)
                if (has_shadow[k] && !blocked[k]) paths[k].L += paths[k].nee;
        }
    }
    for (std::size_t k = 0; k < n; ++k) L[k] = paths[k].L;
    if constexpr ((F & kFeatAlpha) != 0)
        for (std::size_t k = 0; k < n; ++k) T[k] = paths[k].transparent;
}

// ---- direct: local illumination (C&W eq. 2.42) + perfect mirror recursion ----

// The radiance along camera ray `ray`, whose closest hit the caller traced (`first_hit` when
// `found`); `s` starts at dimension 1.
template <std::uint32_t F>
Rgb direct_li(const Scene& scene, Ray ray, [[maybe_unused]] float time, bool found,
              const SurfaceHit& first_hit, Sampler& s, int max_depth, KernelCounters& c,
              [[maybe_unused]] float& T) {
    constexpr bool kSpecular = (F & kFeatSpecular) != 0;
    constexpr bool kEmission = (F & kFeatEmission) != 0;
    constexpr bool kArea = (F & kFeatAreaSampling) != 0;
    constexpr bool kTransmission = (F & kFeatTransmission) != 0;
    constexpr bool kTextured = (F & kFeatTextured) != 0;
    const std::span<const Light> lights = scene.lights();
    // Dimensions of one depth: one per light, then one for the lobe choice of a smooth
    // dielectric (transmission kernel only).
    const std::uint32_t block = 1u + std::uint32_t(lights.size());

    Rgb L(0.f), beta(1.f);
    // The hit being shaded: the caller's record at depth 0 (read in place: the record is large
    // and most kernels shade one hit per sample), `next` for mirror bounces and for a textured
    // hit whose shading normal is changed.
    const SurfaceHit* hp = &first_hit;
    [[maybe_unused]] SurfaceHit next;
    [[maybe_unused]] bool see_through = true;   // alpha (as in path_vertex)
    if (scene.has_camera_lamps()) [[unlikely]]  // as in path_vertex
        L += scene.camera_lamps(ray.o, ray.d, found ? first_hit.t : kInfinity);
    for (int depth = 0;; ++depth) {
        if constexpr (kSpecular) {
            if (depth > 0) {
                found = trace<F>(scene, ray, time, next);
                hp = &next;
            }
        }
        if constexpr ((F & kFeatAlpha) != 0) {
            if (see_through) {
                if (!found) {
                    if (scene.settings().film_transparent) {
                        T += mean3(beta);
                        break;
                    }
                } else if (const float h = holdout_at(scene, *hp, ray.d); h > 0.f) {
                    T += h * mean3(beta);
                    if (h >= 1.f) break;
                }
            }
        }
        if (!found) {
            if constexpr (kEmission) {
                if (const Light* env = scene.environment()) L += beta * env->le_escape(ray.d);
            }
            break;
        }
        if constexpr (kEmission) L += beta * hp->emitted_radiance;
        // A textured hit's material is built for it (only in the textured kernel, as in
        // path_vertex).
        const Material* mp = hp->material;
        [[maybe_unused]] std::optional<Material> textured;
        if constexpr (kTextured) {
            if (hp->textured >= 0) {
                if (hp != &next) next = *hp;
                hp = &next;
                mp = &scene.bsdf_at(next, ray, depth == 0, textured);
            }
        }
        const SurfaceHit& hit = *hp;
        const Material& m = *mp;
        Shading sh;
        bool transmissive = false;
        if constexpr (kTransmission) transmissive = m.transmissive();
        if (transmissive)
            make_transmissive_shading(hit, m, ray.d, sh);
        else if (!make_shading<F>(hit, m, ray.d, sh))
            break;
        const LightSampleContext ctx{hit.p, transmissive ? Vec3(0.f) : sh.ns};
        const std::uint32_t base = 1u + block * std::uint32_t(depth);

        // Sum over every light of f Li |cos theta_i| (delta lights exactly, others one sample).
        if (has_non_specular<F>(m)) {
            for (std::size_t j = 0; j < lights.size(); ++j) {
                const Light& light = lights[j];
                // A textured emitter is not light-sampled (light.h): direct sees it only
                // through camera and mirror rays.
                if (light.textured_emission()) [[unlikely]]
                    continue;
                Vec2 u(0.5f);
                if constexpr (kArea) {
                    if (!light.is_delta()) {
                        s.set_dimension(base + std::uint32_t(j));
                        u = s.get_2d();
                    }
                }
                auto ls = sample_light<F>(light, ctx, u, time);
                if (!ls || !(ls->pdf > 0.f)) continue;
                const Vec3 wi = sh.frame.to_local(ls->wi);
                if (!valid_side(sh, transmissive, ls->wi, wi.z)) continue;
                const Rgb contrib = bsdf_f<F>(m, sh.wo, wi) * std::fabs(wi.z) * ls->li;
                if (!(max3(contrib) > 0.f)) continue;
                ++c.shadow_rays;
                // occluded() starts the shadow ray on the light's side of the surface.
                bool blocked;
                if constexpr ((F & kFeatMotion) != 0)
                    blocked = scene.occluded(hit, *ls, time);
                else
                    blocked = scene.occluded(hit, *ls);
                if (!blocked) L += beta * contrib / ls->pdf;
            }
        }
        // Perfect mirror recursion through the delta lobe.
        if constexpr (kSpecular) {
            std::optional<BSDFSample> ms;
            if (depth < max_depth) {
                if ((transmissive || m.combination()) && is_specular(m.flags())) {
                    // A smooth dielectric or thin pane: one of its two delta lobes, chosen by
                    // Fresnel with the block's last dimension (the estimate stays unbiased). A
                    // combination (mix, add) chooses a child the same way; a non-delta sample
                    // ends the path (light sampling above counted that lobe), so the delta
                    // lobes' expected weight is exactly theirs.
                    s.set_dimension(base + std::uint32_t(lights.size()));
                    ms = m.sample_f(sh.wo, s.get_1d(), Vec2(0.f));
                    if (ms && !ms->is_specular()) break;
                } else if (m.mirror()) {
                    ms = m.mirror()->sample_f(sh.wo, 0.f, Vec2(0.f));
                } else {
                    break;
                }
                // (a principled material may answer with a non-delta lobe: not followed here)
                if (!ms || !ms->is_specular()) break;
                const Vec3 wi_w = sh.frame.from_local(ms->wi);
                if (!valid_side(sh, transmissive, wi_w, ms->wi.z)) break;
                if constexpr ((F & kFeatAlpha) != 0)
                    see_through = see_through && passes_straight(*ms, sh.wo);
                beta *= ms->f * (std::fabs(ms->wi.z) / ms->pdf);
                if (!(max3(beta) > 0.f)) break;
                ray = Scene::spawn_ray(hit, wi_w);
                ++c.rays;
                continue;
            }
        }
        break;
    }
    return L;
}

// ---- media: volumetric path tracing (kFeatMedia; integrator.h conventions, "Media") ----

// The media a path is in: medium indices (Scene::media()), innermost last, above the world
// medium. Crossing a boundary against its normal enters the interior (pushed); along it leaves
// (the innermost entry of that medium is removed). Deeper nesting than kMax replaces the
// innermost entry (never reached by sensible scenes: a glass of water in fog is 2).
struct MediumStack {
    static constexpr int kMax = 8;
    std::array<std::int32_t, kMax> m{};
    int n = 0;
    std::int32_t world = -1;

    std::int32_t current() const { return n > 0 ? m[std::size_t(n - 1)] : world; }
    void cross(std::int32_t interior, bool entering) {
        if (interior < 0) return;
        if (entering) {
            m[std::size_t(n < kMax ? n++ : kMax - 1)] = interior;
            return;
        }
        for (int i = n - 1; i >= 0; --i) {
            if (m[std::size_t(i)] != interior) continue;
            for (int j = i; j + 1 < n; ++j) m[std::size_t(j)] = m[std::size_t(j + 1)];
            --n;
            return;
        }
    }
};

// Dimensions of one segment of a media path (sampler.h; a block of its own per segment), from
// the block's start (a 2D pair takes one dimension index: Sampler::get_2d):
//   0 light choice (read by none: LightDistribution::sample), 1 light position (the vertex's
//     light sample: a surface's, a grid medium's, or any medium's with
//     VolumeSampling::Distance),
//   2 lobe choice (surfaces), 3 direction (BSDF or phase function; a subsurface walk's entry
//     direction), 4 roulette,
//   5 light position of a subsurface walk's exit vertex, 6 its cosine-sampled direction,
//   7 channel choice, 8 free-flight distance,
//   9 the seed of the segment's tracking generator (grid media: TrackingRng; the steps of a
//     subsurface walk after its first),
//   10 light choice, 11 light position of the segment's light samples in a homogeneous
//     medium (segment_light), 12 its equiangular distance, 13 a subsurface walk's first step
//     (channel choice, distance).
// A segment takes the same dimensions whatever it meets, so its vertex's light sample and the
// segment's are independent.
constexpr std::uint32_t kMediaDimsPerSegment = 14;
constexpr std::uint32_t kSegmentLightDim = 10;

// The uniform generator of a segment's tracking in grid media (Medium::sample_free_flight,
// ratio_transmittance) and of subsurface walks' later steps: a PCG32 seeded from the sampler at
// dimension `dim` (Sampler::get_seed) on its first draw, so segments that draw nothing (homogeneous
// media, no medium) do not hash the seed.
class TrackingRng {
  public:
    TrackingRng(const Sampler& s, std::uint32_t dim) : m_sampler(s) {
        m_sampler.set_dimension(dim);
    }
    float operator()() {
        if (!m_seeded) [[unlikely]] {
            m_rng = pcg32(m_sampler.get_seed());
            m_seeded = true;
        }
        return float(m_rng() >> 8) * 0x1p-24f;
    }

  private:
    Sampler m_sampler;
    pcg32 m_rng;
    bool m_seeded = false;
};
// A path crosses at most this many `null` surfaces in a row, and a shadow ray this many
// boundaries: a bound against rays that float error traps between two coincident surfaces.
constexpr int kMaxNullCrossings = 64;

// Whether a ray crossing a surface of geometric normal ng along d enters its interior.
inline bool entering(const Vec3& d, const Vec3& ng) {
    return glm::dot(d, ng) < 0.f;
}

// Transmittance of shadow ray r (Scene::shadow_ray_from) that starts in the media `stack`:
// the product of each medium's transmittance over the part of the ray inside it; `null`
// surfaces are crossed, any other surface blocks it (0). For a heterogeneous kind this is where
// ratio tracking goes (Novák et al. 2014), segment by segment as here.
// With `only_catchers` (the catcher-only run after its split) surfaces other than shadow
// catchers are passed as if absent.
template <std::uint32_t F>
Rgb shadow_transmittance(const Scene& scene, Ray r, float time, MediumStack stack, TrackingRng& rng,
                         KernelCounters& c, bool only_catchers = false) {
    if (!(r.tmax > 0.f)) return Rgb(1.f);
    const std::span<const Medium> media = scene.media();
    const bool finite = std::isfinite(r.tmax);
    const Vec3 end = finite ? r.o + r.d * r.tmax : Vec3(0.f);
    Rgb tr(1.f);
    for (int i = 0; i <= kMaxNullCrossings; ++i) {
        SurfaceHit h;
        ++c.shadow_rays;
        const bool hit = trace<F>(scene, r, time, h);
        if (const std::int32_t med = stack.current(); med >= 0) {
            const Medium& m = media[std::size_t(med)];
            const float t = hit ? h.t : r.tmax;
            tr *= m.heterogeneous() ? m.ratio_transmittance(r.o, r.d, t, rng) : m.transmittance(t);
        }
        if (!hit) return tr;
        if (!(max3(tr) > 0.f)) return Rgb(0.f);
        // A shape that shadow rays do not see (ray visibility), or that is absent from the
        // catcher-only run, is passed as if not there; a Light Path switch may give shadow rays
        // another material.
        const ShapeInfo* si =
            scene.features().has_ray_visibility ? &scene.shapes()[h.shape] : nullptr;
        const bool absent =
            (only_catchers && !is_catcher(scene, h)) || (si && (si->visibility & kRayShadow) == 0);
        if (!absent) {
            const Material* m = h.material;
            if (si && si->light_path >= 0) {
                if (const LightPathSwitch::Entry* e =
                        light_path_entry(scene, si->light_path, kLpShadow))
                    m = e->material;
            }
            const MediumInterface* mi = scene.medium_interface(m);
            if (!mi || !mi->pass_through) return Rgb(0.f);
            stack.cross(mi->interior, entering(r.d, h.ng));
        }
        r.o = offset_ray_origin(h.p, h.p_err, h.ng, r.d);
        if (finite) {
            r.tmax = glm::dot(end - r.o, r.d);
            if (!(r.tmax > 0.f)) return tr;
        }
    }
    return Rgb(0.f);
}

template <std::uint32_t F>
bool trace_catchers(const Scene& scene, const Ray& ray, float time, SurfaceHit& hit,
                    KernelCounters& c) {
    Ray r = ray;
    for (int i = 0; i <= kMaxNullCrossings; ++i) {
        if (!trace<F>(scene, r, time, hit)) return false;
        if (is_catcher(scene, hit)) {
            hit.t = glm::dot(hit.p - ray.o, ray.d);
            return true;
        }
        r = Scene::spawn_ray(hit, ray.d);
        ++c.rays;
    }
    return false;
}

// The media the camera is in: the boundaries a ray from the camera position leaves before it
// has entered them are around the camera (innermost first found). Once per tile.
MediumStack camera_media(const Scene& scene) {
    MediumStack s;
    s.world = scene.world_medium();
    Ray r{scene.camera().position, scene.camera().forward, kInfinity};
    std::array<std::int32_t, MediumStack::kMax> entered{}, around{};
    int n_entered = 0, n_around = 0;
    for (int i = 0; i <= kMaxNullCrossings; ++i) {
        SurfaceHit h;
        if (!scene.intersect(r, h)) break;
        if (const MediumInterface* mi = scene.medium_interface(h.material);
            mi && mi->interior >= 0) {
            if (entering(r.d, h.ng)) {
                if (n_entered < MediumStack::kMax) entered[std::size_t(n_entered++)] = mi->interior;
            } else {
                int k = n_entered - 1;
                while (k >= 0 && entered[std::size_t(k)] != mi->interior) --k;
                if (k >= 0) {
                    for (int j = k; j + 1 < n_entered; ++j)
                        entered[std::size_t(j)] = entered[std::size_t(j + 1)];
                    --n_entered;
                } else if (n_around < MediumStack::kMax) {
                    around[std::size_t(n_around++)] = mi->interior;
                }
            }
        }
        r = Scene::spawn_ray(h, r.d);
    }
    // The outermost boundary is found last: push from there inward.
    for (int i = n_around - 1; i >= 0; --i) s.cross(around[std::size_t(i)], true);
    return s;
}

// Russian roulette for the media kernel, as path_scatter's: from kRouletteDepth on a path
// survives with probability sqrt(max beta) and survivors are reweighted. False: the path ends.
inline bool roulette(Rgb& beta, int depth, float u) {
    if (!(max3(beta) > 0.f)) return false;
    if (depth + 1 >= kRouletteDepth) {
        const float q = std::max(0.f, 1.f - std::sqrt(max3(beta)));
        if (q > 0.f) {
            if (u < q) return false;
            beta /= 1.f - q;
        }
    }
    return true;
}

// The stratified numbers of a walk and its exit vertex (the segment's dimensions: see
// kMediaDimsPerSegment); the walk's later steps draw from the tracking generator.
struct SubsurfaceSamples {
    SubsurfaceWalkStart start;
    Vec2 light{0.f}, direction{0.f};  // the exit's light sample and cosine-sampled direction
};

// A random walk inside the object of `hit` (integrator.h, "Subsurface"; facet/subsurface.h) and
// the exit vertex: next-event estimation and a cosine-sampled direction with the exit lobe.
// beta holds the lobe's weight over its selection probability on entry; on return (true) the
// path's weight after the exit's sample, L the exit's light sample, `ray` the next ray. False:
// the walk found no exit (the path ends). The entry, the first step and the exit take their
// numbers from the segment's sample dimensions (u_sss), the later steps from `rng` (their number
// is unbounded).
template <std::uint32_t F>
bool subsurface_walk(const Scene& scene, const LightDistribution& light_dist, const SurfaceHit& hit,
                     const Vec3& wo_w, float time, const MediumStack& stack,
                     const Material::Subsurface& sss, const SubsurfaceSamples& u_sss,
                     TrackingRng& rng, KernelCounters& c, Rgb& beta, Rgb& L, Ray& ray,
                     float& prev_pdf, LightSampleContext& prev_ctx) {
    // The entry's normals on the viewer's side (the walk goes into the other).
    const bool front = glm::dot(hit.ng, wo_w) > 0.f;
    const Vec3 n = front ? hit.ns : -hit.ns, ng = front ? hit.ng : -hit.ng;
    // The nearest surface of the same shape along o + t d (t < t_max); other shapes are passed.
    SurfaceHit exit;
    auto intersect = [&](const Vec3& o, const Vec3& d, float t_max, bool first) {
        Ray r{first ? offset_ray_origin(hit.p, hit.p_err, ng, d) : o, d, t_max};
        for (int i = 0; i <= kMaxNullCrossings; ++i) {
            SurfaceHit h;
            ++c.rays;
            if (!trace<F>(scene, r, time, h)) return kInfinity;
            if (h.shape == hit.shape) {
                exit = h;
                return glm::dot(h.p - o, d);
            }
            const Vec3 o2 = offset_ray_origin(h.p, h.p_err, h.ng, d);
            r.tmax = t_max - glm::dot(o2 - o, d);
            if (!(r.tmax > 0.f)) return kInfinity;
            r.o = o2;
        }
        return kInfinity;
    };
    const std::optional<SubsurfaceExit> ex =
        subsurface_random_walk(sss.lobe.walk, hit.p, n, ng, beta, u_sss.start, rng, intersect);
    if (!ex || !(max3(beta) > 0.f)) return false;
    // The exit vertex, seen from outside (the side the walk's last segment points to).
    const bool along = glm::dot(exit.ng, ex->d) > 0.f;
    const Vec3 eng = along ? exit.ng : -exit.ng, ens = along ? exit.ns : -exit.ns;
    const Frame frame = Frame::from_z(ens);
    const bool fresnel = sss.lobe.fresnel;
    const LightSampleContext ctx{exit.p, ens};
    Vec2 u_light = u_sss.light;
    const Vec2 u_dir = u_sss.direction;
    if (!light_dist.empty()) {
        float select_pmf = 1.f;
        std::uint32_t light_index = 0;
        if (scene.lights().size() > 1) light_index = light_dist.sample(ctx, u_light, select_pmf);
        const Light& light = scene.lights()[light_index];
        if (scene.features().has_ray_visibility &&
            !light_reaches(scene, light_index, BxDFFlags::Diffuse))  // the exit's lobe
            select_pmf = 0.f;
        if (auto ls = select_pmf > 0.f ? sample_light<F>(light, ctx, u_light, time) : std::nullopt;
            ls && ls->pdf > 0.f) {
            const float cos_i = glm::dot(ls->wi, ens);
            if (cos_i > 0.f && glm::dot(ls->wi, eng) > 0.f) {
                const Rgb contrib = subsurface_exit_f(fresnel, cos_i) * cos_i * ls->li;
                if (max3(contrib) > 0.f) {
                    const Ray sr = Scene::shadow_ray_from(
                        offset_ray_origin(exit.p, exit.p_err, eng, ls->wi), *ls);
                    const Rgb tr = shadow_transmittance<F>(scene, sr, time, stack, rng, c);
                    const float lp = select_pmf * ls->pdf;
                    const float w =
                        light.hittable() ? power_heuristic(lp, cosine_hemisphere_pdf(cos_i)) : 1.f;
                    L += beta * contrib * tr * (w / lp);
                }
            }
        }
    }
    const Vec3 local = sample_cosine_hemisphere(u_dir);
    const Vec3 wi = frame.from_local(local);
    if (!(local.z > 0.f) || !(glm::dot(wi, eng) > 0.f)) return false;
    beta *= subsurface_exit_f(fresnel, local.z) * kPi;  // f cos / (cos / pi)
    prev_pdf = cosine_hemisphere_pdf(local.z);
    prev_ctx = ctx;
    ray = Ray{offset_ray_origin(exit.p, exit.p_err, eng, wi), wi, kInfinity};
    return true;
}

// Delta tracking in an emitting grid medium, gathering its emission into L: out of line, so
// that the tracking of grids that do not emit is compiled as it would be without emission.
[[gnu::noinline]] float emitting_free_flight(const Medium& med, const Ray& ray, float t_max,
                                             TrackingRng& rng, Rgb& beta, Rgb& L) {
    return med.sample_free_flight(ray.o, ray.d, t_max, rng, beta, L);
}

// Free-flight sampling on a segment of length t_max (+inf when the ray escapes) in medium
// `med`, with the segment's samples u_channel, u_dist: the distance to a scattering event
// (returned, < t_max), or t_max when the ray reaches the segment's end. beta takes the
// estimator's weight: T(t) sigma_s / p(t) at an event, T(t_max) / P(t >= t_max) at the end,
// with p the channel-MIS density (integrator.h). L gains the medium's emission on the segment.
float sample_segment(const Medium& med, const Ray& ray, float t_max, float u_channel, float u_dist,
                     TrackingRng& rng, Rgb& beta, Rgb& L) {
    if (med.heterogeneous()) {
        if (med.grid_emission()) [[unlikely]]
            return emitting_free_flight(med, ray, t_max, rng, beta, L);
        return med.sample_free_flight(ray.o, ray.d, t_max, rng, beta);
    }
    if (med.emits()) L += beta * med.emitted(t_max);
    if (med.absorbing_only()) {
        beta *= med.transmittance(t_max);
        return t_max;
    }
    const float sum = beta.r + beta.g + beta.b;
    if (!(sum > 0.f)) {
        beta = Rgb(0.f);
        return t_max;
    }
    const Rgb pc = beta / sum;  // channel probabilities, in proportion to the throughput
    const int ch = u_channel < pc.r ? 0 : u_channel < pc.r + pc.g ? 1 : 2;
    const float st = med.sigma_t()[ch];
    const float t = st > 0.f ? -std::log1p(-u_dist) / st : kInfinity;
    const Rgb& sigma_t = med.sigma_t();
    if (t < t_max) {
        const Rgb tr = med.transmittance(t);
        const float pdf = glm::dot(pc, sigma_t * tr);
        beta *= tr * med.sigma_s() / pdf;
        return t;
    }
    const Rgb tr = med.transmittance(t_max);
    const float p_pass = glm::dot(pc, tr);
    beta = p_pass > 0.f ? beta * tr / p_pass : Rgb(0.f);
    return t_max;
}

// The power heuristic of density a against b (Veach 1997, eq. 9.13 with beta = 2), from the
// ratio b / a so that tiny densities do not underflow when squared.
inline float power_weight(float a, float b) {
    if (!(a > 0.f)) return 0.f;
    const float r = b / a;
    return 1.f / (1.f + r * r);
}

// Below this optical depth sigma_t,max D of the equiangular density's scale D (the distance
// of the light's point from the ray), the transmittance hardly varies where the equiangular
// distances fall (their weight T sigma_s / p_e varies with T only, p_e following the light's
// 1/r^2): the equiangular sample alone is then taken (weight 1), saving the free flight's
// shadow ray. Above it both, by MIS. On the thin-fog test of test_media.cpp (sigma_t D = 0.025)
// the variance per sample is 2.7e-6 alone, 3.1e-6 with both by MIS.
constexpr float kEquiangularAloneDepth = 0.5f;
// At or above this optical depth sigma_t,max D the free flight's density (scale 1 / sigma_t) is
// narrower than the light's falloff (scale D), which varies by at most 1 / 4 over a mean free
// path: the free-flight distance alone carries the light sample, saving the equiangular one's
// shadow ray. Variance per sample of free flight alone against both by MIS: 0.99 at 4, 1.00 at
// 8 (a point lamp in fog, single scattering); cubes_volume (realscenes, sigma_t D between 4 and
// 8): the same noise, 18% fewer instructions.
constexpr float kFreeFlightAloneDepth = 4.f;

// The light samples of a segment [0, t_hit) of `ray` in homogeneous scattering medium `med`
// (integrator.h conventions, "Media"): one light chosen by u_choice and a point c on it by
// u_light (sampled from the segment's origin); a light sample at the free flight's distance
// when it scattered, and one at the equiangular distance of u_equi toward c, each weighted by
// the power heuristic of its distance density against the other's (two-sample MIS), each
// sampling the light again from its point with u_light. beta0 is the throughput at the
// segment's start, t_ff and beta_ff the free flight's distance and weight (t_ff < t_hit: it
// scattered). Returns what they add to the radiance.
template <std::uint32_t F>
Rgb segment_light(const Scene& scene, const LightDistribution& light_dist, const Medium& med,
                  const Ray& ray, float t_hit, float time, const MediumStack& stack,
                  const Rgb& beta0, float t_ff, const Rgb& beta_ff, float u_choice, Vec2 u_light,
                  float u_equi, TrackingRng& rng, KernelCounters& c, bool only_catchers) {
    const std::span<const Light> lights = scene.lights();
    const float sum = beta0.r + beta0.g + beta0.b;
    if (!(sum > 0.f)) return Rgb(0.f);
    float select_pmf = 1.f;
    std::uint32_t li = 0;
    if (lights.size() > 1) li = light_dist.sample(u_choice, select_pmf);
    const Light& light = lights[li];
    // An emitter that volume-scatter rays do not see lights no medium (Cycles'
    // SHADER_EXCLUDE_SCATTER).
    if (!(select_pmf > 0.f) || !lights_run(scene, light, only_catchers) ||
        (scene.features().has_ray_visibility &&
         (scene.light_visibility()[li] & kRayVolumeScatter) == 0))
        return Rgb(0.f);
    // The point c the equiangular distance aims at: a light sample from the segment's origin,
    // or for an area lamp a point of its surface, uniform by area (no solid-angle sampling from
    // a point that may lie behind the lamp), with the distances on the part of the segment in
    // front of the one-sided lamp (behind it nothing is lit: a camera above a lamp that shines
    // down still aims at it below). Each light sample samples the light again from its point.
    const AreaLamp* lamp = light.get<AreaLamp>();
    std::optional<Equiangular> eq;
    float t_lo = 0.f, t_hi = t_hit;
    if (lamp) {
        const float h0 = glm::dot(ray.o - lamp->center, lamp->normal);
        const float dh = glm::dot(ray.d, lamp->normal);
        if (dh > 0.f)
            t_lo = std::fmax(-h0 / dh, 0.f);
        else if (dh < 0.f)
            t_hi = std::fmin(h0 / -dh, t_hit);
        else if (!(h0 > 0.f))
            return Rgb(0.f);
        if (!(t_hi > t_lo)) return Rgb(0.f);
        const Vec2 q = lamp->ellipse ? sample_uniform_disk_concentric(u_light)
                                     : Vec2(2.f * u_light.x - 1.f, 2.f * u_light.y - 1.f);
        const Vec3 c = lamp->center + q.x * lamp->e1 + q.y * lamp->e2;
        const Equiangular e(ray.o, ray.d, t_lo, t_hi, c);
        if (e.valid()) eq = e;
    } else if (auto ls0 =
                   sample_light<F>(light, LightSampleContext{ray.o, Vec3(0.f)}, u_light, time);
               ls0 && ls0->pdf > 0.f && std::isfinite(ls0->dist)) {
        const Equiangular e(ray.o, ray.d, t_hit, ls0->p_light);
        if (e.valid()) eq = e;
    }
    const Rgb pc = beta0 / sum;  // sample_segment's channel probabilities
    auto free_pdf = [&](float t) { return glm::dot(pc, med.sigma_t() * med.transmittance(t)); };
    // The light sample at distance t, weighted by `weight` (the distance's estimator and MIS).
    auto sample_at = [&](float t, const Rgb& weight) {
        if (!(max3(weight) > 0.f)) return Rgb(0.f);
        const Vec3 p = ray.o + ray.d * t;
        const LightSampleContext ctx{p, Vec3(0.f)};
        const auto ls = sample_light<F>(light, ctx, u_light, time);
        if (!ls || !(ls->pdf > 0.f)) return Rgb(0.f);
        const float ph = med.phase().eval(-ray.d, ls->wi);
        const Rgb contrib = ph * ls->li;
        if (!(max3(contrib) > 0.f)) return Rgb(0.f);
        const Rgb tr = shadow_transmittance<F>(scene, Scene::shadow_ray_from(p, *ls), time, stack,
                                               rng, c, only_catchers);
        const float lp = select_pmf * ls->pdf;
        const float w = light.hittable() ? power_heuristic(lp, ph) : 1.f;
        return weight * contrib * tr * (w / lp);
    };
    // Thin over the light's scale: the equiangular distance alone; dense: the free flight's.
    const Rgb& st = med.sigma_t();
    const float depth_d = eq ? std::fmax(std::fmax(st.r, st.g), st.b) * eq->distance() : 0.f;
    if (depth_d >= kFreeFlightAloneDepth) eq.reset();
    const bool both = !eq || depth_d >= kEquiangularAloneDepth;
    Rgb L(0.f);
    if (both && t_ff < t_hit)  // the free flight scattered inside the segment
        L += sample_at(t_ff, eq ? beta_ff * power_weight(free_pdf(t_ff), eq->pdf(t_ff)) : beta_ff);
    if (eq) {
        const float t = eq->sample(u_equi), pe = eq->pdf(t);
        if (pe > 0.f)
            L += sample_at(t, beta0 * med.transmittance(t) * med.sigma_s() *
                                  ((both ? power_weight(pe, free_pdf(t)) : 1.f) / pe));
    }
    return L;
}

// The radiance along camera ray `ray` (closest hit `first` when `found`, traced by the
// caller) through the scene's media; `s` starts at dimension 1.
template <std::uint32_t F>
Rgb media_path_li(const Scene& scene, const LightDistribution& light_dist, Ray ray, float time,
                  bool found, const SurfaceHit& first, MediumStack stack, Sampler& s, int max_depth,
                  bool volume_mis, KernelCounters& c, [[maybe_unused]] float& T,
                  [[maybe_unused]] CatcherPath* catcher = nullptr) {
    const std::span<const Light> lights = scene.lights();
    const std::span<const Medium> media = scene.media();
    const int num_lights = int(lights.size());
    Rgb L(0.f), beta(1.f);
    bool specular_bounce = false;
    float prev_pdf = 0.f;
    LightSampleContext prev_ctx;
    // The previous vertex's light sample chose its light without a position (segment_light):
    // a light the next ray hits is weighted against that choice.
    bool prev_fixed_pmf = false;
    auto prev_pmf = [&](std::size_t li) {
        return prev_fixed_pmf ? light_dist.pmf(li) : light_dist.pmf(prev_ctx, li);
    };
    SurfaceHit hit = first;
    [[maybe_unused]] bool see_through = true;  // alpha (as in path_vertex)
    bool only_catchers = false;                // the catcher-only run, after its split
    // Ray visibility: the RayVisibility bits a shape must have for the current ray to see it
    // (integrator.h, "Ray visibility"), tested only in scenes with the feature.
    const bool ray_visibility = scene.features().has_ray_visibility;
    std::uint8_t ray_kind = kRayCamera;
    std::uint8_t light_path = kLpCamera;  // the ray's Light Path outputs (LightPathRay)
    // The Light Path state light_path textures read (texture.h RayState): its counters, and
    // the distance the current ray travelled before its origin (shapes it did not see).
    RayState rs;
    float carried = 0.f;
    // Cycles' PATH_RAY_DIFFUSE_ANCESTOR: after a diffuse bounce (or a walk) materials with a
    // subsurface lobe are their diffuse fallback.
    bool diffuse_ancestor = false;
    if (scene.has_camera_lamps()) [[unlikely]]  // as in path_vertex (not attenuated)
        L += scene.camera_lamps(ray.o, ray.d, found ? first.t : kInfinity);
    int depth = 0, nulls = 0;
    for (std::uint32_t segment = 0;; ++segment) {
        if (segment > 0) {
            found = only_catchers ? trace_catchers<F>(scene, ray, time, hit, c)
                                  : trace<F>(scene, ray, time, hit);
            ++c.rays;
        }
        const std::uint32_t base = 1u + kMediaDimsPerSegment * segment;
        const float t_hit = found ? hit.t : kInfinity;
        float t = t_hit;
        TrackingRng rng(s, base + 9u);
        bool segment_nee = false;  // the segment's light sample replaces its vertex's
        if (const std::int32_t mi = stack.current(); mi >= 0) {
            const Medium& med = media[std::size_t(mi)];
            s.set_dimension(base + 7u);
            const float u_channel = s.get_1d(), u_dist = s.get_1d();
            segment_nee = volume_mis && !med.heterogeneous() && !med.absorbing_only() &&
                          depth < max_depth && !light_dist.empty();
            const Rgb beta0 = beta;
            t = sample_segment(med, ray, t_hit, u_channel, u_dist, rng, beta, L);
            if (segment_nee) {
                s.set_dimension(base + kSegmentLightDim);
                const float u_choice = s.get_1d();
                const Vec2 u_light = s.get_2d();
                const float u_equi = s.get_1d();
                L += segment_light<F>(scene, light_dist, med, ray, t_hit, time, stack, beta0, t,
                                      beta, u_choice, u_light, u_equi, rng, c, only_catchers);
            }
            if (!(max3(beta) > 0.f)) break;
        }
        const bool in_medium = t < t_hit;
        const Vec3 wo_w = -ray.d;

        if (!in_medium) {
            // A shape this kind of ray does not see: passed without a vertex, as a `null`
            // crossing (the ray keeps its kind).
            if (ray_visibility && found) [[unlikely]] {
                const ShapeInfo& si = scene.shapes()[hit.shape];
                if ((si.visibility & ray_kind) == 0) {
                    if (++nulls > kMaxNullCrossings) break;
                    carried += hit.t;
                    ray = Scene::spawn_ray(hit, ray.d);
                    continue;
                }
                // A Light Path switch: the material and emission this ray sees.
                if (si.light_path >= 0)
                    apply_light_path(scene, si.light_path, light_path, ray.d, hit);
            }
            // Alpha: nothing but `null` crossings and media so far (as in path_vertex).
            if constexpr ((F & kFeatAlpha) != 0) {
                if (see_through) {
                    if (!found) {
                        // The background a shadow catcher's opaque film shows (film.h).
                        if (catcher && !catcher->split) [[unlikely]]
                            if (const Light* env = scene.environment())
                                catcher->background += beta * env->le_escape(ray.d);
                        if (scene.settings().film_transparent) {
                            T += mean3(beta);
                            break;
                        }
                    } else if (const MediumInterface* mi = scene.medium_interface(hit.material);
                               !(mi && mi->pass_through)) {
                        if (const float h = holdout_at(scene, hit, ray.d); h > 0.f) {
                            T += h * mean3(beta);
                            if (h >= 1.f) break;
                        }
                    }
                }
            }
            // The segment's end: emission found by the ray (full weight from the camera and
            // after a delta lobe; otherwise MIS-weighted against light sampling).
            if (!found) {
                if (const Light* env = scene.environment()) {
                    if (depth == 0 || specular_bounce) {
                        L += beta * env->le_escape(ray.d);
                    } else {
                        float pdf;
                        const Rgb le = env->le_escape(ray.d, prev_ctx, pdf);
                        const float lp = prev_pmf(std::size_t(env - lights.data())) * pdf;
                        L += beta * le * power_heuristic(prev_pdf, lp);
                    }
                }
                break;
            }
            // An invisible boundary: cross it without a vertex.
            const MediumInterface* iface = scene.medium_interface(hit.material);
            if (iface && iface->pass_through) {
                if (++nulls > kMaxNullCrossings) break;
                stack.cross(iface->interior, entering(ray.d, hit.ng));
                ray = Scene::spawn_ray(hit, ray.d);
                carried = 0.f;  // a transparent bounce (Cycles restarts the ray there)
                continue;
            }
            nulls = 0;
            // Shadow catcher: a see-through path's first catcher splits it (integrator.h).
            if constexpr ((F & kFeatAlpha) != 0) {
                if (catcher && see_through && !catcher->split && is_catcher(scene, hit)) {
                    catcher->split = true;
                    if (catcher->catchers_only) {
                        L = Rgb(0.f);
                        only_catchers = true;
                    } else {
                        catcher->matte = L;
                        catcher->split_t = mean3(beta);
                        if (const Light* env = scene.environment())
                            catcher->background += beta * env->le_escape(ray.d);
                    }
                }
            }
            if (hit.light >= 0 && max3(hit.emitted_radiance) > 0.f) {
                if (depth == 0 || specular_bounce) {
                    L += beta * hit.emitted_radiance;
                } else {
                    const std::size_t li = std::size_t(hit.light);
                    const float lp =
                        prev_pmf(li) * hit_light_pdf<F>(lights[li], prev_ctx, ray.d, hit, time);
                    L += beta * hit.emitted_radiance * power_heuristic(prev_pdf, lp);
                }
            } else if (hit.light == kEmitterNotSampled) [[unlikely]] {
                // An emitter that is no light source (ray visibility): no light sample can
                // find it, so the ray's own estimate has full weight.
                L += beta * hit.emitted_radiance;
            }
            if (depth >= max_depth) break;

            // A surface vertex: its material (textured hits build theirs), shading frame,
            // light sample with the shadow ray's transmittance, BSDF sample.
            std::optional<Material> textured;
            rs.length = carried + hit.t;
            rs.kinds = light_path;
            carried = 0.f;
            const Material& m = scene.bsdf_at(hit, ray, depth == 0, textured, &rs);
            Shading sh;
            const bool transmissive = m.transmissive();
            if (transmissive)
                make_transmissive_shading(hit, m, ray.d, sh);
            else if (!make_shading<F>(hit, m, ray.d, sh))
                break;
            const LightSampleContext ctx{hit.p, transmissive ? Vec3(0.f) : sh.ns};
            const std::int32_t interior = iface ? iface->interior : -1;
            // The media on the side a direction w leaves to.
            auto stack_toward = [&](const Vec3& w) {
                MediumStack st = stack;
                if (glm::dot(w, hit.ng) * glm::dot(wo_w, hit.ng) < 0.f)
                    st.cross(interior, entering(w, hit.ng));
                return st;
            };
            s.set_dimension(base + 1u);  // past the light choice's dimension (read by none)
            Vec2 u_light = s.get_2d();
            const float u_lobe = s.get_1d();
            const Vec2 u_bsdf = s.get_2d();
            const float u_roulette = s.get_1d();
            // Subsurface (integrator.h, "Subsurface"): on a path without a diffuse bounce the
            // material is its walk beside its surface closures `bm` (chosen with probability
            // 1 - p_walk; their pdfs carry that factor in MIS).
            const Material::Subsurface* sss = diffuse_ancestor ? nullptr : m.subsurface();
            const Material* bm = sss ? sss->surface.get() : &m;
            const float p_walk = sss ? sss->probability(sh.wo) : 0.f;
            const float p_bsdf = 1.f - p_walk;
            if (bm && !light_dist.empty() && has_non_specular<F>(*bm)) {
                const Material& mb = *bm;
                float select_pmf = 1.f;
                std::uint32_t light_index = 0;
                if (num_lights > 1) light_index = light_dist.sample(ctx, u_light, select_pmf);
                const Light& light = lights[light_index];
                if (ray_visibility && !light_reaches(scene, light_index, mb.flags()))
                    select_pmf = 0.f;
                if (auto ls = select_pmf > 0.f && lights_run(scene, light, only_catchers)
                                  ? sample_light<F>(light, ctx, u_light, time)
                                  : std::nullopt) {
                    const Vec3 wi = sh.frame.to_local(ls->wi);
                    if (valid_side(sh, transmissive, ls->wi, wi.z) && ls->pdf > 0.f) {
                        const BSDFEval e = bsdf_eval<F>(mb, sh.wo, wi);
                        const Rgb contrib = e.f * std::fabs(wi.z) * ls->li;
                        if (max3(contrib) > 0.f) {
                            const Ray sr = Scene::shadow_ray_from(
                                offset_ray_origin(hit.p, hit.p_err, hit.ng, ls->wi), *ls);
                            const Rgb tr = shadow_transmittance<F>(
                                scene, sr, time, stack_toward(ls->wi), rng, c, only_catchers);
                            const float lp = select_pmf * ls->pdf;
                            const float w =
                                light.hittable() ? power_heuristic(lp, e.pdf * p_bsdf) : 1.f;
                            L += beta * contrib * tr * (w / lp);
                        }
                    }
                }
            }
            // The walk, after the light sample of the closures beside it (Cycles' entry).
            if (sss && u_lobe < p_walk) {
                beta *= sss->lobe.weight / p_walk;
                SubsurfaceSamples u_sss;
                u_sss.start.entry = u_bsdf;  // the closures' direction pair, unused by a walk
                s.set_dimension(base + 5u);
                u_sss.light = s.get_2d();
                u_sss.direction = s.get_2d();
                s.set_dimension(base + 13u);
                u_sss.start.first = s.get_2d();
                if (!subsurface_walk<F>(scene, light_dist, hit, wo_w, time, stack, *sss, u_sss, rng,
                                        c, beta, L, ray, prev_pdf, prev_ctx))
                    break;
                prev_fixed_pmf = false;
                specular_bounce = false;
                see_through = false;
                diffuse_ancestor = true;
                ray_kind = kRayDiffuse;  // the exit's cosine lobe
                light_path = std::uint8_t(kLpReflection | kLpDiffuse);
                ++rs.depth;
                ++rs.diffuse;
                if (!roulette(beta, depth, u_roulette)) break;
                ++depth;
                ++c.rays;
                continue;
            }
            if (!bm) break;
            const Material& mb = *bm;
            const float u_bsdf_lobe =
                sss ? std::min((u_lobe - p_walk) / p_bsdf, kOneMinusEpsilon) : u_lobe;
            const std::optional<BSDFSample> bs = bsdf_sample<F>(mb, sh.wo, u_bsdf_lobe, u_bsdf);
            if (!bs || !(bs->pdf > 0.f)) break;
            const Vec3 wi_w = sh.frame.from_local(bs->wi);
            if (!valid_side(sh, transmissive, wi_w, bs->wi.z)) break;
            beta *= bs->f * (std::fabs(bs->wi.z) / (bs->pdf * p_bsdf));
            specular_bounce = bs->is_specular();
            if (any(bs->flags & BxDFFlags::Diffuse)) diffuse_ancestor = true;
            if constexpr ((F & kFeatAlpha) != 0)
                see_through = see_through && passes_straight(*bs, sh.wo);
            // The next ray's kind (a straight pass-through keeps it, as Cycles' transparent
            // bounce does); a mirror reflection is a glossy ray, any transmission one kind.
            if (!passes_straight(*bs, sh.wo)) {
                const bool crosses = bs->wi.z * sh.wo.z < 0.f;
                const bool diffuse = any(bs->flags & BxDFFlags::Diffuse);
                ray_kind = crosses ? kRayTransmission : diffuse ? kRayDiffuse : kRayGlossy;
                const int lobe = diffuse             ? kLpDiffuse
                                 : bs->is_specular() ? kLpGlossy | kLpSingular
                                                     : kLpGlossy;
                light_path = std::uint8_t((crosses ? kLpTransmission : kLpReflection) | lobe);
                ++rs.depth;
                ++(crosses ? rs.transmission : diffuse ? rs.diffuse : rs.glossy);
            }
            prev_pdf = bs->pdf * p_bsdf;
            prev_ctx = ctx;
            prev_fixed_pmf = false;
            stack = stack_toward(wi_w);
            ray = Scene::spawn_ray(hit, wi_w);
            if (!roulette(beta, depth, u_roulette)) break;
        } else {
            // A scattering event in the medium: light sample through the media, then the
            // phase function's direction.
            nulls = 0;
            if (depth >= max_depth) break;
            const Medium& med = media[std::size_t(stack.current())];
            const Vec3 p = ray.o + ray.d * t;
            const LightSampleContext ctx{p, Vec3(0.f)};
            // The light sample's numbers (past the light choice's dimension, read by none) when
            // the segment's samples do not replace it; no lobe choice in a medium.
            Vec2 u_light(0.f);
            if (!segment_nee) {
                s.set_dimension(base + 1u);
                u_light = s.get_2d();
            }
            s.set_dimension(base + 3u);  // the direction's (a pair takes one dimension index)
            const Vec2 u_dir = s.get_2d();
            const float u_roulette = s.get_1d();
            if (!segment_nee && !light_dist.empty()) {
                float select_pmf = 1.f;
                std::uint32_t light_index = 0;
                if (num_lights > 1) light_index = light_dist.sample(ctx, u_light, select_pmf);
                const Light& light = lights[light_index];
                // An emitter that volume-scatter rays do not see lights no medium (Cycles'
                // SHADER_EXCLUDE_SCATTER).
                if (ray_visibility &&
                    (scene.light_visibility()[light_index] & kRayVolumeScatter) == 0)
                    select_pmf = 0.f;
                if (auto ls = select_pmf > 0.f && lights_run(scene, light, only_catchers)
                                  ? sample_light<F>(light, ctx, u_light, time)
                                  : std::nullopt;
                    ls && ls->pdf > 0.f) {
                    const float ph = med.phase().eval(wo_w, ls->wi);
                    const Rgb contrib = ph * ls->li;
                    if (max3(contrib) > 0.f) {
                        const Rgb tr =
                            shadow_transmittance<F>(scene, Scene::shadow_ray_from(p, *ls), time,
                                                    stack, rng, c, only_catchers);
                        const float lp = select_pmf * ls->pdf;
                        const float w = light.hittable() ? power_heuristic(lp, ph) : 1.f;
                        L += beta * contrib * tr * (w / lp);
                    }
                }
            }
            const std::optional<PhaseSample> ps = med.phase().sample(wo_w, u_dir);
            if (!ps || !(ps->pdf > 0.f)) break;
            beta *= ps->p / ps->pdf;
            specular_bounce = false;
            see_through = false;
            // Cycles 3.4 lets volume-scatter rays also see what diffuse rays see.
            ray_kind = std::uint8_t(kRayVolumeScatter | kRayDiffuse);
            light_path = 0;
            ++rs.depth;
            carried = 0.f;
            prev_pdf = ps->pdf;
            prev_ctx = ctx;
            prev_fixed_pmf = segment_nee;
            ray = Ray{p, ps->wi, kInfinity};
            if (!roulette(beta, depth, u_roulette)) break;
        }
        ++depth;
        ++c.rays;
    }
    return L;
}

// ---- shadow catcher: a camera sample's two runs (integrator.h, "Shadow catcher") ----

// What a camera sample adds to its pixel's CatcherSums (film.h). (No initialisers: the tile
// loop's array of them costs nothing in the kernels that never use it.)
struct CatcherSample {
    Rgb matte, catcher, background;
    float split_t;
    bool split;
};

// The full run of a camera sample (its radiance, returned, and transparency T), then, when it
// met a catcher, the catcher-only run from the same sample values (`seed`, `index`: every
// decision before the split repeats exactly); `out` gets the sums' shares.
template <std::uint32_t F>
[[gnu::noinline]] Rgb catcher_sample(const Scene& scene, const TileJob& job, const Ray& ray,
                                     float time, bool found, const SurfaceHit& first,
                                     const MediumStack& stack, std::uint32_t seed,
                                     std::uint32_t index, KernelCounters& c, float& T,
                                     CatcherSample& out) {
    CatcherPath full;
    Sampler s(seed, index, 1u);
    const Rgb L = media_path_li<F>(scene, *job.light_distribution, ray, time, found, first, stack,
                                   s, job.max_depth, false, c, T, &full);
    out = CatcherSample{Rgb(0.f), Rgb(0.f), Rgb(0.f), 0.f, false};
    if (!full.split) {
        if (film_accepts(full.background)) out.background = full.background;
        return L;
    }
    CatcherPath only;
    only.catchers_only = true;
    Sampler s2(seed, index, 1u);
    float t_unused = 0.f;
    out.catcher = media_path_li<F>(scene, *job.light_distribution, ray, time, found, first, stack,
                                   s2, job.max_depth, false, c, t_unused, &only);
    // A sample the film drops (film_accepts), or whose shares it would drop, counts as one that
    // met no catcher.
    if (film_accepts(L) && film_accepts(out.catcher) && film_accepts(full.matte) &&
        film_accepts(full.background) && std::fabs(full.split_t) < kMaxSampleValue) {
        out.split = true;
        out.matte = full.matte;
        out.background = full.background;
        out.split_t = full.split_t;
    } else {
        out.catcher = Rgb(0.f);
    }
    return L;
}

// Adds the lanes [k0, k1)'s catcher shares to the film's CatcherSums at `px` (lane k0's pixel).
// L holds the lanes' accepted radiance (0 where the film dropped a sample): a sample that met
// no catcher is all matte.
inline void add_catcher_sums(FixedSum* px, const Rgb* L, const CatcherSample* cs, std::size_t k0,
                             std::size_t k1) {
    using C = CatcherSums;
    for (std::size_t k = k0; k < k1; ++k, px += kCatcherSums) {
        const CatcherSample& s = cs[k];
        const Rgb matte = s.split ? s.matte : L[k];
        if (s.split) px[C::kCount] += to_fixed(1.f);
        for (int i = 0; i < 3; ++i) {
            px[C::kMatte + std::size_t(i)] += to_fixed(matte[i]);
            px[C::kCatcher + std::size_t(i)] += to_fixed(s.catcher[i]);
            px[C::kBackground + std::size_t(i)] += to_fixed(s.background[i]);
        }
        px[C::kSplitT] += to_fixed(s.split_t);
    }
}

// ---- tile loop ----

// The Depth pass of a camera packet (TileJob::depth): lanes [k0, k1) that hit add their first
// hit's view-axis depth (aov.h's, as render_aovs computes it) to `depth` and count to `count`
// (the film pixels of lanes k0...). Out of line: renders without the pass skip it with one test.
[[gnu::noinline]] void add_camera_depth(const Camera& cam, const SurfaceHit* hits,
                                        const bool* found, std::size_t k0, std::size_t k1,
                                        FixedSum* depth, std::uint32_t* count) {
    for (std::size_t k = k0; k < k1; ++k) {
        if (!found[k]) continue;
        depth[k - k0] += to_fixed(view_axis_depth(cam, hits[k].p));
        ++count[k - k0];
    }
}

template <IntegratorKind I, std::uint32_t F>
void render_tile(const Scene& scene, const TileJob& job, FixedRgb* sums, KernelCounters& c) {
    const Camera& cam = scene.camera();
    const int width = cam.width;
    RayPacket rays;
    std::array<bool, kLanes> found;
    std::array<SurfaceHit, kLanes> hits;
    // The lane sampler draws all kLanes lanes; past the end of a short row they hold stale or
    // zero seeds, and their values are never read.
    std::array<std::uint32_t, kLanes> seeds{}, sample_seeds{};
    alignas(32) std::array<float, kLanes> film_x, film_y, lens_x, lens_y;
    [[maybe_unused]] alignas(32) std::array<float, kLanes> times;
    std::array<Rgb, kLanes> L;
    [[maybe_unused]] std::array<float, kLanes> T;               // transparency (alpha kernels)
    [[maybe_unused]] std::array<CatcherSample, kLanes> caught;  // shadow catcher (job.catcher)
    // Packets of kLanes neighbouring pixels of a row, aligned to multiples of kLanes in x over
    // the whole image, so that a pixel is traced in the same packet whatever the tile or region
    // (render.h); lanes outside the tile are traced and not written.
    const int gx_begin = job.x0 - job.x0 % int(kLanes);
    [[maybe_unused]] MediumStack camera_stack;
    if constexpr ((F & kFeatMedia) != 0) camera_stack = camera_media(scene);
    const std::uint32_t seed_hash = Sampler::render_seed_hash(job.seed);
    // The column half of the pixel-seed hash (Sampler::column_seed_hash) is the same in every
    // row: it is computed once per tile for the packets' first kSeedColumns pixels (a
    // 16-pixel tile's packets span 24 at most) and per packet beyond them (wider tiles), so that
    // 1-sample passes do not hash both halves for every packet of every pass (instruction
    // counts: docs/performance.md, "Library").
    constexpr int kSeedColumns = 64;
    std::array<std::uint32_t, kSeedColumns> column_hash;
    const int gx_end = std::min(width, job.x1 + (int(kLanes) - job.x1 % int(kLanes)) % int(kLanes));
    const int hashed_columns = std::min(kSeedColumns, gx_end - gx_begin);
    for (int i = 0; i < hashed_columns; ++i)
        column_hash[std::size_t(i)] = Sampler::column_seed_hash(gx_begin + i, seed_hash);
    for (int y = job.y0; y < job.y1; ++y) {
        FixedRgb* const film_row =
            sums + std::size_t(y - job.film_y0) * std::size_t(job.film_width);
        // The camera rays of a packet for one sample index are traced together (coherent), and
        // the path integrator traces the rest of their paths together too.
        for (int x0 = gx_begin; x0 < job.x1; x0 += int(kLanes)) {
            const std::size_t n = std::min(kLanes, std::size_t(width - x0));
            const int col = x0 - gx_begin;
            if (col + int(n) <= hashed_columns) {
                for (std::size_t k = 0; k < n; ++k)
                    seeds[k] = Sampler::pixel_seed_of_column(column_hash[std::size_t(col) + k], y);
            } else {
                for (std::size_t k = 0; k < n; ++k)
                    seeds[k] = Sampler::pixel_seed_hashed(x0 + int(k), y, seed_hash);
            }
            // The lanes [k0, k1) of the packet that lie in the tile, and their film sums.
            const std::size_t k0 = std::size_t(std::max(job.x0 - x0, 0));
            const std::size_t k1 = std::size_t(std::min(job.x1 - x0, int(n)));
            FixedRgb* const film_px = film_row + std::size_t(x0 + int(k0) - job.film_x0);
            // Each sample is added to the packet's film sums (48 B a pixel) directly (integer
            // sums: the same bits as summing the packet's samples first, with no accumulator to
            // zero and no second pass over the lanes, which matter at 1-sample passes). Fetch
            // the sums now, so that the miss overlaps the tracing: at
            // 1-sample passes of a large film every pass sweeps the whole film.
            if (k0 < k1) {
                const char* b = reinterpret_cast<const char*>(film_px);
                const std::size_t bytes = (k1 - k0) * sizeof(FixedRgb);
                for (std::size_t o = 0; o < bytes; o += 64) __builtin_prefetch(b + o, 1, 3);
                __builtin_prefetch(b + bytes - 1, 1, 3);
            }
            for (int i = job.first_sample; i < job.end_sample; ++i) {
                // Independent samples (RenderOptions::independent_samples): a fresh seed per
                // sample and index 0, whose scrambled point is uniform and independent.
                std::uint32_t index = std::uint32_t(i);
                if (job.independent_samples) {
                    for (std::size_t k = 0; k < n; ++k)
                        sample_seeds[k] = hash_combine(seeds[k], std::uint32_t(i));
                    index = 0u;
                }
                const std::uint32_t* ss =
                    job.independent_samples ? sample_seeds.data() : seeds.data();
                // Film position: dimension 0 (the pixel centre when spp = 1).
                if (job.spp_total == 1) {
                    film_x.fill(0.5f);
                    film_y.fill(0.5f);
                } else {
                    sample_2d_lanes(ss, index, 0u, film_x.data(), film_y.data());
                }
                if (cam.has_lens()) {
                    // The lens point: its own dimension pair (integrator.h), only with a lens.
                    sample_2d_lanes(ss, index, kLensDimension, lens_x.data(), lens_y.data());
                    if constexpr ((F & kFeatMotion) == 0) {
                        for (std::size_t k = 0; k < n; ++k) {
                            const Vec2 film(float(x0 + int(k)) + film_x[k], float(y) + film_y[k]);
                            rays.set(k, cam.generate_ray(film, Vec2(lens_x[k], lens_y[k])));
                        }
                    }
                } else if constexpr ((F & kFeatMotion) == 0) {
                    camera_packet(cam, x0, y, film_x.data(), film_y.data(), n, rays);
                }
                if constexpr ((F & kFeatMotion) != 0) {
                    // The shutter time: its own dimension (integrator.h), drawn from the
                    // shutter curve; the camera ray from the camera at that time.
                    sample_1d_lanes(ss, index, kTimeDimension, times.data());
                    const CameraMotion& motion = scene.camera_motion();
                    for (std::size_t k = 0; k < n; ++k) {
                        const float tau = scene.shutter().sample(times[k]);
                        const Vec2 film(float(x0 + int(k)) + film_x[k], float(y) + film_y[k]);
                        const Vec2 lens(cam.has_lens() ? Vec2(lens_x[k], lens_y[k]) : Vec2(0.f));
                        rays.set(k, motion.moves() ? motion.at(tau).generate_ray(film, lens)
                                                   : cam.generate_ray(film, lens));
                        rays.time[k] = tau;
                    }
                }
                scene.intersect_packet(rays, n, hits.data(), found.data());
                c.camera_rays += n;
                c.rays += n;
                if constexpr ((F & kFeatMotion) == 0) {
                    if (job.depth) [[unlikely]]
                        add_camera_depth(cam, hits.data(), found.data(), k0, k1,
                                         job.depth + (film_px - sums),
                                         job.depth_hits + (film_px - sums));
                }
                if constexpr ((F & kFeatMedia) != 0) {
                    for (std::size_t k = 0; k < n; ++k) {
                        Sampler s(ss[k], index, 1u);
                        T[k] = 0.f;
                        if constexpr ((F & kFeatAlpha) != 0) {
                            if (job.catcher) [[unlikely]] {
                                L[k] = catcher_sample<F>(
                                    scene, job, rays.get(k), lane_time<F>(rays, k), found[k],
                                    hits[k], camera_stack, ss[k], index, c, T[k], caught[k]);
                                continue;
                            }
                        }
                        L[k] = media_path_li<F>(
                            scene, *job.light_distribution, rays.get(k), lane_time<F>(rays, k),
                            found[k], hits[k], camera_stack, s, job.max_depth,
                            job.volume_sampling == VolumeSampling::MultipleImportance, c, T[k]);
                    }
                } else if constexpr (I == IntegratorKind::Path) {
                    path_packet<F>(scene, *job.light_distribution, n, rays, hits, found, ss, index,
                                   job.max_depth, c, L.data(), T.data());
                } else {
                    for (std::size_t k = 0; k < n; ++k) {
                        // Dimension 0 was the film position; direct_li sets every other.
                        Sampler s(ss[k], index, 1u);
                        T[k] = 0.f;
                        L[k] = direct_li<F>(scene, rays.get(k), lane_time<F>(rays, k), found[k],
                                            hits[k], s, job.max_depth, c, T[k]);
                    }
                }
                for (std::size_t k = 0; k < n; ++k) {
                    // A NaN/inf (or absurdly large) estimate would poison the pixel forever:
                    // drop it (a zero adds nothing to the sum) and count it.
                    if (!film_accepts(L[k])) {
                        ++c.nonfinite;
                        L[k] = Rgb(0.f);
                    }
                }
                // Lanes outside the tile were traced (packet alignment) and are not written.
                for (std::size_t k = k0; k < k1; ++k) {
                    FixedRgb& px = film_px[k - k0];
                    px.c[0] += to_fixed(L[k].x);
                    px.c[1] += to_fixed(L[k].y);
                    px.c[2] += to_fixed(L[k].z);
                }
                if constexpr ((F & kFeatMedia) != 0 && (F & kFeatAlpha) != 0) {
                    if (job.catcher) [[unlikely]]
                        add_catcher_sums(job.catcher + (film_px - sums) * kCatcherSums, L.data(),
                                         caught.data(), k0, k1);
                }
                if constexpr ((F & kFeatAlpha) != 0) {
                    // Coverage 1 - T (film.h), when the film keeps it (a transparent film; a
                    // holdout in an opaque one only blacks out); a non-finite T counts as
                    // covered.
                    if (!job.alpha) continue;
                    FixedSum* const alpha_px = job.alpha + (film_px - sums);
                    for (std::size_t k = k0; k < k1; ++k) {
                        const float a = 1.f - T[k];
                        alpha_px[k - k0] += to_fixed(std::fabs(a) < kMaxSampleValue ? a : 1.f);
                    }
                }
            }
        }
    }
}

// Kernel tables indexed by the feature bits.
constexpr std::uint32_t kFeatureBits = 6;
constexpr std::size_t kTableSize = std::size_t(1) << kFeatureBits;

// Features each integrator's kernels actually read; the others are masked off so that only
// 32 path and 16 direct kernels are instantiated.
constexpr std::uint32_t kPathMask =
    kFeatLambertOnly | kFeatSpecular | kFeatMis | kFeatEmission | kFeatIndirect;
constexpr std::uint32_t kDirectMask =
    kFeatLambertOnly | kFeatSpecular | kFeatEmission | kFeatAreaSampling;

template <IntegratorKind I, std::uint32_t Mask, std::size_t... N>
constexpr std::array<TileKernel, kTableSize> make_table(std::index_sequence<N...>) {
    return {&render_tile<I, std::uint32_t(N) & Mask>...};
}

std::string feature_list(IntegratorKind kind, std::uint32_t f) {
    std::string s;
    auto add = [&](bool on, const char* yes, const char* no) {
        const char* w = on ? yes : no;
        if (!*w) return;
        if (!s.empty()) s += ",";
        s += w;
    };
    add(f & kFeatLambertOnly, "lambert-only", "");
    add(f & kFeatTransmission, "transmission", "");
    add(f & kFeatTextured, "textured", "");
    add(f & kFeatSpecular, "specular", "no-specular");
    add(f & kFeatMedia, "media", "");
    add(f & kFeatMotion, "motion", "");
    add(f & kFeatAlpha, "alpha", "");
    if (kind == IntegratorKind::Path) {
        add(f & kFeatMis, "mis", "no-mis");
        add(f & kFeatEmission, "emission", "no-emission");
        add(f & kFeatIndirect, "indirect", "no-indirect");
    } else {
        add(f & kFeatAreaSampling, "area-sampling", "delta-lights-only");
        add(f & kFeatEmission, "emission", "no-emission");
    }
    return s;
}

}  // namespace

[[gnu::noinline]] void apply_light_path(const Scene& scene, std::int32_t index, std::uint8_t lp,
                                        const Vec3& d, SurfaceHit& hit) {
    const LightPathSwitch::Entry* e = light_path_entry(scene, index, lp);
    if (!e) return;
    hit.material = e->material;
    hit.textured = -1;
    hit.emitted_radiance = glm::dot(hit.ng, d) < 0.f ? e->emission : Rgb(0.f);
    if (hit.light == -1 && (e->emission.r > 0.f || e->emission.g > 0.f || e->emission.b > 0.f))
        hit.light = kEmitterNotSampled;
}

// Camera::perspective_direction on SSE vectors, four lanes at a time: the same operations as
// generate_ray's, lane by lane.
void camera_packet(const Camera& cam, int x0, int y, const float* film_x, const float* film_y,
                   std::size_t n, RayPacket& rays) {
#if defined(__SSE2__)
    static_assert(kLanes == RayPacket::kSize && kLanes % 4 == 0);
    if (cam.projection == Projection::Perspective) {
        const __m128 row = _mm_set1_ps(float(y));
        for (std::size_t k = 0; k < kLanes; k += 4) {
            const int x = x0 + int(k);
            const __m128 fx =
                _mm_cvtepi32_ps(_mm_setr_epi32(x, x + 1, x + 2, x + 3)) + _mm_loadu_ps(film_x + k);
            const __m128 fy = row + _mm_loadu_ps(film_y + k);
            __m128 dx, dy, dz;
            cam.perspective_direction(cam.window_x(fx), cam.window_y(fy), dx, dy, dz,
                                      [](__m128 v) { return _mm_sqrt_ps(v); });
            _mm_storeu_ps(rays.dx + k, dx);
            _mm_storeu_ps(rays.dy + k, dy);
            _mm_storeu_ps(rays.dz + k, dz);
            _mm_storeu_ps(rays.ox + k, _mm_set1_ps(cam.position.x));
            _mm_storeu_ps(rays.oy + k, _mm_set1_ps(cam.position.y));
            _mm_storeu_ps(rays.oz + k, _mm_set1_ps(cam.position.z));
            _mm_storeu_ps(rays.tmax + k, _mm_set1_ps(kInfinity));
        }
        return;
    }
#endif
    for (std::size_t k = 0; k < n; ++k)
        rays.set(k, cam.generate_ray(Vec2(float(x0 + int(k)) + film_x[k], float(y) + film_y[k])));
}

IntegratorKind parse_integrator(const std::string& name) {
    if (name == "path") return IntegratorKind::Path;
    if (name == "direct") return IntegratorKind::Direct;
    const std::string near = closest_name(name, {"direct", "path"});
    throw std::invalid_argument("unknown integrator '" + name + "'" +
                                (near.empty() ? std::string(" (expected 'direct' or 'path')")
                                              : " (did you mean '" + near + "'?)"));
}

const char* integrator_name(IntegratorKind kind) {
    return kind == IntegratorKind::Path ? "path" : "direct";
}

KernelChoice choose_kernel(const SceneFeatures& sf, IntegratorKind integrator, int max_depth,
                           bool force_general) {
    KernelChoice k;
    k.integrator = integrator;
    k.max_depth = max_depth;
    k.general = force_general;
    const std::uint32_t motion = sf.has_motion ? std::uint32_t(kFeatMotion) : 0u;
    if (sf.has_motion)
        k.chosen.push_back(
            "motion blur: a shutter time per camera sample, the moving camera and instances "
            "traced at it (the general kernel with time, whatever is chosen below)");
    const std::uint32_t alpha = sf.needs_alpha ? std::uint32_t(kFeatAlpha) : 0u;
    if (sf.needs_alpha)
        k.chosen.push_back(
            "alpha (film transparency or a holdout): the general kernel with each sample's "
            "coverage, whatever is chosen below");
    if (sf.has_shadow_catcher)
        k.chosen.push_back(
            "shadow catcher: the volumetric path kernel with alpha, a second run of each sample "
            "that meets a catcher seeing only catchers from there");
    if (sf.has_media || sf.has_subsurface || sf.has_shadow_catcher || sf.has_ray_visibility) {
        // One kernel for every scene with media or subsurface walks (kernel_function),
        // whichever integrator.
        k.features = (kPathMask & ~kFeatLambertOnly) | kFeatTransmission | kFeatTextured |
                     kFeatMedia | motion | alpha;
        k.chosen.push_back(
            "media: the volumetric path kernel (free-flight sampling, light samples through "
            "media and null surfaces, MIS with the phase function" +
            std::string(sf.has_subsurface ? ", random walks inside subsurface objects" : "") +
            std::string(sf.has_ray_visibility ? ", each ray's kind for ray visibility" : "") +
            "), one path at a time" +
            std::string(integrator == IntegratorKind::Direct
                            ? "; `direct` is path tracing here (media scatter light)"
                            : ""));
        k.name = std::string("path<") + feature_list(IntegratorKind::Path, k.features) + ">";
        return k;
    }
    const bool path = integrator == IntegratorKind::Path;
    if (force_general) {
        k.features = path ? (kFeatSpecular | kFeatMis | kFeatEmission | kFeatIndirect)
                          : (kFeatSpecular | kFeatEmission | kFeatAreaSampling);
        k.chosen.push_back("general kernel forced (--kernel general): every branch present");
    } else {
        std::uint32_t f = 0;
        if (sf.lambert_only) {
            f |= kFeatLambertOnly;
            k.chosen.push_back(
                "Lambert-only kernel: BRDF calls go straight to the Lambertian lobe");
        } else {
            k.skipped.push_back("Lambert-only kernel: some material has a glossy or mirror lobe");
        }
        if (sf.has_specular) {
            f |= kFeatSpecular;
            k.chosen.push_back(path ? "delta (mirror) lobes: specular-bounce bookkeeping"
                                    : "mirror recursion through delta lobes");
        } else {
            k.skipped.push_back(path ? "delta-lobe bookkeeping: no mirror lobe in the scene"
                                     : "mirror recursion: no mirror lobe in the scene");
        }
        if (!sf.can_reflect) {
            k.max_depth = 0;
            k.skipped.push_back("all shading: no surface reflects light (only emitters are seen)");
        }
        if (path) {
            if (sf.any_hittable_light) {
                f |= kFeatMis;
                k.chosen.push_back(
                    "MIS of light and BSDF samples (power heuristic): area or "
                    "environment lights present");
            } else {
                k.skipped.push_back(
                    "MIS and emitter look-ups on BSDF rays: no light can be hit by a ray "
                    "(point, spot, directional); last-vertex BSDF rays are not traced");
            }
            if (sf.any_hittable_light && sf.emitter_visible) {
                f |= kFeatEmission;
                k.chosen.push_back("emission on camera rays: an emitter is visible");
            } else {
                k.skipped.push_back("emission on camera rays: no emitter visible to the camera");
            }
            if (k.max_depth >= 2 && sf.can_reflect) {
                f |= kFeatIndirect;
                k.chosen.push_back("indirect bounces up to max_depth " +
                                   std::to_string(k.max_depth) + " with Russian roulette");
            } else {
                k.skipped.push_back("indirect bounces: max_depth " + std::to_string(k.max_depth) +
                                    (sf.can_reflect ? "" : ", nothing reflects"));
            }
        } else {
            if (sf.any_non_delta_light) {
                f |= kFeatAreaSampling;
                k.chosen.push_back("stochastic light samples for area/environment lights");
            } else {
                k.skipped.push_back(
                    "light sampling: only delta lights, evaluated exactly "
                    "(deterministic image)");
            }
            if (sf.any_non_delta_light && (sf.emitter_visible || sf.has_specular)) {
                f |= kFeatEmission;
                k.chosen.push_back("emission on camera/mirror rays");
            } else {
                k.skipped.push_back("emission look-ups: no emitter can be seen");
            }
        }
        k.features = f;
    }
    k.features &= path ? kPathMask : kDirectMask;
    // Transmission and textures: the general kernel plus what they need (kernel_function
    // instantiates these combinations only).
    if (sf.has_transmission || sf.has_textured) {
        k.features = path ? (kFeatSpecular | kFeatMis | kFeatEmission | kFeatIndirect)
                          : (kFeatSpecular | kFeatEmission | kFeatAreaSampling);
    }
    if (sf.has_transmission) {
        k.features |= kFeatTransmission;
        k.chosen.push_back(
            "transmission (dielectric materials): the general kernel with two-sided shading "
            "frames and rays spawned on the side they leave to");
    }
    if (sf.has_textured) {
        k.features |= kFeatTextured;
        k.chosen.push_back(
            "textured materials: the general kernel, building a hit's material from its "
            "textures where the surface has them");
    } else {
        k.skipped.push_back("per-hit materials: no material is textured");
    }
    if (sf.has_motion) {
        // Motion: the general kernel with transmission, textures and time (kernel_function).
        k.features = (path ? (kFeatSpecular | kFeatMis | kFeatEmission | kFeatIndirect)
                           : (kFeatSpecular | kFeatEmission | kFeatAreaSampling)) |
                     kFeatTransmission | kFeatTextured | kFeatMotion;
    } else {
        k.skipped.push_back("shutter time on rays: nothing moves (or motion blur is off)");
    }
    if (sf.needs_alpha) {
        // Alpha: the general kernel with transmission, textures (and time) and coverage.
        k.features = (path ? (kFeatSpecular | kFeatMis | kFeatEmission | kFeatIndirect)
                           : (kFeatSpecular | kFeatEmission | kFeatAreaSampling)) |
                     kFeatTransmission | kFeatTextured | motion | kFeatAlpha;
    } else {
        k.skipped.push_back("alpha: the film is opaque and nothing is a holdout");
    }
    k.name = std::string(integrator_name(integrator)) + "<" + feature_list(integrator, k.features) +
             ">" + (force_general ? " (general)" : "");
    return k;
}

TileKernel kernel_function(const KernelChoice& choice) {
    // Transmission and textures: the general kernel of each integrator with either or both
    // (choose_kernel).
    constexpr std::uint32_t kPathGeneral = kPathMask & ~kFeatLambertOnly;
    constexpr std::uint32_t kDirectGeneral = kDirectMask & ~kFeatLambertOnly;
    constexpr std::uint32_t kT = kFeatTransmission, kX = kFeatTextured;
    const bool path = choice.integrator == IntegratorKind::Path;
    constexpr std::uint32_t kM = kFeatMotion, kA = kFeatAlpha;
    if ((choice.features & kA) != 0) {
        constexpr std::uint32_t kMedia = kPathGeneral | kT | kX | kFeatMedia | kA;
        if ((choice.features & kFeatMedia) != 0)
            return (choice.features & kM) != 0 ? &render_tile<IntegratorKind::Path, kMedia | kM>
                                               : &render_tile<IntegratorKind::Path, kMedia>;
        if ((choice.features & kM) != 0)
            return path ? &render_tile<IntegratorKind::Path, kPathGeneral | kT | kX | kM | kA>
                        : &render_tile<IntegratorKind::Direct, kDirectGeneral | kT | kX | kM | kA>;
        return path ? &render_tile<IntegratorKind::Path, kPathGeneral | kT | kX | kA>
                    : &render_tile<IntegratorKind::Direct, kDirectGeneral | kT | kX | kA>;
    }
    if ((choice.features & kFeatMedia) != 0)
        return (choice.features & kM) != 0
                   ? &render_tile<IntegratorKind::Path, kPathGeneral | kT | kX | kFeatMedia | kM>
                   : &render_tile<IntegratorKind::Path, kPathGeneral | kT | kX | kFeatMedia>;
    if ((choice.features & kM) != 0)
        return path ? &render_tile<IntegratorKind::Path, kPathGeneral | kT | kX | kM>
                    : &render_tile<IntegratorKind::Direct, kDirectGeneral | kT | kX | kM>;
    switch (choice.features & (kT | kX)) {
        case kT:
            return path ? &render_tile<IntegratorKind::Path, kPathGeneral | kT>
                        : &render_tile<IntegratorKind::Direct, kDirectGeneral | kT>;
        case kX:
            return path ? &render_tile<IntegratorKind::Path, kPathGeneral | kX>
                        : &render_tile<IntegratorKind::Direct, kDirectGeneral | kX>;
        case kT | kX:
            return path ? &render_tile<IntegratorKind::Path, kPathGeneral | kT | kX>
                        : &render_tile<IntegratorKind::Direct, kDirectGeneral | kT | kX>;
        default:
            break;
    }
#ifdef FACET_GENERAL_KERNELS_ONLY
    // Sanitizer trees (CMakeLists.txt, FACET_ALL_KERNELS): the general kernel for every scene.
    return path ? &render_tile<IntegratorKind::Path, kPathGeneral>
                : &render_tile<IntegratorKind::Direct, kDirectGeneral>;
#else
    static constexpr std::array<TileKernel, kTableSize> kPath =
        make_table<IntegratorKind::Path, kPathMask>(std::make_index_sequence<kTableSize>{});
    static constexpr std::array<TileKernel, kTableSize> kDirect =
        make_table<IntegratorKind::Direct, kDirectMask>(std::make_index_sequence<kTableSize>{});
    const std::size_t i = choice.features & (kTableSize - 1);
    return path ? kPath[i] : kDirect[i];
#endif
}

}  // namespace facet::render
