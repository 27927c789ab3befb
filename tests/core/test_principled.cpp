// The principled model (facet/principled.h, docs/principled.md): closed forms of single lobes
// (Disney diffuse, sheen, metallic without specular against the plain GGX model, GTR1
// normalisation), Cycles' special cases, reciprocity without transmission, chi-square of the
// sampler over the sphere (with wo inside for transmission), energy bounds and bad input.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "chi2.h"
#include "facet/fresnel.h"
#include "facet/registry.h"

namespace facet {
namespace {

using test::dir;
using test::stress_scale;

Material principled(const ParamSet& p) {
    return make_material("principled", p);
}

float schlick(float c) {
    const float m = 1.f - c;
    return m * m * m * m * m;
}

// With specular = metallic = 0 Cycles 3.4 allocates no specular closure: the model is Disney
// diffuse alone, f = C / pi [(1 - FV/2)(1 - FL/2) + RR (FL + FV + FL FV (RR - 1))], RR =
// roughness (1 + wi.wo). Compared with the closed form to 1e-5 relative (float rounding).
TEST(Principled, NoSpecularLobeWithSpecularAndMetallicZero) {
    const Rgb c(0.7f, 0.4f, 0.2f);
    for (double r : {0.0, 0.5, 1.0}) {
        const Material m = principled({{"base_color", c}, {"specular", 0.0}, {"roughness", r}});
        EXPECT_EQ(m.flags(), BxDFFlags::Diffuse);
        for (auto [to, ti, phi] : {std::tuple{0.0, 0.0, 0.0},
                                   {30.0, 60.0, 180.0},
                                   {80.0, 80.0, 0.0},
                                   {85.0, 10.0, 90.0}}) {
            const Vec3 wo = dir(to, 0.0), wi = dir(ti, phi);
            const float fv = schlick(wo.z), fl = schlick(wi.z);
            const float rr = float(r) * (1.f + glm::dot(wi, wo));
            const float d =
                (1.f - 0.5f * fv) * (1.f - 0.5f * fl) + rr * (fl + fv + fl * fv * (rr - 1.f));
            const Rgb expected = c * (d * kInvPi);
            const Rgb got = m.f(wo, wi);
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(got[k], expected[k], 1e-5f * expected[k]) << r << " " << to;
        }
    }
    // A tiny specular (above Cycles' cut-off 1e-5) brings the GGX lobe back.
    EXPECT_TRUE(any(principled({{"specular", 1e-4}}).flags() & BxDFFlags::Glossy));
    EXPECT_FALSE(any(principled({{"specular", 1e-6}}).flags() & BxDFFlags::Glossy));
}

// Sheen on a black base with no specular: the only lobe is f = sheen (1 - wi.h)^5 (black base:
// the tint colour is white), with no 1 / pi (Burley 2012's sheen is added outside the 1 / pi).
TEST(Principled, SheenIsSchlickOfTheHalfAngle) {
    const Material m =
        principled({{"base_color", 0.0}, {"specular", 0.0}, {"sheen", 0.8}, {"sheen_tint", 1.0}});
    for (auto [to, ti, phi] :
         {std::tuple{0.0, 45.0, 0.0}, {60.0, 70.0, 180.0}, {89.0, 89.0, 170.0}}) {
        const Vec3 wo = dir(to, 0.0), wi = dir(ti, phi);
        const Vec3 h = glm::normalize(wo + wi);
        const float expected = 0.8f * schlick(glm::dot(wi, h));
        EXPECT_NEAR(m.f(wo, wi).g, expected, 1e-5f * expected + 1e-9f) << to << " " << ti;
    }
}

// Metallic 1 with specular 0: eta_s = 1, so F0 = 0 and FH = 0: F is the base colour itself, at
// every angle (no Fresnel brightening toward grazing), and the lobe is GGX at alpha =
// roughness^2 with Cycles 3.4's separable masking-shadowing G1(wo) G1(wi):
// f = C D G1(wo) G1(wi) / (4 cos_i cos_o). Tolerance 1e-4 relative (float rounding).
TEST(Principled, MetallicWithoutSpecularIsGgxTimesBaseColour) {
    const Rgb c(0.9f, 0.6f, 0.3f);
    const double r = 0.6;
    const Material m =
        principled({{"base_color", c}, {"metallic", 1.0}, {"specular", 0.0}, {"roughness", r}});
    const MicrofacetDistribution d = MicrofacetDistribution::ggx(float(r * r), float(r * r));
    for (auto [to, ti, phi] : {std::tuple{0.0, 30.0, 0.0},
                               {50.0, 50.0, 180.0},
                               {80.0, 85.0, 160.0},
                               {20.0, 70.0, 90.0}}) {
        const Vec3 wo = dir(to, 0.0), wi = dir(ti, phi);
        const Vec3 h = glm::normalize(wo + wi);
        const Rgb b = c * (d.D(h) * d.G1(wo) * d.G1(wi) / (4.f * wo.z * wi.z));
        const Rgb a = m.f(wo, wi);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-4f * b[k]) << to << " " << ti;
    }
}

// GTR1 is normalised so that int D cos dw = 1: the clearcoat lobe alone (black base, no
// specular) sampled by its own sampler has a pdf that integrates to 1 over the hemisphere
// (chi2's quadrature), which the chi-square test below also checks per cell.
TEST(Principled, ClearcoatPdfIntegratesToOne) {
    for (double cr : {0.03, 0.3, 1.0}) {
        const Material m = principled({{"base_color", 0.0},
                                       {"specular", 0.0},
                                       {"clearcoat", 1.0},
                                       {"clearcoat_roughness", cr}});
        test::Chi2Options o;
        o.n_samples = 20000;
        const test::Chi2Result r = test::chi2_sampling_test(m, dir(40.0, 0.0), o);
        // Samples reflected below the horizon fail: the integral is the success rate (< 1).
        EXPECT_NEAR(r.pdf_integral + double(r.failed) / r.n, 1.0, 0.02) << cr;
    }
}

// Without transmission every lobe is symmetric in (wo, wi): f(wo, wi) = f(wi, wo). (The glass
// lobes are not: Cycles splits them by the Fresnel term at wo.) Tolerance 1e-4 relative.
TEST(Principled, ReciprocalWithoutTransmission) {
    const Material m = principled({{"base_color", Rgb(0.8f, 0.5f, 0.2f)},
                                   {"metallic", 0.3},
                                   {"roughness", 0.4},
                                   {"anisotropic", 0.6},
                                   {"anisotropic_rotation", 0.15},
                                   {"sheen", 1.0},
                                   {"clearcoat", 0.7},
                                   {"clearcoat_roughness", 0.2},
                                   {"specular_tint", 0.5}});
    pcg32 rng(3);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 a = dir(89.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
        const Vec3 b = dir(89.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
        const Rgb fab = m.f(a, b), fba = m.f(b, a);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(fab[k], fba[k], 1e-4f * std::max(fab[k], fba[k]) + 1e-9f) << i;
    }
}

// PrincipledBxDF::only (povray-facet shades the lobes separately): the lobes of a partition
// sum to the whole model's f, each part keeps only its own lobes (flags), and a part's sampler
// stays consistent with its pdf (chi-square). Tolerance 1e-5 relative: the parts evaluate the
// same float expressions, only summed in another order. A part that dropped or doubled a lobe
// (e.g. only() ignoring the clearcoat bit) is off by that lobe's f, far above it.
TEST(Principled, LobePartsSumToTheModel) {
    using P = PrincipledBxDF;
    const Material whole = principled({{"base_color", Rgb(0.8f, 0.5f, 0.2f)},
                                       {"metallic", 0.3},
                                       {"roughness", 0.6},
                                       {"sheen", 1.0},
                                       {"clearcoat", 0.7},
                                       {"clearcoat_roughness", 0.2}});
    const PrincipledBxDF& b = *whole.principled();
    for (int k = P::kCosine; k <= P::kClearcoat; ++k) EXPECT_TRUE(b.has_lobe(P::Lobe(k))) << k;
    EXPECT_FALSE(b.has_lobe(P::kGlassReflect));
    const Material cosine(b.only(1u << P::kCosine));
    const Material spec(b.only(1u << P::kSpecular));
    const Material coat(b.only(1u << P::kClearcoat));
    EXPECT_EQ(cosine.flags(), BxDFFlags::Diffuse);
    EXPECT_EQ(spec.flags(), BxDFFlags::Glossy);
    EXPECT_EQ(coat.flags(), BxDFFlags::Glossy);
    EXPECT_FALSE(cosine.principled()->has_lobe(P::kSpecular));
    pcg32 rng(5);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 a = dir(89.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
        const Vec3 c = dir(89.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
        const Rgb sum = cosine.f(a, c) + spec.f(a, c) + coat.f(a, c), f = whole.f(a, c);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(sum[k], f[k], 1e-5f * f[k] + 1e-9f) << i;
    }
    // All lobes kept: the model itself, bit for bit.
    const Material all(b.only(~0u));
    const Vec3 o = dir(50.0, 0.0), i = dir(20.0, 150.0);
    EXPECT_EQ(all.f(o, i), whole.f(o, i));
    EXPECT_EQ(all.pdf(o, i), whole.pdf(o, i));
    // Two lobes: the sampler renormalises over them.
    const Material two(b.only((1u << P::kSpecular) | (1u << P::kClearcoat)));
    test::expect_sphere_chi2(test::sphere_chi2(two, 40.0), 0.01);
    // Smooth specular: the delta lobe is flagged Specular in the part that keeps it.
    const Material smooth = principled({{"roughness", 0.0}, {"clearcoat", 0.5}});
    const P& sb = *smooth.principled();
    EXPECT_TRUE(sb.lobe_is_delta(P::kSpecular));
    EXPECT_FALSE(sb.lobe_is_delta(P::kClearcoat));
    EXPECT_EQ(Material(sb.only(1u << P::kSpecular)).flags(), BxDFFlags::Specular);
}

struct Case {
    std::string name;
    ParamSet params;
    double theta;  // of wo; > 90 is inside (transmission only)
};

std::vector<Case> chi2_cases() {
    const Rgb c(0.8f, 0.5f, 0.3f);
    std::vector<Case> v;
    for (double th : {0.0, 50.0, 85.0}) {
        v.push_back({"default", {{"base_color", c}}, th});
        v.push_back({"metal", {{"base_color", c}, {"metallic", 1.0}, {"roughness", 0.2}}, th});
        v.push_back({"aniso",
                     {{"base_color", c},
                      {"metallic", 0.5},
                      {"roughness", 0.5},
                      {"anisotropic", 0.8},
                      {"anisotropic_rotation", 0.1}},
                     th});
        v.push_back({"coat_sheen",
                     {{"base_color", c},
                      {"sheen", 1.0},
                      {"clearcoat", 1.0},
                      {"clearcoat_roughness", 0.1},
                      {"roughness", 0.9}},
                     th});
    }
    for (double th : {0.0, 60.0, 89.0, 120.0, 175.0}) {
        v.push_back({"glass",
                     {{"base_color", c}, {"transmission", 1.0}, {"roughness", 0.3}, {"ior", 1.5}},
                     th});
        v.push_back({"half_glass",
                     {{"base_color", c},
                      {"transmission", 0.5},
                      {"roughness", 0.5},
                      {"transmission_roughness", 0.4},
                      {"ior", 4.0},
                      {"clearcoat", 0.5},
                      {"clearcoat_roughness", 0.2}},
                     th});
    }
    // |ior - 1| < 1e-3: refraction is a delta (straight through), reflection stays rough.
    v.push_back({"glass_ior1", {{"transmission", 1.0}, {"roughness", 0.4}, {"ior", 1.0005}}, 30.0});
    // A sharp GTR1 clearcoat (Blender's default clearcoat roughness 0.03) at grazing.
    v.push_back({"coat_default", {{"clearcoat", 1.0}}, 85.0});
    // Smooth specular below Cycles' singular threshold: a delta lobe + diffuse (one delta lobe
    // per case: chi2.h pools all specular samples into one cell of one probability).
    v.push_back({"smooth", {{"roughness", 0.0}}, 40.0});
    v.push_back({"smooth_coat", {{"clearcoat", 1.0}, {"clearcoat_roughness", 0.0}}, 40.0});
    v.push_back({"smooth_glass", {{"transmission", 1.0}, {"roughness", 0.0}}, 130.0});
    return v;
}

class PrincipledChi2 : public ::testing::TestWithParam<Case> {};

// Chi-square of sample_f against pdf over the whole sphere (tests/core/chi2.h); delta samples
// are their own cell. Sidak-corrected level 0.01 over the cases; per-sample consistency of f
// and pdf with f() / pdf() to 1e-3 (recomputed half vectors: a few float roundings).
TEST_P(PrincipledChi2, SamplingMatchesPdf) {
    const Case& c = GetParam();
    const Material m = principled(c.params);
    const test::Chi2Result r = test::sphere_chi2(m, c.theta);
    test::expect_sphere_chi2(r, test::sidak_alpha(0.01, int(chi2_cases().size())));
    EXPECT_LE(r.pdf_integral, 1.0 + 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Cases, PrincipledChi2, ::testing::ValuesIn(chi2_cases()),
                         [](const ::testing::TestParamInfo<Case>& info) {
                             return info.param.name + "_theta" +
                                    std::to_string(int(info.param.theta));
                         });

TEST(Principled, ChiSquareRejectsAWrongPdf) {
    const Material m = principled({{"sheen", 1.0}, {"clearcoat", 1.0}});
    test::Chi2Options o;
    o.theta_bins = 20;
    const test::TiltedPdf<Material> bad{m, 0.3f};
    EXPECT_LT(test::chi2_sampling_test(bad, dir(0.0, 0.0), o).chi2.p_value, 1e-6);
}

// Directional albedo by Monte Carlo over sample weights (importance mode: no etap^2), green.
test::SampledAlbedo albedo(const Material& m, const Vec3& wo, int n) {
    return test::sampled_albedo(m, wo, n, 9, 1);
}

// White furnace. Cycles' principled v1 adds its lobes without taking energy from one for
// another, so a white base gains energy (measured and printed; docs/principled.md quotes it).
// What is bounded: a white metal (F = 1) is single-scattering GGX (<= 1; Cycles' default GGX
// loses the multiply scattered part); smooth glass reflects + refracts exactly 1 (Fm + (1 - Fm));
// rough glass <= 1. Tolerances: 4 standard errors.
TEST(Principled, WhiteFurnaceBounds) {
    const int n = std::max(20000, int(200000 * stress_scale()));
    for (double r : {0.2, 0.5, 0.9}) {
        const Material metal =
            principled({{"base_color", 1.0}, {"metallic", 1.0}, {"roughness", r}});
        for (double th : {0.0, 60.0, 85.0}) {
            const auto a = albedo(metal, dir(th, 0.0), n);
            EXPECT_LE(a.mean, 1.0 + 4.0 * a.se) << r << " " << th;
            // Single-scattering GGX loses energy: facet reflectance --model ggx --alpha 0.81
            // --theta-i 0 gives 0.420 (the lowest of these cases).
            EXPECT_GT(a.mean, 0.4) << r << " " << th;
        }
        const Material glass =
            principled({{"base_color", 1.0}, {"transmission", 1.0}, {"roughness", r}});
        for (double th : {0.0, 60.0, 120.0}) {
            const auto a = albedo(glass, dir(th, 0.0), n);
            EXPECT_LE(a.mean, 1.0 + 4.0 * a.se) << r << " " << th;
        }
    }
    const Material smooth =
        principled({{"base_color", 1.0}, {"transmission", 1.0}, {"roughness", 0.0}});
    for (double th : {0.0, 60.0, 120.0, 170.0}) {
        const auto a = albedo(smooth, dir(th, 0.0), 2000);
        // Exactly 1 in expectation; under total internal reflection the refraction lobe keeps
        // Cycles' floor weight 1e-4, is chosen with probability ~1e-4 and fails (TIR), and
        // reflections weigh 1 + 1e-4: allowed 2e-4.
        EXPECT_NEAR(a.mean, 1.0, 2e-4) << th;
    }
    // The documented energy gain of a white dielectric base (diffuse + specular added).
    const Material white = principled({{"base_color", 1.0}, {"roughness", 0.5}});
    for (double th : {0.0, 60.0, 85.0}) {
        const auto a = albedo(white, dir(th, 0.0), n);
        std::printf("white base, roughness 0.5, theta %2.0f: albedo %.4f +- %.4f\n", th, a.mean,
                    a.se);
        EXPECT_LT(a.mean, 1.3);
    }
}

// Extremes: roughness 0 .. 1, ior 0.001 .. 100, grazing directions on both sides: finite,
// non-negative values and unit directions.
TEST(Principled, ExtremesStayFinite) {
    pcg32 rng(5);
    const int n = std::max(500, int(5000 * stress_scale()));
    for (double ior : {1e-3, 0.5, 1.0, 1.0001, 1.45, 100.0}) {
        for (double r : {0.0, 1e-4, 0.02, 0.5, 1.0}) {
            const Material m = principled({{"transmission", 0.7},
                                           {"roughness", r},
                                           {"ior", ior},
                                           {"sheen", 1.0},
                                           {"clearcoat", 1.0},
                                           {"clearcoat_roughness", r},
                                           {"anisotropic", 1.0}});
            for (int i = 0; i < n; ++i) {
                const Vec3 wo =
                    dir(180.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
                const Vec3 wi =
                    dir(180.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
                const BSDFEval e = m.eval(wo, wi);
                ASSERT_TRUE(is_finite(e.f) && std::isfinite(e.pdf)) << ior << " " << r;
                ASSERT_GE(std::min({e.f.r, e.f.g, e.f.b, e.pdf}), 0.f);
                auto s = m.sample_f(wo, test::uniform_float(rng),
                                    Vec2(test::uniform_float(rng), test::uniform_float(rng)));
                if (!s) continue;
                ASSERT_TRUE(is_finite(s->f) && std::isfinite(s->pdf) && s->pdf > 0.f);
                ASSERT_NEAR(glm::length(s->wi), 1.f, 1e-4f);
            }
        }
    }
}

TEST(Principled, BadInputNamesTheParameter) {
    auto param_of = [](const ParamSet& p) {
        try {
            (void)make_material("principled", p);
        } catch (const ParamError& e) {
            return e.param();
        }
        return std::string("(no error)");
    };
    EXPECT_EQ(param_of({{"ior", 0.0}}), "ior");
    EXPECT_EQ(param_of({{"ior", -1.0}}), "ior");
    EXPECT_EQ(param_of({{"metallic", 1.5}}), "metallic");
    EXPECT_EQ(param_of({{"roughness", -0.1}}), "roughness");
    EXPECT_EQ(param_of({{"base_color", Rgb(0.5f, 2.f, 0.f)}}), "base_color");
    EXPECT_EQ(param_of({{"distribution", std::string("multi_ggx")}}), "distribution");
    EXPECT_EQ(param_of({{"clearcoat_gloss", 0.5}}), "clearcoat_gloss");
}

}  // namespace
}  // namespace facet
