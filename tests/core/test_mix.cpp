// Combinations (mix, add) and Oren-Nayar (facet/material.h, facet/oren_nayar.h): end points
// and sums exact, reciprocity, chi-square of sample_f against pdf (with delta and transmissive
// children, nested), the pdf's mass, white furnace, Cycles' Oren-Nayar formula, bad input.
#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "chi2.h"
#include "facet/reflectance.h"
#include "facet/registry.h"

namespace facet {
namespace {

using test::dir;
using test::kDeg;
using test::stress_scale;

using Ptr = std::shared_ptr<const Material>;
Ptr make(std::string_view model, const ParamSet& p = {}) {
    return std::make_shared<const Material>(make_material(model, p));
}
Material mix(const Ptr& a, const Ptr& b, double w) {
    const std::vector<Ptr> kids{a, b};
    return make_material("mix", ParamSet{{"weight", w}}, kids);
}
// A mix whose weight comes from the view (factor fresnel, layer_fresnel, layer_facing).
Material mix_by(const Ptr& a, const Ptr& b, const std::string& factor, const std::string& param,
                double value) {
    const std::vector<Ptr> kids{a, b};
    return make_material("mix", ParamSet{{"factor", factor}, {param, value}}, kids);
}
Material add(const Ptr& a, const Ptr& b) {
    const std::vector<Ptr> kids{a, b};
    return make_material("add", {}, kids);
}

Ptr lambert(double rho) {
    return make("lambert", ParamSet{{"reflectance", rho}});
}
Ptr ggx(double alpha) {
    return make("ggx", ParamSet{{"alpha", alpha}, {"fresnel", std::string("dielectric")}});
}
Ptr ggx_aniso() {
    return make("ggx", ParamSet{{"alpha_u", 0.1}, {"alpha_v", 0.5}});
}
Ptr mirror() {
    return make("mirror", ParamSet{{"reflectance", 0.9}});
}
Ptr rough_glass(double alpha) {
    return make("dielectric", ParamSet{{"ior", 1.5}, {"alpha", alpha}});
}
Ptr smooth_glass() {
    return make("dielectric", ParamSet{{"ior", 1.5}});
}
Ptr oren(double rho, double sigma) {
    return make("oren_nayar", ParamSet{{"reflectance", rho}, {"sigma", sigma}});
}

bool same(const Rgb& a, const Rgb& b) {
    return a.r == b.r && a.g == b.g && a.b == b.b;
}

// mix at w = 0 is a and at w = 1 is b, bit for bit: f, pdf and every sample (Material::mix
// returns the child itself at the end points).
TEST(Mix, EndPointsAreTheChildrenExactly) {
    const std::vector<Ptr> pool{lambert(0.3), ggx(0.3), mirror(), rough_glass(0.4), oren(0.7, 0.8)};
    pcg32 rng(11);
    for (const Ptr& a : pool)
        for (const Ptr& b : pool) {
            const Material m0 = mix(a, b, 0.0), m1 = mix(a, b, 1.0);
            for (int i = 0; i < 200; ++i) {
                const Vec3 wo =
                    dir(85.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
                const Vec3 wi =
                    dir(175.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
                EXPECT_TRUE(same(m0.f(wo, wi), a->f(wo, wi)));
                EXPECT_TRUE(same(m1.f(wo, wi), b->f(wo, wi)));
                EXPECT_EQ(m0.pdf(wo, wi), a->pdf(wo, wi));
                EXPECT_EQ(m1.pdf(wo, wi), b->pdf(wo, wi));
                const float uc = test::uniform_float(rng);
                const Vec2 u(test::uniform_float(rng), test::uniform_float(rng));
                const auto s0 = m0.sample_f(wo, uc, u), sa = a->sample_f(wo, uc, u);
                ASSERT_EQ(s0.has_value(), sa.has_value());
                if (s0) {
                    EXPECT_TRUE(same(s0->f, sa->f));
                    EXPECT_EQ(s0->pdf, sa->pdf);
                    EXPECT_EQ(s0->wi, sa->wi);
                    EXPECT_EQ(s0->flags, sa->flags);
                }
            }
        }
}

// Mix of Lambert 0.2 and 0.8 at weight 0.5 is Lambert 0.5 (issue 23): f to float rounding
// (1e-6 relative: two products and a sum), pdf exactly (both cosine), sample weight 0.5.
TEST(Mix, HalfOfTwoLambertsIsTheirMean) {
    const Material m = mix(lambert(0.2), lambert(0.8), 0.5);
    const Ptr l5 = lambert(0.5);
    pcg32 rng(3);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 wo = dir(89.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
        const Vec3 wi = dir(89.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
        EXPECT_NEAR(m.f(wo, wi).g, l5->f(wo, wi).g, 1e-6 * l5->f(wo, wi).g);
        EXPECT_EQ(m.pdf(wo, wi), l5->pdf(wo, wi));
        const auto s = m.sample_f(wo, test::uniform_float(rng),
                                  Vec2(test::uniform_float(rng), test::uniform_float(rng)));
        ASSERT_TRUE(s);
        EXPECT_NEAR(s->f.g * s->wi.z / s->pdf, 0.5, 1e-6);
    }
    EXPECT_EQ(m.flags(), BxDFFlags::Diffuse);
    EXPECT_FALSE(m.diffuse().has_value());  // not a Lambertian lobe: no Lambert-only kernel
}

// add is f_a + f_b (float sum: exact to one rounding) with pdf (pdf_a + pdf_b) / 2.
TEST(Add, IsTheSumOfItsChildren) {
    const std::vector<std::pair<Ptr, Ptr>> pairs{
        {lambert(0.6), ggx(0.2)}, {oren(0.5, 1.0), ggx_aniso()}, {lambert(0.7), lambert(0.6)}};
    pcg32 rng(5);
    for (const auto& [a, b] : pairs) {
        const Material m = add(a, b);
        for (int i = 0; i < 500; ++i) {
            const Vec3 wo = dir(89.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
            const Vec3 wi = dir(89.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
            EXPECT_TRUE(same(m.f(wo, wi), a->f(wo, wi) + b->f(wo, wi)));
            EXPECT_EQ(m.pdf(wo, wi), 0.5f * a->pdf(wo, wi) + 0.5f * b->pdf(wo, wi));
        }
    }
    EXPECT_TRUE(add(lambert(0.1), ggx_aniso()).anisotropic());
}

// f(wo, wi) = f(wi, wo) for combinations of reciprocal reflection models (Helmholtz), to float
// rounding of the microfacet terms (1e-5 relative).
TEST(Mix, ReciprocityOfReflectionCombinations) {
    const Material m1 = mix(oren(0.8, 0.7), ggx(0.3), 0.35);
    const Material m2 =
        add(lambert(0.4), std::make_shared<const Material>(mix(ggx_aniso(), oren(0.5, 0.2), 0.6)));
    pcg32 rng(9);
    for (const Material* m : {&m1, &m2})
        for (int i = 0; i < 2000; ++i) {
            const Vec3 a = dir(89.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
            const Vec3 b = dir(89.0 * test::uniform_float(rng), 360.0 * test::uniform_float(rng));
            const Rgb fab = m->f(a, b), fba = m->f(b, a);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(fab[c], fba[c], 1e-5 * fab[c] + 1e-7);
        }
}

// Chi-square of sample_f against pdf over the whole sphere, and the mass check the test makes:
// the pdf's integral + the delta probability + the failed fraction = 1 (the failed cell).
struct ComboCase {
    std::string name;
    std::function<Material()> make;
    double theta;
};
std::vector<ComboCase> combo_cases() {
    return {
        {"mix_lambert_ggx", [] { return mix(lambert(0.5), ggx(0.2), 0.3); }, 40.0},
        {"mix_lambert_ggx_grazing", [] { return mix(lambert(0.5), ggx(0.2), 0.7); }, 87.0},
        {"mix_lambert_mirror", [] { return mix(lambert(0.5), mirror(), 0.4); }, 30.0},
        {"mix_oren_glass_outside", [] { return mix(oren(0.8, 0.5), rough_glass(0.3), 0.5); }, 35.0},
        {"mix_oren_glass_inside", [] { return mix(oren(0.8, 0.5), rough_glass(0.3), 0.5); }, 140.0},
        {"add_lambert_aniso", [] { return add(lambert(0.5), ggx_aniso()); }, 60.0},
        {"mix_of_mix",
         [] {
             return mix(std::make_shared<const Material>(mix(lambert(0.3), ggx(0.1), 0.5)),
                        std::make_shared<const Material>(add(oren(0.4, 1.0), ggx(0.5))), 0.25);
         },
         20.0},
        {"oren_nayar", [] { return *oren(0.9, 0.6); }, 70.0},
        {"mix_fresnel_lambert_ggx",
         [] { return mix_by(lambert(0.7), ggx(0.2), "fresnel", "ior", 1.45); }, 60.0},
        {"mix_layer_facing_lambert_mirror",
         [] { return mix_by(lambert(0.6), mirror(), "layer_facing", "blend", 0.3); }, 45.0},
    };
}

class ComboChi2 : public ::testing::TestWithParam<ComboCase> {};

TEST_P(ComboChi2, SamplingMatchesPdf) {
    const ComboCase& c = GetParam();
    const double level = test::sidak_alpha(0.01, int(combo_cases().size()));
    const Material m = c.make();
    const test::Chi2Result r = test::sphere_chi2(m, c.theta);
    test::expect_sphere_chi2(r, level);
    if (!m.transmissive()) {
        EXPECT_EQ(r.below_horizon, 0);
    }
    // Mass: 3 standard deviations of the failed fraction, plus the quadrature's 1e-4.
    const double failed = double(r.failed) / double(r.n);
    EXPECT_NEAR(r.pdf_integral + r.p_spec * (r.specular > 0), 1.0 - failed,
                3.0 * std::sqrt((failed + 1e-4) / double(r.n)) + 1e-4)
        << r.describe();
}

INSTANTIATE_TEST_SUITE_P(Cases, ComboChi2, ::testing::ValuesIn(combo_cases()),
                         [](const ::testing::TestParamInfo<ComboCase>& info) {
                             return info.param.name;
                         });

// Cycles 3.4's Fresnel and Layer Weight outputs, written out here from Cycles' kernel
// (svm_fresnel.h, fresnel_dielectric_cos): w of b at wo, front side.
double cycles_fresnel(double cosi, double eta) {
    const double c = std::abs(cosi);
    double g = eta * eta - 1.0 + c * c;
    if (g <= 0.0) return 1.0;
    g = std::sqrt(g);
    const double a = (g - c) / (g + c), b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    return 0.5 * a * a * (1.0 + b * b);
}
double cycles_facing(double cosi, double blend) {
    double f = std::abs(cosi);
    if (blend != 0.5) {
        blend = std::clamp(blend, 0.0, 1.0 - 1e-5);
        f = std::pow(f, blend < 0.5 ? 2.0 * blend : 0.5 / (1.0 - blend));
    }
    return 1.0 - f;
}

// f = (1 - w(wo)) f_a + w(wo) f_b with Cycles' w, for each factor; float arithmetic: 2e-6.
TEST(Mix, ViewDependentWeightsAreCycles) {
    const Ptr a = lambert(0.8), b = ggx(0.3);
    struct Case {
        std::string factor, param;
        double value;
        std::function<double(double)> w;
    };
    const std::vector<Case> cases = {
        {"fresnel", "ior", 1.45, [](double c) { return cycles_fresnel(c, 1.45); }},
        {"fresnel", "ior", 3.0, [](double c) { return cycles_fresnel(c, 3.0); }},
        {"layer_fresnel", "blend", 0.3, [](double c) { return cycles_fresnel(c, 1.0 / 0.7); }},
        {"layer_facing", "blend", 0.5, [](double c) { return cycles_facing(c, 0.5); }},
        {"layer_facing", "blend", 0.2, [](double c) { return cycles_facing(c, 0.2); }},
        {"layer_facing", "blend", 0.8, [](double c) { return cycles_facing(c, 0.8); }},
    };
    for (const Case& k : cases) {
        const Material m = mix_by(a, b, k.factor, k.param, k.value);
        for (double to : {0.0, 20.0, 45.0, 70.0, 85.0}) {
            const Vec3 wo = dir(to, 10.0), wi = dir(35.0, 200.0);
            const double w = k.w(std::cos(to * kDeg));
            const Rgb expect = float(1.0 - w) * a->f(wo, wi) + float(w) * b->f(wo, wi);
            const Rgb got = m.f(wo, wi);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(got[c], expect[c], 2e-6 * (1.0 + std::abs(expect[c])))
                    << k.factor << " " << k.value << " theta_o " << to;
        }
    }
    // Able to fail: the weight does change with the view.
    const Material m = mix_by(a, b, "fresnel", "ior", 1.45);
    EXPECT_GT(std::abs(m.f(dir(80.0, 0.0), dir(80.0, 180.0)).x -
                       mix(a, b, 0.5).f(dir(80.0, 0.0), dir(80.0, 180.0)).x),
              0.01);
}

// Parameters that the factor does not use are errors naming them.
TEST(Mix, ViewDependentWeightParameters) {
    const std::vector<Ptr> kids{lambert(0.5), lambert(0.2)};
    for (auto [set, bad] : std::vector<std::pair<ParamSet, std::string>>{
             {ParamSet{{"factor", std::string("fresnel")}, {"weight", 0.3}}, "weight"},
             {ParamSet{{"factor", std::string("layer_facing")}, {"ior", 1.5}}, "ior"},
             {ParamSet{{"blend", 0.4}}, "blend"},
             {ParamSet{{"factor", std::string("layer_fresnel")}, {"blend", 1.5}}, "blend"},
             {ParamSet{{"factor", std::string("sideways")}}, "factor"}}) {
        try {
            make_material("mix", set, kids);
            ADD_FAILURE() << bad << " accepted";
        } catch (const ParamError& e) {
            EXPECT_EQ(e.param(), bad) << e.what();
        }
    }
}

// The chi-square test can fail on a combination: a tilted pdf is rejected.
TEST(Mix, ChiSquareRejectsAWrongPdf) {
    const Material m = mix(lambert(0.5), ggx(0.2), 0.3);
    test::Chi2Options o;
    o.theta_bins = 20;
    const test::TiltedPdf<Material> bad{m, 0.3f};
    EXPECT_LT(test::chi2_sampling_test(bad, dir(30.0, 0.0), o).chi2.p_value, 1e-6);
}

// White furnace: a mix of two lossless materials (Lambert 1 and smooth glass of transmittance
// 1, importance mode: no etap^2) scatters all the light, from either side of the interface;
// the reflection child reflects on the side wo is on. Monte Carlo mean of the sample weights,
// within 4 standard errors (the smooth glass' weights are exactly 1, Lambert's exactly 1).
TEST(Mix, WhiteFurnaceOfLosslessChildren) {
    const Material m = mix(lambert(1.0), smooth_glass(), 0.6);
    ASSERT_TRUE(m.transmissive());
    const int n = std::max(2000, int(20000 * stress_scale()));
    for (double th : {0.0, 50.0, 89.0, 120.0, 179.0}) {
        const Vec3 wo = dir(th, 10.0);
        pcg32 rng(2);
        double s = 0.0;
        for (int i = 0; i < n; ++i) {
            const auto smp = m.sample_f(wo, test::uniform_float(rng),
                                        Vec2(test::uniform_float(rng), test::uniform_float(rng)),
                                        TransportMode::Importance);
            if (!smp) continue;
            if (!smp->is_specular()) {  // the Lambert child reflects on wo's side
                EXPECT_GT(smp->wi.z * wo.z, 0.f);
            }
            s += smp->f.r * std::fabs(smp->wi.z) / smp->pdf;
        }
        // Every weight is 1 up to float rounding: the mean is 1 to 1e-5.
        EXPECT_NEAR(s / n, 1.0, 1e-5) << th;
    }
}

// Oren-Nayar against Cycles 3.4's bsdf_oren_nayar (header comment), evaluated here in double
// from the angles: f = rho (A + B t). Tolerance 1e-5 relative (float evaluation).
TEST(OrenNayar, MatchesCyclesFormula) {
    for (double sigma : {0.0, 0.25, 0.5, 1.0}) {
        const Ptr m = oren(0.8, sigma);
        const double a = 1.0 / (kPiD + (3.0 * kPiD - 4.0) / 6.0 * sigma), b = sigma * a;
        for (double to : {0.0, 30.0, 60.0, 85.0})
            for (double ti : {10.0, 45.0, 80.0})
                for (double phi : {0.0, 60.0, 120.0, 180.0}) {
                    const double co = std::cos(to * kDeg), ci = std::cos(ti * kDeg);
                    double t = std::sin(to * kDeg) * std::sin(ti * kDeg) * std::cos(phi * kDeg);
                    if (t > 0.0) t /= std::max(co, ci);
                    const double want = 0.8 * (a + b * t);
                    const double got = m->f(dir(to, 0.0), dir(ti, phi)).r;
                    EXPECT_NEAR(got, want, 1e-5 * want)
                        << sigma << " " << to << " " << ti << " " << phi;
                }
    }
    // sigma 0 is Lambert: rho / pi.
    EXPECT_NEAR(oren(0.8, 0.0)->f(dir(30, 0), dir(70, 90)).r, 0.8 / kPiD, 1e-7);
}

// Directional albedo of Oren-Nayar with rho = 1 (quadrature, order 64): printed for the docs;
// it stays below 1 (no energy gain) and falls with roughness at normal incidence, as the
// roughness term A shrinks. Tolerance 1e-4 for the quadrature.
TEST(OrenNayar, AlbedoAtMostOne) {
    double previous = 1.0 + 1e-4;
    for (double sigma : {0.0, 0.5, 1.0}) {
        const Ptr m = oren(1.0, sigma);
        for (double th : {0.0, 45.0, 80.0}) {
            const double r = hemispherical_directional(*m, dir(th, 0.0), 64).value.x;
            std::printf("oren_nayar sigma %.2f theta %2.0f: albedo %.4f\n", sigma, th, r);
            EXPECT_LE(r, 1.0 + 1e-4);
            if (th == 0.0) {
                EXPECT_LT(r, previous);
                previous = r;
            }
        }
    }
}

// Bad input names the parameter: a weight outside [0, 1], a wrong number of sub-materials,
// sub-materials given to a model that takes none.
TEST(Mix, BadInputNamesTheParameter) {
    const std::vector<Ptr> two{lambert(0.5), lambert(0.5)}, one{lambert(0.5)};
    auto param_of = [](auto&& fn) {
        try {
            fn();
        } catch (const ParamError& e) {
            return e.param();
        }
        return std::string("<no error>");
    };
    EXPECT_EQ(param_of([&] { make_material("mix", ParamSet{{"weight", 1.5}}, two); }), "weight");
    EXPECT_EQ(param_of([&] { make_material("mix", ParamSet{{"weight", -0.1}}, two); }), "weight");
    EXPECT_EQ(param_of([&] { make_material("mix", {}, one); }), "materials");
    EXPECT_EQ(param_of([&] { make_material("add", {}); }), "materials");
    EXPECT_EQ(param_of([&] { make_material("lambert", {}, two); }), "materials");
    EXPECT_EQ(param_of([&] { make_material("oren_nayar", ParamSet{{"sigma", 2.0}}); }), "sigma");
}

}  // namespace
}  // namespace facet
