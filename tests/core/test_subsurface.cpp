// Random-walk subsurface scattering (facet/subsurface.h): the albedo inversion and the radius
// setup against Cycles' formulas evaluated in double; the walk's total diffuse reflectance of a
// semi-infinite isotropic medium against Chandrasekhar's H function (an independent reference);
// energy with no absorption; determinism; and the models' bad input, each naming its parameter.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "facet/material.h"
#include "facet/quadrature.h"
#include "facet/registry.h"
#include "facet/subsurface.h"

using namespace facet;

namespace {

// Cycles' subsurface_random_walk_remap, written again in double from the published
// coefficients (Chiang et al. 2016 with Wrenninge et al.'s anisotropic fit).
double remap_double(double albedo, double g) {
    auto poly = [&](std::initializer_list<double> c) {
        double s = 0.0, gp = 1.0;
        for (double v : c) s += v * gp, gp *= g;
        return s;
    };
    const double A = poly({1.8260523782, -1.28451056436, -1.79904629312, 9.19393289202,
                           -22.8215585862, 32.0234874259, -23.6264803333, 7.21067002658});
    const double B = 4.98511194385 +
                     0.127355959438 * std::exp(poly({0.0, 31.1491581433, -201.847017512,
                                                     841.576016723, -2018.09288505, 2731.71560286,
                                                     -1935.41424244, 559.009054474}));
    const double C = poly({1.09686102424, -0.394704063468, 1.05258115941, -8.83963712726,
                           28.8643230661, -46.8802913581, 38.5402837518, -12.7181042538});
    const double D = poly({0.496310210422, 0.360146581622, -2.15139309747, 17.8896899217,
                           -55.2984010333, 82.065982243, -58.5106008578, 15.8478295021});
    const double E = 4.23190299701 +
                     0.00310603949088 * std::exp(poly({0.0, 76.7316253952, -594.356773233,
                                                       2448.8834203, -5576.68528998, 7116.60171912,
                                                       -4763.54467887, 1303.5318055}));
    const double F = poly({2.40602999408, -2.51814844609, 9.18494908356, -79.2191708682,
                           259.082868209, -403.613804597, 302.85712436, -87.4370473567});
    const double blend = std::pow(albedo, 0.25);
    const double a = (1.0 - blend) * A * std::pow(std::atan(B * albedo), C) +
                     blend * D * std::pow(std::atan(E * albedo), F);
    return std::clamp(a, 0.0, 0.999999);
}

// Chandrasekhar's H function of isotropic scattering with albedo w on Gauss-Legendre nodes,
// by the fixed-point iteration of H(mu) = 1 / (1 - w/2 mu int_0^1 H(mu') / (mu + mu') dmu');
// the total diffuse reflectance of the semi-infinite index-matched medium under cosine-weighted
// incidence is then 1 - 2 sqrt(1 - w) int_0^1 H(mu) mu dmu (the albedo at mu is
// 1 - sqrt(1 - w) H(mu)).
double diffuse_reflectance_h(double w) {
    const QuadratureRule& q = gauss_legendre(256);
    const std::size_t n = q.nodes.size();
    std::vector<double> h(n, 1.0), next(n);
    for (int it = 0; it < 2000; ++it) {
        double change = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            double s = 0.0;
            for (std::size_t j = 0; j < n; ++j)
                s += q.weights[j] * h[j] / (q.nodes[i] + q.nodes[j]);
            next[i] = 1.0 / (1.0 - 0.5 * w * q.nodes[i] * s);
            change = std::max(change, std::fabs(next[i] - h[i]));
        }
        h.swap(next);
        if (change < 1e-13) break;
    }
    double h1 = 0.0;
    for (std::size_t i = 0; i < n; ++i) h1 += q.weights[i] * h[i] * q.nodes[i];
    return 1.0 - 2.0 * std::sqrt(1.0 - w) * h1;
}

// The medium z < 0 under the plane z = 0 (normal +z): the walk's exits through the plane.
struct HalfSpace {
    float operator()(const Vec3& o, const Vec3& d, float t_max, bool first) const {
        if (first || !(d.z > 0.f)) return kInfinity;
        const float t = -o.z / d.z;
        return t < t_max ? t : kInfinity;
    }
};

struct Uniform {
    std::mt19937_64 rng;
    std::uniform_real_distribution<float> u{0.f, 1.f};
    explicit Uniform(std::uint64_t seed) : rng(seed) {}
    float operator()() {
        float x = u(rng);
        return x < 1.f ? x : kOneMinusEpsilon;
    }
};

struct MeanSe {
    double mean[3], se[3];
};
// n walks into the half space from the origin; each one's weight on exit (0 without).
MeanSe walk_reflectance(const SubsurfaceWalk& w, int n, std::uint64_t seed) {
    Uniform u(seed);
    double s[3] = {}, s2[3] = {};
    for (int i = 0; i < n; ++i) {
        Rgb beta(1.f);
        const auto ex = subsurface_random_walk(w, Vec3(0.f), Vec3(0, 0, 1), Vec3(0, 0, 1), beta, u,
                                               HalfSpace{});
        if (!ex) beta = Rgb(0.f);
        for (int c = 0; c < 3; ++c) s[c] += beta[c], s2[c] += double(beta[c]) * beta[c];
    }
    MeanSe r;
    for (int c = 0; c < 3; ++c) {
        r.mean[c] = s[c] / n;
        r.se[c] = std::sqrt(std::max(0.0, s2[c] / n - r.mean[c] * r.mean[c]) / n);
    }
    return r;
}

}  // namespace

// The float fit (as Cycles evaluates it) against the double one. 1e-4 absolute: the exponents
// of B and E sum terms up to 7e3 g^k that cancel to ~10, so float rounding leaves ~4e-4 in the
// exponent, i.e. ~3e-5 in alpha at g = 0.9 (measured); a wrong coefficient moves alpha by far
// more.
TEST(SubsurfaceInversion, MatchesCyclesFormulaInDouble) {
    for (double g : {0.0, 0.1, 0.3, 0.5, 0.7, 0.9})
        for (double a = 0.0; a <= 1.0; a += 1.0 / 64.0)
            EXPECT_NEAR(subsurface_single_scattering_albedo(float(a), float(g)), remap_double(a, g),
                        1e-4)
                << "albedo " << a << " g " << g;
}

// The dipole inversion: alpha' within the 12 bisection steps' 2^-12 of the root of Rd = A found
// in double (60 steps); the radius setups as Cycles writes them.
TEST(SubsurfaceInversion, DipoleAndRadiusSetup) {
    const double eta = 1.4, inv = 1.0 / eta;
    const double fdr = inv * (-1.440 * inv + 0.710) + 0.668 + 0.0636 * eta;
    const float fa = float((4.0 / 3.0) * (1.0 + fdr) / (1.0 - fdr));
    for (float a : {0.05f, 0.2f, 0.5f, 0.8f, 0.95f}) {
        const float ap = subsurface_dipole_alpha_prime(a, fa);
        double lo = 0.0, hi = 1.0;
        for (int i = 0; i < 60; ++i) {
            const double mid = 0.5 * (lo + hi), s = std::sqrt(3.0 * (1.0 - mid));
            const double rd = 0.5 * mid * (1.0 + std::exp(-double(fa) * s)) * std::exp(-s);
            (rd < a ? lo : hi) = mid;
        }
        EXPECT_NEAR(ap, lo, std::ldexp(1.0, -12)) << a;
        const Rgb r =
            subsurface_effective_radius(Rgb(2.f), Rgb(a), 1.4f, SubsurfaceMethod::RandomWalk);
        EXPECT_NEAR(r.r, 2.0 * std::sqrt(3.0 * (1.0 - ap)), 1e-5) << a;
    }
    const Rgb f = subsurface_effective_radius(Rgb(1.f, 2.f, 4.f), Rgb(0.5f), 1.4f,
                                              SubsurfaceMethod::RandomWalkFixedRadius);
    EXPECT_NEAR(f.b, 4.0 / (4.0 * M_PI), 1e-7);
    // The walk's coefficients: sigma_t = 1 / (radius (1 - g)), weight 1 / A, alpha >= 0.2.
    const SubsurfaceWalk w = SubsurfaceWalk::make(Rgb(0.8f, 0.5f, 0.01f), Rgb(0.5f), 0.5f);
    EXPECT_NEAR(w.sigma_t.r, 4.0, 1e-5);
    EXPECT_NEAR(w.entry_weight.r, 1.25, 1e-6);
    EXPECT_NEAR(w.alpha.r, remap_double(0.8, 0.5), 2e-5);
    EXPECT_FLOAT_EQ(w.alpha.b, 0.2f);  // remap(0.01) < 0.2: raised, weight scaled down
    EXPECT_NEAR(w.entry_weight.b, 100.0 * remap_double(0.01, 0.5) / 0.2, 1e-2);
}

// The walk in a semi-infinite isotropic medium of single-scattering albedo w (one per channel:
// channel MIS, Dwivedi guiding and the opposite-interface logic all run) against the H-function
// reflectance. Tolerance: 5 standard errors of the 200k-walk mean, plus 2e-4 for the H
// quadrature and for the walks cut at 256 steps (w^256 < 1e-11 here).
TEST(SubsurfaceWalk, SemiInfiniteReflectanceMatchesChandrasekharH) {
    const double w[3] = {0.3, 0.7, 0.95};
    const SubsurfaceWalk walk = SubsurfaceWalk::from_coefficients(
        Rgb(1.f), Rgb(float(w[0]), float(w[1]), float(w[2])), Rgb(1.f), 0.f);
    const MeanSe m = walk_reflectance(walk, 200000, 7);
    for (int c = 0; c < 3; ++c) {
        const double ref = diffuse_reflectance_h(w[c]);
        EXPECT_NEAR(m.mean[c], ref, 5.0 * m.se[c] + 2e-4)
            << "albedo " << w[c] << ": walk " << m.mean[c] << " +- " << m.se[c] << ", H " << ref;
    }
    // Control: the reference separates neighbouring albedos by far more than the tolerance.
    EXPECT_GT(diffuse_reflectance_h(0.96) - diffuse_reflectance_h(0.95), 10.0 * m.se[2]);
}

// No absorption: in a slab two mean free paths thick (exits through both faces, so walks end
// long before the 256-step cut) the walks' mean weight is 1 (alpha is clamped to 0.999999: the
// loss is ~1e-5) within 5 standard errors: the guided and channel-MIS weights are unbiased.
// Control: the same slab with alpha 0.9 loses energy far beyond that tolerance.
TEST(SubsurfaceWalk, WhiteSlabConservesEnergy) {
    struct Slab {
        float operator()(const Vec3& o, const Vec3& d, float t_max, bool) const {
            float t = kInfinity;
            if (d.z > 0.f) t = -o.z / d.z;
            if (d.z < 0.f) t = (-2.f - o.z) / d.z;
            return t > 0.f && t < t_max ? t : kInfinity;
        }
    };
    auto mean = [](const SubsurfaceWalk& walk, double& se) {
        Uniform u(11);
        double s = 0.0, s2 = 0.0;
        const int n = 50000;
        for (int i = 0; i < n; ++i) {
            Rgb beta(1.f);
            if (!subsurface_random_walk(walk, Vec3(0.f), Vec3(0, 0, 1), Vec3(0, 0, 1), beta, u,
                                        Slab{}))
                beta = Rgb(0.f);
            s += beta.g, s2 += double(beta.g) * beta.g;
        }
        const double m = s / n;
        se = std::sqrt(std::max(0.0, s2 / n - m * m) / n);
        return m;
    };
    const SubsurfaceWalk white = SubsurfaceWalk::make(Rgb(1.f), Rgb(1.f), 0.f);
    EXPECT_NEAR(white.alpha.r, 0.999999f, 1e-7);
    EXPECT_FLOAT_EQ(white.sigma_t.r, 1.f);
    for (float g : {0.f, 0.5f}) {
        const SubsurfaceWalk w =
            SubsurfaceWalk::from_coefficients(Rgb(1.f), white.alpha, Rgb(1.f), g);
        double se = 0.0;
        const double m = mean(w, se);
        EXPECT_NEAR(m, 1.0, 5.0 * se + 1e-4) << "g " << g;
    }
    double se = 0.0;
    const double lossy =
        mean(SubsurfaceWalk::from_coefficients(Rgb(1.f), Rgb(0.9f), Rgb(1.f), 0.f), se);
    EXPECT_LT(lossy, 1.0 - 20.0 * se);
}

TEST(SubsurfaceWalk, Deterministic) {
    const SubsurfaceWalk walk = SubsurfaceWalk::make(Rgb(0.8f, 0.4f, 0.2f), Rgb(1.f), 0.3f);
    const MeanSe a = walk_reflectance(walk, 2000, 3), b = walk_reflectance(walk, 2000, 3);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(a.mean[c], b.mean[c]);
}

// The start numbers (a renderer's stratified dimensions) are the entry's and the first step's:
// the overload without them draws them first from u(), in that order, so the two walk alike;
// and the walk reads them (another entry pair changes where it leaves).
TEST(SubsurfaceWalk, StartNumbersAreTheFirstDraws) {
    const SubsurfaceWalk walk = SubsurfaceWalk::make(Rgb(0.8f, 0.4f, 0.2f), Rgb(1.f), 0.3f);
    const Vec3 n(0.f, 0.f, 1.f);
    Uniform a(11), b(11);
    int exits = 0, moved = 0;
    for (int i = 0; i < 200; ++i) {
        Rgb beta_a(1.f), beta_b(1.f), beta_c(1.f);
        const auto ea = subsurface_random_walk(walk, Vec3(0.f), n, n, beta_a, a, HalfSpace{});
        SubsurfaceWalkStart start;
        start.entry.x = b();
        start.entry.y = b();
        start.first.x = b();
        start.first.y = b();
        Uniform c = b;  // the same later draws
        const auto eb =
            subsurface_random_walk(walk, Vec3(0.f), n, n, beta_b, start, b, HalfSpace{});
        ASSERT_EQ(bool(ea), bool(eb));
        if (ea) {
            ++exits;
            EXPECT_EQ(ea->p, eb->p);
            EXPECT_EQ(ea->steps, eb->steps);
            EXPECT_EQ(beta_a, beta_b);
        }
        start.entry = Vec2(1.f - start.entry.x, 0.5f * start.entry.y);
        const auto ec =
            subsurface_random_walk(walk, Vec3(0.f), n, n, beta_c, start, c, HalfSpace{});
        if (ea && ec) moved += ea->p != ec->p;
    }
    EXPECT_GT(exits, 100);
    EXPECT_GT(moved, exits / 2);
}

// The lobe's selection probability at wo weighs the walk's sample weight (the mean closure
// weight) against the surface closures' at wo (Cycles' sample weights: the specular's Fresnel
// at wo, the retro-reflection's roughness FV), as Cycles picks among closures. The wax of the
// real scene suzanne_sss: at normal incidence the surface closures reflect ~4%, so the walk is
// chosen 94% of the time (the fixed 3 m / (3 m + 1) = 0.64 left a third of the paths to them:
// sigma 1.25x Cycles' on the object); at grazing the specular's Fresnel outweighs it.
TEST(SubsurfaceModels, LobeProbabilityFollowsTheSampleWeightsAtWo) {
    const Rgb wax(0.8f, 0.55f, 0.45f);
    const Material m = make_material("principled", ParamSet{{"base_color", wax},
                                                            {"subsurface", 0.1},
                                                            {"subsurface_color", wax},
                                                            {"roughness", 0.4}});
    const Material::Subsurface* s = m.subsurface();
    ASSERT_NE(s, nullptr);
    ASSERT_NE(s->surface, nullptr);
    ASSERT_TRUE(s->surface->principled().has_value());
    EXPECT_FLOAT_EQ(s->weight, (wax.r + wax.g + wax.b) / 3.f);  // w_d = 1
    float previous = 1.f;
    for (float c : {1.f, 0.8f, 0.5f, 0.3f, 0.1f, 0.02f}) {
        const Vec3 wo(std::sqrt(1.f - c * c), 0.f, c);
        const float ws = s->surface->principled()->sample_weight(wo);
        const float p = s->probability(wo);
        EXPECT_FLOAT_EQ(p, s->weight / (s->weight + ws)) << c;
        EXPECT_LT(p, previous) << c;  // Fresnel: the surface weighs more toward grazing
        previous = p;
    }
    EXPECT_GT(s->probability(Vec3(0.f, 0.f, 1.f)), 0.9f);
    EXPECT_LT(s->probability(glm::normalize(Vec3(1.f, 0.f, 0.02f))), 0.5f);
}

TEST(SubsurfaceModels, BuildTheWalkAndTheFallback) {
    const Material node = make_material("subsurface", ParamSet{{"color", Rgb(0.8f, 0.5f, 0.3f)}});
    ASSERT_NE(node.subsurface(), nullptr);
    EXPECT_EQ(node.subsurface()->surface, nullptr);
    EXPECT_FLOAT_EQ(node.subsurface()->probability(Vec3(0.f, 0.f, 1.f)), 1.f);
    ASSERT_TRUE(node.diffuse().has_value());  // the fallback: Lambert of the colour
    // Scale 0: no walk.
    EXPECT_EQ(make_material("subsurface", ParamSet{{"scale", 0.0}}).subsurface(), nullptr);
    // Principled: subsurface 0 has none; > 0 the walk with the retro-reflection beside it.
    EXPECT_EQ(make_material("principled", ParamSet{}).subsurface(), nullptr);
    const Material p = make_material("principled", ParamSet{{"subsurface", 1.0}});
    ASSERT_NE(p.subsurface(), nullptr);
    EXPECT_TRUE(p.subsurface()->lobe.fresnel);
    ASSERT_NE(p.subsurface()->surface, nullptr);
    const Vec3 normal(0.f, 0.f, 1.f), grazing = glm::normalize(Vec3(1.f, 0.f, 0.05f));
    EXPECT_GT(p.subsurface()->probability(grazing), 0.f);
    EXPECT_LT(p.subsurface()->probability(normal), 1.f);
    // Metallic 1: no diffuse weight, no walk.
    EXPECT_EQ(
        make_material("principled", ParamSet{{"subsurface", 1.0}, {"metallic", 1.0}}).subsurface(),
        nullptr);
}

TEST(SubsurfaceModels, BadInputNamesTheParameter) {
    struct Case {
        std::string model;
        ParamSet params;
        std::string param, words;
    };
    const std::vector<Case> cases = {
        {"subsurface", ParamSet{{"radius", Rgb(1.f, -0.1f, 1.f)}}, "radius", "must be in"},
        {"subsurface", ParamSet{{"scale", -1.0}}, "scale", "must be in"},
        {"subsurface", ParamSet{{"ior", 1.0}}, "ior", "1.01"},
        {"subsurface", ParamSet{{"anisotropy", 0.95}}, "anisotropy", "0.9"},
        {"subsurface", ParamSet{{"anisotropy", -0.2}}, "anisotropy", "must be in"},
        {"subsurface", ParamSet{{"color", Rgb(1.2f)}}, "color", "must be in"},
        {"subsurface", ParamSet{{"method", std::string("christensen_burley")}}, "method",
         "random_walk"},
        {"subsurface", ParamSet{{"radius", Rgb(1.f, 0.f, 1.f)}}, "radius", "all of them 0"},
        {"principled", ParamSet{{"subsurface", 0.5}, {"subsurface_radius", Rgb(-1.f)}},
         "subsurface_radius", "must be in"},
        {"principled", ParamSet{{"subsurface_ior", 5.0}}, "subsurface_ior", "3.8"},
        {"principled", ParamSet{{"subsurface_method", std::string("burley")}}, "subsurface_method",
         "unknown value"},
    };
    for (const Case& c : cases) {
        try {
            make_material(c.model, c.params);
            ADD_FAILURE() << c.model << " " << c.param << ": no error";
        } catch (const ParamError& e) {
            EXPECT_EQ(e.param(), c.param) << e.what();
            EXPECT_NE(std::string(e.what()).find(c.words), std::string::npos) << e.what();
        }
    }
}
