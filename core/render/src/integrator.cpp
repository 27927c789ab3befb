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

#include "facet/frame.h"
#include "facet/registry.h"
#include "facet/render/sampler.h"
#include "facet/sampling.h"

namespace facet::render {

namespace {

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
};

// The sample values one path vertex may use (integrator.h: the dimensions of a vertex), drawn
// for the 8 paths of a packet together (VertexSampleLanes).
struct VertexSamples {
    float light_choice;  // base + 0 (only with more than one light)
    Vec2 light;          // base + 1
    float lobe;          // base + 3 (not in the Lambert-only kernel)
    Vec2 bsdf;           // base + 4
    float roulette;      // base + 6 (only from kRouletteDepth on)
};

// The samples of one depth for every lane of a packet: each dimension of the vertex block is
// drawn for all lanes at once (sample_*_lanes, vectorised), and only the dimensions the kernel
// can read at this depth. Lane k gets exactly the values its own Sampler would give.
struct VertexSampleLanes {
    alignas(32) float light_choice[kSamplerLanes], light_x[kSamplerLanes], light_y[kSamplerLanes],
        lobe[kSamplerLanes], bsdf_x[kSamplerLanes], bsdf_y[kSamplerLanes], roulette[kSamplerLanes];

    template <std::uint32_t F>
    void draw(const std::uint32_t* seeds, std::uint32_t index, int depth, int num_lights) {
        const std::uint32_t base = 1u + std::uint32_t(kDimsPerVertex * depth);
        if (num_lights > 1) sample_1d_lanes(seeds, index, base, light_choice);
        sample_2d_lanes(seeds, index, base + 1u, light_x, light_y);
        if constexpr ((F & kFeatLambertOnly) == 0) sample_1d_lanes(seeds, index, base + 3u, lobe);
        sample_2d_lanes(seeds, index, base + 4u, bsdf_x, bsdf_y);
        if (depth + 1 >= kRouletteDepth) sample_1d_lanes(seeds, index, base + 6u, roulette);
    }
    // Lane k's values (the entries that draw() skipped are never read).
    VertexSamples lane(std::size_t k) const {
        return {light_choice[k],
                {light_x[k], light_y[k]},
                lobe[k],
                {bsdf_x[k], bsdf_y[k]},
                roulette[k]};
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
        if (num_lights > 1) light_index = light_dist.sample(s.light_choice, select_pmf);
        const Light& light = lights[light_index];
        if (auto ls = light.sample_li(ctx, s.light)) {
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

    // Emission reached by this ray: full weight from the camera or after a delta lobe (light
    // sampling cannot produce those paths); MIS-weighted against NEE otherwise.
    if constexpr (kMis) {
        if (depth > 0 || kEmission) {
            if (!found) {
                if (const Light* env = scene.environment()) {
                    const Rgb le = env->le_escape(ray_d);
                    if (depth == 0 || p.specular_bounce) {
                        p.L += p.beta * le;
                    } else {
                        const float lp = light_dist.pmf(std::size_t(env - lights.data())) *
                                         env->pdf_li(p.prev_ctx, ray_d, Vec3(0.f), Vec3(0.f));
                        p.L += p.beta * le * power_heuristic(p.prev_bsdf_pdf, lp);
                    }
                }
            } else if (hit.light >= 0 && max3(hit.emitted_radiance) > 0.f) {
                if (depth == 0 || p.specular_bounce) {
                    p.L += p.beta * hit.emitted_radiance;
                } else {
                    const std::size_t li = std::size_t(hit.light);
                    const float lp =
                        light_dist.pmf(li) * lights[li].pdf_li(p.prev_ctx, ray_d, hit.p, hit.ng);
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
                 int max_depth, KernelCounters& c, Rgb* L) {
    static_assert(kLanes == kSamplerLanes);
    constexpr bool kIndirect = (F & kFeatIndirect) != 0;
    constexpr bool kSpecular = (F & kFeatSpecular) != 0;
    const int num_lights = int(scene.lights().size());
    std::array<PathState, kLanes> paths;
    VertexSampleLanes samples;
    std::array<bool, kLanes> alive, has_shadow, blocked;
    RayPacket shadow;
    alive.fill(false);
    std::fill(alive.begin(), alive.begin() + std::ptrdiff_t(n), true);
    for (int depth = 0;; ++depth) {
        if (depth > 0) {
            int live = 0;
            for (std::size_t k = 0; k < n; ++k) live += alive[k];
            if (live == 0) break;
            if (live < kMinPacketLanes) {
                for (std::size_t k = 0; k < n; ++k)
                    if (alive[k]) found[k] = scene.intersect(rays.get(k), hits[k]);
            } else {
                scene.intersect_packet(rays, n, hits.data(), found.data(), alive.data());
            }
        }
        // Dimension 0 was the film position; a vertex that shades draws from its own block.
        // Past max_depth (and past the first bounce without indirect light or mirrors) a
        // vertex only looks for emission.
        if (depth < max_depth && (kIndirect || kSpecular || depth < 1))
            samples.draw<F>(seeds, index, depth, num_lights);
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
}

// ---- direct: local illumination (C&W eq. 2.42) + perfect mirror recursion ----

// The radiance along camera ray `ray`, whose closest hit the caller traced (`first_hit` when
// `found`); `s` starts at dimension 1.
template <std::uint32_t F>
Rgb direct_li(const Scene& scene, Ray ray, bool found, const SurfaceHit& first_hit, Sampler& s,
              int max_depth, KernelCounters& c) {
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
    if (scene.has_camera_lamps()) [[unlikely]]  // as in path_vertex
        L += scene.camera_lamps(ray.o, ray.d, found ? first_hit.t : kInfinity);
    for (int depth = 0;; ++depth) {
        if constexpr (kSpecular) {
            if (depth > 0) {
                found = scene.intersect(ray, next);
                hp = &next;
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
                auto ls = light.sample_li(ctx, u);
                if (!ls || !(ls->pdf > 0.f)) continue;
                const Vec3 wi = sh.frame.to_local(ls->wi);
                if (!valid_side(sh, transmissive, ls->wi, wi.z)) continue;
                const Rgb contrib = bsdf_f<F>(m, sh.wo, wi) * std::fabs(wi.z) * ls->li;
                if (!(max3(contrib) > 0.f)) continue;
                ++c.shadow_rays;
                // occluded() starts the shadow ray on the light's side of the surface.
                if (!scene.occluded(hit, *ls)) L += beta * contrib / ls->pdf;
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

// ---- tile loop ----

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
    std::array<Rgb, kLanes> L;
    // Packets of kLanes neighbouring pixels of a row, aligned to multiples of kLanes in x over
    // the whole image, so that a pixel is traced in the same packet whatever the tile or region
    // (render.h); lanes outside the tile are traced and not written.
    const int gx_begin = job.x0 - job.x0 % int(kLanes);
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
                    for (std::size_t k = 0; k < n; ++k) {
                        const Vec2 film(float(x0 + int(k)) + film_x[k], float(y) + film_y[k]);
                        rays.set(k, cam.generate_ray(film, Vec2(lens_x[k], lens_y[k])));
                    }
                } else {
                    camera_packet(cam, x0, y, film_x.data(), film_y.data(), n, rays);
                }
                scene.intersect_packet(rays, n, hits.data(), found.data());
                c.camera_rays += n;
                c.rays += n;
                if constexpr (I == IntegratorKind::Path) {
                    path_packet<F>(scene, *job.light_distribution, n, rays, hits, found, ss, index,
                                   job.max_depth, c, L.data());
                } else {
                    for (std::size_t k = 0; k < n; ++k) {
                        // Dimension 0 was the film position; direct_li sets every other.
                        Sampler s(ss[k], index, 1u);
                        L[k] = direct_li<F>(scene, rays.get(k), found[k], hits[k], s, job.max_depth,
                                            c);
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
