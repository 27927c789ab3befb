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
#include "facet/microfacet.h"
#include "facet/reflectance.h"
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

// The same with Multiscatter GGX: the height-correlated G and the compensation lobe
// (1 - E(mu_o)) (1 - E(mu_i)) are symmetric too. A compensation lobe built with E(mu_o) twice
// (a plausible slip) breaks this by ~10% at these roughnesses.
TEST(Principled, MultiscatterIsReciprocal) {
    const Material m = principled({{"base_color", Rgb(0.8f, 0.5f, 0.2f)},
                                   {"metallic", 0.6},
                                   {"roughness", 0.8},
                                   {"anisotropic", 0.6},
                                   {"anisotropic_rotation", 0.15},
                                   {"sheen", 1.0},
                                   {"clearcoat", 0.7},
                                   {"clearcoat_roughness", 0.2},
                                   {"distribution", std::string("multi_ggx")}});
    ASSERT_TRUE(m.principled()->multiscatter_compensated());
    pcg32 rng(4);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 a = dir(89.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
        const Vec3 b = dir(89.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
        const Rgb fab = m.f(a, b), fba = m.f(b, a);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(fab[k], fba[k], 1e-4f * std::max(fab[k], fba[k]) + 1e-9f) << i;
    }
}

// Cycles 3.4 takes single-scattering GGX for a Multiscatter GGX specular of roughness <= 0.075:
// there the two distributions are the same model, bit for bit; above it they differ (the
// height-correlated G, the compensation lobe).
TEST(Principled, MultiscatterSwitchesAtCyclesThreshold) {
    const Vec3 wo = dir(40.0, 10.0), wi = dir(55.0, 200.0);
    for (double r : {0.0, 0.03, 0.075, 0.5}) {
        ParamSet p{{"base_color", Rgb(0.8f, 0.5f, 0.2f)}, {"metallic", 0.5}, {"roughness", r}};
        const Material single = principled(p);
        p.set("distribution", std::string("multi_ggx"));
        const Material multi = principled(p);
        const Rgb a = single.f(wo, wi), b = multi.f(wo, wi);
        if (r <= 0.075) {
            EXPECT_EQ(a, b) << r;
            EXPECT_FALSE(multi.principled()->multiscatter_compensated()) << r;
        } else {
            EXPECT_GT(b.r, a.r * 1.005f) << r;  // measured +0.99%
            EXPECT_TRUE(multi.principled()->multiscatter_compensated()) << r;
        }
    }
}

// The shared E(mu; alpha) table, blended linearly between its roughness nodes, against the
// ggx model's own table built at the exact alpha (the same quadrature): within 2e-3 between
// nodes (measured worst printed; the nodes themselves agree to float rounding). A table of
// half as many nodes misses by ~5e-3.
TEST(Principled, MultiscatterAlbedoTableInterpolates) {
    double worst = 0.0;
    for (double r : {0.1, 0.23, 0.37, 0.5, 0.61, 0.77, 0.89, 0.97, 1.0}) {
        const Material m = principled(
            {{"metallic", 1.0}, {"roughness", r}, {"distribution", std::string("multi_ggx")}});
        const float a = float(r * r);
        // Below ~r 0.15 the lobe misses less than kMinMissingEnergy: no compensation, E = 1.
        if (!m.principled()->multiscatter_compensated()) continue;
        const MicrofacetReflection lobe(MicrofacetDistribution::ggx(a, a), Fresnel::none(),
                                        Rgb(1.f), true);
        for (double mu = 0.0; mu <= 1.0; mu += 1.0 / 128.0) {
            const double d = std::fabs(double(m.principled()->multiscatter_albedo(float(mu))) -
                                       double(lobe.albedo_table(float(mu))));
            worst = std::max(worst, d);
            EXPECT_LT(d, 2e-3) << r << " " << mu;
        }
    }
    std::printf("multiscatter albedo table: worst blend error %.2e\n", worst);
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
    // Multiscatter GGX: the compensation lobe (cosine-sampled) next to the others.
    for (double th : {0.0, 50.0, 85.0}) {
        v.push_back({"multi_metal",
                     {{"base_color", c},
                      {"metallic", 1.0},
                      {"roughness", 0.6},
                      {"distribution", std::string("multi_ggx")}},
                     th});
        v.push_back({"multi_aniso",
                     {{"base_color", c},
                      {"metallic", 0.7},
                      {"roughness", 0.9},
                      {"anisotropic", 0.8},
                      {"anisotropic_rotation", 0.3},
                      {"sheen", 0.5},
                      {"distribution", std::string("multi_ggx")}},
                     th});
    }
    for (double th : {30.0, 150.0}) {
        v.push_back({"multi_glass",
                     {{"base_color", c},
                      {"transmission", 1.0},
                      {"roughness", 0.5},
                      {"ior", 1.5},
                      {"distribution", std::string("multi_ggx")}},
                     th});
        v.push_back({"multi_half_glass",
                     {{"base_color", c},
                      {"transmission", 0.5},
                      {"roughness", 1.0},
                      {"distribution", std::string("multi_ggx")}},
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

// White furnace with Multiscatter GGX: a white metal (base colour 1, metallic 1: F = 1)
// reflects everything, as Cycles' random walk does (Cycles 3.4 renders 0.99999 on the sphere,
// tests/render/multiscatter_cycles.json). Tolerance 4 standard errors + 3e-3: the compensation
// restores 1 - E_table(mu_o), so the albedo is 1 + E(mu_o) - E_table(mu_o) (the blend error
// above, 2e-3, and the quadrature's ~1e-3 near grazing). Anisotropic lobes are compensated with
// the isotropic equivalent alpha, an approximation (docs/principled.md): measured 0.82 .. 1.04
// (worst 0.18 off at anisotropic 0.8, r 0.8); allowed 0.2, the worst printed. This documents
// the approximation's size, it does not claim the anisotropic furnace. With "ggx" the same cases
// reflect 0.42 .. 0.99 (the test fails).
struct FurnaceCase {
    double roughness, anisotropic, theta;
};
TEST(Principled, MultiscatterWhiteMetalIsAWhiteFurnace) {
    const int n = std::max(20000, int(200000 * stress_scale()));
    double worst_iso = 0.0, worst_aniso = 0.0;
    for (double r : {0.1, 0.2, 0.5, 0.8, 1.0}) {
        for (double aniso : {0.0, 0.8}) {
            const Material m = principled({{"base_color", 1.0},
                                           {"metallic", 1.0},
                                           {"roughness", r},
                                           {"anisotropic", aniso},
                                           {"distribution", std::string("multi_ggx")}});
            for (double th : {0.0, 45.0, 70.0, 85.0}) {
                for (double phi : {0.0, 45.0, 90.0}) {
                    if (aniso == 0.0 && phi > 0.0) continue;
                    const auto a = albedo(m, dir(th, phi), n);
                    // Uncompensated (r 0.1: average loss below kMinMissingEnergy = 2e-3)
                    // the lobe still loses 0.8% at 85 degrees: allowed 1e-2.
                    const bool on = m.principled()->multiscatter_compensated();
                    const double tol = (aniso > 0.0 ? 0.2 : on ? 3e-3 : 1e-2) + 4.0 * a.se;
                    EXPECT_NEAR(a.mean, 1.0, tol) << r << " " << aniso << " " << th << " " << phi;
                    double& worst = aniso > 0.0 ? worst_aniso : worst_iso;
                    worst = std::max(worst, std::fabs(a.mean - 1.0));
                }
            }
        }
    }
    std::printf("multiscatter white metal: worst |albedo - 1| isotropic %.4f, anisotropic %.4f\n",
                worst_iso, worst_aniso);
}

// Multiscatter glass (transmission 1, base colour 1): the compensated dielectric reflects plus
// transmits everything from both sides (importance mode: no etap^2), as Cycles' random walk
// does (0.9994 .. 0.99999 on the sphere, tests/render/multiscatter_cycles.json). Tolerance 4
// standard errors + 3e-3, the dielectric's own (tests/core/test_dielectric.cpp). With "ggx" the
// same glass keeps 0.27 .. 0.8 (the test fails).
TEST(Principled, MultiscatterWhiteGlassIsAWhiteFurnace) {
    const int n = std::max(20000, int(200000 * stress_scale()));
    for (double r : {0.1, 0.5, 1.0}) {
        const Material m = principled({{"base_color", 1.0},
                                       {"transmission", 1.0},
                                       {"roughness", r},
                                       {"ior", 1.45},
                                       {"distribution", std::string("multi_ggx")}});
        ASSERT_NE(m.principled()->multiscatter_glass(), nullptr);
        for (double th : {0.0, 60.0, 85.0, 120.0, 170.0}) {
            const auto a = albedo(m, dir(th, 0.0), n);
            // r 0.1 (alpha 0.01) misses less than kMinMissingEnergy on average: the dielectric
            // is not compensated and loses 0.56% at 85 degrees: allowed 1e-2 there.
            const bool on = m.principled()->multiscatter_glass()->has_multiple_scattering();
            EXPECT_NEAR(a.mean, 1.0, (on ? 3e-3 : 1e-2) + 4.0 * a.se) << r << " " << th;
        }
    }
}

// facet reflectance for principled (its sampler-space quadrature, core/src/reflectance.cpp):
// Disney diffuse alone (specular 0, roughness 0) at normal incidence has F_V = 0 and
// rho = C (1 - 1/2 * 2 int (1 - mu)^5 mu dmu) = C (1 - 1/42): 0.5 -> 0.4880952, to 1e-5 (the
// adaptive rule's tolerance; a wrong Schlick exponent 4 gives 0.4833). A white multiscatter
// metal reflects 1 within the compensation's 3e-3 (0.57 with ggx at r 0.8).
TEST(Principled, ReflectanceQuadrature) {
    const Material diffuse =
        principled({{"base_color", 0.5}, {"specular", 0.0}, {"roughness", 0.0}});
    QuadratureSettings q;
    q.tolerance = 1e-5;
    const Reflectance r = directional_hemispherical(diffuse, Vec3(0.f, 0.f, 1.f), q);
    EXPECT_NEAR(r.value.r, 0.5 * (1.0 - 1.0 / 42.0), 1e-5);
    const Material metal = principled({{"base_color", 1.0},
                                       {"metallic", 1.0},
                                       {"roughness", 0.8},
                                       {"distribution", std::string("multi_ggx")}});
    for (double th : {0.0, 30.0, 60.0}) {
        const Reflectance m = hemispherical_directional(metal, dir(th, 0.0), q);
        std::printf("multi_ggx white metal r 0.8, theta %2.0f: rho %.5f (error %.1e)\n", th,
                    m.value.r, m.error.r);
        EXPECT_NEAR(m.value.r, 1.0, 3e-3 + m.error.r) << th;
    }
    EXPECT_THROW((void)directional_hemispherical(principled({{"transmission", 1.0}}),
                                                 Vec3(0.f, 0.f, 1.f), q),
                 std::invalid_argument);
}

// Extremes: roughness 0 .. 1, ior 0.001 .. 100, grazing directions on both sides, both
// distributions: finite, non-negative values and unit directions.
TEST(Principled, ExtremesStayFinite) {
    pcg32 rng(5);
    const int n = std::max(500, int(5000 * stress_scale()));
    for (const char* dist : {"ggx", "multi_ggx"})
        for (double ior : {1e-3, 0.5, 1.0, 1.0001, 1.45, 100.0}) {
            for (double r : {0.0, 1e-7, 1e-4, 0.02, 0.076, 0.5, 1.0}) {
                const Material m = principled({{"distribution", std::string(dist)},
                                               {"transmission", 0.7},
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
    EXPECT_EQ(param_of({{"distribution", std::string("beckmann")}}), "distribution");
    EXPECT_EQ(param_of({{"clearcoat_gloss", 0.5}}), "clearcoat_gloss");
}

}  // namespace
}  // namespace facet
