// The hair model units (core/src/models/principled_hair.cpp, hair.cpp): Cycles 3.4's Principled
// Hair BSDF and Hair BSDF about a fibre along the frame's x axis. They are not in
// tests/core/model_corners.h: the model-wide suites there check reciprocity and reflection into
// the upper hemisphere, which fibres do not have (they scatter over the whole sphere and take h,
// the attenuations and theta_r from wo alone, as Cycles); this file checks what holds instead.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "chi2.h"
#include "facet/bessel.h"
#include "facet/registry.h"

namespace facet {
namespace {

using test::dir;
using test::kDeg;

Material principled_hair(ParamSet p) {
    return make_material("principled_hair", p);
}
Material hair(ParamSet p) {
    return make_material("hair", p);
}

// wo at longitude theta_o (degrees from the fibre's normal plane) and offset h across the fibre
// (Cycles' h = -wo.y / |wo.yz| on the viewer's side z > 0).
Vec3 wo_at(double theta_o_deg, double h) {
    const double s = std::sin(theta_o_deg * kDeg), c = std::cos(theta_o_deg * kDeg);
    return Vec3(glm::normalize(DVec3(s, -h * c, std::sqrt(1.0 - h * h) * c)));
}

// int f |cos_i| dwi over the sphere by adaptive quadrature in (wi.x, phi about x), where the
// solid angle is d(wi.x) dphi: the fibre's lobes are bands about x. Channel c. The hair model's
// density per solid angle grows as 1 / cos theta_i at the fibre's poles (integrable), which
// needs the deeper subdivision (depth 12) for 1e-4.
double sphere_albedo(const Material& m, const Vec3& wo, int c, double rel_tol = 1e-5,
                     int depth = 10) {
    auto integrand = [&](double x, double phi) {
        const double r = std::sqrt(std::max(0.0, 1.0 - x * x));
        const Vec3 wi(glm::normalize(DVec3(x, r * std::cos(phi), r * std::sin(phi))));
        return double(m.f(wo, wi)[c]) * std::fabs(double(wi.z));
    };
    return test::adaptive_integrate_2d(integrand, -1.0, 1.0, 0.0, 2.0 * kPiD, 1e-9, rel_tol, depth,
                                       3);
}

// ---- Cycles 3.4's bsdf_hair_principled.h, written again in double ----------------------------

struct CyclesHair {
    DVec3 sigma;
    double v, s, m0, alpha, eta;
};

double ref_sigma_fac(double x) {
    return (((((0.245 * x) + 5.574) * x - 10.73) * x + 2.532) * x - 0.215) * x + 5.969;
}

// svm_node_closure_bsdf (CLOSURE_BSDF_HAIR_PRINCIPLED_ID) and bsdf_principled_hair_setup.
CyclesHair cycles_setup(const std::string& kind, DVec3 color, double melanin, double redness,
                        DVec3 tint, DVec3 absorption, double roughness, double radial, double coat,
                        double ior, double offset, double random_roughness, double random_color,
                        double random) {
    const double frr = 1.0 + 2.0 * (random - 0.5) * random_roughness;
    roughness *= frr;
    radial *= frr;
    CyclesHair b;
    auto from_color = [&](DVec3 c) {
        DVec3 s = glm::log(c) / ref_sigma_fac(radial);
        return s * s;
    };
    if (kind == "absorption") {
        b.sigma = absorption;
    } else if (kind == "melanin") {
        melanin *= 1.0 + 2.0 * (random - 0.5) * random_color;
        melanin = -std::log(std::max(1.0 - melanin, 0.0001));
        b.sigma = melanin * (1.0 - redness) * DVec3(0.506, 0.841, 1.653) +
                  melanin * redness * DVec3(0.343, 0.733, 1.924) + from_color(tint);
    } else {
        b.sigma = from_color(color);
    }
    auto var = [](double r) {
        return std::pow(0.726 * r + 0.812 * r * r + 3.7 * std::pow(r, 20.0), 2.0);
    };
    const double v = std::clamp(roughness, 0.001, 1.0);
    const double s = std::clamp(radial, 0.001, 1.0);
    b.m0 = var(std::clamp((1.0 - coat) * v, 0.001, 1.0));
    b.v = var(v);
    b.s = (0.265 * s + 1.194 * s * s + 5.372 * std::pow(s, 22.0)) * std::sqrt(kPiD / 8.0);
    b.alpha = offset;
    b.eta = ior;
    return b;
}

// log I0 exactly (std::cyl_bessel_i), not Cycles' ten-term float series.
double ref_log_i0(double x) {
    if (x < 600.0) return std::log(std::cyl_bessel_i(0.0, x));
    return x - 0.5 * std::log(2.0 * kPiD * x) + std::log1p(1.0 / (8.0 * x));
}
double ref_mp(double si, double ci, double so, double co, double v) {
    return std::exp(ref_log_i0(ci * co / v) - si * so / v - 1.0 / v - std::log(v) -
                    std::log1p(-std::exp(-2.0 / v)));
}
double ref_np(double phi, int p, double s, double go, double gt) {
    double a = phi - (2.0 * p * gt - 2.0 * go + p * kPiD);
    a = (a + kPiD) - 2.0 * kPiD * std::floor((a + kPiD) / (2.0 * kPiD)) - kPiD;
    const double v = std::exp(-std::fabs(a) / s);
    const double cdf = 1.0 / (1.0 + std::exp(kPiD / s));
    return v / (s * (1.0 + v) * (1.0 + v)) / (1.0 - 2.0 * cdf);
}
double ref_fresnel(double cosi, double eta) {
    const double c = std::fabs(cosi);
    double g = eta * eta - 1.0 + c * c;
    if (g <= 0.0) return 1.0;
    g = std::sqrt(g);
    const double A = (g - c) / (g + c), B = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    return 0.5 * A * A * (1.0 + B * B);
}

struct RefEval {
    DVec3 F;
    double pdf;  // Cycles' F_energy
};

// bsdf_principled_hair_eval with dPdu = x, Ng = z turned toward I = wo.
RefEval cycles_eval(const CyclesHair& b, DVec3 I, DVec3 w) {
    const DVec3 X(1.0, 0.0, 0.0), Ng(0.0, 0.0, I.z < 0.0 ? -1.0 : 1.0);
    const DVec3 Y = glm::normalize(glm::cross(X, I)), Z = glm::normalize(glm::cross(X, Y));
    const double h = glm::dot(glm::cross(Ng, X), Z);
    const DVec3 wo(glm::dot(I, X), glm::dot(I, Y), glm::dot(I, Z));
    const DVec3 wi(glm::dot(w, X), glm::dot(w, Y), glm::dot(w, Z));
    const double so = wo.x, co = std::sqrt(1.0 - so * so), phi_o = std::atan2(wo.z, wo.y);
    const double st = so / b.eta, ct = std::sqrt(1.0 - st * st);
    const double cgo = std::sqrt(1.0 - h * h), go = std::asin(h);
    const double sgt = h * co / std::sqrt(b.eta * b.eta - so * so);
    const double cgt = std::sqrt(1.0 - sgt * sgt), gt = std::asin(sgt);
    const DVec3 T = glm::exp(-b.sigma * (2.0 * cgt / ct));
    const double f = ref_fresnel(co * cgo, b.eta);
    DVec3 Ap[4];
    double E[4];
    Ap[0] = DVec3(f);
    DVec3 col = (1.0 - f) * (1.0 - f) * T;
    Ap[1] = col;
    col *= T * f;
    Ap[2] = col;
    col *= T * f / (DVec3(1.0) - T * f);
    Ap[3] = col;
    double tot = 0.0;
    for (int p = 0; p < 4; ++p) {
        E[p] = p == 0 ? f : 0.2126 * Ap[p].x + 0.7152 * Ap[p].y + 0.0722 * Ap[p].z;
        tot += E[p];
    }
    for (double& e : E) e /= tot;
    const double si = wi.x, ci = std::sqrt(1.0 - si * si);
    const double phi = std::atan2(wi.z, wi.y) - phi_o;
    const double a = b.alpha;
    const double ang[6] = {si * std::cos(2 * a) + ci * std::sin(2 * a),
                           std::fabs(ci * std::cos(2 * a) - si * std::sin(2 * a)),
                           si * std::cos(a) - ci * std::sin(a),
                           std::fabs(ci * std::cos(a) + si * std::sin(a)),
                           si * std::cos(4 * a) - ci * std::sin(4 * a),
                           std::fabs(ci * std::cos(4 * a) + si * std::sin(4 * a))};
    RefEval r{DVec3(0.0), 0.0};
    for (int p = 0; p < 3; ++p) {
        const double v = p == 0 ? b.m0 : p == 1 ? 0.25 * b.v : 4.0 * b.v;
        const double mp = ref_mp(ang[2 * p], ang[2 * p + 1], so, co, v);
        const double np = ref_np(phi, p, b.s, go, gt);
        r.F += Ap[p] * mp * np;
        r.pdf += E[p] * mp * np;
    }
    const double mp = ref_mp(si, ci, so, co, 4.0 * b.v) / (2.0 * kPiD);
    r.F += Ap[3] * mp;
    r.pdf += E[3] * mp;
    return r;
}

struct HairCase {
    const char* name;
    ParamSet params;
    CyclesHair ref;
};

std::vector<HairCase> hair_cases() {
    const DVec3 color0(0.017513, 0.005763, 0.002059), tint1(1.0), abs0(0.245531, 0.52, 1.365);
    const double deg2 = 2.0 * kDeg;
    return {
        {"defaults", ParamSet{},
         cycles_setup("color", color0, 0.8, 1.0, tint1, abs0, 0.3, 0.3, 0.0, 1.55, deg2, 0, 0, 0)},
        {"color_blond_smooth",
         ParamSet{{"color", Rgb(0.8f, 0.6f, 0.3f)}, {"roughness", 0.15}, {"offset", 0.0}},
         cycles_setup("color", DVec3(0.8f, 0.6f, 0.3f), 0.8, 1.0, tint1, abs0, 0.15, 0.3, 0.0, 1.55,
                      0.0, 0, 0, 0)},
        {"melanin_random",
         ParamSet{{"parametrization", std::string("melanin")},
                  {"melanin", 0.5},
                  {"melanin_redness", 0.3},
                  {"tint", Rgb(0.9f, 0.6f, 0.5f)},
                  {"random", 0.7},
                  {"random_color", 0.4},
                  {"random_roughness", 0.3},
                  {"roughness", 0.4},
                  {"radial_roughness", 0.6}},
         cycles_setup("melanin", color0, 0.5, 0.3, DVec3(0.9f, 0.6f, 0.5f), abs0, 0.4, 0.6, 0.0,
                      1.55, deg2, 0.3, 0.4, 0.7)},
        {"absorption_coat_tilt",
         ParamSet{{"parametrization", std::string("absorption")},
                  {"absorption_coefficient", Rgb(0.3f, 0.6f, 1.2f)},
                  {"coat", 0.4},
                  {"offset", 0.06},
                  {"ior", 1.45},
                  {"roughness", 0.7},
                  {"radial_roughness", 0.9}},
         cycles_setup("absorption", color0, 0.8, 1.0, tint1, DVec3(0.3f, 0.6f, 1.2f), 0.7, 0.9, 0.4,
                      1.45, 0.06, 0, 0, 0)},
    };
}

// f |cos_i| is Cycles' eval F (the closure includes the cosine), per channel, to 1e-4 relative:
// the unit works in float directions and a double evaluation; the reference uses the same
// (float) directions. Where offset = coat = 0 the pdf is Cycles' too (F_energy): then Cycles'
// pdf is its sampler's density, which the unit's pdf is everywhere.
TEST(PrincipledHair, MatchesCyclesFormulas) {
    int compared = 0;
    double worst = 0.0;
    for (const HairCase& hc : hair_cases()) {
        const Material m = principled_hair(hc.params);
        const bool same_pdf = hc.ref.alpha == 0.0 && hc.ref.m0 == hc.ref.v;
        for (double to : {-60.0, -20.0, 0.0, 35.0, 80.0})
            for (double h : {-0.9, -0.3, 0.0, 0.5, 0.99})
                for (double ti : {-70.0, -25.0, 5.0, 40.0})
                    for (double pi : {3.0, 50.0, 130.0, 181.0, 260.0}) {
                        const Vec3 wo = wo_at(to, h);
                        const double s = std::sin(ti * kDeg), c = std::cos(ti * kDeg);
                        const Vec3 wi(glm::normalize(
                            DVec3(s, c * std::cos(pi * kDeg), c * std::sin(pi * kDeg))));
                        const RefEval want = cycles_eval(hc.ref, DVec3(wo), DVec3(wi));
                        const BSDFEval got = m.eval(wo, wi);
                        for (int k = 0; k < 3; ++k) {
                            const double g = double(got.f[k]) * std::fabs(double(wi.z));
                            const double rel = std::fabs(g - want.F[k]) / (want.F[k] + 1e-30);
                            if (want.F[k] > 1e-20) worst = std::max(worst, rel);
                            EXPECT_NEAR(g, want.F[k], 1e-4 * want.F[k] + 1e-20)
                                << hc.name << " to " << to << " h " << h << " ti " << ti << " phi "
                                << pi << " ch " << k;
                        }
                        if (same_pdf)
                            EXPECT_NEAR(got.pdf, want.pdf, 1e-4 * want.pdf)
                                << hc.name << " to " << to << " h " << h << " ti " << ti;
                        ++compared;
                    }
    }
    std::printf("  %d (wo, wi) pairs: worst relative difference to Cycles' F %.2e\n", compared,
                worst);
}

// White furnace: with no absorption, offset 0 and any roughness, radial roughness, coat and h,
// int F dwi over the sphere is 1 (header of principled_hair.cpp). By adaptive quadrature (its
// tolerance 1e-5 relative per cell): within 1e-4. The same albedo by the unit's own sampler
// (1e4 weights f |cos| / pdf, which are all 1 here: F is the pdf) must be 1 within 1e-4, which
// also says that no sample is lost.
TEST(PrincipledHair, WhiteFurnaceForANonAbsorbingFibre) {
    double worst = 0.0;
    for (double rough : {0.15, 0.4, 1.0})
        for (double radial : {0.2, 1.0})
            for (double coat : {0.0, 0.6}) {
                const Material m =
                    principled_hair(ParamSet{{"parametrization", std::string("absorption")},
                                             {"absorption_coefficient", 0.0},
                                             {"offset", 0.0},
                                             {"roughness", rough},
                                             {"radial_roughness", radial},
                                             {"coat", coat}});
                for (double to : {0.0, 65.0})
                    for (double h : {-0.8, 0.4, 0.97}) {
                        const Vec3 wo = wo_at(to, h);
                        const double a = sphere_albedo(m, wo, 0);
                        worst = std::max(worst, std::fabs(a - 1.0));
                        EXPECT_NEAR(a, 1.0, 1e-4)
                            << rough << " " << radial << " " << coat << " to " << to << " h " << h;
                        const test::SampledAlbedo s = test::sampled_albedo(m, wo, 10000, 3, 1);
                        EXPECT_NEAR(s.mean, 1.0, 1e-4) << rough << " " << radial << " " << coat;
                    }
            }
    std::printf("  white furnace: worst |albedo - 1| %.2e (quadrature)\n", worst);
}

// With absorption and the cuticle tilt the albedo is below 1; quadrature of f |cos| and the
// mean sample weight (2e4 samples) agree within 5 standard errors + 1e-3 (quadrature): the
// sampler's pdf is its density also where the tilt folds theta at the poles. The tilt alone
// (no absorption) moves the albedo off 1 by the amount printed (Cycles' model, not renormalised).
TEST(PrincipledHair, AbsorbingAndTiltedAlbedoMatchesSampling) {
    for (const HairCase& hc : hair_cases()) {
        const Material m = principled_hair(hc.params);
        for (auto [to, h] : {std::pair{10.0, -0.5}, {60.0, 0.3}}) {
            const Vec3 wo = wo_at(to, h);
            for (int c : {0, 2}) {  // red and blue: the least and the most absorbed
                const double q = sphere_albedo(m, wo, c);
                const test::SampledAlbedo s = test::sampled_albedo(m, wo, 20000, 11, c);
                EXPECT_LT(q, 1.0) << hc.name;
                EXPECT_NEAR(s.mean, q, 5.0 * s.se + 1e-3) << hc.name << " ch " << c;
            }
        }
    }
    for (double offset : {2.0, 5.0, 10.0}) {
        const Material m = principled_hair(ParamSet{{"parametrization", std::string("absorption")},
                                                    {"absorption_coefficient", 0.0},
                                                    {"offset", offset * kDeg}});
        std::printf("  no absorption, offset %4.1f deg: albedo %.5f (theta_o 0), %.5f (60)\n",
                    offset, sphere_albedo(m, wo_at(0.0, 0.3), 0),
                    sphere_albedo(m, wo_at(60.0, 0.3), 0));
    }
}

// Chi-square of sample_f against pdf over the whole sphere (16 x 16 cells, 1e5 samples), Sidak
// over the cases; the per-sample f and pdf equal f() and pdf().
TEST(PrincipledHair, SamplingMatchesPdf) {
    const std::vector<ParamSet> cases = {
        ParamSet{{"offset", 0.0}},
        ParamSet{{"roughness", 0.6}, {"radial_roughness", 0.8}, {"coat", 0.5}},
        ParamSet{{"parametrization", std::string("absorption")},
                 {"absorption_coefficient", 0.2},
                 {"offset", 10.0 * kDeg},
                 {"roughness", 0.4}},
        ParamSet{{"parametrization", std::string("melanin")},
                 {"melanin", 0.3},
                 {"offset", -0.3},
                 {"roughness", 0.8},
                 {"radial_roughness", 0.4}},
    };
    const std::vector<std::pair<int, double>> runs = {
        {0, 10.0}, {0, 85.0}, {1, 50.0}, {2, 70.0}, {3, 30.0}};  // (case, theta_o)
    const double level = test::sidak_alpha(0.01, int(runs.size()));
    for (auto [i, th] : runs) {
        const test::Chi2Result r = test::sphere_chi2(principled_hair(cases[i]), th);
        test::expect_sphere_chi2(r, level);
        EXPECT_NEAR(r.pdf_integral + double(r.failed) / double(r.n), 1.0, 2e-3) << r.describe();
    }
}

// The chi-square catches a wrong pdf: the tilt's Jacobian left out (Cycles' pdf) at offset 10
// degrees is a density that its sampler does not draw. Shown with a pdf scaled by
// cos(theta_i - 20 deg) / cos theta_i about the fibre, which is that error for the R lobe.
TEST(PrincipledHair, ChiSquareDetectsAMissingJacobian) {
    const Material m = principled_hair(ParamSet{{"offset", 10.0 * kDeg},
                                                {"roughness", 0.4},
                                                {"parametrization", std::string("absorption")},
                                                {"absorption_coefficient", 0.0}});
    struct NoJacobian {
        const Material& m;
        float factor(const Vec3& wi) const {
            const float ci = std::sqrt(wi.y * wi.y + wi.z * wi.z);
            const float t = std::atan2(wi.x, ci) - float(20.0 * kDeg);
            return ci > 0.f ? std::cos(t) / ci : 1.f;
        }
        std::optional<BSDFSample> sample_f(const Vec3& wo, float uc, Vec2 u) const {
            auto s = m.sample_f(wo, uc, u);
            if (s) s->pdf *= factor(s->wi);
            return s;
        }
        float pdf(const Vec3& wo, const Vec3& wi) const { return m.pdf(wo, wi) * factor(wi); }
        Rgb f(const Vec3& wo, const Vec3& wi) const { return m.f(wo, wi); }
    } wrong{m};
    const test::Chi2Result r = test::sphere_chi2(wrong, 50.0);
    EXPECT_LT(r.chi2.p_value, 1e-6) << r.describe();
}

// Reciprocity holds only where Cycles' model is symmetric: offset 0, and wo, wi at the same
// azimuth about the fibre, mirrored in its normal plane (the same h, |theta|, attenuations and
// phi = 0). Elsewhere h, A_p and the azimuthal centres come from wo alone: the largest relative
// asymmetry over random pairs is printed and is large (> 10%), which is Cycles' behaviour.
TEST(PrincipledHair, ReciprocalOnlyWhereCyclesIs) {
    const Material m = principled_hair(ParamSet{
        {"offset", 0.0}, {"color", Rgb(0.6f, 0.4f, 0.2f)}, {"coat", 0.3}, {"roughness", 0.35}});
    for (double th : {5.0, 30.0, 70.0})
        for (double az : {-80.0, -20.0, 0.0, 45.0, 85.0}) {
            const double s = std::sin(th * kDeg), c = std::cos(th * kDeg);
            const double a = std::sin(az * kDeg), b = std::cos(az * kDeg);
            const Vec3 wo(glm::normalize(DVec3(s, c * a, c * b)));
            const Vec3 wi(glm::normalize(DVec3(-s, c * a, c * b)));
            const Rgb x = m.f(wo, wi), y = m.f(wi, wo);
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(x[k], y[k], 1e-5 * x[k]) << th << " " << az << " ch " << k;
        }
    pcg32 rng(5);
    double worst = 0.0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 wo =
            sample_uniform_sphere(Vec2(test::uniform_float(rng), test::uniform_float(rng)));
        const Vec3 wi =
            sample_uniform_sphere(Vec2(test::uniform_float(rng), test::uniform_float(rng)));
        const double x = m.f(wo, wi).g, y = m.f(wi, wo).g;
        if (x > 1e-3 && y > 1e-3) worst = std::max(worst, std::fabs(x - y) / std::max(x, y));
    }
    std::printf("  principled_hair: largest relative asymmetry over random pairs %.3f\n", worst);
    EXPECT_GT(worst, 0.1);
}

// The models read the tangent: the renderer builds their frame from dpdu.
TEST(PrincipledHair, ReadsTheTangent) {
    EXPECT_TRUE(principled_hair({}).anisotropic());
    EXPECT_TRUE(hair({}).anisotropic());
    EXPECT_TRUE(principled_hair({}).transmissive());
    EXPECT_FALSE(hair({}).transmissive());
    EXPECT_TRUE(hair(ParamSet{{"component", std::string("transmission")}}).transmissive());
    EXPECT_FALSE(make_material("lambert", {}).anisotropic());
}

// No NaN, Inf or negative value anywhere, including wo or wi along the fibre, on the surface
// (z = 0), below it, and at the parameter extremes.
TEST(PrincipledHair, NoNaNAtTheEdges) {
    std::vector<Material> ms;
    for (double r : {0.0, 1.0})
        for (double rad : {0.0, 1.0})
            for (double off : {-0.5 * kPiD, 0.0, 0.5 * kPiD}) {
                ms.push_back(principled_hair(ParamSet{
                    {"roughness", r}, {"radial_roughness", rad}, {"offset", off}, {"ior", 1.0}}));
                ms.push_back(principled_hair(ParamSet{{"roughness", r},
                                                      {"radial_roughness", rad},
                                                      {"offset", off},
                                                      {"color", 0.0},
                                                      {"coat", 1.0},
                                                      {"ior", 1000.0}}));
                ms.push_back(
                    hair(ParamSet{{"roughness_u", r}, {"roughness_v", rad}, {"offset", off}}));
                ms.push_back(hair(ParamSet{{"component", std::string("transmission")},
                                           {"roughness_u", r},
                                           {"roughness_v", rad},
                                           {"offset", off}}));
            }
    std::vector<Vec3> dirs = {Vec3(1, 0, 0),
                              Vec3(-1, 0, 0),
                              Vec3(0, 1, 0),
                              Vec3(0, 0, 1),
                              Vec3(0, 0, -1),
                              glm::normalize(Vec3(1, 1e-7f, 0)),
                              glm::normalize(Vec3(1, 0, 1e-7f)),
                              glm::normalize(Vec3(0.3f, 0.9f, 0))};
    pcg32 rng(9);
    for (int i = 0; i < 40; ++i)
        dirs.push_back(
            sample_uniform_sphere(Vec2(test::uniform_float(rng), test::uniform_float(rng))));
    long bad = 0;
    for (const Material& m : ms)
        for (const Vec3& wo : dirs) {
            for (const Vec3& wi : dirs) {
                const BSDFEval e = m.eval(wo, wi);
                if (!is_finite(e.f) || e.f.r < 0.f || !std::isfinite(e.pdf) || e.pdf < 0.f) ++bad;
            }
            for (int k = 0; k < 50; ++k) {
                const auto s = m.sample_f(wo, test::uniform_float(rng),
                                          Vec2(test::uniform_float(rng), test::uniform_float(rng)));
                if (s && (!is_finite(s->f) || !(s->pdf > 0.f) || !std::isfinite(s->pdf) ||
                          std::fabs(glm::length(s->wi) - 1.f) > 1e-5f))
                    ++bad;
            }
        }
    EXPECT_EQ(bad, 0);
}

// A thread keeps the last setup of wo (principled_hair.cpp, setup_of) for the next call with
// the same wo and parameters: any call gives what it gives alone. Materials that differ in each
// parameter the setup reads (absorption, ior, offset), and in one it does not (roughness), are
// evaluated and sampled at the same wo one after the other; each answer equals, bit for bit, that
// material's answer after a call at another wo (a fresh setup), and the pairs' answers differ
// (a cache that kept the first material's setup for the second would return the first's values
// for the setup's part and fail).
TEST(PrincipledHair, SetupReuseGivesEachMaterialItsOwnValues) {
    const Material base = principled_hair(ParamSet{{"color", 0.3}, {"offset", 0.05}});
    const std::vector<Material> others = {
        principled_hair(ParamSet{{"color", 0.6}, {"offset", 0.05}}),
        principled_hair(ParamSet{{"color", 0.3}, {"offset", 0.05}, {"ior", 1.8}}),
        principled_hair(ParamSet{{"color", 0.3}, {"offset", -0.1}}),
        principled_hair(ParamSet{{"color", 0.3}, {"offset", 0.05}, {"roughness", 0.6}})};
    const Vec3 wo = wo_at(20.0, 0.4), elsewhere = wo_at(-35.0, -0.2);
    const Vec3 wi = dir(70.0, 40.0);
    const float uc = 0.37f;
    const Vec2 u(0.61f, 0.23f);
    auto fresh_eval = [&](const Material& m) {
        (void)m.eval(elsewhere, wi);
        return m.eval(wo, wi);
    };
    auto fresh_sample = [&](const Material& m) {
        (void)m.eval(elsewhere, wi);
        return m.sample_f(wo, uc, u);
    };
    for (std::size_t i = 0; i < others.size(); ++i) {
        SCOPED_TRACE("material " + std::to_string(i));
        const Material& m = others[i];
        const BSDFEval want_base = fresh_eval(base), want = fresh_eval(m);
        const auto want_sample = fresh_sample(m);
        ASSERT_TRUE(want_sample.has_value());
        EXPECT_NE(want.f, want_base.f);
        // The other material right after base at the same wo, and base right after it.
        (void)base.eval(wo, wi);
        const BSDFEval got = m.eval(wo, wi);
        EXPECT_EQ(got.f, want.f);
        EXPECT_EQ(got.pdf, want.pdf);
        const BSDFEval got_base = base.eval(wo, wi);
        EXPECT_EQ(got_base.f, want_base.f);
        EXPECT_EQ(got_base.pdf, want_base.pdf);
        (void)base.eval(wo, wi);
        const auto got_sample = m.sample_f(wo, uc, u);
        ASSERT_TRUE(got_sample.has_value());
        EXPECT_EQ(got_sample->wi, want_sample->wi);
        EXPECT_EQ(got_sample->f, want_sample->f);
        EXPECT_EQ(got_sample->pdf, want_sample->pdf);
    }
}

// facet/bessel.h: I0(x) exp(a - x) against the library's I0 (std::cyl_bessel_i, double) below
// 700, where exp(x) still fits a double, and against the asymptotic expansion to 1/x^8 above
// (its remainder below 1e-21 there), at 1e-13 relative: the expansions' own error is 1.2e-14
// (header), and an error in one of their 41 coefficients moves the value by far more. The scale
// exp(a) is applied without overflow or underflow where the product is representable.
TEST(PrincipledHair, BesselI0ScaledMatchesTheLibrary) {
    double worst = 0.0, worst_x = 0.0;
    auto check = [&](double x, double want) {
        const double got = bessel_i0_scaled(x, 0.0);
        const double rel = std::fabs(got / want - 1.0);
        if (rel > worst) worst = rel, worst_x = x;
        EXPECT_NEAR(got, want, 1e-13 * want) << "x " << x;
    };
    for (int i = 0; i <= 70000; ++i) {  // [0, 700] in steps of 0.01, both pieces and the seam
        const double x = 0.01 * i;
        check(x, std::cyl_bessel_i(0.0, x) * std::exp(-x));
    }
    for (double x = 700.0; x < 1e12; x *= 1.01) {
        double term = 1.0, sum = 1.0;  // sum_k ((2k - 1)!!)^2 / (k! (8x)^k)
        for (int k = 1; k <= 8; ++k) {
            term *= (2.0 * k - 1.0) * (2.0 * k - 1.0) / (k * 8.0 * x);
            sum += term;
        }
        check(x, sum / std::sqrt(2.0 * kPiD * x));
    }
    std::printf("  I0(x) exp(-x): worst relative difference %.2e (x = %.2f)\n", worst, worst_x);
    // The scale: exp(a) on both pieces, a product that underflows to 0 and one that would not fit
    // as I0(x) and exp(a) apart.
    for (double x : {0.0, 3.0, 5.0, 5.0001, 40.0, 1e5})
        for (double a : {-1.0, -30.0})
            EXPECT_NEAR(bessel_i0_scaled(x, a), bessel_i0_scaled(x, 0.0) * std::exp(a),
                        1e-14 * bessel_i0_scaled(x, 0.0) * std::exp(a));
    EXPECT_EQ(bessel_i0_scaled(2.0, -2000.0), 0.0);
    const double big = bessel_i0_scaled(2000.0, -10.0);  // I0(2000) overflows a double
    EXPECT_NEAR(
        big, std::exp(-10.0) / std::sqrt(2.0 * kPiD * 2000.0) * (1.0 + 1.0 / 16000.0 + 9.0 / 512e6),
        1e-8 * big);
}

// ---- hair: Cycles 3.4's bsdf_hair.h, written again in double
// ---------------------------------

// bsdf_hair_{reflection,transmission}_eval with T = x, N = z turned toward I = wo, offset
// already negated (Cycles' svm), exact acos / atan / cos for the fast_* ones.
double cycles_hair_eval(bool transmission, double offset, double r1, double r2, DVec3 I, DVec3 w) {
    const DVec3 N(0.0, 0.0, I.z < 0.0 ? -1.0 : 1.0), Tg(1.0, 0.0, 0.0);
    r1 = std::clamp(r1, 0.001, 1.0), r2 = std::clamp(r2, 0.001, 1.0);
    if (transmission ? glm::dot(N, w) >= 0.0 : glm::dot(N, w) < 0.0) return 0.0;
    const double Iz = glm::dot(Tg, I);
    const DVec3 locy = glm::normalize(I - Tg * Iz);
    const double theta_r = 0.5 * kPiD - std::acos(Iz);
    const double wz = glm::dot(Tg, w);
    const DVec3 wy = glm::normalize(w - Tg * wz);
    const double theta_i = 0.5 * kPiD - std::acos(wz);
    const double cosphi = glm::dot(wy, locy);
    if (0.5 * kPiD - std::fabs(theta_i) < 0.001) return 0.0;
    const double a = std::atan(((0.5 * kPiD + theta_r) * 0.5 - offset) / r1);
    const double b = std::atan(((-0.5 * kPiD + theta_r) * 0.5 - offset) / r1);
    const double t = (theta_i + theta_r) * 0.5 - offset;
    const double theta_pdf = r1 / (2.0 * (t * t + r1 * r1) * (a - b) * std::cos(theta_i));
    if (!transmission) {
        if (cosphi < 0.0) return 0.0;
        double phi_i = std::acos(cosphi) / r2;
        phi_i = std::fabs(phi_i) < kPiD ? phi_i : kPiD;
        return std::cos(phi_i * 0.5) * 0.25 / r2 * theta_pdf;
    }
    const double c = 2.0 * std::atan(0.5 * kPiD / r2);
    const double p = kPiD - std::acos(std::clamp(cosphi, -1.0, 1.0));
    return r2 / (c * (p * p + r2 * r2)) * theta_pdf;
}

// f |cos_i| = colour F, and pdf = F (reflection) or F c / c' (transmission, hair.cpp), to 1e-5
// relative (double inside, float directions).
TEST(Hair, MatchesCyclesFormulas) {
    for (bool tr : {false, true})
        for (double off : {0.0, 0.2, -0.5})
            for (double ru : {0.05, 0.3, 1.0})
                for (double rv : {0.2, 0.7, 1.0}) {
                    const Material m = hair(
                        ParamSet{{"component", std::string(tr ? "transmission" : "reflection")},
                                 {"color", Rgb(0.9f, 0.5f, 0.2f)},
                                 {"offset", off},
                                 {"roughness_u", ru},
                                 {"roughness_v", rv}});
                    for (double to : {-50.0, 0.0, 30.0, 80.0})
                        for (double h : {-0.7, 0.0, 0.9})
                            for (double ti : {-60.0, 10.0, 45.0})
                                for (double pi : {20.0, 100.0, 200.0, 300.0}) {
                                    const Vec3 wo = wo_at(to, h);
                                    const double s = std::sin(ti * kDeg), c = std::cos(ti * kDeg);
                                    const Vec3 wi(glm::normalize(DVec3(s, c * std::cos(pi * kDeg),
                                                                       c * std::sin(pi * kDeg))));
                                    const double want =
                                        cycles_hair_eval(tr, -off, ru, rv, DVec3(wo), DVec3(wi));
                                    const BSDFEval e = m.eval(wo, wi);
                                    const double scale =  // pdf / F (hair.cpp)
                                        tr ? 2.0 * std::atan(0.5 * kPiD / rv) /
                                                 (2.0 * std::atan(kPiD / rv))
                                           : 1.0;
                                    EXPECT_NEAR(e.pdf, want * scale, 1e-5 * want + 1e-12);
                                    EXPECT_NEAR(double(e.f.g) * std::fabs(wi.z), 0.5 * want,
                                                1e-5 * want + 1e-12)
                                        << tr << " " << off << " " << ru << " " << rv;
                                }
                }
}

// Chi-square of Cycles' warps against pdf (the samples that fall where F = 0 are no samples:
// the failure cell), Sidak over the cases.
TEST(Hair, SamplingMatchesPdf) {
    const double level = test::sidak_alpha(0.01, 12);
    for (bool tr : {false, true})
        for (auto [ru, rv, off] : {std::tuple{0.1, 1.0, 0.0}, {0.3, 0.4, 0.2}, {0.8, 0.7, -0.3}})
            for (double th : {20.0, 70.0}) {
                const Material m =
                    hair(ParamSet{{"component", std::string(tr ? "transmission" : "reflection")},
                                  {"offset", off},
                                  {"roughness_u", ru},
                                  {"roughness_v", rv}});
                test::expect_sphere_chi2(test::sphere_chi2(m, th), level);
            }
}

// The albedo by quadrature equals the mean sample weight (2e4 samples: 5 standard errors +
// 1e-3); for reflection it is at most the colour (the part of Cycles' density on the viewer's
// side, 1e-4) and the colour itself (1e-3: the 0.001 rad cut at the fibre) for r_v <= 1/2 and
// wo in the plane of the fibre and the normal.
TEST(Hair, AlbedoIsTheColourTimesTheKeptDensity) {
    for (bool tr : {false, true})
        for (double rv : {0.3, 1.0})
            for (double to : {0.0, 50.0})
                for (double h : {0.0, 0.6}) {
                    const Material m = hair(
                        ParamSet{{"component", std::string(tr ? "transmission" : "reflection")},
                                 {"color", 0.7},
                                 {"roughness_u", 0.2},
                                 {"roughness_v", rv},
                                 {"offset", 0.1}});
                    const Vec3 wo = wo_at(to, h);
                    const double q = sphere_albedo(m, wo, 0, 1e-5, 12);
                    const test::SampledAlbedo s = test::sampled_albedo(m, wo, 20000, 4, 0);
                    if (!tr) EXPECT_LE(q, 0.7 + 1e-4);
                    EXPECT_NEAR(s.mean, q, 5.0 * s.se + 1e-3) << tr << " " << rv << " " << to;
                    if (!tr && rv <= 0.5 && h == 0.0) EXPECT_NEAR(q, 0.7, 1e-3);
                    std::printf("  hair %s r_v %.1f theta_o %2.0f h %.1f: albedo %.4f\n",
                                tr ? "transmission" : "reflection", rv, to, h, q);
                }
}

// Range errors and meaningless parameters name the parameter.
TEST(HairModels, BadInputNamesTheParameter) {
    auto param_of = [](const char* model, ParamSet p) {
        try {
            make_material(model, p);
        } catch (const ParamError& e) {
            return e.param();
        }
        return std::string("<no error>");
    };
    const std::string ph = "principled_hair";
    EXPECT_EQ(param_of(ph.c_str(), ParamSet{{"roughness", 1.2}}), "roughness");
    EXPECT_EQ(param_of(ph.c_str(), ParamSet{{"radial_roughness", -0.1}}), "radial_roughness");
    EXPECT_EQ(param_of(ph.c_str(), ParamSet{{"coat", 2.0}}), "coat");
    EXPECT_EQ(param_of(ph.c_str(), ParamSet{{"ior", 0.9}}), "ior");
    EXPECT_EQ(param_of(ph.c_str(), ParamSet{{"offset", 1.6}}), "offset");
    EXPECT_EQ(param_of(ph.c_str(), ParamSet{{"random", 1.5}}), "random");
    EXPECT_EQ(param_of(ph.c_str(), ParamSet{{"color", Rgb(0.5f, 1.5f, 0.5f)}}), "color");
    EXPECT_EQ(param_of(ph.c_str(),
                       ParamSet{{"parametrization", std::string("melanin")}, {"melanin", -0.2}}),
              "melanin");
    EXPECT_EQ(param_of(ph.c_str(), ParamSet{{"parametrization", std::string("absorption")},
                                            {"absorption_coefficient", 2000.0}}),
              "absorption_coefficient");
    EXPECT_EQ(param_of(ph.c_str(), ParamSet{{"parametrization", std::string("melanine")}}),
              "parametrization");
    // Given but meaningless under the parametrization: an error, not ignored.
    EXPECT_EQ(param_of(ph.c_str(), ParamSet{{"melanin", 0.5}}), "melanin");
    EXPECT_EQ(
        param_of(ph.c_str(), ParamSet{{"parametrization", std::string("melanin")}, {"color", 0.5}}),
        "color");
    EXPECT_EQ(param_of(ph.c_str(), ParamSet{{"parametrization", std::string("absorption")},
                                            {"random_color", 0.5}}),
              "random_color");
    EXPECT_EQ(param_of("hair", ParamSet{{"roughness_u", 1.5}}), "roughness_u");
    EXPECT_EQ(param_of("hair", ParamSet{{"roughness_v", -1.0}}), "roughness_v");
    EXPECT_EQ(param_of("hair", ParamSet{{"offset", -2.0}}), "offset");
    EXPECT_EQ(param_of("hair", ParamSet{{"color", 1.1}}), "color");
    EXPECT_EQ(param_of("hair", ParamSet{{"component", std::string("both")}}), "component");
}

}  // namespace
}  // namespace facet
