// Scene tests of the integrators with known radiance, determinism and kernel specialisation.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "facet/render/aov.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec3;

namespace {

using fr::testing::scene_from;
using fr::testing::test_options;

fr::Image render(const fr::Scene& scene, const std::string& integrator, int spp, int threads = 2,
                 bool general = false, int max_depth = -1, std::uint64_t seed = 7,
                 fr::RenderStats* stats = nullptr) {
    fr::RenderOptions o = test_options(integrator, spp, seed, threads);
    o.force_general_kernel = general;
    o.max_depth = max_depth;
    return fr::render(scene, o, stats);
}

struct MeanSe {
    double mean, se;
};
// Mean of one channel over pixels and its standard error: every pixel is an independent
// estimate (independent scrambling per pixel), so SE = stddev / sqrt(pixels).
MeanSe mean_se(const fr::Image& img, int channel = 0) {
    double s = 0, s2 = 0;
    const double n = double(img.pixels().size());
    for (const Rgb& p : img.pixels()) s += p[channel], s2 += double(p[channel]) * p[channel];
    const double mean = s / n;
    const double var = std::max(0.0, s2 / n - mean * mean) * n / (n - 1);
    return {mean, std::sqrt(var / n)};
}

// A closed cube [-1,1]^3 made of six quads whose front sides (and geometric normals) face
// INWARD, so that a camera inside sees their emitting, reflecting side.
std::string inward_cube(const std::string& material, double emission) {
    struct Face {
        Vec3 n, a, b;  // inward normal, tangents with cross(a, b) = n
    };
    const Face faces[] = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                          {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
                          {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}}};
    std::string out;
    for (const Face& f : faces) {
        const Vec3 c = -f.n;  // face centre: the inward normal points from the face to 0
        auto v = [&](float sa, float sb) {
            Vec3 p = c + sa * f.a + sb * f.b;
            return "[" + std::to_string(p.x) + "," + std::to_string(p.y) + "," +
                   std::to_string(p.z) + "]";
        };
        if (!out.empty()) out += ",";
        out += R"({"type": "quad", "material": ")" + material + R"(", "emission": )" +
               std::to_string(emission) + R"(, "vertices": [)" + v(-1, -1) + "," + v(1, -1) + "," +
               v(1, 1) + "," + v(-1, 1) + "]}";
    }
    return out;
}

std::string furnace_scene(double rho, double le, int size) {
    return R"("camera": {"position": [0.1, 0.05, 0.02], "look_at": [1, 0.3, 0.2], "fov": 90,
               "width": )" +
           std::to_string(size) + R"(, "height": )" + std::to_string(size) + R"(},
        "materials": {"grey": {"model": "lambert", "reflectance": )" +
           std::to_string(rho) + R"(}},
        "shapes": [)" +
           inward_cube("grey", le) + R"(],
        "render": {"max_depth": 1024})";
}

// Point light of power Phi at `light` over the Lambertian plane y = 0 (rho), camera above.
constexpr double kPhi = 100.0, kRho = 0.8;
const Vec3 kLight(0.3f, 2.f, 0.1f);
const char* kPlaneScene = R"(
    "camera": {"position": [0, 3, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 50,
               "width": 48, "height": 36},
    "materials": {"white": {"model": "lambert", "reflectance": 0.8}},
    "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "white"}],
    "lights": [{"type": "point", "position": [0.3, 2, 0.1], "power": 100}],
    "render": {"spp": 1, "max_depth": 4})";

}  // namespace

// Cohen & Wallace eq. 2.40/2.42: L = rho/pi * Phi cos(theta) / (4 pi r^2) at the point each
// pixel-centre ray hits, computed here in double. Tolerance 1e-5 relative: the renderer works in
// float (hit point, r^2, cos each carry ~1e-7 relative error, a few ulps in all), so 1e-5 is
// ~50x the expected round-off and far below any modelling error (a missing cosine or 1/pi is
// O(1), a wrong distance O(1e-1)).
TEST(RenderAnalytic, PointLightOverLambertianPlaneDirect) {
    const fr::Scene scene = scene_from(kPlaneScene);
    for (const char* integrator : {"direct", "path"}) {
        // The path integrator agrees exactly here too: NEE of a delta light is deterministic and
        // the plane cannot see itself, so continuation rays add nothing.
        const fr::Image img = render(scene, integrator, 1);
        const fr::Camera& cam = scene.camera();
        int checked = 0;
        for (int y = 0; y < img.height(); ++y) {
            for (int x = 0; x < img.width(); ++x) {
                const auto want = fr::testing::point_light_on_plane(cam, x, y, kLight, kPhi, kRho);
                if (!want) continue;  // above the horizon: black, checked below
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(img.at(x, y)[c], *want, 1e-5 * *want)
                        << integrator << " pixel " << x << "," << y;
                ++checked;
            }
        }
        EXPECT_EQ(checked, img.width() * img.height());  // the camera looks down: all on plane
    }
}

// A sphere light (radius 1.5, centre 2 above the plane) lights the plane exactly as the point
// light of the same power does: the whole sphere is above every plane point's horizon, so E =
// pi L sin^2(theta_max) cos(tilt) = Phi cos / (4 pi d^2) (light.h). Unbiased per pixel: the
// mean over pixels of image / analytic is 1 within 4 standard errors (pixels are independent
// estimates), for the direct and path integrators and the general kernel (MIS on: the sphere's
// samples must keep weight 1, as no BSDF ray finds it; a power-heuristic weight lost 6.5% here).
TEST(RenderAnalytic, SphereLightOverLambertianPlaneEqualsThePointLight) {
    std::string text = kPlaneScene;
    const std::string key = R"("power": 100})";
    text.replace(text.find(key), key.size(), R"("power": 100, "radius": 1.5})");
    const fr::Scene scene = scene_from(text);
    for (int general = 0; general < 2; ++general) {
        for (const char* integrator : {"direct", "path"}) {
            const fr::Image img = render(scene, integrator, 8, 2, general != 0);
            const fr::Camera& cam = scene.camera();
            double s = 0.0, s2 = 0.0;
            int n = 0;
            for (int y = 0; y < img.height(); ++y) {
                for (int x = 0; x < img.width(); ++x) {
                    const auto want =
                        fr::testing::point_light_on_plane(cam, x, y, kLight, kPhi, kRho);
                    if (!want) continue;
                    const double r = img.at(x, y)[0] / *want;
                    s += r;
                    s2 += r * r;
                    ++n;
                }
            }
            ASSERT_GT(n, 100);
            const double mean = s / n, se = std::sqrt(std::max(0.0, s2 / n - mean * mean) / n);
            EXPECT_NEAR(mean, 1.0, 4.0 * se + 1e-5) << integrator << " general " << general;
            EXPECT_GT(se, 0.0);  // a stochastic estimate (not the point light by mistake)
        }
    }
}

// An area lamp (the light kind) lights the plane as the emissive one-sided disc of the same
// radiance P / (4 A) does. The camera hangs between them looking down, so only the lit plane
// is seen. The two images agree in expectation: the mean pixel difference is 0 within 4
// standard errors (pixels are independent estimates; different seeds), for direct, path and
// the general (MIS) kernel. The big, close disc makes BSDF sampling competitive, so a
// power-heuristic weight on the lamp's samples (no ray finds the lamp) would lose most of it.
TEST(RenderAnalytic, AreaLampEqualsTheEmissiveDisc) {
    const std::string head = R"(
      "camera": {"position": [0, 0.5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 50,
                 "width": 24, "height": 24},
      "materials": {"white": {"model": "lambert", "reflectance": 0.8}},
      "render": {"spp": 1, "max_depth": 4},)";
    const std::string plane =
        R"({"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "white"})";
    const std::string lamp = head + R"("shapes": [)" + plane + R"(],
      "lights": [{"type": "area", "shape": "disc", "size": 4, "power": 100,
                  "position": [0, 1, 0], "direction": [0, -1, 0]}])";
    const std::string radiance = std::to_string(100.0 / (4.0 * M_PI * 4.0));
    const std::string disc = head + R"("shapes": [)" + plane + R"(,
        {"type": "disc", "center": [0, 1, 0], "normal": [0, -1, 0], "radius": 2,
         "two_sided": false, "emission": )" +
                             radiance + R"(}], "lights": [])";
    const fr::Scene a = scene_from(lamp), b = scene_from(disc);
    for (int general = 0; general < 2; ++general) {
        for (const char* integrator : {"direct", "path"}) {
            const fr::Image ia = render(a, integrator, 16, 2, general != 0, -1, 5);
            const fr::Image ib = render(b, integrator, 16, 2, general != 0, -1, 6);
            double s = 0.0, s2 = 0.0, sb = 0.0;
            const std::size_t n = ia.pixels().size();
            for (std::size_t i = 0; i < n; ++i) {
                const double d = double(ia.pixels()[i].g) - ib.pixels()[i].g;
                s += d;
                s2 += d * d;
                sb += ib.pixels()[i].g;
            }
            const double mean = s / double(n);
            const double se = std::sqrt(std::max(0.0, s2 / double(n) - mean * mean) / double(n));
            EXPECT_GT(sb, 0.0);
            EXPECT_NEAR(mean, 0.0, 4.0 * se)
                << integrator << " general " << general << " mean image " << sb / double(n);
        }
    }
}

// White furnace (enclosure emitting Le with reflectance rho everywhere): L = Le / (1 - rho)
// for the path integrator (every bounce adds Le), Le (1 + rho) for the direct one (one
// bounce). Tolerance: 3 standard errors of the image mean (pixels are independent estimates);
// a missing MIS weight, a double-counted emission or a biased roulette moves the mean by
// tens of standard errors.
TEST(RenderAnalytic, FurnacePathWithinThreeStandardErrors) {
    const double rho = 0.5, le = 1.0;
    const fr::Scene scene = scene_from(furnace_scene(rho, le, 16));
    const fr::Image img = render(scene, "path", 16);
    for (int c = 0; c < 3; ++c) {
        const MeanSe m = mean_se(img, c);
        EXPECT_GT(m.se, 0.0);
        EXPECT_NEAR(m.mean, le / (1 - rho), 3 * m.se) << "channel " << c << " se " << m.se;
    }
}

TEST(RenderAnalytic, FurnaceDirectIsOneBounce) {
    const double rho = 0.5, le = 1.0;
    const fr::Scene scene = scene_from(furnace_scene(rho, le, 16));
    const fr::Image img = render(scene, "direct", 16);
    const MeanSe m = mean_se(img);
    EXPECT_NEAR(m.mean, le * (1 + rho), 3 * m.se) << "se " << m.se;
}

// Slope s of log(rmse) = a + s log(spp) over spp = 2, 8, 32, 128, rmse of the green channel
// against `want` over every pixel, for the images render_at(spp).
template <class RenderAt>
double rmse_slope(double want, const RenderAt& render_at) {
    std::vector<double> lx, ly;
    for (int spp : {2, 8, 32, 128}) {
        const fr::Image img = render_at(spp);
        double s2 = 0;
        for (const Rgb& p : img.pixels()) s2 += (p.g - want) * (p.g - want);
        lx.push_back(std::log(double(spp)));
        ly.push_back(0.5 * std::log(s2 / double(img.pixels().size())));
    }
    const double n = double(lx.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t i = 0; i < lx.size(); ++i)
        sx += lx[i], sy += ly[i], sxx += lx[i] * lx[i], sxy += lx[i] * ly[i];
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// Convergence: the RMS error over pixels must fall like spp^-1/2 (or faster: Owen-scrambled
// QMC can beat it). A biased estimator plateaus at its bias and gives a slope near 0. We
// require s < -0.4 (-0.5 minus a margin for the fit's noise over four points) and s > -1.2
// (faster than QMC's best rate for this discontinuous integrand would mean the "error" is not
// measuring the estimator).
TEST(RenderAnalytic, FurnaceErrorFallsAsInverseSqrtSpp) {
    const double rho = 0.5, le = 1.0, want = le / (1 - rho);
    const fr::Scene scene = scene_from(furnace_scene(rho, le, 8));
    const double slope =
        rmse_slope(want, [&](int spp) { return render(scene, "path", spp, 2, false, -1, 11); });
    RecordProperty("slope", std::to_string(slope));
    EXPECT_LT(slope, -0.4);
    EXPECT_GT(slope, -1.2);
}

// RenderOptions::independent_samples (the time-to-error benchmark's peer): unbiased (furnace
// mean within 3 standard errors of Le / (1 - rho)), different from the Sobol image of the same
// seed, and converging at the Monte Carlo rate: RMSE slope over spp = 2 .. 128 in
// [-0.65, -0.35] (-0.5 with the same fit-noise margin as above).
TEST(RenderAnalytic, IndependentSamplesAreUnbiasedAtTheMonteCarloRate) {
    const double rho = 0.5, le = 1.0, want = le / (1 - rho);
    const fr::Scene scene = scene_from(furnace_scene(rho, le, 8));
    auto render_ind = [&](int spp) {
        fr::RenderOptions o = test_options("path", spp, 11, 2);
        o.independent_samples = true;
        return fr::render(scene, o);
    };
    const fr::Image img = render_ind(16);
    const MeanSe m = mean_se(img, 1);
    EXPECT_NEAR(m.mean, want, 3 * m.se) << "se " << m.se;
    const fr::Image sobol = render(scene, "path", 16, 2, false, -1, 11);
    EXPECT_NE(img.pixels()[0].g, sobol.pixels()[0].g);
    const double slope = rmse_slope(want, render_ind);
    EXPECT_LT(slope, -0.35);
    EXPECT_GT(slope, -0.65);
}

// Direct vs path where no indirect light exists: a black-backed plane lit by a one-sided
// emitting quad facing it (the plane cannot see itself, the quad is black). Both estimate
// the same integral (light sampling vs NEE+MIS); per-pixel differences are independent, so
// the mean difference must lie within 4 standard errors and the means within 1%.
TEST(RenderAnalytic, DirectEqualsPathWithoutIndirectLight) {
    const fr::Scene scene = scene_from(R"(
        "camera": {"position": [0, 2, 4], "look_at": [0, 0, 0], "fov": 45, "width": 24,
                   "height": 16},)" + std::string(fr::testing::kQuadLightOverPlane));
    const fr::Image a = render(scene, "direct", 64);
    const fr::Image b = render(scene, "path", 64);
    fr::Image d(a.width(), a.height());
    for (size_t i = 0; i < a.pixels().size(); ++i) d.pixels()[i] = a.pixels()[i] - b.pixels()[i];
    const MeanSe md = mean_se(d);
    const MeanSe ma = mean_se(a);
    EXPECT_GT(ma.mean, 0.01);
    EXPECT_NEAR(md.mean, 0.0, 4 * md.se + 1e-12) << "se " << md.se << " mean " << ma.mean;
    EXPECT_NEAR(mean_se(b).mean / ma.mean, 1.0, 0.01);
}

namespace {

// A small Cornell-like box with every feature: glossy + mirror composite, an area light, a
// point light and an exact sphere.
const char* kFeatureScene = R"(
    "camera": {"position": [0, 1, 0.95], "look_at": [0, 0.9, -1], "fov": 70, "width": 40,
               "height": 30},
    "materials": {
      "white": {"model": "lambert", "reflectance": 0.75},
      "red": {"model": "lambert", "reflectance": [0.7, 0.1, 0.1]},
      "shiny": {"model": "composite", "diffuse_reflectance": 0.4, "glossy_reflectance": 0.3,
                "mirror_reflectance": 0.3, "alpha": 0.2},
      "chrome": {"model": "mirror", "reflectance": 0.9}
    },
    "shapes": [
      {"type": "box", "min": [-1, 0, -1], "max": [1, 2, 1], "material": "white", "two_sided": true},
      {"type": "quad", "material": "red",
       "vertices": [[-0.99, 0, -1], [-0.99, 0, 1], [-0.99, 2, 1], [-0.99, 2, -1]]},
      {"type": "sphere", "center": [0.4, 0.35, 0.2], "radius": 0.35, "material": "shiny"},
      {"type": "sphere", "center": [-0.4, 0.3, -0.3], "radius": 0.3, "material": "chrome"},
      {"type": "quad", "emission": 8,
       "vertices": [[-0.25, 1.98, -0.25], [0.25, 1.98, -0.25], [0.25, 1.98, 0.25], [-0.25, 1.98, 0.25]]}
    ],
    "lights": [{"type": "point", "position": [0.5, 1.5, 0.5], "power": 5}],
    "render": {"max_depth": 6})";

void expect_identical(const fr::Image& a, const fr::Image& b, const std::string& what) {
    ASSERT_EQ(a.width(), b.width());
    ASSERT_EQ(a.height(), b.height());
    int differing = 0;
    for (size_t i = 0; i < a.pixels().size(); ++i)
        if (a.pixels()[i] != b.pixels()[i]) ++differing;
    EXPECT_EQ(differing, 0) << what;
}

}  // namespace

// Same seed, 1 vs 2 threads (and a different tile size): bit-identical images, because every
// sample depends only on (pixel, index, seed) and each pixel is summed by one tile in order.
TEST(RenderDeterminism, ThreadCountDoesNotChangeTheImage) {
    const fr::Scene scene = scene_from(kFeatureScene);
    for (const char* integrator : {"path", "direct"}) {
        const fr::Image one = render(scene, integrator, 4, 1);
        const fr::Image two = render(scene, integrator, 4, 2);
        fr::RenderOptions o = test_options(integrator, 4, 7);
        o.tile_size = 7;
        const fr::Image odd_tiles = fr::render(scene, o);
        expect_identical(one, two, integrator);
        expect_identical(one, odd_tiles, std::string(integrator) + " tile size 7");
    }
    // And the seed matters (the test above would pass for a constant image otherwise).
    const fr::Image s1 = render(scene, "path", 4, 2, false, -1, 1);
    const fr::Image s2 = render(scene, "path", 4, 2, false, -1, 2);
    int differing = 0;
    for (size_t i = 0; i < s1.pixels().size(); ++i) differing += s1.pixels()[i] != s2.pixels()[i];
    EXPECT_GT(differing, int(s1.pixels().size()) / 2);
}

// The Depth pass summed while rendering (RenderOptions::depth_pass) is render_aovs' depth pass
// at the same spp and seed: the same camera rays (sample dimension 0, the lens's), the same
// first hits, the same fixed-point sums, so the same value in every pixel (compared bit for bit:
// the kernel traces a packet of 8 pixels, render_aovs one of 8 samples of a pixel, and Embree
// answers each ray alike here). The Cornell box, a field of hair strands over a quad (curves),
// with a region; without the option, or where the pass is not available (ray visibility), the
// session has none. Fails when the kernel skips the pass (every pixel would be the miss value).
TEST(RenderSession, DepthPassEqualsTheAovPass) {
    std::string strands, counts;
    for (int i = 0; i < 40; ++i) {
        const double x = -0.8 + 0.04 * i, y = 0.1 * std::sin(3.0 * i);
        strands += (strands.empty() ? "" : ", ") + std::to_string(x) + ", " + std::to_string(y) +
                   ", -1.2,  " + std::to_string(x) + ", " + std::to_string(y) + ", -1,  " +
                   std::to_string(x + 0.1) + ", " + std::to_string(y) + ", 0.5,  " +
                   std::to_string(x + 0.2) + ", " + std::to_string(y) + ", 1.2";
        counts += std::string(counts.empty() ? "" : ", ") + "4";
    }
    const std::string hair =
        R"("materials": {"m": {"model": "lambert", "reflectance": 0.5}},
           "shapes": [{"type": "curves", "material": "m", "basis": "catmull_rom", "points": [)" +
        strands + R"(], "counts": [)" + counts +
        R"(], "radius": 0.012},
           {"type": "quad", "vertices": [[-2, 1, -2], [2, 1, -2], [2, 1, 2], [-2, 1, 2]],
            "material": "m"}],
           "camera": {"position": [0, -5, 0], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 30,
                      "width": 48, "height": 40},
           "lights": [{"type": "environment", "radiance": 1}])";
    struct Case {
        const char* name;
        fr::Scene scene;
        std::optional<fr::Region> region;
    };
    Case cases[] = {{"cornell", fr::load_scene(std::string(FACET_SCENES_DIR) + "/cornell_box.json"),
                     std::nullopt},
                    {"hair", scene_from(hair), std::nullopt},
                    {"hair region", scene_from(hair), fr::Region{5, 7, 41, 30}}};
    for (Case& c : cases) {
        SCOPED_TRACE(c.name);
        ASSERT_TRUE(fr::depth_pass_available(c.scene));
        fr::RenderOptions o = test_options("path", 8, 2);
        o.seed = 5;
        o.max_depth = 2;
        o.region = c.region;
        o.depth_pass = true;
        fr::RenderSession session(c.scene, o);
        session.render();
        const fr::Image depth = session.depth();
        fr::AovOptions ao;
        ao.which = fr::kAovDepth;
        ao.spp = 8;
        ao.seed = 5;
        ao.region = c.region;
        const fr::Image want = fr::render_aovs(c.scene, ao).depth;
        ASSERT_EQ(depth.width(), want.width());
        ASSERT_EQ(depth.height(), want.height());
        int differing = 0, missed = 0;
        for (std::size_t i = 0; i < want.pixels().size(); ++i) {
            differing += depth.pixels()[i] != want.pixels()[i];
            missed += want.pixels()[i].x == fr::kMissDepth;
        }
        EXPECT_EQ(differing, 0);
        EXPECT_LT(missed, int(want.pixels().size()) / 2);  // the scenes fill most of the view
        fr::RenderOptions without = o;
        without.depth_pass = false;
        fr::RenderSession plain(c.scene, without);
        plain.render();
        EXPECT_EQ(plain.depth().width(), 0);
    }
    const fr::Scene invisible = scene_from(
        R"("materials": {"m": {"model": "lambert", "reflectance": 0.5}},
           "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m",
                       "visibility": {"camera": false}}],
           "camera": {"position": [0, -5, 0], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 30,
                      "width": 8, "height": 8},
           "lights": [{"type": "environment", "radiance": 1}])");
    EXPECT_FALSE(fr::depth_pass_available(invisible));
    fr::RenderOptions o = test_options("path", 2, 1);
    o.depth_pass = true;
    fr::RenderSession session(invisible, o);
    session.render();
    EXPECT_EQ(session.depth().width(), 0);
}

// Specialised kernels compute the same estimator with fewer branches and the same sample
// dimensions, so their images must equal the general kernel's bit for bit.
TEST(RenderKernels, SpecialisedEqualsGeneral) {
#ifdef FACET_GENERAL_KERNELS_ONLY
    GTEST_SKIP() << "this tree instantiates only the general kernels (FACET_ALL_KERNELS off: "
                    "sanitizer builds); the Release tree runs this test";
#endif
    struct Case {
        const char* name;
        std::string body;
        const char* integrator;
        std::uint32_t expect_on, expect_off;  // kernel feature bits that must be on / off
    };
    const std::vector<Case> cases = {
        {"lambert point light (direct)", kPlaneScene, "direct", fr::kFeatLambertOnly,
         fr::kFeatMis | fr::kFeatSpecular | fr::kFeatAreaSampling | fr::kFeatEmission},
        {"lambert point light (path)", kPlaneScene, "path", fr::kFeatLambertOnly,
         fr::kFeatMis | fr::kFeatSpecular | fr::kFeatEmission},
        {"furnace (path)", furnace_scene(0.5, 1.0, 12), "path",
         fr::kFeatLambertOnly | fr::kFeatMis | fr::kFeatIndirect, fr::kFeatSpecular},
        {"all features (path)", kFeatureScene, "path",
         fr::kFeatSpecular | fr::kFeatMis | fr::kFeatIndirect, fr::kFeatLambertOnly},
        {"all features (direct)", kFeatureScene, "direct",
         fr::kFeatSpecular | fr::kFeatAreaSampling, fr::kFeatLambertOnly},
    };
    for (const Case& c : cases) {
        const fr::Scene scene = scene_from(c.body);
        fr::RenderStats sa, sg;
        const fr::Image a = render(scene, c.integrator, 4, 2, false, -1, 3, &sa);
        const fr::Image g = render(scene, c.integrator, 4, 2, true, -1, 3, &sg);
        EXPECT_EQ(sa.kernel.features & c.expect_on, c.expect_on) << c.name << " " << sa.kernel.name;
        EXPECT_EQ(sa.kernel.features & c.expect_off, 0u) << c.name << " " << sa.kernel.name;
        EXPECT_TRUE(sg.kernel.general);
        expect_identical(a, g, c.name);
        EXPECT_LE(sa.rays + sa.shadow_rays, sg.rays + sg.shadow_rays) << c.name;
    }
}

TEST(RenderOptions, BadOptionsThrowNamingTheOption) {
    const fr::Scene scene = scene_from(kPlaneScene);
    fr::RenderOptions o;
    o.integrator = "pth";
    try {
        fr::render(scene, o);
        FAIL() << "expected a throw";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean 'path'"), std::string::npos) << e.what();
    }
    o.integrator = "";
    o.spp = -3;
    EXPECT_THROW(fr::render(scene, o), std::invalid_argument);
    o.spp = 1;
    o.threads = -1;
    EXPECT_THROW(fr::render(scene, o), std::invalid_argument);
}

// A time budget renders whole passes and reports how many samples it took.
TEST(RenderOptions, TimeBudgetStopsEarly) {
    const fr::Scene scene = scene_from(furnace_scene(0.5, 1.0, 8));
    fr::RenderOptions o;
    o.spp = 1 << 20;  // a cap the budget will not reach
    o.time_budget_s = 0.05;
    o.threads = 2;
    fr::RenderStats st;
    const fr::Image img = fr::render(scene, o, &st);
    EXPECT_GE(st.spp, 1);
    EXPECT_LT(st.spp, 1 << 20);
    EXPECT_LT(st.seconds, 5.0);  // generous: sanitizer builds are slow, but not 100x over
    EXPECT_GT(mean_se(img).mean, 1.0);
}

// The repository's furnace scene (an inside-out emitting sphere, Le = 0.5, rho = 0.8): path
// converges to Le / (1 - rho) = 2.5, direct to Le (1 + rho) = 0.9. Same 3-standard-error
// tolerance as above. This caught points on the sphere being rejected as "outside" it (direct
// gave 0.58).
TEST(RenderAnalytic, SceneFileFurnaceBothIntegrators) {
    const fr::Scene scene = fr::load_scene(std::string(FACET_SCENES_DIR) + "/furnace.json");
    const MeanSe path = mean_se(render(scene, "path", 4));
    EXPECT_NEAR(path.mean, 2.5, 3 * path.se) << "se " << path.se;
    const MeanSe direct = mean_se(render(scene, "direct", 4));
    // Uniform-by-area sampling of a sphere from a point on it makes every direct sample equal
    // rho Le exactly (the cosines and distances cancel), so the SE is ~0: allow float round-off
    // (1e-5 relative) on top.
    EXPECT_NEAR(direct.mean, 0.9, 3 * direct.se + 1e-5 * 0.9) << "se " << direct.se;
}

// Directional and spot lights over the Lambertian plane (direct integrator, pixel centres),
// against light.h's definitions computed here in double; tolerance 1e-5 relative as for the
// point light (float round-off only), plus 1e-7 absolute for the spot's zero region.
TEST(RenderAnalytic, DirectionalAndSpotLightsOverLambertianPlane) {
    const double rho = 0.6, e = 3.0, phi = 40.0;
    const double cos_in = std::cos(20.0 * facet::kPiD / 180.0);
    const double cos_out = std::cos(35.0 * facet::kPiD / 180.0);
    const facet::DVec3 dir_travel = glm::normalize(facet::DVec3(0.3, -1.0, 0.2));
    const facet::DVec3 spot_pos(0.2, 1.5, -0.1);
    const fr::Scene scene = scene_from(R"(
        "camera": {"position": [0, 3, 3], "look_at": [0, 0, 0], "fov": 60, "width": 40,
                   "height": 30},
        "materials": {"m": {"model": "lambert", "reflectance": 0.6}},
        "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "m"}],
        "lights": [
          {"type": "directional", "direction": [0.3, -1.0, 0.2], "irradiance": 3},
          {"type": "spot", "position": [0.2, 1.5, -0.1], "direction": [0, -1, 0], "power": 40,
           "inner_angle": 20, "outer_angle": 35}
        ])");
    const fr::Image img = render(scene, "direct", 1);
    const double i0 = phi / (2 * facet::kPiD * ((1 - cos_in) + (cos_in - cos_out) / 2));
    int in_cone = 0, in_blend = 0;
    for (int y = 0; y < img.height(); ++y) {
        for (int x = 0; x < img.width(); ++x) {
            const fr::Ray ray = scene.camera().generate_ray({float(x) + 0.5f, float(y) + 0.5f});
            const facet::DVec3 o(ray.o), d(ray.d);
            ASSERT_LT(d.y, 0.0);
            const facet::DVec3 p = o + (-o.y / d.y) * d;
            double want = rho / facet::kPiD * e * (-dir_travel.y);  // E cos(theta), eq. 2.42
            const facet::DVec3 v = spot_pos - p;
            const double r2 = glm::dot(v, v);
            const double cos_axis = v.y / std::sqrt(r2);  // angle from the downward axis
            double falloff = 0;
            if (cos_axis >= cos_in)
                falloff = 1, ++in_cone;
            else if (cos_axis > cos_out)
                falloff = (cos_axis - cos_out) / (cos_in - cos_out), ++in_blend;
            want += rho / facet::kPiD * i0 * falloff / r2 * (v.y / std::sqrt(r2));
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(img.at(x, y)[c], want, 1e-5 * want + 1e-7) << x << "," << y;
        }
    }
    EXPECT_GT(in_cone, 20);  // the image covers the inner cone, the blend ring and beyond
    EXPECT_GT(in_blend, 20);
}
