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

#include <cmath>
#include <cstring>
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
