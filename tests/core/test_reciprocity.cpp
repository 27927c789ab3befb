// Helmholtz reciprocity f(wo, wi) = f(wi, wo) (Cohen & Wallace eq. 2.24) for every model and
// parameter corner (tests/core/model_corners.h), on random and adversarial direction pairs.
//
// Tolerance. Every model evaluates f from symmetric ingredients: the half vector
// normalize(wo + wi) is bitwise symmetric (float addition commutes), cos_o cos_i commutes, but
// G = 1 / (1 + Lambda_o + Lambda_i) adds in a different order and F is evaluated at wo.h
// versus wi.h, which are equal in exact arithmetic but differ by float round-off (~1e-7
// absolute). Through F this moves f by (dF/dc)/F * 1e-7 relative, which stays below ~1e-6 except
// where F is tiny or steep. So we require a relative difference <= 1e-5 (about 100 float ulps)
// in general, and <= 1e-3 for the dielectric corners whose F is steep in cos: IOR 1.0001 and
// 1.0 (F ~ 1e-9 or 0 plus round-off; for nearly opposite grazing pairs wo.h ~ 0.03 comes from
// a cancelling sum and d(ln F)/d(cos) ~ 1e3) and IOR 0.7 near the critical angle of total
// internal reflection (F' is infinite there); measured worst there 2.1e-4. Values below 1e-30 / sr
// are compared absolutely (|difference| <= 1e-30): they come from intermediates near float
// underflow (1.2e-38), where relative precision is lost, and contribute nothing to any image. IOR
// exactly 1 has F = 0 exactly, so f must be ~0 both ways: there the absolute floor is 1e-20 (the
// float F round-off gives f ~ 1e-28). The worst asymmetry seen is printed.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <variant>

#include "chi2.h"
#include "model_corners.h"

namespace facet {
namespace {

constexpr double kRelTol = 1e-5;
constexpr double kRelTolSteepFresnel = 1e-3;
constexpr double kAbsFloor = 1e-30;

// Direction pairs: uniform random, grazing (cos down to 1e-9), exactly the normal, wi = wo,
// wi = the mirror direction of wo (the lobe's peak), and nearly opposite grazing pairs.
std::vector<std::pair<Vec3, Vec3>> direction_pairs(int n_random) {
    pcg32 rng(2024);
    auto rnd = [&] {
        return sample_uniform_hemisphere(Vec2(test::uniform_float(rng), test::uniform_float(rng)));
    };
    auto grazing = [&](float c) {
        float phi = 2.f * kPi * test::uniform_float(rng);
        float s = std::sqrt(1.f - c * c);
        return Vec3(s * std::cos(phi), s * std::sin(phi), c);
    };
    std::vector<std::pair<Vec3, Vec3>> v;
    for (int i = 0; i < n_random; ++i) v.push_back({rnd(), rnd()});
    const Vec3 n(0.f, 0.f, 1.f);
    for (float c : {1e-9f, 1e-7f, 1e-5f, 1e-3f, 0.05f}) {
        for (int i = 0; i < 8; ++i) {
            Vec3 g = grazing(c), r = rnd();
            v.push_back({g, r});
            v.push_back({g, grazing(c)});
            v.push_back({g, Vec3(-g.x, -g.y, g.z)});
            v.push_back({g, n});
        }
    }
    for (int i = 0; i < 16; ++i) {
        Vec3 a = rnd();
        v.push_back({a, a});
        v.push_back({a, Vec3(-a.x, -a.y, a.z)});
        v.push_back({n, a});
    }
    v.push_back({n, n});
    return v;
}

struct Worst {
    double rel = 0.0;
    std::string where;
    void update(double r, const std::string& name, const Vec3& a, const Vec3& b) {
        if (r > rel) {
            rel = r;
            char buf[200];
            std::snprintf(buf, sizeof buf, " wo (%.9g %.9g %.9g) wi (%.9g %.9g %.9g)", a.x, a.y,
                          a.z, b.x, b.y, b.z);
            where = name + buf;
        }
    }
};

template <class B>
int check_reciprocity(const B& b, const std::string& name,
                      const std::vector<std::pair<Vec3, Vec3>>& pairs, Worst& worst,
                      double rel_tol = kRelTol, double abs_floor = kAbsFloor) {
    int failures = 0;
    for (const auto& [wo, wi] : pairs) {
        Rgb f1 = b.f(wo, wi), f2 = b.f(wi, wo);
        for (int c = 0; c < 3; ++c) {
            double m = std::fmax(std::fabs(f1[c]), std::fabs(f2[c]));
            double diff = std::fabs(double(f1[c]) - double(f2[c]));
            if (m < abs_floor && diff <= abs_floor) continue;
            double r = m == 0.0 ? 0.0 : diff / m;
            worst.update(r, name, wo, wi);
            if (!(r <= rel_tol)) {
                if (++failures <= 5)
                    ADD_FAILURE() << name << ": f(wo,wi)[" << c << "] = " << f1[c]
                                  << " but f(wi,wo) = " << f2[c] << " (rel " << r << ") wo ("
                                  << wo.x << " " << wo.y << " " << wo.z << ") wi (" << wi.x << " "
                                  << wi.y << " " << wi.z << ")";
            }
        }
    }
    return failures;
}

TEST(Reciprocity, LambertAndMirror) {
    auto pairs = direction_pairs(2000);
    Worst worst;
    for (float rho : {0.f, 0.3f, 1.f})
        EXPECT_EQ(check_reciprocity(LambertReflection(Rgb(rho)), "lambert", pairs, worst), 0);
    // Deltas: f is identically 0 both ways.
    EXPECT_EQ(check_reciprocity(MirrorReflection(Fresnel::dielectric(1.5f), Rgb(1.f)), "mirror",
                                pairs, worst),
              0);
    EXPECT_EQ(worst.rel, 0.0);
}

TEST(Reciprocity, EveryMicrofacetCorner) {
    auto pairs = direction_pairs(400);
    Worst worst, worst_steep;
    auto corners = test::lobe_corners(false);
    for (const auto& spec : corners) {
        MicrofacetReflection lobe = spec.lobe(Rgb(0.9f, 0.6f, 0.3f));
        const std::string& fn = spec.fresnel.name;
        bool steep = fn.rfind("dielectric", 0) == 0 && fn != "dielectric1.500000";
        check_reciprocity(lobe, spec.name(), pairs, steep ? worst_steep : worst,
                          steep ? kRelTolSteepFresnel : kRelTol,
                          fn == "dielectric1.000000" ? 1e-20 : kAbsFloor);
    }
    std::printf("  %zu lobes x %zu pairs: worst relative asymmetry %.3g at %s\n", corners.size(),
                pairs.size(), worst.rel, worst.where.c_str());
    std::printf("  steep-Fresnel corners: worst %.3g at %s\n", worst_steep.rel,
                worst_steep.where.c_str());
}

TEST(Reciprocity, EveryRegistryMaterial) {
    auto pairs = direction_pairs(1000);
    Worst worst;
    for (const auto& m : test::material_corners()) {
        Material mat = make_material(m.model, m.params);
        bool steep = m.name.find("ior1") != std::string::npos;  // IOR 1.0001, see top
        check_reciprocity(mat, m.name, pairs, worst, steep ? kRelTolSteepFresnel : kRelTol);
    }
    std::printf("  materials: worst relative asymmetry %.3g at %s\n", worst.rel,
                worst.where.c_str());
}

// The check can fail: a deliberately non-reciprocal BRDF (Lambert times (1 + 0.001 cos_o)) is
// caught.
TEST(Reciprocity, DetectsNonReciprocalModel) {
    struct Skewed {
        LambertReflection base{Rgb(0.5f)};
        Rgb f(const Vec3& wo, const Vec3& wi) const {
            return base.f(wo, wi) * (1.f + 1e-3f * wo.z);
        }
    } skewed;
    auto pairs = direction_pairs(50);
    Worst worst;
    int failures = 0;
    {
        ::testing::TestPartResultArray swallowed;  // the expected failures are not reported
        ::testing::ScopedFakeTestPartResultReporter silence(
            ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &swallowed);
        failures = check_reciprocity(skewed, "skewed", pairs, worst);
    }
    EXPECT_GT(failures, 0);
    EXPECT_GT(worst.rel, kRelTol);
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// eval(wo, wi) is f and pdf in one pass: it must equal f() and pdf() exactly (same arithmetic;
// zero tolerance, NaN-free inputs), for every registry material and every microfacet corner on
// the reciprocity pairs (both orders). Bit equality also covers the grazing and degenerate pairs.
TEST(Eval, EqualsFAndPdfBitForBit) {
    auto pairs = direction_pairs(500);
    int checked = 0;
    auto check = [&](const auto& b, const std::string& name) {
        for (const auto& [a, c] : pairs) {
            for (const auto& [wo, wi] : {std::pair{a, c}, std::pair{c, a}}) {
                BSDFEval e = b.eval(wo, wi);
                Rgb f = b.f(wo, wi);
                float p = b.pdf(wo, wi);
                ASSERT_TRUE(e.f.x == f.x && e.f.y == f.y && e.f.z == f.z && e.pdf == p)
                    << name << " wo " << wo.x << "," << wo.y << "," << wo.z << " wi " << wi.x << ","
                    << wi.y << "," << wi.z << ": eval (" << e.f.x << ", " << e.pdf << ") vs ("
                    << f.x << ", " << p << ")";
                ++checked;
            }
        }
    };
    for (const auto& m : test::material_corners()) check(make_material(m.model, m.params), m.name);
    for (const auto& spec : test::lobe_corners(false)) check(spec.lobe(), spec.name());
    std::printf("  %d (model, pair) evaluations identical\n", checked);
}

// A material's sample carries its full f and pdf: for single-lobe materials (returned as the
// lobe sampled them) and composites (one-sample MIS) alike, s.f and s.pdf equal f() and pdf()
// at the sampled direction to 1e-4 relative (the lobe's sampler may reach the same values by a
// different float path, e.g. from the sampled normal instead of the recomputed half vector).
TEST(Eval, MaterialSamplesCarryFullFAndPdf) {
    pcg32 rng(7);
    double worst = 0.0;
    std::string where_worst;
    for (const auto& m : test::material_corners()) {
        Material mat = make_material(m.model, m.params);
        for (int i = 0; i < 2000; ++i) {
            Vec3 wo =
                sample_uniform_hemisphere(Vec2(test::uniform_float(rng), test::uniform_float(rng)));
            auto s = mat.sample_f(wo, test::uniform_float(rng),
                                  Vec2(test::uniform_float(rng), test::uniform_float(rng)));
            if (!s || s->is_specular()) continue;
            Rgb f = mat.f(wo, s->wi);
            float p = mat.pdf(wo, s->wi);
            auto rel = [](double x, double y) {
                return std::fabs(x - y) / std::fmax(std::fmax(std::fabs(x), std::fabs(y)), 1e-30);
            };
            double r = std::fmax(
                rel(s->pdf, p),
                std::fmax(rel(s->f.x, f.x), std::fmax(rel(s->f.y, f.y), rel(s->f.z, f.z))));
            if (r > worst) worst = r, where_worst = m.name;
            EXPECT_LT(r, 1e-4) << m.name << " sample " << i;
        }
    }
    std::printf("  material samples: worst relative difference to f()/pdf() %.2e (%s)\n", worst,
                where_worst.c_str());
}

}  // namespace
}  // namespace facet
