// Chi-square goodness of fit of every sampler against its pdf (issue 2, "Tests").
//
// Every case runs sample_f N times at a fixed wo with a fixed seed, bins the directions in
// (cos theta, phi) and compares the counts with N * (integral of pdf over each cell); see
// tests/core/chi2.h for the method. The significance level 0.01 is shared by all cases of the
// suite with a Sidak correction: each case must reach p >= 1 - 0.99^(1/n_cases).
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "chi2.h"
#include "facet/lambert.h"
#include "facet/microfacet.h"
#include "facet/mirror.h"
#include "facet/registry.h"

namespace facet {
namespace {

using test::Chi2Options;
using test::Chi2Result;

using test::kDeg;
constexpr double kAlpha = 0.01;

Vec3 wo_at(double theta_deg, double phi_deg) {
    double t = theta_deg * kDeg, p = phi_deg * kDeg;
    return Vec3(
        glm::normalize(DVec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t))));
}

struct Chi2Case {
    std::string name;
    std::function<Chi2Result()> run;
};

// Incidence angles the issue asks for; 89 degrees is grazing.
const double kThetas[] = {0.0, 45.0, 80.0, 89.0};

std::vector<Chi2Case> make_cases() {
    std::vector<Chi2Case> cases;
    auto add = [&](std::string name, std::function<Chi2Result()> run) {
        for (char& c : name)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        cases.push_back({std::move(name), std::move(run)});
    };

    // Lambert: cosine-weighted sampling.
    for (double th : kThetas) {
        add("lambert_theta" + std::to_string(int(th)), [th] {
            LambertReflection b(Rgb(0.5f, 0.7f, 0.2f));
            return test::chi2_sampling_test(b, wo_at(th, 30.0));
        });
    }

    // Bare microfacet lobes. Sharp lobes (equivalent alpha < 0.15) are binned about the mirror
    // direction, over a cap of 8 lobe widths, so that the lobe spans many cells; the rest of
    // the sphere is the band below the cap.
    using MD = MicrofacetDistribution;
    auto lobe_options = [](const MicrofacetReflection& b, const Vec3& wo) {
        Chi2Options o;
        float a = b.distribution().equivalent_alpha();
        if (a < 0.15f) {
            o.axis = Vec3(-wo.x, -wo.y, wo.z);
            o.cos_min = std::cos(std::min(80.0 * kDeg, 8.0 * a));
            // Near grazing the cap straddles the horizon and the lobe is a thin sliver along it:
            // refine every cell 3 levels (1024 nodes), 4 (4096) beyond 85 degrees, before
            // adapting, or the 4x4 rule and its check can agree on a wrong value (seen: Beckmann
            // 0.05 at 89 deg, integral 0.9755 with 2 levels vs 0.98336 with 4 and 6 levels).
            o.quad_min_depth = wo.z < 0.087f ? 4 : 3;
        }
        return o;
    };
    auto add_lobe = [&](const std::string& name, std::function<MD()> dist, Fresnel fr, bool ec,
                        double th, double ph) {
        add(name + "_theta" + std::to_string(int(th)) + "_phi" + std::to_string(int(ph)), [=] {
            MicrofacetReflection b(dist(), fr, Rgb(1.f), ec);
            Vec3 wo = wo_at(th, ph);
            return test::chi2_sampling_test(b, wo, lobe_options(b, wo));
        });
    };
    // Isotropic: several roughnesses per distribution, all four incidences.
    for (float a : {0.05f, 0.3f, 1.0f}) {
        for (double th : kThetas) {
            add_lobe(
                "ggx_a" + std::to_string(a), [a] { return MD::ggx(a, a); }, Fresnel::none(), false,
                th, 20.0);
            add_lobe(
                "beckmann_a" + std::to_string(a), [a] { return MD::beckmann(a, a); },
                Fresnel::none(), false, th, 20.0);
        }
    }
    for (float k : {0.f, 10.f, 1000.f}) {
        for (double th : kThetas)
            add_lobe(
                "blinn_k" + std::to_string(int(k)), [k] { return MD::blinn(k, k); },
                Fresnel::none(), false, th, 20.0);
    }
    // Anisotropic, with wo at several azimuths (rotated anisotropy) and both axis orders.
    for (double th : {45.0, 80.0}) {
        for (double ph : {0.0, 30.0, 90.0, 135.0}) {
            add_lobe(
                "ggx_aniso_0_1_0_6", [] { return MD::ggx(0.1f, 0.6f); }, Fresnel::none(), false, th,
                ph);
            add_lobe(
                "beckmann_aniso_0_5_0_08", [] { return MD::beckmann(0.5f, 0.08f); },
                Fresnel::none(), false, th, ph);
            add_lobe(
                "blinn_aniso_5_500", [] { return MD::blinn(5.f, 500.f); }, Fresnel::none(), false,
                th, ph);
        }
    }
    // Energy compensation adds a cosine lobe to the mixture; a coloured conductor makes the
    // lobe-selection weights depend on F_avg.
    Fresnel gold = Fresnel::conductor(Rgb(0.18f, 0.42f, 1.37f), Rgb(3.42f, 2.35f, 1.77f));
    for (double th : {0.0, 60.0, 85.0}) {
        add_lobe(
            "ggx_ec_a0_8", [] { return MD::ggx(0.8f, 0.8f); }, Fresnel::none(), true, th, 0.0);
        add_lobe(
            "beckmann_ec_gold_a0_5", [] { return MD::beckmann(0.5f, 0.5f); }, gold, true, th, 0.0);
        add_lobe(
            "blinn_ec_aniso_k1_k20", [] { return MD::blinn(1.f, 20.f); }, gold, true, th, 45.0);
    }

    // Materials through the registry (the same path scenes take), incl. composite mixtures
    // with a delta lobe (their specular fraction gets its own chi-square cell).
    struct Mat {
        std::string name, model;
        ParamSet params;
    };
    std::vector<Mat> mats;
    {
        Mat m{"mat_lambert", "lambert", {}};
        m.params.set("reflectance", Rgb(0.2f, 0.5f, 0.9f));
        mats.push_back(m);
        Mat g{"mat_ggx_conductor", "ggx", {}};
        g.params.set("alpha", 0.25);
        g.params.set("fresnel", std::string("conductor"));
        mats.push_back(g);
        Mat c{"mat_composite_default", "composite", {}};
        mats.push_back(c);
        Mat cm{"mat_composite_mirror", "composite", {}};
        cm.params.set("glossy_reflectance", 0.5);
        cm.params.set("mirror_reflectance", 0.3);
        cm.params.set("alpha", 0.4);
        mats.push_back(cm);
        Mat cb{"mat_composite_blinn_aniso_ec", "composite", {}};
        cb.params.set("distribution", std::string("blinn"));
        cb.params.set("exponent_u", 3.0);
        cb.params.set("exponent_v", 60.0);
        cb.params.set("energy_compensation", true);
        cb.params.set("mirror_reflectance", 0.2);
        cb.params.set("glossy_reflectance", 0.8);
        mats.push_back(cb);
        Mat ck{"mat_composite_beckmann_schlick", "composite", {}};
        ck.params.set("distribution", std::string("beckmann"));
        ck.params.set("alpha_u", 0.2);
        ck.params.set("alpha_v", 0.7);
        ck.params.set("fresnel", std::string("schlick"));
        ck.params.set("f0", 0.3);
        ck.params.set("diffuse_reflectance", Rgb(0.9f, 0.1f, 0.4f));
        mats.push_back(ck);
    }
    for (const Mat& m : mats) {
        for (double th : kThetas) {
            add(m.name + "_theta" + std::to_string(int(th)), [m, th] {
                Material mat = make_material(m.model, m.params);
                return test::chi2_sampling_test(mat, wo_at(th, 50.0));
            });
        }
    }
    return cases;
}

const std::vector<Chi2Case>& all_cases() {
    static const std::vector<Chi2Case> cases = make_cases();

    return cases;
}

class Chi2 : public ::testing::TestWithParam<int> {};

TEST_P(Chi2, SamplerMatchesPdf) {
    const Chi2Case& c = all_cases()[GetParam()];
    const double alpha = test::sidak_alpha(kAlpha, int(all_cases().size()));
    Chi2Result r = c.run();
    std::printf("  %s: %s\n", c.name.c_str(), r.describe().c_str());
    SCOPED_TRACE(c.name + ": " + r.describe());
    EXPECT_GE(r.chi2.p_value, alpha);
    EXPECT_FALSE(r.chi2.zero_expected_hit);
    EXPECT_EQ(r.below_horizon, 0);
    EXPECT_EQ(r.not_unit, 0);
    EXPECT_EQ(r.bad_values, 0);
    // The pdf integrates to at most 1 (quadrature tolerance 1e-9 per unit area over 4 pi).
    EXPECT_LE(r.pdf_integral, 1.0 + 1e-5);
    // A sample's own pdf and f equal pdf() and f() at its direction. Both are float
    // evaluations of the same formulas along different paths (e.g. the half vector is
    // re-derived from wo + wi), so they differ by round-off amplified by the lobe's slope:
    // 2e-3 leaves a margin of ~10x over the worst case seen for alpha >= 0.02.
    EXPECT_LE(r.max_pdf_rel_err, 2e-3);
    EXPECT_LE(r.max_f_rel_err, 2e-3);
}

INSTANTIATE_TEST_SUITE_P(AllSamplers, Chi2, ::testing::Range(0, int(all_cases().size())),
                         [](const ::testing::TestParamInfo<int>& info) {
                             return all_cases()[info.param].name;
                         });

// The test can fail: a pdf tilted by (1 + 0.1 x) integrates to 1 (x is odd over a lobe
// symmetric in x) but has the wrong shape; it must be rejected at the same level, and a 5%
// tilt already gives p far below it with 2e5 samples.
TEST(Chi2Power, RejectsTiltedLambertPdf) {
    LambertReflection lambert(Rgb(0.8f));
    const double alpha = test::sidak_alpha(kAlpha, int(all_cases().size()));
    for (float tilt : {0.1f, 0.05f}) {
        test::TiltedPdf<LambertReflection> wrong{lambert, tilt};
        Chi2Result r = test::chi2_sampling_test(wrong, wo_at(30.0, 90.0));
        std::printf("  tilt %.2f: %s\n", tilt, r.describe().c_str());
        SCOPED_TRACE(r.describe());
        EXPECT_NEAR(r.pdf_integral, 1.0, 1e-6);
        EXPECT_LT(r.chi2.p_value, alpha) << "tilt " << tilt;
    }
}

// A sampler that puts mass where pdf() is zero is rejected outright (p = 0).
TEST(Chi2Power, RejectsSamplesOutsideSupport) {
    struct Leaky {
        LambertReflection base{Rgb(1.f)};
        std::optional<BSDFSample> sample_f(const Vec3& wo, float uc, Vec2 u) const {
            auto s = base.sample_f(wo, uc, u);
            if (s && u.x < 0.01f) s->wi.z = -s->wi.z;  // 1% of samples below the horizon
            return s;
        }
        float pdf(const Vec3& wo, const Vec3& wi) const { return base.pdf(wo, wi); }
        Rgb f(const Vec3& wo, const Vec3& wi) const { return base.f(wo, wi); }
    } leaky;
    Chi2Result r = test::chi2_sampling_test(leaky, wo_at(10.0, 0.0));
    EXPECT_TRUE(r.chi2.zero_expected_hit) << r.describe();
    EXPECT_EQ(r.chi2.p_value, 0.0);
    EXPECT_GT(r.below_horizon, 0);
}

// Pooling and the statistic on a hand-made table (so the statistic itself can be checked).
TEST(Chi2Power, StatisticOnKnownTable) {
    // Cells 3 and 4 (expected 2 and 1) are pooled into (o 4, e 3), which is still < 5 and joins
    // the smallest kept cell (e 10, o 12 -> o 16, e 13).
    std::vector<double> o{12, 18, 30, 3, 1}, e{10, 20, 30, 2, 1};
    test::Chi2Statistic s = test::chi2_statistic(o, e);
    double expect = 9.0 / 13.0 + 4.0 / 20.0 + 0.0;
    EXPECT_NEAR(s.statistic, expect, 1e-12);
    EXPECT_EQ(s.dof, 2);
    EXPECT_EQ(s.cells_pooled, 2);
    // Q(1, x/2) = exp(-x/2) for 2 degrees of freedom.
    EXPECT_NEAR(s.p_value, std::exp(-0.5 * expect), 1e-12);
    EXPECT_NEAR(test::sidak_alpha(0.01, 1), 0.01, 1e-15);
    EXPECT_NEAR(1.0 - std::pow(1.0 - test::sidak_alpha(0.01, 100), 100), 0.01, 1e-12);
}

// Specular (delta) samples are excluded from the chi-square; the mirror is checked directly:
// every sample is the exact mirror direction, pdf 1, and f cos = F.
TEST(Chi2Specular, MirrorSamplesAreExactDeltas) {
    MirrorReflection m(Fresnel::conductor(Rgb(0.2f, 0.9f, 1.1f), Rgb(3.9f, 2.4f, 2.2f)), Rgb(1.f));
    pcg32 rng(11);
    for (double th : kThetas) {
        Vec3 wo = wo_at(th, 70.0);
        for (int i = 0; i < 1000; ++i) {
            Vec2 u(test::uniform_float(rng), test::uniform_float(rng));
            auto s = m.sample_f(wo, test::uniform_float(rng), u);
            ASSERT_TRUE(s.has_value());
            EXPECT_TRUE(s->is_specular());
            EXPECT_EQ(s->wi, Vec3(-wo.x, -wo.y, wo.z));
            EXPECT_EQ(s->pdf, 1.f);
            Rgb fc = s->f * s->wi.z, F = m.reflectance(wo.z);
            // f = F / cos then times cos: 2 roundings, relative 2^-23 each.
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(fc[c], F[c], 4e-7f * F[c]);
            EXPECT_EQ(m.pdf(wo, s->wi), 0.f);
            EXPECT_EQ(m.f(wo, s->wi), Rgb(0.f));
        }
        // The chi-square machinery sees only the specular cell: nothing to test, nothing wrong.
        Chi2Result r = test::chi2_sampling_test(m, wo, Chi2Options{.n_samples = 2000});
        EXPECT_EQ(r.specular, 2000);
        EXPECT_EQ(r.p_spec, 1.0);
        EXPECT_EQ(r.pdf_integral, 0.0);
    }
}

}  // namespace
}  // namespace facet
