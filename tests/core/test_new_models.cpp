// The model units added as one unit each (core/src/models/): translucent (Blender's Translucent
// BSDF) and velvet (Cycles 3.4's Ashikhmin velvet). Reciprocity and the hemisphere energy
// bound of velvet also run through tests/core/model_corners.h with every other model.
#include <gtest/gtest.h>

#include <cmath>

#include "chi2.h"
#include "facet/reflectance.h"
#include "facet/registry.h"

namespace facet {
namespace {

using test::dir;
using test::kDeg;

Material velvet(double sigma, Rgb color = Rgb(1.f)) {
    return make_material("velvet", ParamSet{{"reflectance", color}, {"sigma", sigma}});
}
Material translucent(Rgb rho) {
    return make_material("translucent", ParamSet{{"transmittance", rho}});
}

// Cycles 3.4's bsdf_ashikhmin_velvet_eval, written here again in double from the angles (the
// closure's eval is f cos_i; f = that / cos_i): D = exp(-cot^2 / s^2) / (pi s^2 sin^4),
// G = min(1, 2 cos_h cos_o / (wo.h), 2 cos_h cos_i / (wo.h)), f = D G / (4 cos_o cos_i).
double cycles_velvet(const DVec3& wo, const DVec3& wi, double sigma) {
    const double s = std::max(sigma, 0.01), inv = 1.0 / (s * s);
    const DVec3 h = glm::normalize(wo + wi);
    const double ch = h.z, cho = std::fabs(glm::dot(wo, h));
    if (!(std::fabs(ch) < 1.0 - 1e-5 && cho > 1e-5)) return 0.0;
    const double r = std::max(ch / cho, 1e-5);
    const double g = std::min(1.0, std::min(2.0 * r * wo.z, 2.0 * r * wi.z));
    const double s2 = 1.0 - ch * ch;
    const double d = std::exp(-ch * ch / s2 * inv) * inv / kPiD / (s2 * s2);
    return 0.25 * d * g / (wo.z * wi.z);
}

// Tolerance 1e-4 relative: the unit evaluates in float (exp of up to ~1e2, the half vector).
TEST(Velvet, MatchesCyclesFormula) {
    for (double sigma : {0.005, 0.1, 0.35, 1.0})
        for (double to : {5.0, 40.0, 75.0, 88.0})
            for (double ti : {10.0, 50.0, 85.0})
                for (double phi : {0.0, 70.0, 180.0}) {
                    const Vec3 wo = dir(to, 0.0), wi = dir(ti, phi);
                    const double want = 0.6 * cycles_velvet(DVec3(wo), DVec3(wi), sigma);
                    const double got = velvet(sigma, Rgb(0.6f)).f(wo, wi).r;
                    EXPECT_NEAR(got, want, 1e-4 * want + 1e-30)
                        << sigma << " " << to << " " << ti << " " << phi;
                }
    // Below the surface: nothing.
    EXPECT_EQ(velvet(0.5).f(dir(30, 0), dir(120, 0)).r, 0.f);
}

// The sampler (uniform over the hemisphere, as Cycles') against its pdf; Sidak over the cases.
TEST(Velvet, SamplingMatchesPdf) {
    const double level = test::sidak_alpha(0.01, 6);
    for (double sigma : {0.1, 1.0})
        for (double th : {0.0, 45.0, 85.0}) {
            const test::Chi2Result r = test::sphere_chi2(velvet(sigma), th);
            test::expect_sphere_chi2(r, level);
            EXPECT_EQ(r.below_horizon, 0);
        }
}

// Albedo by quadrature (order 64, error estimate below 1e-3 where it converges): at most 1 for
// a white velvet, printed for the docs; a grazing sheen reflects more than a head-on one.
TEST(Velvet, AlbedoAtMostOneAndGrazingSheen) {
    for (double sigma : {0.2, 0.5, 1.0}) {
        double head_on = 0.0;
        for (double th : {0.0, 45.0, 80.0}) {
            const Reflectance a = hemispherical_directional(velvet(sigma), dir(th, 0.0), 64);
            std::printf("velvet sigma %.2f theta %2.0f: albedo %.4f (error %.1e)\n", sigma, th,
                        a.value.x, a.error.x);
            EXPECT_LE(a.value.x - a.error.x, 1.0);
            if (th == 0.0) head_on = a.value.x;
            if (th == 80.0) EXPECT_GT(a.value.x, head_on);
        }
    }
}

TEST(Translucent, TransmitsOnlyToTheFarSide) {
    const Material m = translucent(Rgb(0.9f, 0.5f, 0.1f));
    EXPECT_TRUE(m.transmissive());
    // Same side: 0, from above and from below. Far side: rho / pi, symmetric.
    EXPECT_EQ(m.f(dir(30, 0), dir(60, 90)).r, 0.f);
    EXPECT_EQ(m.f(dir(150, 0), dir(120, 90)).r, 0.f);
    for (auto [a, b] : {std::pair{30.0, 140.0}, {170.0, 20.0}, {89.0, 91.0}}) {
        const Rgb f = m.f(dir(a, 0), dir(b, 200));
        EXPECT_NEAR(f.r, 0.9 / kPiD, 1e-7);
        EXPECT_NEAR(f.b, 0.1 / kPiD, 1e-7);
        EXPECT_EQ(f, m.f(dir(b, 200), dir(a, 0)));  // reciprocal, exactly
    }
}

// The sampler against its pdf from above (chi-square over the whole sphere, 1e5 samples at
// every stress scale: one case, level 0.01); from below, the same random numbers give exactly
// the z-mirrored directions, so the test covers both sides. (The cosine warp is Lambert's: at
// 2e4 samples and the harness's seed its statistic is Lambert's p = 0.0015, a property of that
// draw, which is why the count is not scaled down.) Every weight f |cos| / pdf is rho (1e-6).
TEST(Translucent, SamplingMatchesPdfOnTheFarSide) {
    const Material m = translucent(Rgb(0.7f));
    test::Chi2Options o;
    o.cos_min = -1.0;
    o.theta_bins = o.phi_bins = 16;
    o.n_samples = 100000;
    o.seed = 3;
    test::expect_sphere_chi2(test::chi2_sampling_test(m, dir(60.0, 30.0), o), 0.01);
    for (float u0 : {0.05f, 0.4f, 0.93f}) {
        const Vec2 u(u0, 1.f - u0 * u0);
        const auto above = m.sample_f(dir(60.0, 30.0), 0.5f, u);
        const auto below = m.sample_f(dir(120.0, 30.0), 0.5f, u);
        ASSERT_TRUE(above && below);
        EXPECT_EQ(above->wi, Vec3(below->wi.x, below->wi.y, -below->wi.z));
        EXPECT_EQ(above->pdf, below->pdf);
    }
    for (double th : {0.0, 60.0, 150.0}) {
        const Vec3 wo = dir(th, 30.0);
        for (float u : {0.1f, 0.5f, 0.9f}) {
            const auto s = m.sample_f(wo, 0.5f, Vec2(u, 1.f - u));
            ASSERT_TRUE(s);
            EXPECT_LT(s->wi.z * wo.z, 0.f);
            EXPECT_NEAR(s->f.r * std::fabs(s->wi.z) / s->pdf, 0.7, 1e-6);
        }
    }
}

// The units' parameters: range errors name the parameter.
TEST(NewModels, BadInputNamesTheParameter) {
    auto param_of = [](const char* model, ParamSet p) {
        try {
            make_material(model, p);
        } catch (const ParamError& e) {
            return e.param();
        }
        return std::string("<no error>");
    };
    EXPECT_EQ(param_of("velvet", ParamSet{{"sigma", 1.5}}), "sigma");
    EXPECT_EQ(param_of("velvet", ParamSet{{"reflectance", -0.1}}), "reflectance");
    EXPECT_EQ(param_of("translucent", ParamSet{{"transmittance", 2.0}}), "transmittance");
    EXPECT_EQ(param_of("translucent", ParamSet{{"reflectance", 0.5}}), "reflectance");
}

}  // namespace
}  // namespace facet
