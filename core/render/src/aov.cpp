// Render passes of first-hit data (aov.h): albedo, shading normal, view-axis depth, emission.
#include "facet/render/aov.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "facet/frame.h"
#include "facet/render/film.h"
#include "facet/render/integrator.h"
#include "facet/render/sampler.h"
#include "light_path.h"

namespace facet::render {

namespace {

// Depths are clamped to this before they are squared (aov.h): z^2 2^kFixedFracBits times 2^20
// samples then stays below 2^120, far from the fixed-point sums' 2^127.
constexpr double kMaxSquaredDepth = 0x1p20;
// A sample variance at most this fraction of the mean square is rounding, not noise (aov.h):
// per-sample float rounding spreads a value by ~2^-24 of itself (a variance of 2^-48 of its
// square) and the double sums round at 2^-53; 2^-44 is 16 times the first.
constexpr double kVarianceFloor = 0x1p-44;

// Exact fixed-point value (film.h) of a double with |v| < 2^63, truncated below
// 2^-kFixedFracBits: the integer part and the fraction are converted separately (both exact).
FixedSum fixed_from_double(double v) {
    constexpr double kScale = double(std::int64_t(1) << kFixedFracBits);
    if (std::fabs(v) < 8.0) return FixedSum(std::int64_t(v * kScale));
    const double whole = std::trunc(v);
    return (FixedSum(std::int64_t(whole)) << kFixedFracBits) +
           FixedSum(std::int64_t((v - whole) * kScale));
}

void add_fixed(FixedRgb& sum, const Rgb& v) {
    for (int c = 0; c < 3; ++c) sum.c[c] += to_fixed(v[c]);
}
// Adds v^2 per channel, squared in double (exact for a float).
void add_squares(FixedRgb& sum, const Rgb& v) {
    for (int c = 0; c < 3; ++c) sum.c[c] += fixed_from_double(double(v[c]) * double(v[c]));
}

// One pixel's sums (film.h's fixed point: exact, whatever the order).
struct PixelSums {
    FixedRgb albedo, normal, emission;
    FixedRgb albedo_sq, normal_sq;  // with AovOptions::variances
    FixedSum depth = 0, depth_sq = 0;
    std::uint32_t hits = 0;
};

// Shapes that camera rays do not see passed in a row at most (against rays trapped between
// coincident surfaces, as the media kernel's kMaxNullCrossings).
constexpr int kMaxPassed = 64;

constexpr std::size_t kLanes = Scene::kPacketSize;

// One camera sample's first hit added to `sums` (aov.h conventions): `first` is what `ray` hit
// (null for a miss).
void add_sample(const Scene& scene, const Ray& ray, const SurfaceHit* first, Sampler& s,
                std::uint32_t which, bool variances, PixelSums& sums) {
    if (!first) return;
    SurfaceHit hit = *first;
    RayState rs;  // a camera ray's Light Path state (light_path textures)
    if (scene.features().has_ray_visibility) [[unlikely]] {
        // What camera rays see (integrator.h, "Ray visibility"): shapes they do not see are
        // passed, a Light Path switch gives the hit its camera material and emission.
        Ray r = ray;
        for (int i = 0; (scene.shapes()[hit.shape].visibility & kRayCamera) == 0; ++i) {
            rs.length += hit.t;
            r = Scene::spawn_ray(hit, r.d);
            if (i >= kMaxPassed || !scene.intersect(r, hit)) return;
        }
        if (const std::int32_t lp = scene.shapes()[hit.shape].light_path; lp >= 0)
            apply_light_path(scene, lp, kLpCamera, ray.d, hit);
    }
    ++sums.hits;
    const Camera& cam = scene.camera();
    if (which & kAovDepth) {
        const float z = view_axis_depth(cam, hit.p);
        sums.depth += to_fixed(z);
        if (variances) {
            const double zc = std::min(double(z), kMaxSquaredDepth);
            sums.depth_sq += fixed_from_double(zc * zc);
        }
    }
    if ((which & kAovEmission) && film_accepts(hit.emitted_radiance))
        add_fixed(sums.emission, hit.emitted_radiance);
    if (!(which & (kAovAlbedo | kAovNormal))) return;
    std::optional<Material> textured;
    rs.length += hit.t;
    const Material& m = scene.bsdf_at(hit, ray, true, textured, &rs);
    // Turned toward the viewer by the geometric normal (Cycles' backfacing flip).
    const bool front = glm::dot(hit.ng, ray.d) < 0.f;
    const Vec3 ns = front ? hit.ns : -hit.ns;
    if (which & kAovNormal) {
        const Rgb n(ns.x, ns.y, ns.z);
        add_fixed(sums.normal, n);
        if (variances) add_squares(sums.normal_sq, n);
    }
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
    if (film_accepts(v)) {
        add_fixed(sums.albedo, v);
        if (variances) add_squares(sums.albedo_sq, v);
    }
}

// The variance of the mean of n samples from their sum and sum of squares (aov.h): the
// samples' unbiased variance / n; 0 for n < 2 and below the rounding floor.
float mean_variance(FixedSum sum, FixedSum sum_sq, std::uint32_t n) {
    if (n < 2) return 0.f;
    const double inv = 1.0 / double(n);
    const double mean = from_fixed(sum) * inv, mean_sq = from_fixed(sum_sq) * inv;
    const double spread = mean_sq - mean * mean;
    if (!(spread > kVarianceFloor * mean_sq)) return 0.f;
    return float(spread / double(n - 1));
}

Rgb mean_variance(const FixedRgb& sum, const FixedRgb& sum_sq, std::uint32_t n) {
    return Rgb(mean_variance(sum.c[0], sum_sq.c[0], n), mean_variance(sum.c[1], sum_sq.c[1], n),
               mean_variance(sum.c[2], sum_sq.c[2], n));
}

Rgb mean(const FixedRgb& sum, std::uint32_t n) {
    const double inv = 1.0 / double(n);
    return Rgb(float(from_fixed(sum.c[0]) * inv), float(from_fixed(sum.c[1]) * inv),
               float(from_fixed(sum.c[2]) * inv));
}

}  // namespace

Aovs render_aovs(const Scene& scene, const AovOptions& o) {
    if (o.spp < 1) throw std::invalid_argument("aov spp: must be >= 1");
    const Camera& cam = scene.camera();
    const Region r = o.region.value_or(Region{0, 0, cam.width, cam.height});
    if (r.empty() || r.x0 < 0 || r.y0 < 0 || r.x1 > cam.width || r.y1 > cam.height)
        throw std::invalid_argument(
            "aov region: (" + std::to_string(r.x0) + ", " + std::to_string(r.y0) + ", " +
            std::to_string(r.x1) + ", " + std::to_string(r.y1) + ") is empty or not inside the " +
            std::to_string(cam.width) + " x " + std::to_string(cam.height) + " image");
    const int w = r.width(), h = r.height();
    const bool variances = o.variances;
    Aovs out;
    auto make = [&](std::uint32_t bit, Image& img, Image* var) {
        if (!(o.which & bit)) return;
        img = Image(w, h);
        if (variances && var != nullptr) *var = Image(w, h);
    };
    make(kAovAlbedo, out.albedo, &out.albedo_variance);
    make(kAovNormal, out.normal, &out.normal_variance);
    make(kAovDepth, out.depth, &out.depth_variance);
    make(kAovEmission, out.emission, nullptr);
    if (!o.which) return out;
    const std::uint32_t seed_hash = Sampler::render_seed_hash(o.seed);
    const std::uint32_t n = std::uint32_t(o.spp);
    auto rows = [&](const tbb::blocked_range<int>& range) {
        for (int y = range.begin(); y < range.end(); ++y) {
            for (int x = 0; x < w; ++x) {
                const int px = r.x0 + x, py = r.y0 + y;  // in the image
                const std::uint32_t ps = Sampler::pixel_seed_hashed(px, py, seed_hash);
                PixelSums sums;
                // The pixel's camera rays 8 at a time in one Embree packet query (coherent: one
                // pixel's), each then added in sample order.
                for (int i0 = 0; i0 < o.spp; i0 += int(kLanes)) {
                    const std::size_t lanes = std::min(kLanes, std::size_t(o.spp - i0));
                    RayPacket packet;
                    std::array<Ray, kLanes> rays;
                    for (std::size_t k = 0; k < lanes; ++k) {
                        const std::uint32_t i = std::uint32_t(i0) + std::uint32_t(k);
                        Sampler s(ps, i, 0u);
                        const Vec2 f = o.spp == 1 ? Vec2(0.5f) : s.get_2d();
                        const Vec2 film(float(px) + f.x, float(py) + f.y);
                        rays[k] = cam.generate_ray(film);
                        if (cam.has_lens()) {
                            Sampler lens(ps, i, kLensDimension);
                            rays[k] = cam.generate_ray(film, lens.get_2d());
                        }
                        packet.set(k, rays[k]);
                    }
                    std::array<SurfaceHit, kLanes> hits;
                    bool found[kLanes];
                    scene.intersect_packet(packet, lanes, hits.data(), found);
                    for (std::size_t k = 0; k < lanes; ++k) {
                        Sampler s(ps, std::uint32_t(i0) + std::uint32_t(k), 0u);
                        add_sample(scene, rays[k], found[k] ? &hits[k] : nullptr, s, o.which,
                                   variances, sums);
                    }
                }
                if (o.which & kAovAlbedo) {
                    out.albedo.at(x, y) = mean(sums.albedo, n);
                    if (variances)
                        out.albedo_variance.at(x, y) =
                            mean_variance(sums.albedo, sums.albedo_sq, n);
                }
                if (o.which & kAovNormal) {
                    out.normal.at(x, y) = mean(sums.normal, n);
                    if (variances)
                        out.normal_variance.at(x, y) =
                            mean_variance(sums.normal, sums.normal_sq, n);
                }
                if (o.which & kAovEmission) out.emission.at(x, y) = mean(sums.emission, n);
                if (o.which & kAovDepth) {
                    out.depth.at(x, y) = Rgb(resolved_depth(sums.depth, sums.hits));
                    if (variances)
                        out.depth_variance.at(x, y) =
                            Rgb(mean_variance(sums.depth, sums.depth_sq, sums.hits));
                }
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
