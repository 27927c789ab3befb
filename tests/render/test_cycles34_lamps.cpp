// Blender 3.4's Cycles lamps (lights/point.cpp, lights/directional.cpp): the point and spot
// lamp of radius r as a disc facing the lit point ("radius_model": "cycles34_disc") and the sun
// with an angle as Cycles 3.4 samples it ("angle_model": "cycles34"). Irradiance against exact
// quadratures of the models (written here from the models' definitions, not from the
// samplers), the sampling densities (E[1/pdf] = the solid angle, chi-square of the sampled
// points), and that scenes without the keys are unchanged.
//
// Monte Carlo tolerances are 4 standard errors of the estimate, computed from the samples (a
// false failure has probability ~6e-5 per check), plus 1e-6 relative for float round-off; the
// quadratures' own error is stated where they are built and is far below that.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "facet/render/light_units.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/light_test_util.h"
#include "facet/testsupport/render_test_util.h"

using namespace facet;
using namespace facet::render;

namespace {

using Mc = facet::render::testing::McResult;
using facet::render::testing::expect_mc;
using facet::render::testing::irradiance;
using facet::render::testing::scaled;

template <class F>
Mc mc(int n, F f) {
    return facet::render::testing::mc_unit_square(n, 4242, f);
}

// Midpoint rule over a disc in polar coordinates (n_r rings x n_phi sectors) of
// g(radius, phi) rho d rho d phi. The integrands below are smooth except for the kink of a
// horizon cut (max(0, cos)), where the midpoint rule is still O(h^2): with 600 x 1200 nodes
// the relative error is below 1e-5 (checked by halving: the results agree to that).
template <class G>
double disc_quadrature(double radius, G g, int n_r = 600, int n_phi = 1200) {
    double sum = 0.0;
    for (int i = 0; i < n_r; ++i) {
        const double rho = (i + 0.5) * radius / n_r;
        for (int j = 0; j < n_phi; ++j) {
            const double phi = (j + 0.5) * 2.0 * kPiD / n_phi;
            sum += g(rho, phi) * rho;
        }
    }
    return sum * (radius / n_r) * (2.0 * kPiD / n_phi);
}

// Two unit vectors perpendicular to the unit n and to each other.
void basis(const glm::dvec3& n, glm::dvec3& a, glm::dvec3& b) {
    a = glm::normalize(
        glm::cross(n, std::fabs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    b = glm::cross(n, a);
}

// The irradiance at p (normal n) from Cycles 3.4's facing disc of a lamp at c, radius r,
// radiance L toward w times falloff(cos from axis of w) (w from the disc point to p): the
// Lambertian disc's E = int L cos_l max(0, cos_r) / t^2 dA (Cohen & Wallace eq. 2.42).
template <class Falloff>
double disc_irradiance(const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& c, double r,
                       double big_l, Falloff falloff) {
    const glm::dvec3 nl = glm::normalize(p - c);
    glm::dvec3 a, b;
    basis(nl, a, b);
    return disc_quadrature(r, [&](double rho, double phi) {
        const glm::dvec3 q = c + rho * (std::cos(phi) * a + std::sin(phi) * b);
        const glm::dvec3 v = p - q;  // from the disc to p
        const double t2 = glm::dot(v, v);
        const glm::dvec3 w = v / std::sqrt(t2);
        const double cos_l = glm::dot(nl, w), cos_r = std::max(0.0, -glm::dot(n, w));
        return big_l * falloff(w) * cos_l * cos_r / t2;
    });
}

const auto kNoFalloff = [](const glm::dvec3&) { return 1.0; };

// Chi-square of points uniform on a disc: in (rho^2 / R^2, phi / 2 pi) they are uniform on the
// unit square. 8 x 8 cells, 63 degrees of freedom: the 1e-4 quantile of chi2(63) is ~117.
struct DiscChi2 {
    static constexpr int kCells = 8;
    std::vector<int> count = std::vector<int>(kCells * kCells, 0);
    int n = 0;
    void add(double rho2_rel, double phi) {
        double ph = phi / (2.0 * kPiD);
        if (ph < 0.0) ph += 1.0;
        const int ix = std::min(kCells - 1, std::max(0, int(rho2_rel * kCells)));
        const int iy = std::min(kCells - 1, std::max(0, int(ph * kCells)));
        ++count[ix * kCells + iy];
        ++n;
    }
    double chi2() const {
        const double e = double(n) / (kCells * kCells);
        double c = 0.0;
        for (int k : count) c += (k - e) * (k - e) / e;
        return c;
    }
};

std::string scene_text(const std::string& lights) {
    return R"({"format": "facet-scene", "version": 1,
      "camera": {"position": [0, 4, 6], "look_at": [0, 0, 0], "fov": 50, "width": 24, "height": 16},
      "render": {"integrator": "path", "spp": 4, "max_depth": 2, "seed": 5},
      "materials": {"white": {"model": "lambert", "reflectance": 0.6}},
      "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "white"},
                 {"type": "sphere", "center": [0.5, 0.6, 0], "radius": 0.6, "material": "white"}],
      "lights": [)" +
           lights + "]}";
}

std::string error_of(const std::string& lights) {
    try {
        (void)build_scene(parse_scene_description(scene_text(lights), "t.json"), "t.json");
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

// --- the point lamp's facing disc --------------------------------------------------------------

// On the axis of a disc of radius r at distance d, facing it: E = pi L r^2 / (d^2 + r^2) =
// I / (d^2 + r^2) (I = Phi / 4 pi = pi r^2 L). Checked three ways: the quadrature of the
// Lambertian disc against the closed form (1e-6), the sampler against the closed form (MC),
// and that the sphere model gives I / d^2 instead (what a scene without the key keeps).
TEST(Cycles34Lamps, DiscOnAxisIrradianceIsIOverD2PlusR2) {
    const double phi = 100.0, d = 1.5, i0 = phi / (4.0 * kPiD);
    for (double r : {0.05, 1.0, 2.5}) {
        SCOPED_TRACE(r);
        const double closed = i0 / (d * d + r * r);
        const double big_l = i0 / (kPiD * r * r);
        const double quad = disc_irradiance({0, 0, 0}, {0, 1, 0}, {0, d, 0}, r, big_l, kNoFalloff);
        EXPECT_NEAR(quad / closed, 1.0, 1e-6);
        const Light l =
            Light::point({0, float(d), 0}, Rgb(float(phi)), float(r), RadiusModel::Cycles34Disc);
        EXPECT_FALSE(l.is_delta());
        EXPECT_FALSE(l.hittable());
        EXPECT_EQ(l.power(1.f), Rgb(float(phi)));
        const LightSampleContext ctx{{0, 0, 0}, {0, 1, 0}};
        const Mc m = mc(scaled(40000), [&](Vec2 u) { return irradiance(l, ctx, u); });
        expect_mc(m, closed);
        // The sphere (r < d) is the point light's I / d^2: far outside the noise for r >= 1.
        if (r < d) {
            const Light s = Light::point({0, float(d), 0}, Rgb(float(phi)), float(r));
            expect_mc(mc(scaled(40000), [&](Vec2 u) { return irradiance(s, ctx, u); }),
                      i0 / (d * d));
        }
    }
}

// Off the axis and tilted, including a receiver whose horizon cuts the disc: the sampler against
// the quadrature of the Lambertian disc.
TEST(Cycles34Lamps, DiscOffAxisAndTiltedMatchesQuadrature) {
    const double phi = 40.0, r = 0.9;
    const glm::dvec3 c(0.7, 1.2, -0.3);
    const double big_l = phi / (4.0 * kPiD) / (kPiD * r * r);
    const Light l = Light::point(Vec3(c), Rgb(float(phi)), float(r), RadiusModel::Cycles34Disc);
    for (const glm::dvec3& n : {glm::dvec3(0, 1, 0), glm::normalize(glm::dvec3(1, 0.3, 0)),
                                glm::normalize(glm::dvec3(-1, 0.4, 0.2))}) {
        SCOPED_TRACE(n.x);
        const double quad = disc_irradiance({0, 0, 0}, n, c, r, big_l, kNoFalloff);
        ASSERT_GT(quad, 0.0);
        const LightSampleContext ctx{{0, 0, 0}, Vec3(n)};
        expect_mc(mc(scaled(40000), [&](Vec2 u) { return irradiance(l, ctx, u); }), quad);
    }
}

// The density: every sampled point lies on the disc through the centre perpendicular to the
// direction to the lit point; pdf = t^2 / (cos_l pi r^2) from the sample's geometry; the points
// are uniform over the disc (chi-square); E[1/pdf] = the disc's solid angle
// 2 pi (1 - d / sqrt(d^2 + r^2)).
TEST(Cycles34Lamps, DiscSamplingIsUniformOverTheDiscChiSquare) {
    const glm::dvec3 c(1.0, 2.0, -0.5), p(0.2, -0.3, 0.4);
    const double r = 1.3;
    const Light l = Light::point(Vec3(c), Rgb(1.f), float(r), RadiusModel::Cycles34Disc);
    const LightSampleContext ctx{Vec3(p), {0, 0, 0}};
    const glm::dvec3 nl = glm::normalize(p - c);
    glm::dvec3 a, b;
    basis(nl, a, b);
    const double d = glm::length(p - c);
    DiscChi2 chi;
    const Mc inv = mc(scaled(64000), [&](Vec2 u) {
        const auto s = l.sample_li(ctx, u);
        EXPECT_TRUE(s);
        if (!s) return 0.0;
        const glm::dvec3 q = p + double(s->dist) * glm::dvec3(s->wi);
        const glm::dvec3 off = q - c;
        EXPECT_NEAR(glm::dot(off, nl), 0.0, 1e-5);
        EXPECT_NEAR(glm::length(q - glm::dvec3(s->p_light)), 0.0, 1e-5);
        const double rho2 = glm::dot(off, off);
        EXPECT_LE(rho2, r * r * (1.0 + 1e-5));
        const double t = glm::length(q - p);
        const double cos_l = glm::dot(nl, glm::normalize(p - q));
        EXPECT_NEAR(double(s->pdf), t * t / (cos_l * kPiD * r * r), 1e-4 * s->pdf);
        chi.add(rho2 / (r * r), std::atan2(glm::dot(off, b), glm::dot(off, a)));
        EXPECT_FALSE(s->delta);
        return 1.0 / double(s->pdf);
    });
    expect_mc(inv, 2.0 * kPiD * (1.0 - d / std::sqrt(d * d + r * r)));
    EXPECT_LT(chi.chi2(), 117.0);
    // The lit point at the centre: no disc to face.
    EXPECT_FALSE(l.sample_li({Vec3(c), {0, 1, 0}}, {0.3f, 0.3f}).has_value());
}

// The spot's disc: each disc point's radiance toward the lit point is attenuated by the spot's
// fall-off along its own direction (Cycles 3.4). Blender's form, cone 30 degrees, blend 0.2, a
// disc large enough (atan(1.5 / 2) = 37 degrees) that its rim lies outside the cone.
TEST(Cycles34Lamps, SpotDiscFollowsTheFalloffPerDirection) {
    const double phi = 60.0, d = 2.0, r = 1.5, outer = 30.0, blend = 0.2;
    const glm::dvec3 c(0, d, 0), axis(0, -1, 0);
    const Light l = Light::spot_blend(Vec3(c), Vec3(axis), Rgb(float(phi)), float(outer),
                                      float(blend), float(r), RadiusModel::Cycles34Disc);
    const double k = cycles_spot_intensity(glm::dvec3(phi), outer, blend).x;
    const double cos_outer = std::cos(outer * kPiD / 180.0);
    const auto falloff = [&](const glm::dvec3& w) {
        return cycles_spot_attenuation(glm::dot(w, axis), cos_outer, (1.0 - cos_outer) * blend);
    };
    for (const glm::dvec3& p : {glm::dvec3(0, 0, 0), glm::dvec3(0.8, 0, 0.3)}) {
        SCOPED_TRACE(p.x);
        const double quad = disc_irradiance(p, {0, 1, 0}, c, r, k / (kPiD * r * r), falloff);
        ASSERT_GT(quad, 0.0);
        const LightSampleContext ctx{Vec3(p), {0, 1, 0}};
        expect_mc(mc(scaled(40000), [&](Vec2 u) { return irradiance(l, ctx, u); }), quad);
    }
}

// --- the sun -------------------------------------------------------------------------------------

// Cycles 3.4's sun of strength E and angle 2 delta: radiance L(theta) = E / (pi T^2 cos^3 theta)
// inside the cone of half-angle delta (T = tan delta). The irradiance is integrated here over
// the cone in (theta, phi) (not over the sampler's disc), for a facing surface (against the
// closed form E 2 (sqrt(1 + T^2) - 1) / T^2) and tilted ones, one with the horizon cutting the
// cone; the sampler must agree. The uniform cone gives E cos tau instead: at 30 degrees the
// facing surface differs by 1.8%, some 100 standard errors.
TEST(Cycles34Lamps, SunIrradianceMatchesTheQuadratureOfTheModel) {
    const double e = 2.0;
    for (double angle : {10.0, 30.0, 60.0}) {
        SCOPED_TRACE(angle);
        const double delta = 0.5 * angle * kPiD / 180.0, tan_d = std::tan(delta);
        const glm::dvec3 axis(0, 1, 0);  // toward the sun
        const Light sun =
            Light::directional({0, -1, 0}, Rgb(float(e)), float(angle), SunAngleModel::Cycles34);
        EXPECT_FALSE(sun.is_delta());
        EXPECT_FALSE(sun.hittable());
        for (double tau_deg : {0.0, 40.0, 80.0}) {
            SCOPED_TRACE(tau_deg);
            const double tau = tau_deg * kPiD / 180.0;
            const glm::dvec3 n(0, std::cos(tau), std::sin(tau));
            // Midpoint rule in (theta, phi) on [0, delta] x [0, 2 pi): 2000 x 1000 nodes, relative
            // error below 1e-6 for the smooth facing case, ~1e-6 with the horizon's kink.
            const int nt = 2000, np = 1000;
            double quad = 0.0;
            for (int i = 0; i < nt; ++i) {
                const double th = (i + 0.5) * delta / nt;
                const double ct = std::cos(th), st = std::sin(th);
                const double big_l = e / (kPiD * tan_d * tan_d * ct * ct * ct);
                for (int j = 0; j < np; ++j) {
                    const double ph = (j + 0.5) * 2.0 * kPiD / np;
                    const glm::dvec3 w(st * std::cos(ph), ct, st * std::sin(ph));
                    quad += big_l * std::max(0.0, glm::dot(w, n)) * st;
                }
            }
            quad *= (delta / nt) * (2.0 * kPiD / np);
            (void)axis;
            if (tau_deg == 0.0) {
                const double closed =
                    e * 2.0 * (std::sqrt(1.0 + tan_d * tan_d) - 1.0) / (tan_d * tan_d);
                EXPECT_NEAR(quad / closed, 1.0, 1e-6);
                EXPECT_LT(closed, e);
            }
            const LightSampleContext ctx{{0, 0, 0}, Vec3(n)};
            expect_mc(mc(scaled(20000), [&](Vec2 u) { return irradiance(sun, ctx, u); }), quad);
        }
    }
}

// The sun's density: directions within delta of the axis, pdf = 1 / (pi T^2 cos^3 theta) from
// each direction's angle, every sample giving li / pdf = E, the disc points
// w / (w . axis) - axis uniform on the disc of radius T (chi-square), and
// E[1/pdf] = the cone's solid angle 2 pi (1 - cos delta).
TEST(Cycles34Lamps, SunSamplingMatchesItsPdfChiSquare) {
    const double e = 3.0, angle = 25.0;
    const double delta = 0.5 * angle * kPiD / 180.0, tan_d = std::tan(delta);
    const glm::dvec3 axis = glm::normalize(glm::dvec3(0.3, 1.0, -0.2));
    const Light sun =
        Light::directional(Vec3(-axis), Rgb(float(e)), float(angle), SunAngleModel::Cycles34);
    glm::dvec3 a, b;
    basis(axis, a, b);
    DiscChi2 chi;
    const Mc inv = mc(scaled(64000), [&](Vec2 u) {
        const auto s = sun.sample_li({{0, 0, 0}, {0, 1, 0}}, u);
        EXPECT_TRUE(s);
        if (!s) return 0.0;
        const glm::dvec3 w(s->wi);
        const double ct = glm::dot(w, axis);
        EXPECT_GE(ct, std::cos(delta) - 1e-6);
        EXPECT_NEAR(double(s->pdf), 1.0 / (kPiD * tan_d * tan_d * ct * ct * ct), 1e-4 * s->pdf);
        EXPECT_NEAR(double(s->li.r) / double(s->pdf), e, 1e-5 * e);
        EXPECT_TRUE(std::isinf(s->dist));
        const glm::dvec3 q = w / ct - axis;
        chi.add(glm::dot(q, q) / (tan_d * tan_d), std::atan2(glm::dot(q, b), glm::dot(q, a)));
        return 1.0 / double(s->pdf);
    });
    expect_mc(inv, 2.0 * kPiD * (1.0 - std::cos(delta)));
    EXPECT_LT(chi.chi2(), 117.0);
    // Angle 0 stays the parallel light whatever the model.
    EXPECT_TRUE(Light::directional({0, -1, 0}, Rgb(1.f), 0.f, SunAngleModel::Cycles34).is_delta());
}

// --- the scene format ------------------------------------------------------------------------

TEST(Cycles34Lamps, LoaderReadsTheModelsAndNamesUnknownOnes) {
    EXPECT_EQ(error_of(R"({"type": "point", "position": [0, 5, 0], "power": 1, "radius": 0.2,
                           "radius_model": "cycles34_disc"})"),
              "");
    EXPECT_EQ(error_of(R"({"type": "spot", "position": [0, 5, 0], "direction": [0, -1, 0],
                           "power": 1, "outer_angle": 30, "spot_blend": 0.1, "radius": 0.2,
                           "radius_model": "sphere"})"),
              "");
    EXPECT_EQ(error_of(R"({"type": "directional", "direction": [0, -1, 0], "irradiance": 1,
                           "angle": 20, "angle_model": "cycles34"})"),
              "");
    EXPECT_NE(error_of(R"({"type": "point", "position": [0, 5, 0], "power": 1, "radius": 0.2,
                           "radius_model": "disc"})")
                  .find("t.json: /lights/0/radius_model: unknown radius model 'disc'"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"type": "directional", "direction": [0, -1, 0], "irradiance": 1,
                           "angle": 20, "angle_model": "cycles4"})")
                  .find("/lights/0/angle_model: unknown angle model 'cycles4'"),
              std::string::npos);
    // Each key belongs to its kinds.
    EXPECT_NE(error_of(R"({"type": "directional", "direction": [0, -1, 0], "irradiance": 1,
                           "radius_model": "sphere"})")
                  .find("/lights/0/radius_model: unknown key"),
              std::string::npos);
}

// Scenes without the keys are untouched: the keys are not written back, the lights built
// without them sample bit for bit as Light's defaults and as the explicit default names, and a
// fixed-seed render is identical to the one with the explicit names (and differs with the
// Cycles 3.4 names).
TEST(Cycles34Lamps, WithoutTheKeysNothingChanges) {
    const std::string plain =
        R"({"type": "point", "position": [-1, 1.5, 0.5], "power": 80, "radius": 0.7},
           {"type": "spot", "position": [1.5, 2, 1], "look_at": [0, 0, 0], "power": 60,
            "outer_angle": 40, "spot_blend": 0.3, "radius": 0.4},
           {"type": "directional", "direction": [0.3, -1, -0.2], "irradiance": 1.5, "angle": 25})";
    const auto with = [](const std::string& point_model, const std::string& sun_model) {
        return R"({"type": "point", "position": [-1, 1.5, 0.5], "power": 80, "radius": 0.7,
                   "radius_model": ")" +
               point_model + R"("},
           {"type": "spot", "position": [1.5, 2, 1], "look_at": [0, 0, 0], "power": 60,
            "outer_angle": 40, "spot_blend": 0.3, "radius": 0.4, "radius_model": ")" +
               point_model + R"("},
           {"type": "directional", "direction": [0.3, -1, -0.2], "irradiance": 1.5, "angle": 25,
            "angle_model": ")" +
               sun_model + R"("})";
    };
    const SceneDescription d = parse_scene_description(scene_text(plain), "t.json");
    const std::string text = write_scene_json(d);
    EXPECT_EQ(text.find("radius_model"), std::string::npos);
    EXPECT_EQ(text.find("angle_model"), std::string::npos);
    EXPECT_EQ(parse_scene_description(text, "back.json"), d);

    const Scene s0 = build_scene(d, "t.json");
    const Light p_default = Light::point({-1.f, 1.5f, 0.5f}, Rgb(80.f), 0.7f);
    const Light p_disc =
        Light::point({-1.f, 1.5f, 0.5f}, Rgb(80.f), 0.7f, RadiusModel::Cycles34Disc);
    const LightSampleContext ctx{{0.2f, 0.f, 0.1f}, {0, 1, 0}};
    for (Vec2 u : {Vec2(0.1f, 0.7f), Vec2(0.6f, 0.2f)}) {
        const auto a = s0.lights()[0].sample_li(ctx, u), b = p_default.sample_li(ctx, u);
        ASSERT_TRUE(a && b);
        EXPECT_EQ(a->wi, b->wi);
        EXPECT_EQ(a->pdf, b->pdf);
        EXPECT_EQ(a->li, b->li);
        EXPECT_NE(p_disc.sample_li(ctx, u)->pdf, a->pdf);
    }

    const auto render_of = [](const std::string& lights) {
        const Scene s =
            build_scene(parse_scene_description(scene_text(lights), "t.json"), "t.json");
        RenderOptions o;
        o.threads = 2;
        return facet::render::render(s, o);
    };
    const Image base = render_of(plain);
    const Image named = render_of(with("sphere", "uniform"));
    const Image cycles = render_of(with("cycles34_disc", "cycles34"));
    ASSERT_EQ(base.pixels().size(), named.pixels().size());
    EXPECT_TRUE(base.pixels() == named.pixels());
    EXPECT_FALSE(base.pixels() == cycles.pixels());
}
