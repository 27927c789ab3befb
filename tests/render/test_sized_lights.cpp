// Lights with size (light.h, "Lights with size"): point and spot lights with a radius (sphere
// lights) and a directional light with an angle (the sun). Analytic irradiance, the sampling
// density (E[1/pdf] = solid angle, a chi-square test of the directions), penumbra, the scene
// loader's checks and the POV-Ray exporter's refusals.
//
// Monte Carlo tolerances are 4 standard errors of the estimate, computed from the samples
// (a false failure has probability ~6e-5 per check), plus 1e-6 relative for float round-off.
// Sample counts scale with FACET_STRESS_SCALE.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "facet/render/pov_export.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/sampling.h"
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
    return facet::render::testing::mc_unit_square(n, 12345, f);
}

std::string scene_text(const std::string& lights, const std::string& shapes = "[]") {
    return R"({"format": "facet-scene", "version": 1,
      "camera": {"position": [0, 1, 5], "look_at": [0, 0, 0], "fov": 40, "width": 8, "height": 6},
      "materials": {"white": {"model": "lambert", "reflectance": 0.5}},
      "shapes": )" +
           shapes + R"(, "lights": [)" + lights + "]}";
}

// The message of the SceneError that building (or exporting) the scene throws; "" if none.
std::string error_of(const std::string& lights, bool pov = false) {
    try {
        const SceneDescription d = parse_scene_description(scene_text(lights), "t.json");
        if (pov)
            (void)export_pov(d, "t.json");
        else
            (void)build_scene(d, "t.json");
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

// Expects building (with `pov`: exporting) a scene with `lights` to fail with a message that
// contains `what` (the JSON pointer and the start of the message).
void expect_error(const std::string& lights, const std::string& what, bool pov = false) {
    const std::string e = error_of(lights, pov);
    EXPECT_NE(e.find(what), std::string::npos) << "error: '" << e << "'";
}

}  // namespace

// --- sphere lights ----------------------------------------------------------------------------

TEST(SizedLights, SphereLightKeepsPowerAndIsNotDeltaNorHittable) {
    const Light p = Light::point({0, 0, 0}, Rgb(100.f), 0.5f);
    EXPECT_FALSE(p.is_delta());
    EXPECT_FALSE(p.hittable());
    EXPECT_EQ(p.power(1.f), Rgb(100.f));  // the same Phi as the point light
    const Light p0 = Light::point({0, 0, 0}, Rgb(100.f), 0.f);
    EXPECT_TRUE(p0.is_delta());
    const auto s = p.sample_li({{0, 3, 0}, {0, -1, 0}}, {0.3f, 0.8f});
    ASSERT_TRUE(s);
    EXPECT_FALSE(s->delta);
    // Radiance L = Phi / (4 pi^2 r^2) (Cycles 3.4's point lamp); float round-off.
    EXPECT_NEAR(s->li.r, 100.0 / (4.0 * kPiD * kPiD * 0.25), 1e-4);
    EXPECT_EQ(p.pdf_li({{0, 3, 0}, {0, -1, 0}}, s->wi, s->p_light, s->n_light), 0.f);
}

// E = pi L (r/d)^2 = Phi / (4 pi d^2) on a surface facing the centre, for r small and r
// comparable to d; the mean of 1/pdf is the cone's solid angle 2 pi (1 - cos theta_max); every
// sampled point lies on the sphere.
TEST(SizedLights, SphereIrradianceOnAFacingSurfaceIsExact) {
    const double phi = 100.0, d = 2.0;
    for (double r : {0.02, 0.5, 1.5, 1.99}) {
        SCOPED_TRACE(r);
        const Light l = Light::point({0, float(d), 0}, Rgb(float(phi)), float(r));
        const LightSampleContext ctx{{0, 0, 0}, {0, 1, 0}};
        const int n = scaled(40000);
        expect_mc(mc(n, [&](Vec2 u) { return irradiance(l, ctx, u); }), phi / (4.0 * kPiD * d * d));
        const double omega = 2.0 * kPiD * (1.0 - std::sqrt(1.0 - r * r / (d * d)));
        expect_mc(mc(n,
                     [&](Vec2 u) {
                         const auto s = l.sample_li(ctx, u);
                         if (!s) return 0.0;
                         const Vec3 q = ctx.p + s->dist * s->wi;
                         EXPECT_NEAR(glm::length(q - Vec3(0, float(d), 0)), r, 1e-5 * d);
                         EXPECT_NEAR(glm::length(q - s->p_light), 0.f, 1e-5f);
                         return 1.0 / double(s->pdf);
                     }),
                  omega);
    }
}

// A surface tilted by tau whose horizon does not cut the cone (tau <= 90 - theta_max): the
// irradiance is the vector irradiance's projection, E cos tau (the cone is symmetric about its
// axis, so int_cone w dw is along the axis). The point light gives the same, exactly.
TEST(SizedLights, SphereIrradianceOnATiltedSurfaceIsEcosTau) {
    const double phi = 10.0, d = 3.0, r = 1.0;  // theta_max = 19.5 degrees
    const Light l = Light::point({0, float(d), 0}, Rgb(float(phi)), float(r));
    for (double tau_deg : {30.0, 60.0, 70.0}) {
        SCOPED_TRACE(tau_deg);
        const double tau = tau_deg * kPiD / 180.0;
        const LightSampleContext ctx{{0, 0, 0}, {float(std::sin(tau)), float(std::cos(tau)), 0}};
        expect_mc(mc(scaled(40000), [&](Vec2 u) { return irradiance(l, ctx, u); }),
                  phi / (4.0 * kPiD * d * d) * std::cos(tau));
    }
}

// Chi-square test of the cone sampling: in the cone's coordinates ((1 - cos theta) / (1 - cos
// theta_max), phi / 2 pi) the directions must be uniform on the unit square. 8 x 8 cells,
// 63 degrees of freedom: the 1e-4 quantile of chi2(63) is ~117.
TEST(SizedLights, SphereConeSamplingIsUniformChiSquare) {
    const Vec3 c(1.f, 2.f, -0.5f);
    const float r = 0.8f;
    const LightSampleContext ctx{{0, 0, 0}, {0, 0, 0}};
    const Light l = Light::point(c, Rgb(1.f), r);
    const glm::dvec3 axis = glm::normalize(glm::dvec3(c));
    const double dc2 = glm::dot(glm::dvec3(c), glm::dvec3(c));
    const double cos_max = std::sqrt(1.0 - double(r) * r / dc2);
    // A frame about the axis: phi measured from any fixed perpendicular (uniformity in phi
    // does not depend on its origin).
    const glm::dvec3 t = glm::normalize(glm::cross(axis, glm::dvec3(0, 0, 1)));
    const glm::dvec3 b = glm::cross(axis, t);
    const int cells = 8, n = scaled(64000);
    std::vector<int> count(cells * cells, 0);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (int i = 0; i < n; ++i) {
        const auto s = l.sample_li(ctx, {u(rng), u(rng)});
        ASSERT_TRUE(s);
        const glm::dvec3 w(s->wi);
        const double x = (1.0 - glm::dot(w, axis)) / (1.0 - cos_max);
        double ph = std::atan2(glm::dot(w, b), glm::dot(w, t)) / (2.0 * kPiD);
        if (ph < 0.0) ph += 1.0;
        ASSERT_LE(x, 1.0 + 1e-4);  // inside the cone (float round-off of wi)
        const int ix = std::min(cells - 1, std::max(0, int(x * cells)));
        const int iy = std::min(cells - 1, int(ph * cells));
        ++count[ix * cells + iy];
        // The density is the uniform one of the cone.
        ASSERT_NEAR(s->pdf, 1.0 / (2.0 * kPiD * (1.0 - cos_max)), 1e-4 * s->pdf);
    }
    const double expected = double(n) / (cells * cells);
    double chi2 = 0.0;
    for (int k : count) chi2 += (k - expected) * (k - expected) / expected;
    EXPECT_LT(chi2, 117.0);
}

// Inside the sphere a point sees L from every direction: E = pi L exactly, per sample (cosine
// sampling makes L cos / pdf = pi L). The light point is on the sphere (the far intersection).
TEST(SizedLights, InsideTheSphereEachSampleGivesPiL) {
    const Light l = Light::point({0, 0, 0}, Rgb(50.f), 2.f);
    const double big_l = 50.0 / (4.0 * kPiD * kPiD * 4.0);
    const LightSampleContext ctx{{0.5f, 1.f, 0.f}, glm::normalize(Vec3(1, 1, 0))};
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (int i = 0; i < 200; ++i) {
        const auto s = l.sample_li(ctx, {u(rng), u(rng)});
        if (!s) continue;
        EXPECT_NEAR(double(s->li.r) * glm::dot(s->wi, ctx.n) / s->pdf, kPiD * big_l,
                    1e-5 * kPiD * big_l);
        EXPECT_NEAR(glm::length(s->p_light), 2.f, 1e-5f);
    }
}

// A spot sphere on its axis, well inside the inner cone (every direction from the sphere to the
// point is within it): the irradiance of the point spot, I0 / d^2. Outside the outer cone
// (every direction beyond it) nothing arrives.
TEST(SizedLights, SpotSphereOnAxisMatchesThePointSpot) {
    const double d = 4.0, r = 0.5;  // theta_max = 7.2 degrees < inner 20
    const Light point = Light::spot({0, float(d), 0}, {0, -1, 0}, Rgb(30.f), 20.f, 40.f);
    const Light sphere = Light::spot({0, float(d), 0}, {0, -1, 0}, Rgb(30.f), 20.f, 40.f, float(r));
    const LightSampleContext ctx{{0, 0, 0}, {0, 1, 0}};
    const double e_point = irradiance(point, ctx, {0.5f, 0.5f});
    EXPECT_GT(e_point, 0.0);
    expect_mc(mc(scaled(20000), [&](Vec2 u) { return irradiance(sphere, ctx, u); }), e_point);
    const LightSampleContext side{{float(d), float(d), 0}, {-1, 0, 0}};  // 90 degrees off axis
    for (Vec2 u : {Vec2(0.1f, 0.2f), Vec2(0.9f, 0.7f)})
        EXPECT_FALSE(sphere.sample_li(side, u).has_value());
}

// --- the sun ----------------------------------------------------------------------------------

TEST(SizedLights, SunIrradianceFacingAndTilted) {
    const double e = 3.0;
    for (double angle : {0.53, 10.0, 60.0}) {
        SCOPED_TRACE(angle);
        const Light sun = Light::directional({0, -1, 0}, Rgb(float(e)), float(angle));
        EXPECT_FALSE(sun.is_delta());
        EXPECT_FALSE(sun.hittable());
        const double delta = 0.5 * angle * kPiD / 180.0;
        // Radiance L = E / (pi sin^2 delta).
        const auto s = sun.sample_li({{0, 0, 0}, {0, 1, 0}}, {0.4f, 0.4f});
        ASSERT_TRUE(s);
        EXPECT_NEAR(s->li.r / (e / (kPiD * std::sin(delta) * std::sin(delta))), 1.0, 1e-5);
        EXPECT_TRUE(std::isinf(s->dist));
        for (double tau_deg : {0.0, 40.0, 89.0 - 0.5 * angle}) {
            SCOPED_TRACE(tau_deg);
            const double tau = tau_deg * kPiD / 180.0;
            const LightSampleContext ctx{{0, 0, 0},
                                         {0, float(std::cos(tau)), float(std::sin(tau))}};
            const Mc m = mc(scaled(20000), [&](Vec2 u) { return irradiance(sun, ctx, u); });
            expect_mc(m, e * std::cos(tau));
        }
        // Every direction within delta of the axis; E[1/pdf] = 2 pi (1 - cos delta).
        expect_mc(mc(scaled(20000),
                     [&](Vec2 u) {
                         const auto t = sun.sample_li({{0, 0, 0}, {0, 1, 0}}, u);
                         EXPECT_GE(double(t->wi.y), std::cos(delta) - 1e-6);
                         return 1.0 / double(t->pdf);
                     }),
                  2.0 * kPiD * (1.0 - std::cos(delta)));
    }
    // Angle 0 is today's parallel light, bit for bit.
    const Light flat = Light::directional({0, -1, 0}, Rgb(3.f), 0.f);
    EXPECT_TRUE(flat.is_delta());
    const auto f = flat.sample_li({{0, 0, 0}, {0, 1, 0}}, {0.4f, 0.4f});
    EXPECT_EQ(f->wi, Vec3(0, 1, 0));
    EXPECT_EQ(f->li, Rgb(3.f));
}

// Penumbra: an opaque half-plane (x < 0) at height h above a point; the sun straight down.
// Directly under the edge exactly half of the (symmetric) cone is blocked: E / 2. Beyond
// h tan delta from the edge the point is fully lit or fully in shadow.
TEST(SizedLights, SunPenumbraUnderAnEdge) {
    const std::string occluder =
        R"([{"type": "quad", "vertices": [[-100, 1, -100], [-100, 1, 100], [0, 1, 100], [0, 1, -100]], "material": "white"}])";
    const SceneDescription d = parse_scene_description(
        scene_text(
            R"({"type": "directional", "direction": [0, -1, 0], "irradiance": 2, "angle": 20})",
            occluder),
        "t.json");
    const Scene scene = build_scene(d, "t.json");
    const Light& sun = scene.lights()[0];
    const double half = std::tan(10.0 * kPiD / 180.0);  // h tan delta, h = 1
    auto lit = [&](float x) {
        const LightSampleContext ctx{{x, 0, 0}, {0, 1, 0}};
        return mc(scaled(20000), [&](Vec2 u) {
            const auto s = sun.sample_li(ctx, u);
            if (!s || scene.occluded(ctx.p, ctx.n, s->wi, s->dist)) return 0.0;
            return double(s->li.r) * glm::dot(s->wi, ctx.n) / s->pdf;
        });
    };
    expect_mc(lit(0.f), 1.0);
    EXPECT_EQ(lit(float(-1.01 * half)).mean, 0.0);
    expect_mc(lit(float(1.01 * half)), 2.0);
}

// --- scene format -------------------------------------------------------------------------------

TEST(SizedLights, LoaderChecksNameTheKey) {
    EXPECT_EQ(error_of(R"({"type": "point", "position": [0, 5, 0], "power": 1, "radius": 0.2})"),
              "");
    expect_error(R"({"type": "point", "position": [0, 5, 0], "power": 1, "radius": -1})",
                 "t.json: /lights/0/radius: ");
    expect_error(R"({"type": "spot", "position": [0, 5, 0], "direction": [0, -1, 0],
                          "power": 1, "outer_angle": 30, "radius": -0.1})",
                 "/lights/0/radius");
    expect_error(R"({"type": "directional", "direction": [0, -1, 0], "irradiance": 1,
                          "angle": 180})",
                 "t.json: /lights/0/angle: must be in [0, 180) degrees");
    expect_error(R"({"type": "directional", "direction": [0, -1, 0], "irradiance": 1,
                          "angle": -2})",
                 "/lights/0/angle");
    // A key of another kind is unknown ("angle" is the sun's, "radius" the point's).
    expect_error(R"({"type": "point", "position": [0, 5, 0], "power": 1, "angle": 2})",
                 "/lights/0/angle: unknown key");
    // Non-finite values (not expressible in JSON) through the description.
    SceneDescription d = parse_scene_description(
        scene_text(R"({"type": "point", "position": [0, 5, 0], "power": 1})"), "t.json");
    d.lights[0].radius = std::nan("");
    try {
        (void)build_scene(d, "t.json");
        FAIL() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("/lights/0/radius: must be a finite number"),
                  std::string::npos)
            << e.what();
    }
}

TEST(SizedLights, JsonRoundTripWritesTheKeysOnlyWhenGiven) {
    const SceneDescription d = parse_scene_description(
        scene_text(R"({"type": "point", "position": [0, 5, 0], "power": 1, "radius": 0.25},
                      {"type": "directional", "direction": [0, -1, 0], "irradiance": 1, "angle": 0.5},
                      {"type": "point", "position": [0, 5, 0], "power": 1})"),
        "t.json");
    const std::string text = write_scene_json(d);
    EXPECT_EQ(parse_scene_description(text, "back.json"), d);
    EXPECT_EQ(d.lights[0].radius, 0.25);
    EXPECT_EQ(d.lights[1].angle, 0.5);
    EXPECT_FALSE(d.lights[2].radius.has_value());
    // Only the two given keys are written.
    std::size_t n = 0;
    for (std::size_t p = text.find("\"radius\""); p != std::string::npos;
         p = text.find("\"radius\"", p + 1))
        ++n;
    EXPECT_EQ(n, 1u);
}

// POV-Ray has no sphere light or sun disc of uniform radiance: an error naming the key, never
// a silent drop; radius 0 / angle 0 export as today.
TEST(SizedLights, PovExportRefusesSizesItCannotExpress) {
    expect_error(R"({"type": "point", "position": [0, 5, 0], "power": 1, "radius": 0.2})",
                 "/lights/0/radius", true);
    expect_error(R"({"type": "spot", "position": [0, 5, 0], "direction": [0, -1, 0],
                          "power": 1, "outer_angle": 30, "radius": 0.2})",
                 "/lights/0/radius", true);
    expect_error(R"({"type": "directional", "direction": [0, -1, 0], "irradiance": 1,
                          "angle": 0.5})",
                 "/lights/0/angle", true);
    EXPECT_EQ(error_of(R"({"type": "point", "position": [0, 5, 0], "power": 1, "radius": 0},
                          {"type": "directional", "direction": [0, -1, 0], "irradiance": 1,
                          "angle": 0})",
                       true),
              "");
}

// --- area lamps -------------------------------------------------------------------------------

namespace {

// The one light of a scene holding `light`.
Light lamp(const std::string& light) {
    const Scene s = build_scene(parse_scene_description(scene_text(light), "t.json"), "t.json");
    return s.lights()[0];
}

}  // namespace

// On the axis of a disc lamp (diameter 2R, power P, emitting down from height d) facing it:
// L = P / (4 pi R^2) (Cycles 3.4), E = pi L R^2 / (R^2 + d^2) (unit-sphere method). Emitted flux
// pi L A = pi P / 4. Behind the lamp nothing arrives.
TEST(SizedLights, AreaDiscOnAxis) {
    const double p = 40.0, r = 0.75, d = 1.5;
    const Light l = lamp(R"({"type": "area", "shape": "disc", "size": 1.5, "power": 40,
                             "position": [0, 1.5, 0], "direction": [0, -1, 0]})");
    EXPECT_FALSE(l.is_delta());
    EXPECT_FALSE(l.hittable());
    const double big_l = p / (4.0 * kPiD * r * r);
    EXPECT_NEAR(l.emission().r / big_l, 1.0, 1e-6);
    EXPECT_NEAR(l.power(1.f).r / (kPiD * p / 4.0), 1.0, 1e-6);
    const LightSampleContext ctx{{0, 0, 0}, {0, 1, 0}};
    expect_mc(mc(scaled(40000), [&](Vec2 u) { return irradiance(l, ctx, u); }),
              kPiD * big_l * r * r / (r * r + d * d));
    EXPECT_FALSE(l.sample_li({{0, 3, 0}, {0, -1, 0}}, {0.3f, 0.3f}).has_value());
}

// On the axis of a rectangle lamp of half-sides a, b at distance d: E = 2 L [a / sqrt(a^2 + d^2)
// atan(b / sqrt(a^2 + d^2)) + b / sqrt(b^2 + d^2) atan(a / sqrt(b^2 + d^2))] (four corner
// rectangles, Howell's catalogue C-11), L = P / (4 A). `up` orients it: size along local x.
TEST(SizedLights, AreaRectangleOnAxisAndOrientation) {
    const double p = 10.0, a = 0.5 * 2.0, b = 0.5 * 0.5, d = 1.0;
    // Emitting down; up = +x: local y = world x, local x = y x z = x x y = world z.
    const Light l = lamp(R"({"type": "area", "shape": "rectangle", "size": 2, "size_y": 0.5,
                             "power": 10, "position": [0, 1, 0], "look_at": [0, 0, 0],
                             "up": [1, 0, 0]})");
    const double big_l = p / (4.0 * 2.0 * 0.5);
    EXPECT_NEAR(l.emission().r / big_l, 1.0, 1e-6);
    const LightSampleContext ctx{{0, 0, 0}, {0, 1, 0}};
    const double ra = std::sqrt(a * a + d * d), rb = std::sqrt(b * b + d * d);
    const double e = 2.0 * big_l * (a / ra * std::atan(b / ra) + b / rb * std::atan(a / rb));
    expect_mc(mc(scaled(40000),
                 [&](Vec2 u) {
                     const auto s = l.sample_li(ctx, u);
                     // size 2 along world z, size_y 0.5 along world x.
                     EXPECT_LE(std::fabs(s->p_light.z), 1.f + 1e-6f);
                     EXPECT_LE(std::fabs(s->p_light.x), 0.25f + 1e-6f);
                     return irradiance(l, ctx, u);
                 }),
              e);
    // A square and an ellipse build (defaults: shape square, up [0, 0, 1] for a vertical lamp).
    EXPECT_NEAR(lamp(R"({"type": "area", "size": 2, "power": 8, "position": [0, 1, 0],
                         "direction": [0, -1, 0]})")
                    .emission()
                    .r,
                1.f / 2.f, 1e-6f);
    EXPECT_NEAR(lamp(R"({"type": "area", "shape": "ellipse", "size": 2, "size_y": 1, "power": 8,
                         "position": [0, 1, 0], "direction": [0, -1, 0]})")
                    .emission()
                    .r,
                8.0 / (4.0 * kPiD / 4.0 * 2.0), 1e-6);
}

TEST(SizedLights, AreaLoaderChecksAndPovRefusal) {
    const std::string at = R"("position": [0, 1, 0], "direction": [0, -1, 0], "power": 1)";
    auto err = [&](const std::string& keys, bool pov = false) {
        return error_of(R"({"type": "area", )" + keys + ", " + at + "}", pov);
    };
    EXPECT_EQ(err(R"("size": 1)"), "");
    EXPECT_NE(err(R"("size": 1, "shape": "circle")").find("/lights/0/shape: unknown area light"),
              std::string::npos);
    EXPECT_NE(err(R"("size": 0)").find("/lights/0/size: must be > 0"), std::string::npos);
    EXPECT_NE(err(R"("size": 1, "size_y": 2)").find("/lights/0/size_y: only the rectangle"),
              std::string::npos);
    EXPECT_NE(err(R"("size": 1, "shape": "rectangle")").find("/lights/0: missing required key"),
              std::string::npos);
    EXPECT_NE(err(R"("size": 1, "shape": "rectangle", "size_y": -1)").find("/lights/0/size_y"),
              std::string::npos);
    EXPECT_NE(err(R"("size": 1, "up": [0, 2, 0])").find("/lights/0/up: must not be parallel"),
              std::string::npos);
    EXPECT_NE(err(R"("size": 1)", true).find("t.json: /lights/0: POV-Ray has no flat emitter"),
              std::string::npos);
    // The JSON round trip keeps every key.
    const SceneDescription d = parse_scene_description(
        scene_text(R"({"type": "area", "shape": "ellipse", "size": 1, "size_y": 0.5,
                       "up": [1, 0, 0], )" +
                   at + "}"),
        "t.json");
    EXPECT_EQ(parse_scene_description(write_scene_json(d), "back.json"), d);
    EXPECT_EQ(d.lights[0].shape, "ellipse");
}

// --- area lamps sampled by solid angle (light.h, "Area lamps") ----------------------------------

namespace {

// An area lamp of `shape` ("rectangle" or "ellipse"), size sx x sy, power 4 sx sy (radiance 1
// for the rectangle), centred at height h above the origin and emitting down; its local y
// (size_y) is world x, its local x (size) world z (see AreaRectangleOnAxisAndOrientation).
Light down_lamp(const std::string& shape, double sx, double sy, double h) {
    return lamp(R"({"type": "area", "shape": ")" + shape + R"(", "size": )" + std::to_string(sx) +
                R"(, "size_y": )" + std::to_string(sy) + R"(, "power": )" +
                std::to_string(4.0 * sx * sy) + R"(, "position": [0, )" + std::to_string(h) +
                R"(, 0], "look_at": [0, 0, 0], "up": [1, 0, 0]})");
}

// Irradiance at the origin (normal +y) from a rectangle of radiance L in the plane y = h
// spanning x in [x1, x2], z in [z1, z2], facing down: inclusion-exclusion over the four corner
// rectangles of the foot point, each E_c(a, b) = L/2 [a/ra atan(b/ra) + b/rb atan(a/rb)],
// ra = sqrt(a^2 + h^2) (Howell's catalogue C-11; odd in a and in b, so signed corners work).
double rect_irradiance(double big_l, double h, double x1, double x2, double z1, double z2) {
    auto corner = [&](double a, double b) {
        const double ra = std::sqrt(a * a + h * h), rb = std::sqrt(b * b + h * h);
        return 0.5 * big_l * (a / ra * std::atan(b / ra) + b / rb * std::atan(a / rb));
    };
    return corner(x2, z2) - corner(x1, z2) - corner(x2, z1) + corner(x1, z1);
}

// Irradiance on a surface parallel to a disc of radius R and radiance L at height h, offset rho
// from its axis: E = pi L / 2 [1 - (h^2 + rho^2 - R^2) / sqrt((h^2 + rho^2 + R^2)^2 -
// 4 R^2 rho^2)] (Howell's catalogue B-13).
double disc_irradiance(double big_l, double h, double rho, double r) {
    const double a = h * h + rho * rho;
    return 0.5 * kPiD * big_l *
           (1.0 - (a - r * r) / std::sqrt((a + r * r) * (a + r * r) - 4.0 * r * r * rho * rho));
}

}  // namespace

// Off the axis and near the plane, where sampling by area is at its worst: the irradiance from a
// rectangle lamp (foot point inside and outside it) and a disc lamp (near: its bounding
// spherical rectangle with rejection; far: by area) against the closed forms above.
TEST(SizedLights, AreaLampOffAxisIrradianceIsExact) {
    const double sx = 2.0, sy = 1.0;  // along world z and world x
    const Light rect = down_lamp("rectangle", sx, sy, 0.1);
    const double big_l = rect.emission().r;
    EXPECT_NEAR(big_l, 1.0, 1e-6);
    for (const Vec3 p : {Vec3(0.3f, 0.f, 0.6f), Vec3(0.8f, 0.f, -1.5f), Vec3(0, 0, 0)}) {
        SCOPED_TRACE(::testing::PrintToString(std::vector<float>{p.x, p.y, p.z}));
        const LightSampleContext ctx{p, {0, 1, 0}};
        // The lamp seen from p: x in [-sy/2, sy/2] - p.x, z in [-sx/2, sx/2] - p.z, h = 0.1.
        const double e = rect_irradiance(big_l, 0.1, -0.5 * sy - p.x, 0.5 * sy - p.x,
                                         -0.5 * sx - p.z, 0.5 * sx - p.z);
        const Mc m = mc(scaled(20000), [&](Vec2 u) { return irradiance(rect, ctx, u); });
        expect_mc(m, e);
        // Solid-angle sampling: the estimate's spread is the cosine's alone (relative standard
        // deviation < 1 per sample; sampling by area gives ~5 at this height).
        EXPECT_LT(m.stderr_ * std::sqrt(double(scaled(20000))), 1.0 * e);
    }
    const double r = 0.5;
    for (double h : {0.1, 0.3, 2.0}) {  // 0.1, 0.3: rejection (h < R); 2: by area
        SCOPED_TRACE(h);
        const Light disc = down_lamp("ellipse", 2 * r, 2 * r, h);
        const double l = disc.emission().r;
        for (float rho : {0.f, 0.3f, 0.9f}) {
            const LightSampleContext ctx{{rho, 0, 0}, {0, 1, 0}};
            expect_mc(mc(scaled(20000), [&](Vec2 u) { return irradiance(disc, ctx, u); }),
                      disc_irradiance(l, h, rho, r));
        }
    }
}

// Chi-square test of a lamp's sampling against its own pdf (Light::pdf_li): cells on the lamp
// (8 x 8 in its local coordinates a, b in [-1, 1]), each cell's expected probability the
// integral of pdf_li over the directions toward it, int pdf cos_l / r^2 dA (midpoint rule, 24 x
// 24 points per cell: ~1e-4 relative at these distances), and for an ellipse one more cell for
// the lost samples (nullopt: 1 - the sum). The rectangle's cells must sum to 1 (1e-3: the
// midpoint rule), so that 1 / pdf is the solid angle. A false failure: chi2(64) above 120 has
// probability ~3e-5. Every sample's pdf equals pdf_li's to 1e-4 (float round-off).
TEST(SizedLights, AreaLampSamplingMatchesItsPdfChiSquare) {
    struct Case {
        const char* shape;
        double h;
        Vec3 p;
    };
    for (const Case c :
         {Case{"rectangle", 0.2, {0.3f, 0.f, 0.5f}}, Case{"rectangle", 1.5, {1.5f, 0.f, -2.f}},
          Case{"ellipse", 0.2, {0.1f, 0.f, 0.4f}}, Case{"ellipse", 0.3, {0.8f, 0.f, 0.f}},
          Case{"ellipse", 3.0, {0.5f, 0.f, 0.5f}}}) {
        SCOPED_TRACE(std::string(c.shape) + " h " + std::to_string(c.h));
        const double sx = 2.0, sy = 1.0;
        const Light l = down_lamp(c.shape, sx, sy, c.h);
        const bool ellipse = std::string(c.shape) == "ellipse";
        const LightSampleContext ctx{c.p, {0, 0, 0}};
        // Lamp point of local (a, b): world x = b sy/2, z = a sx/2 (a along size).
        auto point = [&](double a, double b) {
            return glm::dvec3(0.5 * sy * b, c.h, 0.5 * sx * a);
        };
        constexpr int kCells = 8, kSub = 24;
        std::vector<double> expected(kCells * kCells + 1, 0.0);
        const double da = 2.0 / (kCells * kSub), cell_area = 0.25 * sx * sy * da * da;
        double total = 0.0;
        for (int i = 0; i < kCells * kSub; ++i)
            for (int j = 0; j < kCells * kSub; ++j) {
                const double a = -1.0 + (i + 0.5) * da, b = -1.0 + (j + 0.5) * da;
                if (ellipse && a * a + b * b > 1.0) continue;
                const glm::dvec3 q = point(a, b), v = q - glm::dvec3(c.p);
                const double r2 = glm::dot(v, v), cos_l = v.y / std::sqrt(r2);
                const Vec3 wi(v / std::sqrt(r2));
                const double pdf = l.pdf_li(ctx, wi, Vec3(q), {0, -1, 0});
                const double prob = pdf * cos_l / r2 * cell_area;
                expected[(i / kSub) * kCells + j / kSub] += prob;
                total += prob;
            }
        if (!ellipse) {
            EXPECT_NEAR(total, 1.0, 1e-3);
        }
        expected.back() = std::max(0.0, 1.0 - total);
        const int n = scaled(64000);
        std::vector<int> count(expected.size(), 0);
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        for (int k = 0; k < n; ++k) {
            const auto s = l.sample_li(ctx, {u(rng), u(rng)});
            if (!s) {
                ++count.back();
                continue;
            }
            const double a = 2.0 * double(s->p_light.z) / sx, b = 2.0 * double(s->p_light.x) / sy;
            ASSERT_LE(std::fabs(a), 1.0 + 1e-5);
            ASSERT_LE(std::fabs(b), 1.0 + 1e-5);
            if (ellipse) {
                ASSERT_LE(a * a + b * b, 1.0 + 1e-5);
            }
            ASSERT_NEAR(s->pdf, l.pdf_li(ctx, s->wi, s->p_light, s->n_light), 1e-4 * s->pdf);
            const int ia = std::clamp(int((a + 1.0) * 0.5 * kCells), 0, kCells - 1);
            const int ib = std::clamp(int((b + 1.0) * 0.5 * kCells), 0, kCells - 1);
            ++count[ia * kCells + ib];
        }
        double chi2 = 0.0;
        int dof = -1;
        for (std::size_t k = 0; k < expected.size(); ++k) {
            const double e = expected[k] * n;
            if (e < 5.0) {  // cells outside the ellipse (or never reached) must stay empty
                EXPECT_LE(count[k], int(std::ceil(5.0 + 4.0 * std::sqrt(5.0)))) << "cell " << k;
                continue;
            }
            chi2 += (count[k] - e) * (count[k] - e) / e;
            ++dof;
        }
        EXPECT_LT(chi2, 120.0) << "dof " << dof;
    }
}

// From behind or in its plane a lamp gives nothing (one-sided), by either sampler.
TEST(SizedLights, AreaLampIsOneSided) {
    for (const char* shape : {"rectangle", "ellipse"}) {
        const Light l = down_lamp(shape, 2.0, 1.0, 1.0);
        for (const Vec3 p : {Vec3(0, 2, 0), Vec3(0.1f, 1, 0.2f), Vec3(0, 1.5f, 5)}) {
            EXPECT_FALSE(l.sample_li({p, {0, 0, 0}}, {0.3f, 0.6f}).has_value());
            EXPECT_EQ(l.pdf_li({p, {0, 0, 0}}, {0, -1, 0}, {0, 1, 0}, {0, -1, 0}), 0.f);
        }
    }
}

// "camera_visible": a camera looking up at a lamp (radiance L = P / (4A) = 1) sees L in the
// pixels inside it and nothing elsewhere; by default (Blender's) and from behind it sees none.
// Direct and path integrators alike; the lamp is transparent (Cycles): nothing else changes.
TEST(SizedLights, AreaLampCameraVisible) {
    auto render_lamp = [](const std::string& extra, const std::string& integrator, double lamp_y) {
        const std::string body =
            R"("camera": {"position": [0, 0, 0], "look_at": [0, 1, 0], "up": [0, 0, 1],
                          "fov": 90, "width": 8, "height": 8},
               "materials": {}, "shapes": [],
               "lights": [{"type": "area", "shape": "rectangle", "size": 1, "size_y": 1,
                           "power": 4, "position": [0, )" +
            std::to_string(lamp_y) + R"(, 0], "direction": [0, -1, 0])" + extra + "}]";
        const Scene scene = facet::render::testing::scene_from(body);
        return facet::render::render(scene,
                                     facet::render::testing::test_options(integrator, 1, 1, 1));
    };
    for (const char* integrator : {"path", "direct"}) {
        SCOPED_TRACE(integrator);
        // fov 90 at distance 1: the image spans [-1, 1]^2 on the lamp's plane, the lamp the
        // middle half, so the 4 x 4 central pixels (1 spp, jittered within the pixel; those
        // 4 pixels span exactly [-0.5, 0.5]) see it and the border pixels do not.
        const Image seen = render_lamp(R"(, "camera_visible": true)", integrator, 1.0);
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                const bool inside = x >= 2 && x < 6 && y >= 2 && y < 6;
                EXPECT_FLOAT_EQ(seen.at(x, y).g, inside ? 1.f : 0.f) << x << "," << y;
            }
        const Image hidden = render_lamp("", integrator, 1.0);
        const Image behind = render_lamp(R"(, "camera_visible": true)", integrator, -1.0);
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                EXPECT_EQ(hidden.at(x, y).g, 0.f);
                EXPECT_EQ(behind.at(x, y).g, 0.f);
            }
    }
}

// --- Blender's spot form ------------------------------------------------------------------------

namespace {

// Cycles 3.4's spot_light_attenuation, written out here independently of light_units.h.
double cycles_attenuation(double mu, double spot_angle_cos, double spot_smooth) {
    double attenuation = mu;
    if (attenuation <= spot_angle_cos) return 0.0;
    const double t = attenuation - spot_angle_cos;
    if (t < spot_smooth && spot_smooth != 0.0) {
        const double x = t / spot_smooth;
        attenuation *= x * x * (3.0 - 2.0 * x);
    }
    return attenuation;
}

}  // namespace

// A spot in Blender's form (outer_angle = spot_size / 2, spot_blend): the intensity at distance
// 1 follows Cycles' attenuation g(mu) (relative 1e-5: float round-off of cos and li), and the
// total power, integrated numerically over mu (midpoint rule, 2e5 cells), is Phi to 1e-4. The
// on-axis K of a Blender lamp of power P, K = P / (4 pi), gives Phi = P / 2 int g.
TEST(SizedLights, SpotBlenderFormFollowsCycles) {
    for (double blend : {0.0, 0.15, 1.0}) {
        SCOPED_TRACE(blend);
        const double outer = 40.0, phi = 10.0;
        const Light l = lamp(R"({"type": "spot", "position": [0, 0, 0], "direction": [0, 0, -1],
                                 "power": 10, "outer_angle": 40, "spot_blend": )" +
                             std::to_string(blend) + "}");
        const double c = std::cos(outer * kPiD / 180.0), s = (1.0 - c) * blend;
        const int n = 200000;
        double total = 0.0, g_integral = 0.0, k = 0.0;
        for (int i = 0; i < n; ++i) {
            const double mu = -1.0 + 2.0 * (i + 0.5) / n;
            const Vec3 p(float(std::sqrt(1 - mu * mu)), 0.f, float(-mu));
            const auto smp = l.sample_li({p, {0, 0, 0}}, {0.5f, 0.5f});
            const double intensity = smp ? double(smp->li.r) : 0.0;
            total += intensity * 2.0 * kPiD * (2.0 / n);
            g_integral += cycles_attenuation(mu, c, s) * (2.0 / n);
            if (mu > 0.9 && mu < 0.9 + 2.0 / n) k = intensity / cycles_attenuation(mu, c, s);
        }
        ASSERT_GT(k, 0.0);  // the cell at mu = 0.9 was found
        EXPECT_NEAR(total / phi, 1.0, 1e-4);
        for (double mu : {0.99, c + 0.5 * s, c + 0.9 * s, 0.8, c + 1e-3}) {
            const Vec3 p(float(std::sqrt(1 - mu * mu)), 0.f, float(-mu));
            const auto smp = l.sample_li({p, {0, 0, 0}}, {0.5f, 0.5f});
            const double want = k * cycles_attenuation(mu, c, s);
            EXPECT_NEAR(smp ? smp->li.r : 0.0, want, 1e-5 * k + 1e-4 * want) << mu;
        }
        EXPECT_FALSE(l.sample_li({{1, 0, -0.5f}, {0, 0, 0}}, {0.5f, 0.5f}).has_value());
        // Blender's lamp of power P: K = P / (4 pi) when Phi = P / 2 int g.
        const double p_blender = 2.0 * phi / g_integral;
        EXPECT_NEAR(k / (p_blender / (4.0 * kPiD)), 1.0, 1e-4);
    }
    expect_error(R"({"type": "spot", "position": [0, 5, 0], "direction": [0, -1, 0],
                          "power": 1, "outer_angle": 30, "spot_blend": 1.5})",
                 "/lights/0/spot_blend");
    expect_error(R"({"type": "spot", "position": [0, 5, 0], "direction": [0, -1, 0],
                          "power": 1, "outer_angle": 30, "inner_angle": 10, "spot_blend": 0.5})",
                 "/lights/0/spot_blend: give inner_angle or spot_blend");
    expect_error(R"({"type": "spot", "position": [0, 5, 0], "direction": [0, -1, 0],
                          "power": 1, "outer_angle": 100, "spot_blend": 0.5})",
                 "/lights/0/outer_angle: must be <= 90");
    expect_error(R"({"type": "spot", "position": [0, 5, 0], "direction": [0, -1, 0],
                          "power": 1, "outer_angle": 30, "spot_blend": 0.5})",
                 "/lights/0/spot_blend", true);
}
