// Reflectances (Cohen & Wallace table 2.2) against closed forms, and the quadrature's own
// error estimate against a higher-order reference.
#include <gtest/gtest.h>

#include "facet/reflectance.h"
#include "facet/registry.h"

namespace facet {
namespace {

Material model(const std::string& name,
               std::initializer_list<std::pair<std::string, ParamValue>> list) {
    ParamSet p;
    for (const auto& [k, v] : list) p.set(k, v);
    return make_material(name, p);
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

}  // namespace
}  // namespace facet
