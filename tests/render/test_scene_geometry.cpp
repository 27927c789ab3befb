// Geometry and light tests: exact sphere/plane/disc intersection accuracy, Embree mesh hits,
// robust ray offsets, the camera mapping, and light sampling (pdf consistency, analytic
// irradiance, power normalisation).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "facet/render/mesh.h"
#include "facet/render/scene.h"
#include "facet/sampling.h"
#include "facet/testsupport/render_test_util.h"

using namespace facet;
using namespace facet::render;

namespace {

std::string wrap(
    const std::string& shapes,
    const std::string& lights = R"([{"type": "point", "position": [0, 50, 0], "power": 100}])") {
    return R"({"format": "facet-scene", "version": 1,
      "camera": {"position": [0, 0, 10], "look_at": [0, 0, 0], "fov": 40, "width": 64, "height": 48},
      "materials": {"white": {"model": "lambert", "reflectance": 0.5}},
      "shapes": )" +
           shapes + R"(, "lights": )" + lights + "}";
}

Vec3 random_unit(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.f, 1.f);
    return sample_uniform_sphere({u(rng), u(rng)});
}

}  // namespace

// --- camera ---------------------------------------------------------------------------------

TEST(Camera, PixelConventions) {
    Camera c = Camera::make({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60.f, 400, 200);
    // Image centre looks straight ahead.
    Ray r = c.generate_ray({200.f, 100.f});
    EXPECT_NEAR(r.d.z, -1.f, 1e-7f);
    // The top edge of the image (film y = 0) is fov/2 above the axis; the left edge (x = 0) is
    // fov_x/2 to the left with tan(fov_x/2) = aspect tan(fov_y/2).
    Ray top = c.generate_ray({200.f, 0.f});
    EXPECT_NEAR(std::atan2(top.d.y, -top.d.z), 30.f * kPi / 180.f, 1e-6f);
    Ray left = c.generate_ray({0.f, 100.f});
    EXPECT_NEAR(-left.d.x / -left.d.z, 2.f * std::tan(30.f * kPi / 180.f), 1e-6f);
    // x to the right (+x world), y down.
    EXPECT_GT(c.generate_ray({300.f, 100.f}).d.x, 0.f);
    EXPECT_LT(c.generate_ray({200.f, 150.f}).d.y, 0.f);
    // project() inverts generate_ray at pixel centres (x + 0.5, y + 0.5); tolerance: float
    // round-off of a normalise + 3 dots, ~1e-4 px on a 400 px image.
    for (int y = 0; y < 200; y += 37) {
        for (int x = 0; x < 400; x += 41) {
            Vec2 film(float(x) + 0.5f, float(y) + 0.5f);
            Ray ray = c.generate_ray(film);
            auto back = c.project(ray.o + 3.f * ray.d);
            ASSERT_TRUE(back.has_value());
            EXPECT_NEAR(back->x, film.x, 1e-3f);
            EXPECT_NEAR(back->y, film.y, 1e-3f);
        }
    }
    EXPECT_FALSE(c.project({0, 0, 1}).has_value());
}

// --- exact analytic shapes -----------------------------------------------------------------

// Rays at a sphere far from the origin: every hit lies on the exact sphere to float round-off
// of the point itself (a few ulps of |p|), and t matches a double-precision reference.
TEST(Geometry, ExactSphereIntersection) {
    const Vec3 c(1000.f, -2000.f, 500.f);
    const float radius = 0.75f;
    Scene s = load_scene_from_string(
        wrap(R"([{"type": "sphere", "center": [1000, -2000, 500], "radius": 0.75,
                  "material": "white"}])"),
        "t.json");
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    int hits = 0;
    double worst_radial = 0.0, worst_t = 0.0;
    for (int i = 0; i < 2000; ++i) {
        // From a random point ~10 away toward a random point inside the sphere's silhouette.
        Vec3 o = c + 10.f * random_unit(rng);
        Vec3 target = c + 0.99f * radius * Vec3(u(rng), u(rng), u(rng)) / std::sqrt(3.f);
        Ray r{o, glm::normalize(target - o), kInfinity};
        SurfaceHit h;
        ASSERT_TRUE(s.intersect(r, h));
        ++hits;
        glm::dvec3 p(h.p), cd(c);
        worst_radial = std::max(worst_radial, std::fabs(glm::length(p - cd) - radius));
        // Double reference.
        glm::dvec3 od(r.o), dd(r.d);
        glm::dvec3 oc = od - cd;
        // |d| is 1 only to float round-off: solve a t^2 + 2 b t + c = 0 with a = |d|^2.
        double a = glm::dot(dd, dd);
        double b = glm::dot(oc, dd), cc = glm::dot(oc, oc) - double(radius) * radius;
        double t_ref = (-b - std::sqrt(b * b - a * cc)) / a;
        worst_t = std::max(worst_t, std::fabs(double(h.t) - t_ref));
        EXPECT_NEAR(glm::length(h.ng), 1.f, 1e-6f);
        EXPECT_GT(glm::dot(h.ng, glm::normalize(h.p - c)), 0.99999f);
    }
    EXPECT_EQ(hits, 2000);
    std::printf("sphere at |c| ~ 2300: max | |p - c| - r | = %.3g, max |t - t_ref| = %.3g\n",
                worst_radial, worst_t);
    // |p| ~ 2300: one float ulp there is 2.4e-4; allow 2 ulps. A float-only quadratic would be
    // off by ~1e-1 here (catastrophic cancellation of |o - c|^2 - r^2 at |o| ~ 2300).
    EXPECT_LT(worst_radial, 5e-4) << "hit points off the sphere";
    // t ~ 10: the only error left is rounding t to float (half an ulp, 5e-7); allow 2 ulps.
    EXPECT_LT(worst_t, 2e-6);
}

TEST(Geometry, SphereMissesAndInsideHits) {
    Scene s = load_scene_from_string(
        wrap(R"([{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"}])"),
        "t.json");
    SurfaceHit h;
    // Just above the tangent: miss; just below: hit.
    EXPECT_FALSE(s.intersect({{-5.f, 1.0001f, 0.f}, {1.f, 0.f, 0.f}, kInfinity}, h));
    EXPECT_TRUE(s.intersect({{-5.f, 0.9999f, 0.f}, {1.f, 0.f, 0.f}, kInfinity}, h));
    // From inside: hits the far side, normal still outward (not flipped).
    ASSERT_TRUE(s.intersect({{0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, kInfinity}, h));
    EXPECT_NEAR(h.t, 1.f, 1e-6f);
    EXPECT_NEAR(h.ng.z, 1.f, 1e-6f);
    // tmax is respected.
    EXPECT_FALSE(s.intersect({{0.f, 0.f, -5.f}, {0.f, 0.f, 1.f}, 3.9f}, h));
    EXPECT_TRUE(s.intersect({{0.f, 0.f, -5.f}, {0.f, 0.f, 1.f}, 4.1f}, h));
    EXPECT_NEAR(h.t, 4.f, 1e-6f);
}

TEST(Geometry, ExactPlaneAndDisc) {
    Scene s = load_scene_from_string(
        wrap(R"([{"type": "plane", "point": [0, -1, 0], "normal": [0, 1, 0], "material": "white",
                  "transform": {"rotate": {"axis": [1, 0, 0], "angle": 10}}},
                 {"type": "disc", "center": [0, 0, 3], "normal": [0, 0, 1], "radius": 0.5,
                  "material": "white"}])"),
        "t.json");
    // The plane after the rotation: normal R (0,1,0), through R (0,-1,0).
    float a = 10.f * kPi / 180.f;
    glm::dvec3 n(0.0, std::cos(double(a)), std::sin(double(a)));
    glm::dvec3 q = -n;
    std::mt19937 rng(3);
    double worst = 0.0;
    int hits = 0;
    for (int i = 0; i < 1000; ++i) {
        Vec3 d = random_unit(rng);
        Ray r{Vec3(0.f, 2.f, 0.f), d, kInfinity};
        SurfaceHit h;
        if (!s.intersect(r, h) || h.shape != 0) continue;
        ++hits;
        worst = std::max(worst, std::fabs(glm::dot(glm::dvec3(h.p) - q, n)));
        EXPECT_NEAR(glm::dot(glm::dvec3(h.ng), n), 1.0, 1e-6);
    }
    EXPECT_GT(hits, 300);
    std::printf("plane: max distance of hit points to the exact plane = %.3g\n", worst);
    // Far grazing hits sit at |p| up to ~1e4: the distance to the exact plane is bounded by
    // float round-off of p (1 ulp of 1e4 = 1e-3), not by the ray's parameterisation.
    EXPECT_LT(worst, 2e-3);
    // Disc: inside the radius hits, outside misses (the plane behind catches nothing here).
    SurfaceHit h;
    ASSERT_TRUE(s.intersect({{0.49f, 0.f, 10.f}, {0.f, 0.f, -1.f}, kInfinity}, h));
    EXPECT_EQ(h.shape, 1u);
    EXPECT_NEAR(h.t, 7.f, 1e-6f);
    EXPECT_EQ(h.ng, Vec3(0, 0, 1));
    EXPECT_FALSE(s.intersect({{0.51f, 0.f, 10.f}, {0.f, 0.f, -1.f}, 20.f}, h) && h.shape == 1u);
}

// --- Embree triangle meshes -----------------------------------------------------------------

TEST(Geometry, EmbreeMeshHits) {
    Scene s = load_scene_from_string(
        wrap(R"([{"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1], "material": "white"},
                 {"type": "icosphere", "center": [5, 0, 0], "radius": 1, "subdivisions": 3,
                  "material": "white"},
                 {"type": "mesh", "positions": [10,0,0, 11,0,0, 10,1,0], "indices": [0, 1, 2],
                  "normals": [0,0,1, 0,0,1, 0,0,1], "material": "white",
                  "transform": {"scale": [-1, 1, 1]}}])"),
        "t.json");
    SurfaceHit h;
    // Box faces: outward geometric normals, exact t.
    const Vec3 dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const Vec3& d : dirs) {
        ASSERT_TRUE(s.intersect(
            {-4.f * d + Vec3(0.f, 0.f, 0.f) + 0.3f * Vec3(d.y, d.z, d.x), d, kInfinity}, h));
        EXPECT_EQ(h.shape, 0u);
        EXPECT_NEAR(h.t, 3.f, 1e-6f);
        EXPECT_NEAR(glm::dot(h.ng, -d), 1.f, 1e-6f);
        EXPECT_NEAR(glm::dot(h.p, -d), 1.f, 1e-6f);
    }
    // Icosphere (smooth): shading normal near the radial direction, geometric outward; the hit
    // is between the inscribed and circumscribed radius of the tessellation.
    ASSERT_TRUE(s.intersect({{5.f, 0.2f, 5.f}, {0.f, 0.f, -1.f}, kInfinity}, h));
    EXPECT_EQ(h.shape, 1u);
    float rad = glm::length(h.p - Vec3(5, 0, 0));
    EXPECT_GT(rad, 0.98f);
    EXPECT_LE(rad, 1.f + 1e-6f);
    EXPECT_GT(glm::dot(h.ns, glm::normalize(h.p - Vec3(5, 0, 0))), 0.9999f);
    EXPECT_GT(glm::dot(h.ng, h.ns), 0.99f);
    // The mirrored triangle (scale x by -1) keeps its front: ng = +z as authored.
    ASSERT_TRUE(s.intersect({{-10.2f, 0.2f, 5.f}, {0.f, 0.f, -1.f}, kInfinity}, h));
    EXPECT_EQ(h.shape, 2u);
    EXPECT_NEAR(h.ng.z, 1.f, 1e-6f);
    EXPECT_NEAR(h.ns.z, 1.f, 1e-6f);
    EXPECT_NEAR(h.p.x, -10.2f, 1e-5f);
}

// Rays leaving a surface through spawn_ray never re-hit it (sphere: convex, so any outgoing
// ray into the outer hemisphere must escape), and a shadow ray to a light sample on an emitter
// is not blocked by the emitter itself.
TEST(Geometry, RobustOffsetsNoSelfIntersection) {
    Scene s = load_scene_from_string(
        wrap(R"([{"type": "sphere", "center": [300, 200, -100], "radius": 2, "material": "white"},
                 {"type": "icosphere", "center": [-300, 0, 0], "radius": 2, "subdivisions": 4,
                  "material": "white"}])"),
        "t.json");
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    int self_hits = 0, n = 0;
    for (Vec3 c : {Vec3(300, 200, -100), Vec3(-300, 0, 0)}) {
        for (int i = 0; i < 2000; ++i) {
            Vec3 dir_in = random_unit(rng);
            SurfaceHit h;
            if (!s.intersect({c + 10.f * dir_in, -dir_in, kInfinity}, h)) continue;
            Frame f = Frame::from_z(h.ng);
            Vec3 d = f.from_local(sample_uniform_hemisphere({u(rng), u(rng)}));
            if (glm::dot(d, h.ng) < 1e-3f) continue;  // grazing tangent rays may legally re-hit
            SurfaceHit h2;
            ++n;
            if (s.intersect(Scene::spawn_ray(h, d), h2)) ++self_hits;
            LightLiSample toward;  // a directional light's sample: a ray to infinity
            toward.wi = d;
            toward.dist = kInfinity;
            if (s.occluded(h, toward)) ++self_hits;
        }
    }
    EXPECT_GT(n, 3000);
    EXPECT_EQ(self_hits, 0);
}

TEST(Geometry, OcclusionAndAreaLightShadowRays) {
    Scene s = load_scene_from_string(
        wrap(R"([{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "white"},
                 {"type": "sphere", "center": [0, 2, 0], "radius": 0.5, "material": "white"},
                 {"type": "quad", "vertices": [[-1,4,-1], [1,4,-1], [1,4,1], [-1,4,1]],
                  "emission": 10}])",
             "[]"),
        "t.json");
    ASSERT_EQ(s.lights().size(), 1u);
    const Light& light = s.lights()[0];
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    // From a floor point far to the side, no sample is blocked: the quad itself must never
    // shadow its own sample (the shadow ray stops short of it).
    LightSampleContext ctx{{3.f, 0.f, 0.f}, {0.f, 1.f, 0.f}};
    for (int i = 0; i < 500; ++i) {
        auto ls = light.sample_li(ctx, {u(rng), u(rng)});
        ASSERT_TRUE(ls.has_value());
        EXPECT_FALSE(s.occluded(ctx.p, Vec3(0, 1, 0), ls->wi, ls->dist));
    }
    // Straight below the sphere, the centre of the light is blocked.
    Vec3 p(0.f, 0.f, 0.f);
    EXPECT_TRUE(s.occluded(p, Vec3(0, 1, 0), Vec3(0, 1, 0), 4.f));
    // ... but not if the shadow ray ends before the sphere.
    EXPECT_FALSE(s.occluded(p, Vec3(0, 1, 0), Vec3(0, 1, 0), 1.4f));
    // Hitting the quad from below: emitted radiance toward the ray, light index set.
    SurfaceHit h;
    ASSERT_TRUE(s.intersect({{0.9f, 3.f, 0.9f}, {0.f, 1.f, 0.f}, kInfinity}, h));
    EXPECT_EQ(h.light, 0);
    EXPECT_EQ(h.emitted_radiance, Rgb(10.f));
    EXPECT_NEAR(h.ng.y, -1.f, 1e-6f);
    // From above (the back of the one-sided emitter): no emission.
    ASSERT_TRUE(s.intersect({{0.9f, 5.f, 0.9f}, {0.f, -1.f, 0.f}, kInfinity}, h));
    EXPECT_EQ(h.emitted_radiance, Rgb(0.f));
}

// --- lights ---------------------------------------------------------------------------------

TEST(Lights, PointLightIrradianceEq240) {
    // E = Phi cos theta / (4 pi r^2), Cohen & Wallace eq. 2.40; tolerance: float round-off.
    Light l = Light::point({0, 3, 0}, Rgb(100.f, 50.f, 25.f));
    LightSampleContext ctx{{4.f, 0.f, 0.f}, {0.f, 1.f, 0.f}};
    auto s = l.sample_li(ctx, {0.5f, 0.5f});
    ASSERT_TRUE(s.has_value());
    EXPECT_TRUE(s->delta);
    EXPECT_EQ(s->pdf, 1.f);
    EXPECT_NEAR(s->dist, 5.f, 1e-6f);
    float cos_t = glm::dot(s->wi, ctx.n);
    EXPECT_NEAR(cos_t, 0.6f, 1e-6f);
    Rgb e = s->li * cos_t;
    EXPECT_NEAR(e.r, 100.f * 0.6f / (4.f * kPi * 25.f), 1e-6f);
    EXPECT_NEAR(e.g, 50.f * 0.6f / (4.f * kPi * 25.f), 1e-6f);
    EXPECT_EQ(l.pdf_li(ctx, s->wi, s->p_light, s->n_light), 0.f);
}

TEST(Lights, SpotPowerIsExact) {
    // Integrate I(theta) over the sphere numerically (Gauss-like fine midpoint rule in cos):
    // must give Phi back; tolerance 1e-4 relative covers the midpoint rule's error on the kink.
    Light l = Light::spot({0, 0, 0}, {0, 0, -1}, Rgb(10.f), 20.f, 35.f);
    const int n = 200000;
    double total = 0.0;
    for (int i = 0; i < n; ++i) {
        double mu = -1.0 + 2.0 * (i + 0.5) / n;                  // cos of the angle to the axis
        Vec3 p(float(std::sqrt(1 - mu * mu)), 0.f, float(-mu));  // point at distance 1
        auto s = l.sample_li({p, {0, 0, 0}}, {0.5f, 0.5f});
        double intensity = s ? double(s->li.r) : 0.0;  // li = I / r^2 with r = 1
        total += intensity * 2.0 * kPiD * (2.0 / n);
    }
    EXPECT_NEAR(total / 10.0, 1.0, 1e-4);
    // Outside the outer cone nothing arrives.
    EXPECT_FALSE(l.sample_li({{0, 0, 1}, {0, 0, 0}}, {0.5f, 0.5f}).has_value());
}

TEST(Lights, DirectionalAndEnvironment) {
    Light d = Light::directional({0, -1, 0}, Rgb(3.f));
    auto s = d.sample_li({{0, 0, 0}, {0, 1, 0}}, {0.2f, 0.7f});
    ASSERT_TRUE(s);
    EXPECT_EQ(s->wi, Vec3(0, 1, 0));
    EXPECT_EQ(s->li, Rgb(3.f));
    EXPECT_TRUE(std::isinf(s->dist));
    // Environment with cosine sampling: E = pi L by MC, exact per sample (li cos / pdf = pi L).
    Light env = Light::environment(Rgb(2.f));
    LightSampleContext ctx{{0, 0, 0}, glm::normalize(Vec3(1, 2, 3))};
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (int i = 0; i < 100; ++i) {
        auto e = env.sample_li(ctx, {u(rng), u(rng)});
        if (!e) continue;
        float est = e->li.r * glm::dot(e->wi, ctx.n) / e->pdf;
        EXPECT_NEAR(est, 2.f * kPi, 1e-4f);
        EXPECT_NEAR(env.pdf_li(ctx, e->wi, {}, {}), e->pdf, 1e-5f * e->pdf);
    }
}

// For area lights: the pdf returned by sample_li equals pdf_li at the same point; E[1/pdf] is
// the solid angle the light subtends, and E[L cos/pdf] the irradiance, both against analytic
// values. Tolerances: 4 standard errors of the MC estimate (computed from the samples).
namespace {

using facet::render::testing::mc;

Vec2 halton2(int i) {
    auto radical = [](int n, int base) {
        double f = 1.0, r = 0.0;
        while (n > 0) {
            f /= base;
            r += f * (n % base);
            n /= base;
        }
        return float(r);
    };
    return {radical(i + 1, 2), radical(i + 1, 3)};
}

}  // namespace

TEST(Lights, AreaLightPdfConsistencyAndIrradiance) {
    const double d = 2.0, R = 0.5;
    // Disc of radius R facing down at height d above the origin; a quad (two triangles) of the
    // same area; a sphere of radius R at height d.
    Light disc =
        Light::area_disc({0, float(d), 0}, {float(R), 0, 0}, {0, 0, float(R)}, Rgb(1.f), 0);
    ASSERT_LT(glm::dot(glm::cross(Vec3(1, 0, 0), Vec3(0, 0, 1)), Vec3(0, 1, 0)), 0.f);
    float h = float(R * std::sqrt(kPiD) / 2.0);  // square of area pi R^2
    std::vector<Vec3> tri = {{-h, float(d), -h}, {h, float(d), -h}, {h, float(d), h},
                             {-h, float(d), -h}, {h, float(d), h},  {-h, float(d), h}};
    Light quad = Light::area_triangles(tri, Rgb(1.f), 1);
    Light sphere = Light::area_sphere({0, float(d), 0}, float(R), Rgb(1.f), 2);
    EXPECT_NEAR(quad.area(), kPi * R * R, 1e-5);
    EXPECT_NEAR(disc.area(), kPi * R * R, 1e-5);

    LightSampleContext ctx{{0, 0, 0}, {0, 1, 0}};
    const int n = 20000;
    for (const Light* l : {&disc, &quad, &sphere}) {
        SCOPED_TRACE(int(l->shape()));
        auto one_over_pdf = mc(n, [&](int i) {
            auto s = l->sample_li(ctx, halton2(i));
            if (!s) return 0.0;
            float pdf2 = l->pdf_li(ctx, s->wi, s->p_light, s->n_light);
            EXPECT_NEAR(pdf2, s->pdf, 1e-3f * s->pdf);
            // The sampled point is on the light and wi points at it.
            EXPECT_NEAR(glm::length(ctx.p + s->dist * s->wi - s->p_light), 0.f, 1e-5f);
            return 1.0 / double(s->pdf);
        });
        auto irradiance = mc(n, [&](int i) {
            auto s = l->sample_li(ctx, halton2(i));
            return s ? double(s->li.r) * glm::dot(s->wi, ctx.n) / s->pdf : 0.0;
        });
        double omega, e;
        if (l == &sphere) {
            double cos_max = std::sqrt(1.0 - R * R / (d * d));
            omega = 2.0 * kPiD * (1.0 - cos_max);
            e = kPiD * R * R / (d * d);  // sphere: E = pi L sin^2(theta_max)
        } else if (l == &disc) {
            omega = 2.0 * kPiD * (1.0 - d / std::sqrt(d * d + R * R));
            e = kPiD * R * R / (d * d + R * R);  // on-axis disc (unit-sphere method)
        } else {
            omega = -1.0;  // square: no simple closed form for the solid angle
            e = -1.0;
        }
        if (omega > 0) {
            EXPECT_NEAR(one_over_pdf.mean, omega, 4.0 * one_over_pdf.stderr_ + 1e-6 * omega);
            EXPECT_NEAR(irradiance.mean, e, 4.0 * irradiance.stderr_ + 1e-6 * e);
        } else {
            // Square of half-side h at distance d, on axis: four rectangles with a corner over
            // the point; differential-to-parallel-rectangle form factor (Howell's catalogue,
            // C-11), E = pi L F = 4 L x / sqrt(1 + x^2) atan(x / sqrt(1 + x^2)), x = h / d.
            double x = double(h) / d;
            double ff = 4.0 * x / std::sqrt(1 + x * x) * std::atan(x / std::sqrt(1 + x * x));
            EXPECT_NEAR(irradiance.mean, ff, 4.0 * irradiance.stderr_ + 1e-6);
        }
        EXPECT_GT(l->power(1.f).r, 0.f);
    }
    // The back side of a one-sided emitter gets nothing; pdf_li agrees.
    LightSampleContext above{{0, 5, 0}, {0, -1, 0}};
    EXPECT_FALSE(disc.sample_li(above, {0.3f, 0.3f}).has_value());
    EXPECT_EQ(disc.pdf_li(above, {0, -1, 0}, {0, float(d), 0}, {0, -1, 0}), 0.f);
}

TEST(Lights, TinyDistantSphereKeepsPrecision) {
    // A sphere subtending ~1e-10 sr: 1 - cos(theta_max) is formed without cancellation, so the
    // pdf is finite and E = pi L sin^2 is recovered per sample to 1e-3.
    Light l = Light::area_sphere({0, 1e4f, 0}, 0.1f, Rgb(1.f), 0);
    LightSampleContext ctx{{0, 0, 0}, {0, 1, 0}};
    auto s = l.sample_li(ctx, {0.3f, 0.6f});
    ASSERT_TRUE(s);
    double e = s->li.r * glm::dot(s->wi, ctx.n) / s->pdf;
    EXPECT_NEAR(e / (kPiD * 0.01 / 1e8), 1.0, 1e-3);
}

// --- mesh files -----------------------------------------------------------------------------

TEST(MeshFiles, PlyAsciiAndBinary) {
    std::string ascii =
        "ply\nformat ascii 1.0\ncomment x\nelement vertex 4\nproperty float x\nproperty float "
        "y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
        "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
    TriangleMesh m = parse_ply(ascii);
    EXPECT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.num_triangles(), 2u);
    EXPECT_EQ(validate_mesh(m), "");

    std::string bin =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty "
        "double y\nproperty double z\nproperty float nx\nproperty float ny\nproperty float nz\n"
        "element face 1\nproperty list uchar uint vertex_indices\nend_header\n";
    auto put = [&](const void* p, size_t n) { bin.append(static_cast<const char*>(p), n); };
    double pos[3][3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
    for (auto& v : pos) {
        put(v, 24);
        float nrm[3] = {0, 0, 2};
        put(nrm, 12);
    }
    unsigned char c = 3;
    put(&c, 1);
    std::uint32_t idx[3] = {0, 1, 2};
    put(idx, 12);
    m = parse_ply(bin);
    ASSERT_EQ(m.positions.size(), 3u);
    EXPECT_EQ(m.positions[1], Vec3(2, 0, 0));
    ASSERT_EQ(m.normals.size(), 3u);
    EXPECT_EQ(m.normals[0], Vec3(0, 0, 1));
    EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2}));

    // Truncated and lying files are errors, not crashes.
    EXPECT_THROW(parse_ply(bin.substr(0, bin.size() - 3)), std::runtime_error);
    std::string lie = ascii;
    lie.replace(lie.find("vertex 4"), 8, "vertex 4000000000");
    EXPECT_THROW(parse_ply(lie), std::runtime_error);
    EXPECT_THROW(parse_ply("ply\nformat binary_big_endian 1.0\nend_header\n"), std::runtime_error);
}

TEST(MeshFiles, ObjAndPlyThroughTheLoader) {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("facet_scene_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    {
        std::ofstream(dir / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
                                          "f 1//1 2//1 3//1 4//1\n";
        std::ofstream(dir / "tri.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty "
                                          "float x\nproperty float y\nproperty float z\nelement "
                                          "face 1\nproperty list uchar int vertex_indices\n"
                                          "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        std::ofstream(dir / "scene.json") << wrap(
            R"([{"type": "mesh", "file": "tri.obj", "material": "white"},
                {"type": "mesh", "file": "tri.ply", "material": "white",
                 "transform": {"translate": [5, 0, 0]}}])");
    }
    Scene s = load_scene((dir / "scene.json").string());
    EXPECT_EQ(s.shapes()[0].triangles, 2u);
    EXPECT_EQ(s.shapes()[1].triangles, 1u);
    SurfaceHit h;
    ASSERT_TRUE(s.intersect({{5.2f, 0.2f, 3.f}, {0.f, 0.f, -1.f}, kInfinity}, h));
    EXPECT_EQ(h.shape, 1u);
    ASSERT_TRUE(s.intersect({{0.8f, 0.7f, 3.f}, {0.f, 0.f, -1.f}, kInfinity}, h));
    EXPECT_EQ(h.shape, 0u);
    EXPECT_NEAR(h.ns.z, 1.f, 1e-6f);
    fs::remove_all(dir);
}

TEST(MeshFiles, ProceduralCounts) {
    EXPECT_EQ(make_icosphere(0, false).num_triangles(), 20u);
    TriangleMesh ico = make_icosphere(3, true);
    EXPECT_EQ(ico.num_triangles(), 20u * 64u);
    EXPECT_EQ(ico.positions.size(), 10u * 64u + 2u);  // Euler: V = 10 * 4^s + 2
    // Every triangle faces outward.
    for (size_t i = 0; i < ico.indices.size(); i += 3) {
        const Vec3 &a = ico.positions[ico.indices[i]], &b = ico.positions[ico.indices[i + 1]],
                   &c = ico.positions[ico.indices[i + 2]];
        ASSERT_GT(glm::dot(glm::cross(b - a, c - a), a + b + c), 0.f);
    }
    TriangleMesh g = make_grid(7, 5, 0.f, 0.f);
    EXPECT_EQ(g.num_triangles(), 70u);
    EXPECT_EQ(validate_mesh(g), "");
    TriangleMesh box = make_box({0, 0, 0}, {1, 2, 3});
    Vec3 c(0.5f, 1.f, 1.5f);
    for (size_t i = 0; i < box.indices.size(); i += 3) {
        const Vec3 &a = box.positions[box.indices[i]], &b = box.positions[box.indices[i + 1]],
                   &cc = box.positions[box.indices[i + 2]];
        ASSERT_GT(glm::dot(glm::cross(b - a, cc - a), (a + b + cc) / 3.f - c), 0.f);
    }
}

// "flip_normals" turns a sphere inside out (normals, emission and light sampling face the
// centre); a mirroring transform does not (it keeps the authored front side), and emissive discs
// under such transforms sample the same side the hits report.
TEST(Geometry, FlipNormalsAndMirroringTransforms) {
    Scene s = load_scene_from_string(
        wrap(R"([{"type": "sphere", "center": [0, 0, 0], "radius": 2, "flip_normals": true,
                  "emission": 0.5, "material": "white"},
                 {"type": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 0.2,
                  "emission": 1, "transform": {"scale": [1, 1, -1]}},
                 {"type": "sphere", "center": [0, 0, 0], "radius": 0.1, "material": "white",
                  "transform": {"scale": -1}}])",
             "[]"),
        "t.json");
    SurfaceHit h;
    ASSERT_TRUE(s.intersect({{0.f, 0.f, 0.5f}, {1.f, 0.f, 0.f}, kInfinity}, h));
    EXPECT_EQ(h.shape, 0u);
    EXPECT_NEAR(glm::dot(h.ng, -glm::normalize(h.p)), 1.f, 1e-6f);  // inward
    EXPECT_EQ(h.emitted_radiance, Rgb(0.5f));
    // The inside-out sphere's light: samples from inside, pdf_li agrees, E[L cos / pdf] over
    // the hemisphere = pi L (the whole hemisphere is the emitter).
    const Light& big = s.lights()[std::size_t(s.shapes()[0].light)];
    LightSampleContext ctx{{0.f, 0.5f, 0.f}, {0.f, 1.f, 0.f}};
    double sum = 0.0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        auto ls = big.sample_li(ctx, halton2(i));
        if (!ls) continue;
        EXPECT_NEAR(big.pdf_li(ctx, ls->wi, ls->p_light, ls->n_light), ls->pdf, 1e-3f * ls->pdf);
        float c = glm::dot(ls->wi, ctx.n);
        if (c > 0.f) sum += double(ls->li.r) * c / ls->pdf;
    }
    // Tolerance 2%: uniform-area sampling of a sphere seen from off-centre, 2e4 Halton samples.
    EXPECT_NEAR(sum / n, kPiD * 0.5, 0.02 * kPiD * 0.5);
    EXPECT_FALSE(big.sample_li({{0.f, 3.f, 0.f}, {0.f, 1.f, 0.f}}, {0.5f, 0.5f}).has_value());
    // The disc mirrored in z faces -z: hit from -z it emits, and its light agrees.
    ASSERT_TRUE(s.intersect({{0.15f, 0.05f, -1.f}, {0.f, 0.f, 1.f}, 1.5f}, h));
    EXPECT_EQ(h.shape, 1u);
    EXPECT_NEAR(h.ng.z, -1.f, 1e-6f);
    EXPECT_EQ(h.emitted_radiance, Rgb(1.f));
    const Light& disc = s.lights()[std::size_t(s.shapes()[1].light)];
    auto ls = disc.sample_li({{0.f, 0.f, -1.f}, {0.f, 0.f, 1.f}}, {0.3f, 0.4f});
    ASSERT_TRUE(ls.has_value());
    EXPECT_NEAR(ls->n_light.z, -1.f, 1e-6f);
    // scale -1 on a sphere keeps its normals outward.
    ASSERT_TRUE(s.intersect({{0.f, 0.f, 0.05f}, {0.f, 1.f, 0.f}, 1.f}, h));
    EXPECT_EQ(h.shape, 2u);
    EXPECT_GT(glm::dot(h.ng, h.p), 0.f);
}

TEST(Geometry, EmptySceneHitsNothing) {
    Scene s;
    SurfaceHit h;
    EXPECT_FALSE(s.intersect({{0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, kInfinity}, h));
    EXPECT_FALSE(s.occluded({0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, {0.f, 0.f, 1.f}, kInfinity));
    EXPECT_EQ(s.lights().size(), 0u);
    EXPECT_EQ(s.environment(), nullptr);
}

// A point on (or rounded to just outside) an emitting sphere gets no light from that sphere: a
// convex emitter cannot light itself. Without the guard, the sample lands at distance ~0, no
// shadow ray can block it, and the sphere glows from the back (a bias seen as a furnace error).
TEST(Lights, EmittingSphereDoesNotLightItself) {
    Light l = Light::area_sphere({0, 0, 0}, 1.f, Rgb(1.f), 0);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    int lit = 0;
    for (int i = 0; i < 1000; ++i) {
        Vec3 n = random_unit(rng);
        Vec3 p = n * (1.f + 2e-7f * float(i % 5));  // on the surface, up to a few ulps outside
        if (l.sample_li({p, n}, {u(rng), u(rng)})) ++lit;
        EXPECT_EQ(l.pdf_li({p, n}, -n, -n, n), 0.f);
    }
    EXPECT_EQ(lit, 0);
    // A point a little way off still sees it.
    EXPECT_TRUE(l.sample_li({{0.f, 0.f, 1.01f}, {0.f, 0.f, 1.f}}, {0.5f, 0.5f}).has_value());
}

// The benchmark peer (bare Embree calls) sees the same geometry as Scene::intersect/occluded.
TEST(Geometry, TraceRawAgreesWithIntersect) {
    Scene s = load_scene_from_string(
        wrap(R"([{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"},
                 {"type": "box", "min": [2, -1, -1], "max": [3, 1, 1], "material": "white"}])"),
        "t.json");
    std::mt19937 rng(9);
    std::vector<Ray> rays(4000);
    std::uint64_t hits = 0;
    for (Ray& r : rays) {
        r = {Vec3(1.f, 0.f, 6.f) + random_unit(rng), random_unit(rng), kInfinity};
        SurfaceHit h;
        hits += s.intersect(r, h);
    }
    EXPECT_GT(hits, 0u);
    EXPECT_EQ(s.trace_raw(rays, false), hits);
    EXPECT_EQ(s.trace_raw(rays, true), hits);  // tmax = inf: occluded iff something is hit
}

// Packet queries (Scene::intersect_packet / occluded_packet, rtcIntersect8 / rtcOccluded8) give
// the single-ray answers: the same hits (shape, t, point, normals) and the same occlusion, over
// meshes, exact spheres and discs, and an infinite plane (tested outside Embree); lanes masked
// off are left untouched and rays with tmax <= 0 are not blocked. Random rays, so none grazes
// an edge exactly (where Embree's packet and single-ray kernels may round differently).
TEST(Geometry, PacketQueriesAgreeWithSingleRays) {
    Scene s = load_scene_from_string(
        wrap(R"([{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"},
                 {"type": "box", "min": [2, -1, -1], "max": [3, 1, 1], "material": "white"},
                 {"type": "disc", "center": [-2, 0, 0], "normal": [0, 0, 1], "radius": 0.8,
                  "material": "white"},
                 {"type": "plane", "point": [0, -2, 0], "normal": [0, 1, 0],
                  "material": "white"}])"),
        "t.json");
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    int hits = 0, blocked = 0;
    for (int batch = 0; batch < 500; ++batch) {
        const std::size_t n = 1 + std::size_t(batch) % Scene::kPacketSize;
        std::array<Ray, Scene::kPacketSize> rays;
        std::array<bool, Scene::kPacketSize> active, found, shadowed;
        std::array<SurfaceHit, Scene::kPacketSize> packet_hits;
        for (std::size_t k = 0; k < n; ++k) {
            rays[k] = {Vec3(0.f, 0.f, 5.f) + 3.f * random_unit(rng), random_unit(rng),
                       k % 3 == 0 ? kInfinity : 8.f * u01(rng) - 0.5f};  // some tmax <= 0
            active[k] = (k + std::size_t(batch)) % 4 != 0;
            found[k] = false;
            packet_hits[k].shape = 999u;  // a mark for "untouched"
        }
        RayPacket packet;
        for (std::size_t k = 0; k < n; ++k) packet.set(k, rays[k]);
        s.intersect_packet(packet, n, packet_hits.data(), found.data(), active.data());
        s.occluded_packet(packet, n, active.data(), shadowed.data());
        for (std::size_t k = 0; k < n; ++k) {
            SurfaceHit h;
            const bool f = s.intersect(rays[k], h);
            if (!active[k]) {
                EXPECT_FALSE(found[k]);
                EXPECT_EQ(packet_hits[k].shape, 999u);
                EXPECT_FALSE(shadowed[k]);
                continue;
            }
            ASSERT_EQ(found[k], f) << "batch " << batch << " lane " << k;
            if (f) {
                ++hits;
                EXPECT_EQ(packet_hits[k].shape, h.shape);
                EXPECT_EQ(packet_hits[k].t, h.t);
                EXPECT_EQ(packet_hits[k].p, h.p);
                EXPECT_EQ(packet_hits[k].ng, h.ng);
                EXPECT_EQ(packet_hits[k].ns, h.ns);
            }
            // Occlusion: something on the ray with t < tmax, i.e. a closest hit (intersect
            // searches t in (0, tmax]; t = tmax exactly has probability 0).
            blocked += shadowed[k];
            EXPECT_EQ(shadowed[k], f) << "batch " << batch << " lane " << k;
        }
    }
    EXPECT_GT(hits, 300);
    EXPECT_GT(blocked, 100);
    // Empty packets are allowed and do nothing.
    SurfaceHit h;
    bool f = true;
    s.intersect_packet(RayPacket(), 0, &h, &f);
    EXPECT_TRUE(f);
}

// The Cornell box is closed except for its front (z = 0): a ray from inside moving away from the
// front (d.z > 0) must hit a wall, the floor, the ceiling or a block, whatever its direction.
// Rays start on a grid of interior points and aim at corners and edges (where two walls meet,
// the place a non-watertight triangle test leaks) as well as at random directions. Zero misses
// allowed: a crack would show as black speckles along the edges of the box.
TEST(Geometry, CornellBoxIsWatertight) {
    const Scene s = load_scene(std::string(FACET_SCENES_DIR) + "/cornell_box.json");
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    // The walls' corners (Cornell's measured data: the box is not quite rectangular).
    const Vec3 corners[] = {{552.8f, 0.f, 0.f},    {0.f, 0.f, 0.f},        {0.f, 0.f, 559.2f},
                            {549.6f, 0.f, 559.2f}, {556.f, 548.8f, 0.f},   {0.f, 548.8f, 0.f},
                            {0.f, 548.8f, 559.2f}, {556.f, 548.8f, 559.2f}};
    int misses = 0, rays = 0;
    for (int i = 0; i < 200000; ++i) {
        const Vec3 o(20.f + 510.f * u01(rng), 20.f + 500.f * u01(rng), 5.f + 100.f * u01(rng));
        Vec3 target;
        if (i % 2 == 0) {
            // Along an edge between two corners (walls meet there), jittered by < 1e-3 mm.
            const Vec3& a = corners[i % 8];
            const Vec3& b = corners[(i / 8 + 1 + i % 8) % 8];
            target = a + u01(rng) * (b - a) + 1e-3f * (Vec3(u01(rng), u01(rng), u01(rng)) - 0.5f);
        } else {
            target = o + Vec3(u01(rng) - 0.5f, u01(rng) - 0.5f, u01(rng)) * 1000.f;
        }
        const Vec3 d = glm::normalize(target - o);
        if (!(d.z > 1e-3f)) continue;
        SurfaceHit h;
        ++rays;
        if (!s.intersect({o, d, kInfinity}, h)) ++misses;
    }
    EXPECT_GT(rays, 100000);
    EXPECT_EQ(misses, 0) << "of " << rays << " rays";
}
