// Moving emitters under motion blur (scenes/FORMAT.md "Motion blur"; light type
// emissive_moving_triangles, core/render/src/lights/emissive_moving.cpp): the irradiance under a
// translating emissive quad against the time average of the static irradiance (by quadrature),
// for a quad moved by its "motion" and by its "motion_positions"; the light sample's pdf against
// the pdf multiple importance sampling takes for a BSDF ray that hits the emitter at the same
// time; the light selection's bounds holding the emitter over the whole shutter.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "facet/render/light.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec2;
using facet::Vec3;

namespace {

const char* const kHead = R"({"format": "facet-scene", "version": 1, )";

fr::Scene scene_of(const std::string& body) {
    return fr::build_scene(
        fr::parse_scene_description(std::string(kHead) + body + "}", "moving.json"), "moving.json");
}

// The emissive quad: side kSide, centred on (x, 0, kHeight), facing down (-z), radiance kL.
constexpr double kSide = 0.5, kHeight = 1.0, kL = 5.0, kRho = 0.8;
// Over the shutter its centre goes from x = -kTravel to x = +kTravel at constant speed.
constexpr double kTravel = 1.0;
// The camera at (0, 0, kCamZ) looks down at the plane z = 0 and sees x, y in [-kHalf, kHalf].
constexpr double kCamZ = 0.5, kHalf = 0.1;
constexpr int kRes = 16;

std::string quad_vertices(double cx) {
    const double h = kSide / 2;
    auto v = [&](double x, double y) {
        return "[" + std::to_string(cx + x) + ", " + std::to_string(y) + ", " +
               std::to_string(kHeight) + "]";
    };
    // Counter-clockwise seen from below: the front faces -z.
    return "[" + v(-h, -h) + ", " + v(-h, h) + ", " + v(h, h) + ", " + v(h, -h) + "]";
}

// The scene: a Lambertian plane (reflectance kRho) lit only by the quad, max_depth 1 (the
// plane's direct light: light samples and BSDF rays weighed by MIS). `how`: "motion" (the quad
// moves by its placement), "deform" (a mesh whose motion_positions move it), "still" (motion
// blur off: the quad rests at the shutter's centre), "media" ("motion" in a world medium that
// neither absorbs nor scatters: the one-path media kernel).
std::string emitter_scene(const std::string& how, int spp) {
    const double fov = 2.0 * std::atan(kHalf / kCamZ) * 180.0 / M_PI;
    std::string quad;
    if (how == "deform") {
        auto flat = [&](double cx) {
            std::string s = quad_vertices(cx);
            std::string out;
            for (char c : s)
                if (c != '[' && c != ']') out += c;
            return "[" + out + "]";
        };
        quad = R"({"type": "mesh", "emission": )" + std::to_string(kL) + R"(, "positions": )" +
               flat(0.0) + R"(, "indices": [0, 1, 2, 0, 2, 3],
                  "motion_positions": [)" +
               flat(-kTravel) + ", " + flat(kTravel) + "]}";
    } else {
        quad = R"({"type": "quad", "emission": )" + std::to_string(kL) + R"(, "vertices": )" +
               quad_vertices(0.0) + R"(, "motion": [{"translate": [)" + std::to_string(-kTravel) +
               R"(, 0, 0]}, {"translate": [)" + std::to_string(kTravel) + R"(, 0, 0]}]})";
    }
    return R"("camera": {"type": "perspective", "fov": )" + std::to_string(fov) +
           R"(, "position": [0, 0, )" + std::to_string(kCamZ) +
           R"(], "look_at": [0, 0, 0], "up": [0, 1, 0], "width": )" + std::to_string(kRes) +
           R"(, "height": )" + std::to_string(kRes) + R"(},
      "materials": {"plane": {"model": "lambert", "reflectance": )" +
           std::to_string(kRho) + R"(}},
      "shapes": [{"type": "quad", "material": "plane",
                  "vertices": [[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]]}, )" +
           quad + R"(],
      "render": {"integrator": "path", "max_depth": 1, "spp": )" +
           std::to_string(spp) + R"(, "motion_blur": )" +
           (how == "still" ? R"({"enabled": false})" : R"({"shutter": 0.5})") + "}" +
           (how == "media" ? R"(, "media": {"air": {"kind": "homogeneous", "sigma_a": 0,
                                "sigma_s": 0}}, "world_medium": "air")"
                           : "");
}

// Irradiance at (x, y, 0) from the still quad centred on (cx, 0, kHeight): L times the integral
// over the quad of cos_r cos_l / r^2 = h^2 / r^4 (both cosines h / r), by the midpoint rule on
// 48 x 48 points (relative error below 1e-4 for this smooth integrand: the quad is 2 heights
// across at most).
double irradiance(double x, double y, double cx) {
    constexpr int n = 48;
    const double d = kSide / n;
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double qx = cx - kSide / 2 + (i + 0.5) * d - x;
            const double qy = -kSide / 2 + (j + 0.5) * d - y;
            const double r2 = qx * qx + qy * qy + kHeight * kHeight;
            sum += kHeight * kHeight / (r2 * r2);
        }
    return kL * sum * d * d;
}

// The image's expected mean radiance: rho / pi times the irradiance averaged over the plane's
// seen square (8 x 8 midpoints) and over the shutter (`moving`: the centre at -kTravel +
// 2 kTravel tau, tau uniform, 128 midpoints; else still at 0).
double expected_mean(bool moving) {
    constexpr int nx = 8, nt = 128;
    double sum = 0.0;
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < nx; ++j) {
            const double x = -kHalf + (i + 0.5) * 2 * kHalf / nx;
            const double y = -kHalf + (j + 0.5) * 2 * kHalf / nx;
            if (!moving) {
                sum += irradiance(x, y, 0.0);
                continue;
            }
            double e = 0.0;
            for (int k = 0; k < nt; ++k)
                e += irradiance(x, y, -kTravel + 2 * kTravel * (k + 0.5) / nt);
            sum += e / nt;
        }
    return kRho / M_PI * sum / (nx * nx);
}

struct Measured {
    double mean = 0.0, standard_error = 0.0;
};

// The image's mean (of the three channels) and its standard error from the spread of the
// pixels (independent pixel estimates; the irradiance's own variation over the seen square
// only adds to the spread, so the error is overstated, never understated).
Measured render_mean(const std::string& how, int spp, const std::string& integrator = "path") {
    const fr::Scene scene = scene_of(emitter_scene(how, spp));
    if (how == "media") EXPECT_TRUE(scene.features().has_media && scene.features().has_motion);
    const fr::Image img = fr::render(scene, fr::testing::test_options(integrator, spp, 1));
    std::vector<double> v;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) {
            const Rgb& c = img.at(x, y);
            v.push_back((double(c.x) + double(c.y) + double(c.z)) / 3.0);
        }
    Measured m;
    for (double a : v) m.mean += a;
    m.mean /= double(v.size());
    double var = 0.0;
    for (double a : v) var += (a - m.mean) * (a - m.mean);
    var /= double(v.size() - 1);
    m.standard_error = std::sqrt(var / double(v.size()));
    return m;
}

}  // namespace

// The quad sweeps 2 units under the camera's patch over the shutter: the plane's radiance is
// rho / pi times the time average of the still irradiance. Tolerance: 5 standard errors of the
// image mean (measured from the pixels' spread; about 0.5% at 128 spp) plus 1e-3 relative for
// the quadrature. Moved by "motion" and by "motion_positions" alike, in the media kernel, and
// by the `direct` integrator (light samples only, no MIS). The control, the same quad
// still at the shutter's centre (motion blur off), is 1.49 times brighter: it fails the bound.
TEST(MovingEmitter, IrradianceIsTheTimeAverageOfTheStillIrradiance) {
    const int spp = std::max(32, int(128 * fr::testing::stress_scale()));
    const double expected = expected_mean(true);
    const double still = expected_mean(false);
    for (const std::string how : {"motion", "deform", "media", "direct"}) {
        const Measured m =
            how == "direct" ? render_mean("motion", spp, "direct") : render_mean(how, spp);
        const double tol = 5.0 * m.standard_error + 1e-3 * expected;
        EXPECT_NEAR(m.mean, expected, tol)
            << how << ": standard error " << m.standard_error << ", still " << still;
        std::printf("%s: mean %.5f, expected %.5f (ratio %.4f), standard error %.5f\n", how.c_str(),
                    m.mean, expected, m.mean / expected, m.standard_error);
    }
    const Measured control = render_mean("still", spp);
    std::printf("still: mean %.5f, expected %.5f\n", control.mean, still);
    EXPECT_NEAR(control.mean, still, 5.0 * control.standard_error + 1e-3 * still);
    EXPECT_GT(std::fabs(control.mean - expected), 10.0 * (5.0 * control.standard_error))
        << "the still quad must miss the moving one's mean (the test could not fail)";
}

namespace {

// An emitter whose triangles change their areas differently over the shutter: a fan of three
// triangles, rotated, translated and scaled unevenly by "motion" ("rigid") or deformed by
// "motion_positions" and rotated ("deform"). Motion blur on, shutter 1.
std::string pdf_scene(const std::string& how) {
    const std::string positions =
        "[-0.4, -0.3, 0,  0.5, -0.2, 0,  0.3, 0.4, 0,  -0.2, 0.5, 0,  -0.6, 0.1, 0]";
    const std::string indices = "[0, 2, 1, 0, 3, 2, 0, 4, 3]";  // front faces -z
    std::string motion =
        R"([{"translate": [0, 0, 2]},
            {"rotate": {"axis": [0, 0, 1], "angle": 30}, "scale": [1.5, 0.7, 1], "translate": [0.3, 0.1, 2.2]},
            {"rotate": {"axis": [0.2, 0, 1], "angle": 70}, "scale": [0.6, 1.8, 1], "translate": [-0.2, 0.2, 1.9]}])";
    std::string shape = R"({"type": "mesh", "emission": 3, "positions": )" + positions +
                        R"(, "indices": )" + indices + R"(, "motion": )" + motion;
    if (how == "deform") {
        shape += R"(, "motion_positions": [
            [-0.4, -0.3, 0,  0.5, -0.2, 0,  0.3, 0.4, 0,  -0.2, 0.5, 0,  -0.6, 0.1, 0],
            [-0.5, -0.4, 0.1,  0.9, -0.2, 0,  0.3, 0.2, 0,  -0.2, 0.9, 0,  -0.6, 0.1, 0.2],
            [-0.2, -0.3, 0,  0.5, -0.6, 0,  0.6, 0.4, 0.1,  -0.1, 0.5, 0,  -0.9, 0.3, 0]])";
    }
    shape += "}";
    return R"("camera": {"type": "perspective", "fov": 40, "position": [0, 0, -3],
               "look_at": [0, 0, 0], "width": 8, "height": 8},
      "materials": {"m": {"model": "lambert", "reflectance": 0.5}},
      "shapes": [)" +
           shape + R"(], "render": {"motion_blur": {"shutter": 1}})";
}

}  // namespace

// A light sample at time tau and the BSDF ray along its direction traced at tau: the ray hits
// the emitter at the sampled point (within the sample's error box plus the hit's), and the pdf
// that MIS takes for that hit (Light::pdf_li with the hit's triangle) equals the sample's pdf.
// Tolerance 1e-3 relative: both are the same float expression of a point and normal that agree
// to ~1e-5 (the hit's point and normal are Embree's float interpolation of the same motion).
// The control: the hit's pdf taken at another time (tau + 0.37) misses by more than 1% for
// most samples, so the comparison sees the time.
TEST(MovingEmitter, LightSamplePdfEqualsTheHitPdfAtTheSameTime) {
    for (const std::string how : {"rigid", "deform"}) {
        const fr::Scene scene = scene_of(pdf_scene(how));
        ASSERT_EQ(scene.lights().size(), 1u);
        const fr::Light& light = scene.lights()[0];
        ASSERT_EQ(light.type_name(), "emissive_moving_triangles");
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> u01(0.f, 0.99999f);
        int checked = 0, time_sensitive = 0;
        for (int k = 0; k < 400; ++k) {
            fr::LightSampleContext ctx;
            ctx.p = Vec3(2.f * u01(rng) - 1.f, 2.f * u01(rng) - 1.f, -0.5f);
            ctx.n = Vec3(0.f, 0.f, 1.f);
            const float time = u01(rng);
            const auto ls = light.sample_li_at(ctx, Vec2(u01(rng), u01(rng)), time);
            if (!ls) continue;
            fr::Ray ray;
            ray.o = ctx.p;
            ray.d = ls->wi;
            ray.tmax = 2.f * ls->dist;
            fr::SurfaceHit hit;
            ASSERT_TRUE(scene.intersect(ray, time, hit)) << how << " sample " << k;
            ASSERT_EQ(hit.light, 0) << how;
            const Vec3 gap = glm::abs(hit.p - ls->p_light);
            const Vec3 allowed = ls->p_light_err + hit.p_err + Vec3(1e-5f);
            EXPECT_TRUE(gap.x <= allowed.x && gap.y <= allowed.y && gap.z <= allowed.z)
                << how << " sample " << k << ": the hit is " << glm::length(gap)
                << " from the sampled point";
            const float pdf = light.pdf_li_at(ctx, ray.d, hit.p, hit.ng, hit.emitter_prim, time);
            EXPECT_NEAR(pdf, ls->pdf, 1e-3f * ls->pdf) << how << " sample " << k;
            const float later = std::fmod(time + 0.37f, 1.f);
            const float other = light.pdf_li_at(ctx, ray.d, hit.p, hit.ng, hit.emitter_prim, later);
            if (std::fabs(other - ls->pdf) > 0.01f * ls->pdf) ++time_sensitive;
            ++checked;
        }
        EXPECT_GT(checked, 300) << how;
        EXPECT_GT(time_sensitive, checked / 2) << how;
    }
}

// The light tree's view of a moving emitter: its box holds the emitter's corners at every time
// (checked at 1000 times, finer than the factory's 32 per segment), its power is pi L times the
// largest total area at the factory's times, which is within 1e-3 of pi L A(tau) at every
// time or above it (the area is not linear in time between them: scale and deformation steps
// are interpolated linearly, the cross product of the edges is quadratic; measured shortfall
// 1.5e-4), and a rotating emitter's cone covers every direction.
TEST(MovingEmitter, SelectionBoundsHoldTheWholeShutter) {
    const fr::Scene scene = scene_of(pdf_scene("rigid"));
    const fr::Light& light = scene.lights()[0];
    const auto* l = light.get<fr::EmissiveMovingTriangles>();
    ASSERT_NE(l, nullptr);
    const auto b = light.bounds();
    ASSERT_TRUE(b.has_value());
    EXPECT_EQ(b->cos_theta_o, -1.f);
    for (int k = 0; k <= 1000; ++k) {
        const float tau = float(k) / 1000.f;
        double area = 0.0;
        for (std::uint32_t i = 0; i < l->num_triangles(); ++i) {
            glm::dvec3 p[3];
            l->corners_at(i, tau, p);
            area += 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
            for (const glm::dvec3& q : p)
                for (int a = 0; a < 3; ++a) {
                    EXPECT_GE(q[a], double(b->lo[a])) << "tau " << tau;
                    EXPECT_LE(q[a], double(b->hi[a])) << "tau " << tau;
                }
        }
        EXPECT_GE(double(light.power(1.f).x), M_PI * 3.0 * area * (1.0 - 1e-3)) << "tau " << tau;
    }
}
