// Energy: the directional-hemispherical reflectance rho(wo -> 2 pi) = int f cos(theta_i) dwi
// (Cohen & Wallace table 2.2) is <= 1 for every model and parameter corner, = 1 for a white
// mirror and a white Lambertian, and ~1 for a white rough lobe with energy compensation.
//
// Method: deterministic quadrature, independent of the model's own sampler. With a defensive
// mixture proposal q = (p_cos + p_ref) / 2, where p_cos is the cosine density and p_ref the
// density of a *reference* lobe with the same distribution (F = 1, no compensation; it resolves
// sharp lobes), rho = 1/2 int_u w(x_cos(u)) du + 1/2 int_u w(x_ref(u)) du with
// w = f cos / q, and each u-integral is an n x n Gauss-Legendre product rule over [0,1)^2. The
// weight w is bounded (<= 2 f cos / p_ref ~ 2 F G / G1) but discontinuous in u where samples
// leave the hemisphere. The difference between the n = 32 and n = 64 results is the stated
// error estimate. Where it is < 2e-3 we require rho_64 <= 1 + 2e-3; where the rule has not
// converged (sharp lobes at grazing incidence), we fall back to Monte Carlo with the model's
// own sampler (5e4 samples) and require mean - 5 standard errors <= 1 + 2e-3.
// Lobes with Kulla-Conty compensation get 5e-3 instead of 2e-3: their extra lobe is built from
// a 64-node table of E (over mu, or over the stretched direction when anisotropic) with linear
// interpolation, which over-compensates by up to ~3e-3 (measured: max rho 1.0032, GGX
// 1e-3 x 10 at 89.9 degrees).
// Delta lobes add their reflected fraction f cos of the specular sample (found by scanning uc).
#include <gtest/gtest.h>

#include <cstdio>

#include "chi2.h"
#include "facet/quadrature.h"
#include "model_corners.h"

namespace facet {
namespace {

constexpr double kEnergyTol = 2e-3;

Vec3 wo_at(double theta_deg, double phi_deg) {
    double t = theta_deg * kPiD / 180.0, p = phi_deg * kPiD / 180.0;
    return Vec3(
        glm::normalize(DVec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t))));
}

struct Albedo {
    DVec3 value{0.0};
    double error_estimate = 0.0;  // max over channels of |rho_n - rho_2n|
};

// rho(wo) per channel by the mixture quadrature with an n x n Gauss-Legendre rule per
// proposal.
template <class B>
DVec3 albedo_quadrature(const B& b, const std::optional<MicrofacetReflection>& ref, const Vec3& wo,
                        int n) {
    const QuadratureRule& q = gauss_legendre(n);
    DVec3 sum(0.0);
    auto add = [&](const Vec3& wi, double weight) {
        if (!(wi.z > 0.f)) return;
        double pc = cosine_hemisphere_pdf(wi.z);
        double p = ref ? 0.5 * pc + 0.5 * double(ref->pdf(wo, wi)) : pc;
        if (!(p > 0.0)) return;
        sum += weight * DVec3(b.f(wo, wi)) * double(wi.z) / p;
    };
    const double mix = ref ? 0.5 : 1.0;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            Vec2 u(float(q.nodes[i]), float(q.nodes[j]));
            double w = q.weights[i] * q.weights[j] * mix;
            add(sample_cosine_hemisphere(u), w);
            if (ref) {
                auto s = ref->sample_f(wo, 0.5f, u);
                if (s && !s->is_specular()) add(s->wi, w);
            }
        }
    }
    return sum;
}

// Monte Carlo fallback with the model's own sampler: mean and standard error of f cos / pdf.
template <class B>
std::pair<DVec3, DVec3> albedo_mc(const B& b, const Vec3& wo, int n) {
    pcg32 rng(99);
    DVec3 s1(0.0), s2(0.0);
    for (int i = 0; i < n; ++i) {
        float uc = test::uniform_float(rng);
        Vec2 u(test::uniform_float(rng), test::uniform_float(rng));
        auto s = b.sample_f(wo, uc, u);
        if (!s) continue;
        DVec3 w = DVec3(s->f) * double(std::fabs(s->wi.z)) / double(s->pdf);
        s1 += w;
        s2 += w * w;
    }
    DVec3 mean = s1 / double(n);
    DVec3 se = glm::sqrt(glm::max(DVec3(0.0), s2 / double(n) - mean * mean) / double(n));
    return {mean, se};
}

// The reflected fraction of the delta lobes: the mean over uc of f cos / pdf of the specular
// samples (pdf = the discrete probability of the delta lobe that was chosen), so that several
// delta lobes (a mirror plus a glossy lobe below the smoothness threshold) all count. uc is on
// a 10^4-point midpoint grid: lobe selection is piecewise constant in uc, so the error is at
// most (number of lobes) x 1e-4 of a lobe's weight. 0 when the model has no delta lobe.
template <class B>
DVec3 delta_fraction(const B& b, const Vec3& wo) {
    const int k_max = 10000;
    DVec3 sum(0.0);
    for (int k = 0; k < k_max; ++k) {
        auto s = b.sample_f(wo, (k + 0.5f) / float(k_max), Vec2(0.5f));
        if (s && s->is_specular()) sum += DVec3(s->f) * double(s->wi.z) / double(s->pdf);
    }
    return sum / double(k_max);
}

template <class B>
Albedo albedo(const B& b, const std::optional<MicrofacetReflection>& ref, const Vec3& wo) {
    DVec3 a = albedo_quadrature(b, ref, wo, 32), c = albedo_quadrature(b, ref, wo, 64);
    DVec3 d = delta_fraction(b, wo);
    Albedo r;
    r.value = c + d;
    for (int k = 0; k < 3; ++k)
        r.error_estimate = std::fmax(r.error_estimate, std::fabs(a[k] - c[k]));
    return r;
}

// The reference lobe for a distribution: same D, F = 1, no compensation; none when smooth.
std::optional<MicrofacetReflection> reference_lobe(const MicrofacetDistribution& d) {
    if (d.effectively_smooth()) return std::nullopt;
    return MicrofacetReflection(d, Fresnel::none(), Rgb(1.f), false);
}

const double kThetas[] = {0.0, 30.0, 60.0, 80.0, 89.0, 89.9};

struct Worst {
    double rho = 0.0, err = 0.0;
    std::string rho_where, err_where;
};

void record(Worst& w, const Albedo& a, const std::string& where) {
    double m = std::fmax(a.value.x, std::fmax(a.value.y, a.value.z));
    if (m > w.rho) w.rho = m, w.rho_where = where;
    if (a.error_estimate > w.err) w.err = a.error_estimate, w.err_where = where;
}

TEST(Energy, WhiteLambertAndWhiteMirrorReflectExactlyOne) {
    LambertReflection lambert(Rgb(1.f));
    MirrorReflection mirror(Fresnel::none(), Rgb(1.f));
    Material lm = make_material("lambert", [] {
        ParamSet p;
        p.set("reflectance", 1.0);
        return p;
    }());
    Material mm = make_material("mirror", ParamSet{});
    for (double th : kThetas) {
        Vec3 wo = wo_at(th, 40.0);
        // Lambert: w = (1/pi) cos / (cos/pi) = 1 at every node; the rule's weights sum to 1
        // in double: 1e-6 covers the float f and pdf round-off.
        Albedo a = albedo(lambert, std::nullopt, wo), b = albedo(lm, std::nullopt, wo);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(a.value[c], 1.0, 1e-6) << "theta " << th;
            EXPECT_NEAR(b.value[c], 1.0, 1e-6) << "theta " << th;
        }
        // Mirror: F = 1, so f cos = 1 up to the division and multiplication by cos (2 ulps).
        DVec3 m1 = delta_fraction(mirror, wo), m2 = delta_fraction(mm, wo);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(m1[c], 1.0, 4e-7) << "theta " << th;
            EXPECT_NEAR(m2[c], 1.0, 4e-7) << "theta " << th;
        }
    }
}

// Checks rho <= 1 + tol by quadrature, or by MC where the quadrature has not converged.
template <class B>
void check_energy(const B& b, const std::optional<MicrofacetReflection>& ref, const Vec3& wo,
                  double tol, const std::string& where, Worst& worst, int& mc_fallbacks) {
    Albedo a = albedo(b, ref, wo);
    if (a.error_estimate < kEnergyTol) {
        record(worst, a, where);
        for (int c = 0; c < 3; ++c) EXPECT_LE(a.value[c], 1.0 + tol) << where;
        return;
    }
    ++mc_fallbacks;
    auto [mean, se] = albedo_mc(b, wo, 50000);
    DVec3 d = delta_fraction(b, wo);
    (void)d;  // the MC estimator includes the delta lobes already
    for (int c = 0; c < 3; ++c)
        EXPECT_LE(mean[c] - 5.0 * se[c], 1.0 + tol)
            << where << " (MC fallback, quadrature error estimate " << a.error_estimate << ")";
}

// Every distribution x roughness corner (including anisotropy ratios 1e4) with F = 1 (the most
// energetic Fresnel term) and with a gold conductor, with and without compensation, at
// phi_o = 30 deg. Compensated lobes must stay within 5e-3 of the bound: the compensation is
// exact only up to the E table's interpolation error (measured <= 3.4e-3, see the furnace test
// below); uncompensated ones within the quadrature tolerance.
TEST(Energy, EveryLobeCornerReflectsAtMostOne) {
    Worst worst;
    int checked = 0, mc = 0;
    for (const auto& spec : test::lobe_corners(false)) {
        const std::string& fn = spec.fresnel.name;
        if (fn != "none" && fn != "conductor_gold") continue;
        MicrofacetReflection lobe = spec.lobe();
        auto ref = reference_lobe(lobe.distribution());
        double tol = spec.energy_compensation ? 5e-3 : kEnergyTol;
        for (double th : kThetas) {
            check_energy(lobe, ref, wo_at(th, 30.0), tol,
                         spec.name() + " theta " + std::to_string(th), worst, mc);
            ++checked;
        }
    }
    std::printf(
        "  %d (lobe, angle) pairs, %d by MC fallback: max rho %.6f at %s; max error "
        "estimate %.2e at %s\n",
        checked, mc, worst.rho, worst.rho_where.c_str(), worst.err, worst.err_where.c_str());
}

// Anisotropic compensated white lobes are white furnaces in every direction, including the
// grazing azimuths where E(wo) has ridges as narrow as the anisotropy: |rho - 1| < 5e-3
// (the E table's interpolation error, measured <= 3.4e-3 with 64 x 9 nodes; a table over
// (mu_o, phi_o) instead of the stretched direction missed by 0.12 here, a 32-node one by 0.013).
TEST(Energy, CompensatedAnisotropicLobesAreWhiteFurnacesAtGrazingAzimuths) {
    struct Case {
        bool beckmann;
        float ax, ay;
    };
    const Case cases[] = {{false, 0.1f, 1.f},   {false, 0.01f, 1.f}, {false, 1e-4f, 1.f},
                          {false, 0.3f, 0.05f}, {true, 0.01f, 1.f},  {true, 1e-3f, 10.f}};
    double worst = 0.0;
    std::string where_worst;
    for (const Case& c : cases) {
        MicrofacetDistribution d = c.beckmann ? MicrofacetDistribution::beckmann(c.ax, c.ay)
                                              : MicrofacetDistribution::ggx(c.ax, c.ay);
        MicrofacetReflection lobe(d, Fresnel::none(), Rgb(1.f), true);
        for (double th : {0.0, 60.0, 80.0, 89.0, 89.9}) {
            for (double ph : {0.0, 0.5, 2.0, 5.0, 15.0, 45.0, 90.0}) {
                std::string where = std::string(c.beckmann ? "beckmann(" : "ggx(") +
                                    std::to_string(c.ax) + "," + std::to_string(c.ay) + ") theta " +
                                    std::to_string(th) + " phi " + std::to_string(ph);
                Albedo a = albedo(lobe, reference_lobe(d), wo_at(th, ph));
                double rho = a.value.x, slack = 0.0;
                if (a.error_estimate >= kEnergyTol) {  // quadrature unresolved: MC, 5 sigma
                    auto [mean, se] = albedo_mc(lobe, wo_at(th, ph), 200000);
                    rho = mean.x, slack = 5.0 * se.x;
                }
                double dev = std::fmax(std::fabs(rho - 1.0) - slack, 0.0);
                if (dev > worst) worst = dev, where_worst = where;
                EXPECT_LT(dev, 5e-3) << where << " rho " << rho;
            }
        }
    }
    std::printf("  anisotropic compensated furnace: worst |rho - 1| = %.2e at %s\n", worst,
                where_worst.c_str());
}

TEST(Energy, EveryRegistryMaterialReflectsAtMostOne) {
    Worst worst;
    int mc = 0;
    for (const auto& m : test::material_corners()) {
        Material mat = make_material(m.model, m.params);
        std::optional<MicrofacetReflection> ref;
        if (mat.glossy()) ref = reference_lobe(mat.glossy()->distribution());
        bool ec = mat.glossy() && mat.glossy()->energy_compensation();
        for (double th : kThetas)
            check_energy(mat, ref, wo_at(th, 30.0), ec ? 5e-3 : kEnergyTol,
                         m.name + " theta " + std::to_string(th), worst, mc);
    }
    std::printf(
        "  materials (%d by MC fallback): max rho %.6f at %s; max error estimate %.2e at "
        "%s\n",
        mc, worst.rho, worst.rho_where.c_str(), worst.err, worst.err_where.c_str());
}

// With Kulla & Conty compensation a white (F = 1) rough lobe loses (almost) no energy. The
// compensation is built from a 64-node E(mu) table with linear interpolation, so it is exact
// only up to the table's interpolation error: we require |rho - 1| < 1e-2 and print the worst.
TEST(Energy, CompensatedWhiteRoughLobeIsAWhiteFurnace) {
    double worst = 0.0;
    std::string where_worst;
    for (auto make : {+[](float a) { return MicrofacetDistribution::ggx(a, a); },
                      +[](float a) { return MicrofacetDistribution::beckmann(a, a); }}) {
        for (float alpha : {0.2f, 0.5f, 1.f}) {
            MicrofacetDistribution d = make(alpha);
            MicrofacetReflection lobe(d, Fresnel::none(), Rgb(1.f), true);
            for (double th : {0.0, 30.0, 60.0, 80.0}) {
                Albedo a = albedo(lobe, reference_lobe(d), wo_at(th, 0.0));
                double dev = std::fabs(a.value.x - 1.0);
                std::string where = "alpha " + std::to_string(alpha) + " theta " +
                                    std::to_string(th) + " kind " + std::to_string(int(d.kind()));
                if (dev > worst) worst = dev, where_worst = where;
                EXPECT_LT(dev, 1e-2) << where << " rho " << a.value.x;
            }
        }
    }
    std::printf("  compensated white furnace: worst |rho - 1| = %.2e at %s\n", worst,
                where_worst.c_str());
}

// The quadrature can fail: a lobe scaled by 1.01 (a BRDF that creates 1% energy at F = 1 and
// alpha = 1e-3, where rho is ~1) is caught by the same bound.
TEST(Energy, DetectsEnergyGain) {
    MicrofacetDistribution d = MicrofacetDistribution::ggx(1e-3f, 1e-3f);
    MicrofacetReflection lobe(d, Fresnel::none(), Rgb(1.f), false);
    struct Scaled {
        const MicrofacetReflection& b;
        Rgb f(const Vec3& wo, const Vec3& wi) const { return 1.01f * b.f(wo, wi); }
        std::optional<BSDFSample> sample_f(const Vec3&, float, Vec2) const { return {}; }
    } scaled{lobe};
    Albedo a = albedo(scaled, reference_lobe(d), wo_at(10.0, 0.0));
    EXPECT_GT(a.value.x, 1.0 + kEnergyTol);
}

// The quadrature agrees with the model's own importance sampler (mean of f cos / pdf over
// sample_f), which checks the sampling weights an integrator would use. 20000 samples; the
// bound is 5 standard errors + the quadrature tolerance.
TEST(Energy, QuadratureAgreesWithImportanceSampling) {
    for (const auto& m : test::material_corners()) {
        Material mat = make_material(m.model, m.params);
        std::optional<MicrofacetReflection> ref;
        if (mat.glossy()) ref = reference_lobe(mat.glossy()->distribution());
        for (double th : {0.0, 60.0, 85.0}) {
            Vec3 wo = wo_at(th, 30.0);
            Albedo a = albedo(mat, ref, wo);
            auto [mean, se] = albedo_mc(mat, wo, 20000);
            if (!(a.error_estimate < kEnergyTol)) continue;  // quadrature not converged
            for (int c = 0; c < 3; ++c) {
                double bound = 5.0 * se[c] + kEnergyTol;
                EXPECT_NEAR(mean[c], a.value[c], bound) << m.name << " theta " << th << " ch " << c;
            }
        }
    }
}

}  // namespace
}  // namespace facet
