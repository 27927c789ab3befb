// Tests of the batched microfacet evaluation (facet/microfacet_batch.h): every lobe corner of
// the model-wide suites, on random and adversarial direction pairs (below the horizon, grazing
// down to cos 1e-9, at the normal, wo = wi, wo = -wi, NaN), with batch lengths that are not
// multiples of the internal block.
//
// Tolerance: zero. The header promises the scalar result bit for bit (same IEEE operations in
// the same order, no FMA contraction, sqrt and division correctly rounded in SSE/AVX as in
// scalar code), so any difference is a bug: a reordered sum, a missing clamp or a leaked NaN.
#include <gtest/gtest.h>

#include <pcg_random.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "facet/microfacet_batch.h"
#include "facet/sampling.h"
#include "model_corners.h"

namespace facet {
namespace {

struct Pairs {
    std::vector<float> ox, oy, oz, ix, iy, iz;
    void add(const Vec3& o, const Vec3& i) {
        ox.push_back(o.x), oy.push_back(o.y), oz.push_back(o.z);
        ix.push_back(i.x), iy.push_back(i.y), iz.push_back(i.z);
    }
    std::size_t size() const { return ox.size(); }
    Vec3Soa wo() const { return {ox.data(), oy.data(), oz.data()}; }
    Vec3Soa wi() const { return {ix.data(), iy.data(), iz.data()}; }
    Vec3 o(std::size_t k) const { return {ox[k], oy[k], oz[k]}; }
    Vec3 i(std::size_t k) const { return {ix[k], iy[k], iz[k]}; }
};

Vec3 spherical(float cos_theta, float phi) {
    float s = std::sqrt(std::fmax(0.f, 1.f - cos_theta * cos_theta));
    return {s * std::cos(phi), s * std::sin(phi), cos_theta};
}

// 1000 random pairs on the whole sphere (a quarter below the horizon on each side), then the
// adversarial ones: 1000 + 17 pairs in all, not a multiple of the 256-element block.
Pairs make_pairs() {
    Pairs p;
    pcg32 rng(2024);
    auto uf = [&] { return float(rng() >> 8) * 0x1p-24f; };
    for (int k = 0; k < 1000; ++k) {
        Vec3 o = sample_uniform_hemisphere(Vec2(uf(), uf()));
        Vec3 i = sample_uniform_hemisphere(Vec2(uf(), uf()));
        if (k % 4 == 1) o.z = -o.z;
        if (k % 4 == 2) i.z = -i.z;
        p.add(o, i);
    }
    const Vec3 n(0.f, 0.f, 1.f);
    const Vec3 graze = spherical(1e-9f, 0.3f), graze2 = spherical(1e-9f, 2.5f);
    const Vec3 mid = spherical(0.6f, 1.1f);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    p.add(n, n);
    p.add(n, graze);
    p.add(graze, n);
    p.add(graze, graze);                      // wo = wi at grazing
    p.add(graze, graze2);                     // both grazing, different azimuths
    p.add(mid, mid);                          // wo = wi
    p.add(mid, Vec3(-mid.x, -mid.y, mid.z));  // mirror pair
    p.add(mid, -mid);                         // wo = -wi: h = 0
    p.add(n, -n);
    p.add(Vec3(1.f, 0.f, 0.f), Vec3(0.f, 1.f, 0.f));  // exactly in the plane
    p.add(Vec3(nan, 0.f, 1.f), n);
    p.add(n, Vec3(0.f, nan, 1.f));
    p.add(Vec3(0.f, 0.f, nan), mid);
    p.add(spherical(1e-4f, 0.f), spherical(0.9999f, 3.f));
    p.add(spherical(0.01f, 0.5f), spherical(0.01f, 0.5f + 3.14159f));
    p.add(spherical(0.3f, 0.f), spherical(0.3f, 1.5707964f));
    p.add(spherical(1.f, 0.f), spherical(0.5f, 0.f));
    return p;
}

// Bitwise float equality that also treats NaN == NaN (neither side may produce one here, but a
// failure message is clearer than a tolerance mismatch if one does).
bool same_bits(float a, float b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST(MicrofacetBatch, EqualsScalarBitForBitOnEveryLobeCorner) {
    const Pairs p = make_pairs();
    const std::size_t n = p.size();
    std::vector<float> r(n), g(n), b(n), pdf(n);
    int vectorised = 0, lobes = 0;
    for (const test::LobeSpec& spec : test::lobe_corners(false)) {
        MicrofacetReflection lobe = spec.lobe(Rgb(0.9f, 0.7f, 0.5f));
        MicrofacetBatch batch(lobe);
        ++lobes;
        vectorised += batch.vectorised();
        batch.f(n, p.wo(), p.wi(), {r.data(), g.data(), b.data()});
        batch.pdf(n, p.wo(), p.wi(), pdf.data());
        int bad = 0;
        for (std::size_t k = 0; k < n && bad < 3; ++k) {
            Rgb f = lobe.f(p.o(k), p.i(k));
            float q = lobe.pdf(p.o(k), p.i(k));
            bool ok = same_bits(f.r, r[k]) && same_bits(f.g, g[k]) && same_bits(f.b, b[k]) &&
                      same_bits(q, pdf[k]);
            if (!ok) {
                ++bad;
                ADD_FAILURE() << spec.name() << " pair " << k << ": scalar f (" << f.r << ", "
                              << f.g << ", " << f.b << ") pdf " << q << "; batch (" << r[k] << ", "
                              << g[k] << ", " << b[k] << ") pdf " << pdf[k];
            }
        }
    }
    // The fast path must actually be taken: every non-smooth, uncompensated GGX corner.
    EXPECT_GT(vectorised, 20) << "of " << lobes << " lobes";
}

// f_single_fixed (one fixed direction, many free ones) against the scalar f_single on every
// lobe corner, both roles of the fixed direction, fixed directions from the normal to 1e-4 of
// the horizon (and below it) against the 1017 directions of make_pairs (both of its sides,
// adversarial ones included). GGX (also compensated) and Beckmann: bit for bit. Blinn (its
// vectorised kernel with polynomial exp / log / log1p): to float precision: relative
// difference at most 16 ulp (2^-20) times 1 + |E|, E the larger of D's log-space exponent and
// Lambda's (the conditioning of exp(E): an ulp of E is |E| ulp of the result; |E| reaches ~100
// for kappa = 1e9), and values below 1e-30 compared absolutely (denormal underflow). The worst
// case is printed (measured: 0.28 of the bound, ~4.5 ulp, kappa = 1e-3).
TEST(MicrofacetBatch, FixedDirectionBatchEqualsScalarFSingle) {
    const Pairs p = make_pairs();
    std::vector<Vec3> free_dirs;
    for (std::size_t k = 0; k < p.size(); ++k)
        free_dirs.push_back(p.o(k)), free_dirs.push_back(p.i(k));
    const std::size_t n = free_dirs.size();
    std::vector<float> x(n), y(n), z(n), r(n), g(n), b(n);
    for (std::size_t k = 0; k < n; ++k)
        x[k] = free_dirs[k].x, y[k] = free_dirs[k].y, z[k] = free_dirs[k].z;
    const std::vector<Vec3> fixed_dirs = {Vec3(0.f, 0.f, 1.f),      spherical(0.866f, 0.4f),
                                          spherical(0.342f, 2.f),   spherical(0.0175f, 0.f),
                                          spherical(1.75e-3f, 1.f), spherical(1e-4f, 5.f),
                                          spherical(-0.5f, 0.f)};
    double worst_blinn = 0.0;
    std::string worst_label;
    long compared = 0;
    for (const test::LobeSpec& spec : test::lobe_corners(false)) {
        MicrofacetReflection lobe = spec.lobe(Rgb(0.9f, 0.7f, 0.5f));
        MicrofacetBatch batch(lobe);
        const MicrofacetDistribution& d = lobe.distribution();
        const bool blinn = d.kind() == DistributionKind::Blinn;
        for (const Vec3& fixed : fixed_dirs) {
            for (bool fixed_is_wo : {true, false}) {
                batch.f_single_fixed(n, fixed, fixed_is_wo, {x.data(), y.data(), z.data()},
                                     {r.data(), g.data(), b.data()});
                int bad = 0;
                for (std::size_t k = 0; k < n && bad < 3; ++k) {
                    const Vec3 wo = fixed_is_wo ? fixed : free_dirs[k];
                    const Vec3 wi = fixed_is_wo ? free_dirs[k] : fixed;
                    const Rgb f = lobe.f_single(wo, wi);
                    const float got[3] = {r[k], g[k], b[k]}, want[3] = {f.r, f.g, f.b};
                    for (int c = 0; c < 3; ++c) {
                        ++compared;
                        if (!blinn) {
                            if (same_bits(got[c], want[c])) continue;
                        } else {
                            // Exponents of D (at the half vector) and of Lambda (both directions).
                            double e = 0.0;
                            const Vec3 h = wo + wi;
                            if (wo.z > 0.f && wi.z > 0.f && glm::dot(h, h) > 0.f) {
                                const Vec3 wm = glm::normalize(h);
                                const double t = (sqr(double(wm.x) / d.alpha_x()) +
                                                  sqr(double(wm.y) / d.alpha_y())) /
                                                 sqr(double(wm.z));
                                e = 0.5 * (double(d.nu()) + 2.0) * std::log1p(t) +
                                    2.0 * std::fabs(std::log(sqr(double(wm.z))));
                                for (const Vec3& w : {wo, wi}) {
                                    const double rr = std::hypot(double(d.alpha_x()) * w.x,
                                                                 double(d.alpha_y()) * w.y);
                                    if (rr > 0.0)
                                        e = std::max(e, 0.5 * (double(d.nu()) - 1.0) *
                                                            std::log1p(sqr(double(w.z) / rr)));
                                }
                            }
                            const double diff = std::fabs(double(got[c]) - double(want[c]));
                            const double scale = std::fabs(double(want[c]));
                            if (scale < 1e-30 && diff < 1e-30) continue;
                            const double rel = diff / scale;
                            const double bound = 0x1p-20 * (1.0 + std::min(e, 110.0));
                            if (rel / bound > worst_blinn)
                                worst_blinn = rel / bound, worst_label = spec.name();
                            if (rel <= bound) continue;
                        }
                        ++bad;
                        ADD_FAILURE()
                            << spec.name() << " fixed (" << fixed.x << ", " << fixed.y << ", "
                            << fixed.z << ") fixed_is_wo " << fixed_is_wo << " free #" << k
                            << " channel " << c << ": scalar " << want[c] << ", batch " << got[c];
                        break;
                    }
                }
            }
        }
    }
    std::printf("Blinn: worst relative difference %.3g of its bound (%s); %ld values compared\n",
                worst_blinn, worst_label.c_str(), compared);
}

TEST(MicrofacetBatch, TakesTheVectorisedPathOnlyForUncompensatedRoughGgx) {
    auto lobe = [](MicrofacetDistribution d, bool ec) {
        return MicrofacetReflection(d, Fresnel::schlick(Rgb(0.5f)), Rgb(1.f), ec);
    };
    EXPECT_TRUE(MicrofacetBatch(lobe(MicrofacetDistribution::ggx(0.3f, 0.1f), false)).vectorised());
    EXPECT_FALSE(MicrofacetBatch(lobe(MicrofacetDistribution::ggx(0.3f, 0.1f), true)).vectorised());
    EXPECT_FALSE(
        MicrofacetBatch(lobe(MicrofacetDistribution::ggx(1e-5f, 1e-5f), false)).vectorised());
    EXPECT_FALSE(
        MicrofacetBatch(lobe(MicrofacetDistribution::beckmann(0.3f, 0.3f), false)).vectorised());
    EXPECT_FALSE(
        MicrofacetBatch(lobe(MicrofacetDistribution::blinn(20.f, 20.f), false)).vectorised());
}

TEST(MicrofacetBatch, EmptyBatchWritesNothing) {
    MicrofacetBatch batch(MicrofacetReflection(MicrofacetDistribution::ggx(0.3f, 0.3f),
                                               Fresnel::none(), Rgb(1.f), false));
    float sentinel = -7.f;
    batch.f(0, {nullptr, nullptr, nullptr}, {nullptr, nullptr, nullptr},
            {&sentinel, &sentinel, &sentinel});
    batch.pdf(0, {nullptr, nullptr, nullptr}, {nullptr, nullptr, nullptr}, &sentinel);
    EXPECT_EQ(sentinel, -7.f);
}

}  // namespace
}  // namespace facet
