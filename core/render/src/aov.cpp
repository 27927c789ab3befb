// Render passes of first-hit data (aov.h): albedo, shading normal, view-axis depth, emission.
#include "facet/render/aov.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <optional>
#include <stdexcept>

#include "facet/frame.h"
#include "facet/render/integrator.h"
#include "facet/render/sampler.h"

namespace facet::render {

namespace {

struct PixelSums {
    Rgb albedo{0.f}, normal{0.f}, emission{0.f};
    double depth = 0.0;
    int hits = 0;
};

// One camera sample's first hit added to `sums` (aov.h conventions).
void add_sample(const Scene& scene, const Ray& ray, Sampler& s, std::uint32_t which,
                PixelSums& sums) {
    SurfaceHit hit;
    if (!scene.intersect(ray, hit)) return;
    ++sums.hits;
    const Camera& cam = scene.camera();
    if (which & kAovDepth) sums.depth += double(glm::dot(hit.p - cam.position, cam.forward));
    if (which & kAovEmission) sums.emission += hit.emitted_radiance;
    if (!(which & (kAovAlbedo | kAovNormal))) return;
    std::optional<Material> textured;
    const Material& m = scene.bsdf_at(hit, ray, true, textured);
    // Turned toward the viewer by the geometric normal (Cycles' backfacing flip).
    const bool front = glm::dot(hit.ng, ray.d) < 0.f;
    const Vec3 ns = front ? hit.ns : -hit.ns;
    if (which & kAovNormal) sums.normal += Rgb(ns.x, ns.y, ns.z);
    if (!(which & kAovAlbedo)) return;
    // A transmissive material's frame is its own (outside = the normal's side), as the
    // integrators shade it; a reflecting one's faces the viewer. One-sided backs reflect
    // nothing (the integrators stop there).
    const bool transmissive = m.transmissive();
    if (!front && !hit.two_sided && !transmissive) return;
    const Vec3 z = transmissive ? hit.ns : ns;
    const Frame frame = m.anisotropic() ? Frame::from_z_x(z, hit.dpdu) : Frame::from_z(z);
    const Vec3 wo = frame.to_local(-ray.d);
    s.set_dimension(1u);
    const float uc = s.get_1d();
    const Vec2 u = s.get_2d();
    const auto bs = m.sample_f(wo, uc, u);
    if (!bs || !(bs->pdf > 0.f)) return;
    const Rgb v = bs->f * (std::fabs(bs->wi.z) / bs->pdf);
    if (std::isfinite(v.r) && std::isfinite(v.g) && std::isfinite(v.b)) sums.albedo += v;
}

}  // namespace

Aovs render_aovs(const Scene& scene, const AovOptions& o) {
    if (o.spp < 1) throw std::invalid_argument("aov spp: must be >= 1");
    const Camera& cam = scene.camera();
    const int w = cam.width, h = cam.height;
    Aovs out;
    auto make = [&](std::uint32_t bit, Image& img) {
        if (o.which & bit) img = Image(w, h);
    };
    make(kAovAlbedo, out.albedo);
    make(kAovNormal, out.normal);
    make(kAovDepth, out.depth);
    make(kAovEmission, out.emission);
    if (!o.which) return out;
    const std::uint32_t seed_hash = Sampler::render_seed_hash(o.seed);
    auto rows = [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) {
            for (int x = 0; x < w; ++x) {
                const std::uint32_t ps = Sampler::pixel_seed_hashed(x, y, seed_hash);
                PixelSums sums;
                for (int i = 0; i < o.spp; ++i) {
                    Sampler s(ps, std::uint32_t(i), 0u);
                    const Vec2 f = o.spp == 1 ? Vec2(0.5f) : s.get_2d();
                    const Vec2 film(float(x) + f.x, float(y) + f.y);
                    Ray ray = cam.generate_ray(film);
                    if (cam.has_lens()) {
                        Sampler lens(ps, std::uint32_t(i), kLensDimension);
                        ray = cam.generate_ray(film, lens.get_2d());
                    }
                    add_sample(scene, ray, s, o.which, sums);
                }
                const float inv = 1.f / float(o.spp);
                if (o.which & kAovAlbedo) out.albedo.at(x, y) = sums.albedo * inv;
                if (o.which & kAovNormal) out.normal.at(x, y) = sums.normal * inv;
                if (o.which & kAovEmission) out.emission.at(x, y) = sums.emission * inv;
                if (o.which & kAovDepth)
                    out.depth.at(x, y) =
                        Rgb(sums.hits ? float(sums.depth / sums.hits) : kMissDepth);
            }
        }
    };
    if (o.threads > 0) {
        tbb::task_arena arena(o.threads);
        arena.execute([&] { tbb::parallel_for(tbb::blocked_range<int>(0, h), rows); });
    } else {
        tbb::parallel_for(tbb::blocked_range<int>(0, h), rows);
    }
    return out;
}

}  // namespace facet::render
