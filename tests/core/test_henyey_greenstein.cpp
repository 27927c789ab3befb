// The Henyey-Greenstein phase function (facet/henyey_greenstein.h): its sampler against its own
// pdf by chi-square over the sphere, normalisation, eval == pdf, reciprocity, the mean cosine
// (which fixes the sign convention of g: Cycles' positive = forward), and the sample weight.
#include <gtest/gtest.h>
#include <pcg_random.hpp>

#include <cmath>
#include <vector>

#include "chi2.h"
#include "facet/henyey_greenstein.h"

namespace facet {
namespace {

// The g values of the tests: both signs, the isotropic case and strong lobes.
const std::vector<float> kGs = {-0.9f, -0.5f, -0.1f, 0.f, 0.3f, 0.7f, 0.9f};

// The phase function as the chi-square harness' sampler type (chi2.h: f, pdf, sample_f).
struct PhaseAsBxDF {
    HenyeyGreenstein hg;
    Rgb f(const Vec3& wo, const Vec3& wi) const { return Rgb(hg.eval(wo, wi)); }
    float pdf(const Vec3& wo, const Vec3& wi) const { return hg.pdf(wo, wi); }
    std::optional<BSDFSample> sample_f(const Vec3& wo, float /*uc*/, Vec2 u) const {
        const std::optional<PhaseSample> s = hg.sample(wo, u);
        if (!s) return std::nullopt;
        return BSDFSample{Rgb(s->p), s->wi, s->pdf, BxDFFlags::Diffuse};
    }
};

// Integral over the sphere of g(w) by the midpoint rule in (cos theta, phi) about `axis`
// (20000 x 16 nodes, in double): for the lobes here, peaked about the axis, its error is below
// 1e-5 (at g = 0.9 the midpoint error h^2/24 |f'(1)| is ~2e-6).
double sphere_integral(const std::function<double(const Vec3&)>& g, const Vec3& axis) {
    const Frame fr = Frame::from_z(axis);
    constexpr int kMu = 20000, kPhi = 16;
    double sum = 0.0;
    for (int i = 0; i < kMu; ++i) {
        const double c = -1.0 + (i + 0.5) * 2.0 / kMu;
        for (int j = 0; j < kPhi; ++j)
            sum += g(test::detail::cell_direction(fr, c, (j + 0.5) * 2.0 * kPiD / kPhi));
    }
    return sum * (2.0 / kMu) * (2.0 * kPiD / kPhi);
}

// Sampling matches the pdf: chi-square over 16 x 16 cells of the whole sphere about the
// normal, at two viewing directions, 1e5 samples each. Significance 1% over all cases (Sidak):
// a correct sampler fails one run in a hundred; a sampler with g's sign flipped, or the
// density of another g, fails with p ~ 0 (see HenyeyGreenstein.ChiSquareRejectsAWrongG).
TEST(HenyeyGreenstein, SamplingMatchesPdfChiSquare) {
    const double alpha = test::sidak_alpha(0.01, int(2 * kGs.size()));
    for (float g : kGs) {
        for (double theta : {20.0, 110.0}) {
            const test::Chi2Result r = test::sphere_chi2(PhaseAsBxDF{HenyeyGreenstein(g)}, theta);
            EXPECT_GE(r.chi2.p_value, alpha) << "g " << g << " theta " << theta << "\n"
                                             << r.describe();
            EXPECT_EQ(r.failed, 0) << "g " << g;
            EXPECT_EQ(r.bad_values, 0) << "g " << g;
            EXPECT_EQ(r.not_unit, 0) << "g " << g;
            // Float round-off of a sample's own pdf against pdf() at its direction.
            EXPECT_LT(r.max_pdf_rel_err, 1e-4) << "g " << g;
        }
    }
}

// The harness can fail here: samples of g = 0.5 against the pdf of g = 0.45, and of g against
// -g (the sign convention), are rejected.
TEST(HenyeyGreenstein, ChiSquareRejectsAWrongG) {
    struct Mismatched {
        HenyeyGreenstein sampler, density;
        Rgb f(const Vec3& wo, const Vec3& wi) const { return Rgb(density.eval(wo, wi)); }
        float pdf(const Vec3& wo, const Vec3& wi) const { return density.pdf(wo, wi); }
        std::optional<BSDFSample> sample_f(const Vec3& wo, float uc, Vec2 u) const {
            auto s = PhaseAsBxDF{sampler}.sample_f(wo, uc, u);
            if (s) s->pdf = density.pdf(wo, s->wi);
            return s;
        }
    };
    for (auto [gs, gd] : {std::pair{0.5f, 0.45f}, std::pair{0.5f, -0.5f}}) {
        const test::Chi2Result r =
            test::sphere_chi2(Mismatched{HenyeyGreenstein(gs), HenyeyGreenstein(gd)}, 30.0);
        EXPECT_LT(r.chi2.p_value, 1e-6) << "sampled g " << gs << ", density g " << gd;
    }
}

// The pdf integrates to 1 over the sphere (the 1e-4 tolerance: the quadrature's 1e-5 and float
// evaluation of a lobe whose peak is (1 + g) / (4 pi (1 - g)^2) = 15 at g = 0.9).
TEST(HenyeyGreenstein, PdfIntegratesToOne) {
    const Vec3 wo = test::dir(40.0, 75.0);
    for (float g : kGs) {
        const HenyeyGreenstein hg(g);
        // Nodes concentrated about the peak: the axis is the forward direction -wo.
        const double total =
            sphere_integral([&](const Vec3& wi) { return double(hg.pdf(wo, wi)); }, -wo);
        EXPECT_NEAR(total, 1.0, 1e-4) << "g " << g;
    }
}

// The mean cosine of the scattering angle, <dot(-wi, wo)> = g: positive g scatters forward
// (light keeps its direction), Cycles' convention. Tolerance as above.
TEST(HenyeyGreenstein, MeanCosineIsGForwardPositive) {
    const Vec3 wo = test::dir(10.0, 200.0);
    for (float g : kGs) {
        const HenyeyGreenstein hg(g);
        const double mean = sphere_integral(
            [&](const Vec3& wi) { return double(hg.pdf(wo, wi)) * -double(glm::dot(wi, wo)); },
            -wo);
        EXPECT_NEAR(mean, double(g), 1e-4) << "g " << g;
    }
    // Forward scattering: the sampled wi lies near -wo (toward where the light came from).
    const std::optional<PhaseSample> s = HenyeyGreenstein(0.9f).sample(wo, Vec2(0.5f, 0.3f));
    ASSERT_TRUE(s.has_value());
    EXPECT_LT(glm::dot(s->wi, wo), -0.8f);
}

// eval == pdf (sampling is exact), reciprocity p(wo, wi) = p(wi, wo), and each sample carries
// value == pdf == eval at its direction, so the weight p / pdf is 1: over random direction
// pairs, to float round-off (relative 1e-5: one denominator's cube root of ~1e-7 errors).
TEST(HenyeyGreenstein, EvalEqualsPdfReciprocalAndUnitWeight) {
    pcg32 rng(11);
    auto uniform_dir = [&] {
        const float z = 1.f - 2.f * test::uniform_float(rng);
        const float phi = 2.f * kPi * test::uniform_float(rng);
        const float r = std::sqrt(std::fmax(0.f, 1.f - z * z));
        return Vec3(r * std::cos(phi), r * std::sin(phi), z);
    };
    for (float g : kGs) {
        const HenyeyGreenstein hg(g);
        for (int i = 0; i < 2000; ++i) {
            const Vec3 wo = uniform_dir(), wi = uniform_dir();
            EXPECT_EQ(hg.eval(wo, wi), hg.pdf(wo, wi));
            EXPECT_NEAR(hg.eval(wo, wi), hg.eval(wi, wo), 1e-5f * hg.eval(wo, wi));
            const Vec2 u(test::uniform_float(rng), test::uniform_float(rng));
            const std::optional<PhaseSample> s = hg.sample(wo, u);
            ASSERT_TRUE(s.has_value());
            EXPECT_NEAR(glm::length(s->wi), 1.f, 1e-5f);
            EXPECT_EQ(s->p, s->pdf);
            EXPECT_NEAR(s->pdf, hg.pdf(wo, s->wi), 1e-4f * s->pdf) << "g " << g;
        }
    }
}

}  // namespace
}  // namespace facet
