// Reflectances (Cohen & Wallace table 2.2) against closed forms, and the quadrature's own
// error estimate against a higher-order reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "facet/reflectance.h"
#include "facet/registry.h"
#include "reference_double.h"
#include "reflectance_reference.h"

namespace facet {
namespace {

Material model(const std::string& name,
               std::initializer_list<std::pair<std::string, ParamValue>> list) {
    return make_material(name, ParamSet(list));
}

// Lambert: rho(wi -> 2pi) = rho exactly; the cosine map integrates it with zero error up to
// float round-off of the map (1e-6).
TEST(Reflectance, LambertDirectionalHemisphericalIsRho) {
    Material m = model("lambert", {{"reflectance", Rgb(0.2f, 0.5f, 0.9f)}});
    for (float t : {0.f, 0.5f, 1.2f, 1.55f}) {
        Reflectance r = directional_hemispherical(m, spherical_direction(t, 0.3f));
        EXPECT_NEAR(r.value.r, 0.2f, 1e-5f);
        EXPECT_NEAR(r.value.g, 0.5f, 1e-5f);
        EXPECT_NEAR(r.value.b, 0.9f, 1e-5f);
    }
    EXPECT_NEAR(bihemispherical(m, 8).value.g, 0.5f, 1e-5f);
}

// White mirror reflects everything; a dielectric mirror reflects exactly F(theta).
TEST(Reflectance, MirrorIsItsFresnelTerm) {
    EXPECT_NEAR(
        directional_hemispherical(model("mirror", {}), spherical_direction(0.7f, 0.f)).value.g, 1.f,
        1e-6f);
    Material glass = model("mirror", {{"fresnel", std::string("dielectric")}, {"ior", 1.5}});
    for (float t : {0.f, 0.8f, 1.4f}) {
        float expected = fresnel_dielectric(std::cos(t), 1.5f);
        EXPECT_NEAR(directional_hemispherical(glass, spherical_direction(t, 0.f)).value.r, expected,
                    1e-6f);
    }
}

// Biconical Lambert over a cone of half-angle d around the normal, from any incident cone:
// rho/pi * int_cone cos dw = rho sin^2(d). Smooth integrand: 1e-5.
TEST(Reflectance, LambertBiconicalClosedForm) {
    Material m = model("lambert", {{"reflectance", 0.6}});
    float d = 0.4f;
    Reflectance r = biconical(m, {spherical_direction(0.5f, 1.f), 0.2f}, {Vec3(0, 0, 1), d}, 16);
    EXPECT_NEAR(r.value.r, 0.6f * sqr(std::sin(d)), 1e-5f);
}

// Reciprocity of the integrals: rho(wi -> 2pi) at theta equals rho(2pi -> wo) at the same
// theta (eq. 2.24 integrated), and the error estimate bounds the true error, measured against
// an order-128 reference (Q(256)). Tolerance: the estimate itself, + 1e-6 for float round-off
// in the integrand.
TEST(Reflectance, GlossyIntegralsAgreeAndErrorEstimateHolds) {
    for (const char* name : {"ggx", "beckmann", "blinn"}) {
        Material m = std::string(name) == "blinn"
                         ? model(name, {{"exponent", 20.0}, {"fresnel", std::string("dielectric")}})
                         : model(name, {{"alpha", 0.35}, {"fresnel", std::string("dielectric")}});
        for (float t : {0.1f, 0.9f, 1.4f, 1.52f}) {
            Vec3 w = spherical_direction(t, 0.f);
            Reflectance ref = directional_hemispherical(m, w, 128);
            for (int order : {8, 16, 32}) {
                Reflectance a = directional_hemispherical(m, w, order);
                Reflectance b = hemispherical_directional(m, w, order);
                EXPECT_NEAR(a.value.g, b.value.g, a.error.g + b.error.g + 1e-6f) << name << t;
                EXPECT_LE(std::fabs(a.value.g - ref.value.g), a.error.g + 1e-6f)
                    << name << " theta " << t << " order " << order;
            }
        }
    }
}

// Energy conservation of the composite (Material header): with rho_d = 1 the diffuse lobe takes
// exactly what the specular lobes leave, so a white composite reflects everything at every
// angle. Tolerance 2e-3: the Es table is piecewise linear in mu (64 nodes) and its entries carry
// the order-16 quadrature error.
TEST(Reflectance, WhiteCompositeIsAWhiteFurnace) {
    for (const char* dist : {"ggx", "beckmann"}) {
        Material m = model("composite", {{"diffuse_reflectance", 1.0},
                                         {"distribution", std::string(dist)},
                                         {"alpha", 0.3},
                                         {"mirror_reflectance", 0.3},
                                         {"glossy_reflectance", 0.7}});
        for (float t : {0.f, 0.6f, 1.2f, 1.5f}) {
            Reflectance r = hemispherical_directional(m, spherical_direction(t, 0.f), 24);
            EXPECT_NEAR(r.value.g, 1.f, 2e-3f) << dist << " theta " << t;
        }
    }
}

// A grey composite reflects Es + rho_d (1 - Es) <= 1 (header formula), checked through the
// independent quadrature of the full f.
TEST(Reflectance, CompositeAlbedoMatchesItsConstruction) {
    Material m = model("composite", {{"diffuse_reflectance", 0.4}, {"alpha", 0.2}});
    for (float t : {0.2f, 1.0f, 1.45f}) {
        Vec3 w = spherical_direction(t, 0.f);
        float es = m.specular_albedo(w.z).g;
        float expected = es + 0.4f * (1.f - es);
        EXPECT_NEAR(hemispherical_directional(m, w, 24).value.g, expected, 2e-3f) << t;
    }
}

// Debug / ASan builds run with FACET_STRESS_SCALE = 0.1: fewer incidence angles there.
bool reduced_run() {
    const char* s = std::getenv("FACET_STRESS_SCALE");
    return s && std::atof(s) < 1.0;
}

std::vector<double> test_angles() {
    if (reduced_run()) return {0.0, 70.0, 89.9};
    return {0.0, 30.0, 70.0, 85.0, 89.0, 89.9};
}

// Float floor: the core BxDFs evaluate in float, so the integral of the core's f differs from the
// exact integral of the model by a float round-off bias, measured here up to 1.6e-7 (Beckmann
// alpha = 0.05 at normal incidence: 0.99999984 for an exact 1). The quadrature's error estimate
// covers the quadrature only; comparisons against exact references allow this floor on top.
constexpr double kFloatFloor = 3e-7;

struct Tally {
    int cases = 0, within_10x = 0;
    void add(double true_error, double estimate) {
        ++cases;
        // "At most 10x above": counted where the true error is above the float floor (below it
        // the true error is round-off, which no quadrature estimate can track).
        if (estimate <= 10.0 * std::max(true_error, kFloatFloor)) ++within_10x;
    }
};

// The adaptive default against an independent double-precision reference: the oracle f of
// reference_double.h integrated by nested adaptive Gauss-Kronrod through the half vector in
// spherical coordinates (reflectance_reference.h), over GGX and Beckmann, isotropic and
// anisotropic, Fresnel none / dielectric / conductor, incidence up to 89.9 degrees. Checks:
// |value - ref| <= 1e-6 + floor (the accuracy promised), |value - ref| <= estimate + floor
// (never below), and estimate <= 10 max(|value - ref|, floor) in at least 80% of the cases (a
// tight estimate can exceed 10x the true error when the error happens to cross zero: the
// count is printed).
TEST(Reflectance, AdaptiveDefaultAgainstDoubleReference) {
    struct Case {
        const char* label;
        ref::Dist dist;
        double ax, ay;
        int fresnel;  // 0 none, 1 dielectric 1.5, 2 conductor (aluminium)
    };
    const std::vector<Case> cases = {
        {"ggx 0.2", ref::Dist::GGX, 0.2, 0.2, 0},
        {"ggx 0.3 dielectric", ref::Dist::GGX, 0.3, 0.3, 1},
        {"ggx 1", ref::Dist::GGX, 1.0, 1.0, 0},
        {"ggx 0.05/0.5", ref::Dist::GGX, 0.05, 0.5, 0},
        {"beckmann 0.05", ref::Dist::Beckmann, 0.05, 0.05, 0},
        {"beckmann 0.8 conductor", ref::Dist::Beckmann, 0.8, 0.8, 2},
    };
    Tally tally;
    for (const Case& c : cases) {
        ParamSet p;
        if (c.ax == c.ay) {
            p.set("alpha", c.ax);
        } else {
            p.set("alpha_u", c.ax);
            p.set("alpha_v", c.ay);
        }
        ref::FresnelSpec fr;
        if (c.fresnel == 1) {
            p.set("fresnel", std::string("dielectric"));
            fr.kind = ref::FresnelSpec::Kind::Dielectric;
            fr.eta = DVec3(1.5);
        } else if (c.fresnel == 2) {
            p.set("fresnel", std::string("conductor"));
            fr.kind = ref::FresnelSpec::Kind::Conductor;
            fr.eta = DVec3(1.657, 0.880, 0.521);
            fr.k = DVec3(9.224, 6.270, 4.837);
        }
        Material m = make_material(c.dist == ref::Dist::GGX ? "ggx" : "beckmann", p);
        ref::Distribution d{c.dist, c.ax, c.ay};
        for (double deg : test_angles()) {
            const Vec3 wi = spherical_direction(float(deg * kPiD / 180.0), 0.3f);
            const DVec3 v(wi);
            const double reference = ref::directional_albedo(
                [&](const DVec3& w) { return ref::microfacet_f(d, fr, DVec3(1.0), w, v).g * w.z; },
                v, std::min(c.ax, c.ay), 1e-10, 10);
            const Reflectance r = directional_hemispherical(m, wi);
            const double e = std::fabs(r.value.g - reference);
            EXPECT_LE(e, 1e-6 + kFloatFloor) << c.label << " theta " << deg;
            EXPECT_LE(e, r.error.g + kFloatFloor) << c.label << " theta " << deg;
            EXPECT_LE(r.error.g, 1e-6) << c.label << " theta " << deg;
            tally.add(e, r.error.g);
        }
    }
    std::printf("estimate within 10x of the true error in %d of %d cases\n", tally.within_10x,
                tally.cases);
    EXPECT_GE(tally.within_10x, int(0.8 * tally.cases));
}

// The estimate's tightness where the true error is far above the float floor: the refinement is
// stopped after the initial cells (max_evaluations = 1), so the error is the initial partition's
// (1e-6 .. 1e-2), and the estimate must bound it (never below) and be at most 10x above it.
// Measured: 4.3-7.4x in all but one case (GGX alpha = 0.05 at 89.9 degrees: 12x, where the
// cells' Gauss - Kronrod differences partly cancel and sqrt(sum d^2) dominates); at least 90% of
// the cases within 10x is required. Checked to fail for an estimator 3x more pessimistic (0 of
// 23 within 10x); one without the factor 3 passes here (1.4-2.5x) but fails
// AdaptiveDefaultAgainstDoubleReference and AdaptiveDefaultOverTheOtherModels (estimate below the
// error). Cases whose capped error is below 10 kFloatFloor are skipped (their error is
// round-off, not quadrature).
TEST(Reflectance, EstimateBoundsAndTracksALargeError) {
    struct Case {
        ref::Dist dist;
        double alpha;
    };
    const std::vector<Case> cases = {{ref::Dist::GGX, 0.05},      {ref::Dist::GGX, 0.2},
                                     {ref::Dist::GGX, 0.3},       {ref::Dist::GGX, 1.0},
                                     {ref::Dist::Beckmann, 0.05}, {ref::Dist::Beckmann, 0.8}};
    QuadratureSettings capped;
    capped.max_evaluations = 1;
    int counted = 0, within_10x = 0;
    for (const Case& c : cases) {
        ParamSet p;
        p.set("alpha", c.alpha);
        Material m = make_material(c.dist == ref::Dist::GGX ? "ggx" : "beckmann", p);
        ref::Distribution d{c.dist, c.alpha, c.alpha};
        for (double deg : test_angles()) {
            const Vec3 wi = spherical_direction(float(deg * kPiD / 180.0), 0.3f);
            const DVec3 v(wi);
            const double reference = ref::directional_albedo(
                [&](const DVec3& w) { return ref::microfacet_f(d, {}, DVec3(1.0), w, v).g * w.z; },
                v, c.alpha, 1e-10, 10);
            const Reflectance r = directional_hemispherical(m, wi, capped);
            const double e = std::fabs(r.value.g - reference);
            if (e < 10.0 * kFloatFloor) continue;
            ++counted;
            EXPECT_LE(e, r.error.g) << c.alpha << " theta " << deg;
            if (r.error.g <= 10.0 * e) ++within_10x;
        }
    }
    std::printf("capped: estimate within [1, 10]x of the true error in %d of %d cases\n",
                within_10x, counted);
    EXPECT_GE(counted, reduced_run() ? 3 : 10);
    EXPECT_GE(within_10x, int(0.9 * counted));
}

// Sharp GGX lobes at grazing incidence, the hardest case: within 1e-6 of the double reference
// and the estimate never below the error (no float floor allowed: the rounding correction of the
// nodes' directions removes the float noise that would put it there; without the correction
// alpha = 1e-3 at 85 degrees, phi = 0 reads 2.3e-6 off with an estimate of 1.0e-6, and this
// test fails).
// Up to 88 degrees: beyond, the model's albedo of a sharp lobe depends on the float rounding of
// the incident direction itself (see the header comment), so no reference is exact.
TEST(Reflectance, SharpLobesAtGrazingIncidence) {
    struct Case {
        double alpha, deg;
        float phi;
    };
    std::vector<Case> cases = {{1e-3, 85.0, 0.f},
                               {1e-3, 85.0, 0.3f},
                               {2e-3, 88.0, 0.f},
                               {5e-3, 80.0, 0.3f},
                               {1e-2, 88.0, 0.3f}};
    if (reduced_run()) cases.resize(2);
    for (const Case& c : cases) {
        ParamSet p;
        p.set("alpha", c.alpha);
        Material m = make_material("ggx", p);
        const Vec3 wi = spherical_direction(float(c.deg * kPiD / 180.0), c.phi);
        const DVec3 v(wi);
        ref::Distribution d{ref::Dist::GGX, c.alpha, c.alpha};
        const double reference = ref::directional_albedo(
            [&](const DVec3& w) { return ref::microfacet_f(d, {}, DVec3(1.0), w, v).g * w.z; }, v,
            c.alpha, 1e-10, 10);
        const Reflectance r = directional_hemispherical(m, wi);
        const double e = std::fabs(r.value.g - reference);
        EXPECT_LE(e, 1e-6) << c.alpha << " theta " << c.deg << " phi " << c.phi;
        EXPECT_LE(e, r.error.g) << c.alpha << " theta " << c.deg << " phi " << c.phi;
        EXPECT_LE(r.error.g, 1e-6);
        EXPECT_LT(r.evaluations, 50'000);  // it took 210,600 with the float noise
    }
}

// Mirror symmetry: the glossy term is integrated over half of the azimuths (each cell counted
// twice) when the integrand is symmetric about the plane of incidence: isotropic lobes (the
// tests above, at phi = 0.3), and an anisotropic lobe whose incidence lies in one of its
// symmetry planes (wi.y = 0 or wi.x = 0 exactly). There the answer must still meet the double
// reference, and it must cost clearly fewer evaluations than the same lobe 1e-3 rad off the
// plane (full domain; measured ~0.5x). Fails if the fold is dropped for the anisotropic
// symmetric case (evaluations) or applied about the wrong axis (value).
TEST(Reflectance, AnisotropicLobeInItsSymmetryPlanesIsFolded) {
    ref::Distribution d{ref::Dist::GGX, 0.05, 0.5};
    ParamSet p;
    p.set("alpha_u", 0.05);
    p.set("alpha_v", 0.5);
    Material m = make_material("ggx", p);
    for (double deg : {60.0, 89.0}) {
        const float t = float(deg * kPiD / 180.0);
        for (bool along_x : {true, false}) {
            // In the xz plane (y = 0) or the yz plane (x = 0), exactly.
            const Vec3 wi =
                along_x ? Vec3(std::sin(t), 0.f, std::cos(t)) : Vec3(0.f, std::sin(t), std::cos(t));
            const float off = along_x ? 1e-3f : kPiOver2 - 1e-3f;
            const Vec3 wi_off = spherical_direction(t, off);
            const DVec3 v(wi);
            const double reference = ref::directional_albedo(
                [&](const DVec3& w) { return ref::microfacet_f(d, {}, DVec3(1.0), w, v).g * w.z; },
                v, 0.05, 1e-10, 10);
            const Reflectance r = directional_hemispherical(m, wi);
            const Reflectance r_off = directional_hemispherical(m, wi_off);
            const double e = std::fabs(r.value.g - reference);
            EXPECT_LE(e, 1e-6 + kFloatFloor) << deg << (along_x ? " xz" : " yz");
            EXPECT_LE(e, r.error.g + kFloatFloor) << deg << (along_x ? " xz" : " yz");
            EXPECT_LT(3 * r.evaluations, 2 * r_off.evaluations) << deg << (along_x ? " xz" : " yz");
        }
    }
}

// The limit stated in reflectance.h: beyond ~88 degrees a sharp lobe's albedo depends on the
// float rounding of the incident direction itself. The double reference (no quadrature of
// ours) for GGX alpha = 0.01 at 89.5 degrees and the same direction with one ulp less in x
// (|wi| - 1: -1.0e-8, -7.0e-8) differ by ~1.2e-4, far above the tolerance: no estimate of the
// quadrature can cover that, and docs/cli.md ("Limits") says so.
TEST(Reflectance, SharpLobeAlbedoAtGrazingDependsOnTheInputRounding) {
    if (reduced_run()) GTEST_SKIP() << "slow reference";
    ref::Distribution d{ref::Dist::GGX, 0.01, 0.01};
    const Vec3 wi = spherical_direction(float(89.5 * kPiD / 180.0), 0.f);
    Vec3 nudged = wi;
    nudged.x = std::nextafter(nudged.x, 0.f);
    auto reference = [&](const Vec3& w_in) {
        const DVec3 v(w_in);
        return ref::directional_albedo(
            [&](const DVec3& w) { return ref::microfacet_f(d, {}, DVec3(1.0), w, v).g * w.z; }, v,
            0.01, 1e-10, 10);
    };
    EXPECT_GT(std::fabs(reference(wi) - reference(nudged)), 1e-5);
}

// The models without an independent double oracle for their integrals (Blinn, whose oracle
// Lambda is itself a quadrature; the compensation and composite lobes, which read tables):
// against the adaptive quadrature at tolerance 1e-8 (its estimate checked against the oracle
// above) and against the fixed order-256 path (an independent map: the lobe's own sampler)
// where that one's own estimate is small. Same checks as above.
TEST(Reflectance, AdaptiveDefaultOverTheOtherModels) {
    struct Case {
        const char* label;
        const char* model;
        ParamSet params;
    };
    auto p = [](std::initializer_list<std::pair<std::string, ParamValue>> l) {
        return ParamSet(l);
    };
    const std::vector<Case> cases = {
        {"blinn 50", "blinn", p({})},
        {"blinn 1e4 dielectric", "blinn",
         p({{"exponent", 1e4}, {"fresnel", std::string("dielectric")}})},
        {"blinn 10/1000", "blinn", p({{"exponent_u", 10.0}, {"exponent_v", 1000.0}})},
        {"ggx 0.5 compensated", "ggx", p({{"alpha", 0.5}, {"energy_compensation", true}})},
        {"composite", "composite", p({})},
        {"composite beckmann mirror", "composite",
         p({{"distribution", std::string("beckmann")},
            {"alpha", 0.3},
            {"glossy_reflectance", 0.6},
            {"mirror_reflectance", 0.3}})},
        {"lambert", "lambert", p({})},
    };
    QuadratureSettings tight;
    tight.tolerance = 1e-8;
    tight.max_evaluations = 2'000'000;
    Tally tally;
    for (const Case& c : cases) {
        Material m = make_material(c.model, c.params);
        for (double deg : test_angles()) {
            const Vec3 wi = spherical_direction(float(deg * kPiD / 180.0), 0.3f);
            const Reflectance t = directional_hemispherical(m, wi, tight);
            const Reflectance r = directional_hemispherical(m, wi);
            const double e = std::fabs(r.value.g - t.value.g);
            const double floor = kFloatFloor + t.error.g;
            EXPECT_LE(e, 1e-6 + floor) << c.label << " theta " << deg;
            EXPECT_LE(e, r.error.g + floor) << c.label << " theta " << deg;
            tally.add(e, r.error.g);
            if (reduced_run()) continue;  // the order-256 rule costs 344k evaluations
            const Reflectance q = directional_hemispherical(m, wi, 256);
            if (q.error.g < 1e-6) {
                EXPECT_LE(std::fabs(r.value.g - q.value.g), r.error.g + q.error.g + kFloatFloor)
                    << c.label << " theta " << deg << " (order 256)";
            }
        }
    }
    std::printf("estimate within 10x of the true error in %d of %d cases\n", tally.within_10x,
                tally.cases);
    EXPECT_GE(tally.within_10x, int(0.8 * tally.cases));
}

// Reciprocity: rho(wi -> 2pi) = rho(2pi -> wo) at the same direction (eq. 2.24 integrated),
// through the adaptive path, within the two estimates + the float floor.
TEST(Reflectance, AdaptiveIntegralsAreReciprocal) {
    for (const char* name : {"ggx", "beckmann", "blinn", "composite"}) {
        Material m = make_material(name, ParamSet{});
        for (double deg : {10.0, 60.0, 88.0}) {
            const Vec3 w = spherical_direction(float(deg * kPiD / 180.0), 1.1f);
            const Reflectance a = directional_hemispherical(m, w);
            const Reflectance b = hemispherical_directional(m, w);
            EXPECT_NEAR(a.value.g, b.value.g, a.error.g + b.error.g + kFloatFloor)
                << name << " theta " << deg;
        }
    }
}

// The bihemispherical default: Lambert exactly rho, a white composite (rho_d = 1) a furnace
// up to its Es table (2e-3, as for the directional case), and GGX against the fixed path at
// order 32 for its outer and inner rules (an independent map), within both estimates.
TEST(Reflectance, AdaptiveBihemispherical) {
    Material lambert = make_material("lambert", ParamSet{});
    Reflectance l = bihemispherical(lambert);
    EXPECT_NEAR(l.value.g, 0.5, 1e-6 + kFloatFloor);
    EXPECT_LE(l.error.g, 1e-6);
    ParamSet p;
    p.set("alpha", 0.4);
    Material ggx = make_material("ggx", p);
    Reflectance a = bihemispherical(ggx);
    Reflectance f = bihemispherical(ggx, 32);
    EXPECT_LE(a.error.g, 1e-6);
    EXPECT_NEAR(a.value.g, f.value.g, a.error.g + f.error.g + kFloatFloor);
}

// The default meets 1e-6 at the case (GGX alpha = 0.2, 70 degrees).
TEST(Reflectance, GgxAt70DegreesTo1e6) {
    Material m = make_material("ggx", ParamSet{});
    const Vec3 wi = spherical_direction(float(70.0 * kPiD / 180.0), 0.f);
    const DVec3 v(wi);
    ref::Distribution d{ref::Dist::GGX, 0.2, 0.2};
    const double reference = ref::directional_albedo(
        [&](const DVec3& w) { return ref::microfacet_f(d, {}, DVec3(1.0), w, v).g * w.z; }, v, 0.2,
        1e-10, 10);
    const Reflectance r = directional_hemispherical(m, wi);
    EXPECT_LE(std::fabs(r.value.g - reference), 1e-6);
    EXPECT_LE(std::fabs(r.value.g - reference), r.error.g + kFloatFloor);
    EXPECT_THROW(directional_hemispherical(m, wi, QuadratureSettings{0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace facet
