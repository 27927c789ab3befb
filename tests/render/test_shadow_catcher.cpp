// Shadow catchers (scenes/FORMAT.md "Shadow catchers"; integrator.h "Shadow catcher"; film.h):
// over a transparent film a catcher keeps only the shadow the other objects cast on it, as
// alpha, with no colour; in an opaque film it shows the environment darkened by the same
// amount; scenes with a catcher run the alpha media kernel; the flag's JSON errors name their
// place.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "facet/render/film.h"
#include "facet/render/image.h"
#include "facet/render/pov_export.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;

namespace {

fr::Scene scene_of(const std::string& body) {
    return fr::load_scene_from_string(R"({"format": "facet-scene", "version": 1, )" + body + "}",
                                      "catcher.json");
}

// A 16 x 16 orthographic camera looking down -z, seeing [-1, 1]^2 of the plane z = 0: pixel
// (x, y) covers [-1 + x/8, -1 + (x+1)/8] x [1 - (y+1)/8, 1 - y/8].
constexpr int kSide = 16;
constexpr double kPixel = 2.0 / kSide;

// The fraction of pixel (x, y) where |y'| < sqrt(g(x')) (a region bounded by a chord function),
// by the midpoint rule over the pixel's columns (4000 steps: error below 1e-6 of the pixel).
template <class G>
double chord_coverage(int x, int y, G g) {
    const double x0 = -1.0 + x * kPixel, y1 = 1.0 - y * kPixel, y0 = y1 - kPixel;
    constexpr int kSteps = 4000;
    double area = 0.0;
    for (int i = 0; i < kSteps; ++i) {
        const double u = x0 + (i + 0.5) * kPixel / kSteps;
        const double g2 = g(u);
        if (g2 <= 0.0) continue;
        const double h = std::sqrt(g2);
        area += std::max(0.0, std::min(y1, h) - std::max(y0, -h));
    }
    return area * (kPixel / kSteps) / (kPixel * kPixel);
}

// The scene: a Lambertian disc of radius 0.8 on z = 0 (the catcher when `catcher`), a black
// sphere of radius 0.2 at (0.4, 0, 0.6) above it, a directional light travelling along
// -(1, 0, 1) / sqrt 2 and `extra` lights. The sphere's shadow on z = 0 is the ellipse of points
// p whose ray toward the light passes the centre c closer than 0.2:
// |c - p|^2 - ((c - p).d)^2 < 0.04, i.e. y^2 < 0.04 - 0.36 - (0.4 - x)^2 + (1 - x)^2 / 2
// (x in [-0.483, 0.083]); seen from above the sphere covers the disc of radius 0.2 about
// (0.4, 0), apart from the shadow.
std::string scene_text(bool catcher, bool transparent, const std::string& extra = "") {
    return std::string(
               R"("camera": {"type": "orthographic", "position": [0, 0, 5], "look_at": [0, 0, 0],
                             "up": [0, 1, 0], "scale": 2, "width": 16, "height": 16},
                  "shapes": [{"type": "disc", "center": [0, 0, 0], "normal": [0, 0, 1],
                              "radius": 0.8, "shadow_catcher": )") +
           (catcher ? "true" : "false") + R"(,
                              "material": {"model": "lambert", "reflectance": 0.8}},
                             {"type": "sphere", "center": [0.4, 0, 0.6], "radius": 0.2,
                              "material": {"model": "lambert", "reflectance": 0}}],
                  "lights": [{"type": "directional", "direction": [-1, 0, -1],
                              "irradiance": 2})" +
           extra + R"(], "render": {"max_depth": 4, "film_transparent": )" +
           (transparent ? "true" : "false") + "}";
}

double shadow_coverage(int x, int y) {
    return chord_coverage(x, y, [](double u) {
        return 0.04 - 0.36 - (0.4 - u) * (0.4 - u) + 0.5 * (1.0 - u) * (1.0 - u);
    });
}
double sphere_coverage(int x, int y) {
    return chord_coverage(x, y, [](double u) { return 0.04 - (u - 0.4) * (u - 0.4); });
}

}  // namespace

// Over a transparent film the catcher keeps only its shadow: alpha is the shadowed fraction of
// each pixel (the sphere's own pixels are opaque as any object's), and no pixel has colour
// (the sphere is black, the catcher leaves none, nothing lights the matte). With one delta
// light every sample's full radiance is either the catcher-only run's (lit: the same light
// sample, bit for bit) or 0 (shadowed: the black sphere reflects nothing onto it), so alpha
// is the fraction of samples in the shadow: 0 or 1 per sample, on film positions stratified
// over the pixel, as the sphere's coverage in test_alpha.cpp: sigma <= sqrt(32 / 4) / 256 =
// 0.011 per pixel at 256 spp, tolerance 5 sigma. Unshadowed catcher pixels are exactly 0.
// Control: the disc without the flag is opaque (alpha 1 over it) and lit: both fail.
TEST(ShadowCatcher, AlphaIsTheShadowedFraction) {
    const int spp = 256;
    const fr::Scene scene = scene_of(scene_text(true, true));
    EXPECT_TRUE(scene.features().has_shadow_catcher);
    EXPECT_TRUE(scene.features().needs_alpha);
    fr::RenderStats st;
    const fr::Image img = fr::render(scene, fr::testing::test_options("path", spp, 3), &st);
    ASSERT_TRUE(img.has_alpha());
    EXPECT_NE(st.kernel.name.find("media"), std::string::npos) << st.kernel.name;
    EXPECT_NE(st.kernel.name.find("alpha"), std::string::npos) << st.kernel.name;
    const fr::Image plain =
        fr::render(scene_of(scene_text(false, true)), fr::testing::test_options("path", spp, 3));
    ASSERT_TRUE(plain.has_alpha());
    const double sigma = std::sqrt(2.0 * std::sqrt(double(spp)) * 0.25) / spp;
    const double tol = 5.0 * sigma + 1e-6;
    double worst = 0.0, worst_control = 0.0;
    int partial = 0, full = 0, lit = 0;
    for (int y = 0; y < kSide; ++y) {
        for (int x = 0; x < kSide; ++x) {
            const std::size_t i = std::size_t(y * kSide + x);
            const double s = shadow_coverage(x, y), expect = s + sphere_coverage(x, y);
            const double a = img.alpha()[i];
            EXPECT_NEAR(a, expect, tol) << "pixel " << x << ", " << y;
            EXPECT_EQ(img.pixels()[i], Rgb(0.f)) << "pixel " << x << ", " << y;
            worst = std::max(worst, std::fabs(a - expect));
            worst_control = std::max(worst_control, std::fabs(plain.alpha()[i] - expect));
            partial += s > 0.05 && s < 0.95;
            full += s == 1.0;
            // A pixel wholly on the unshadowed catcher (inside the disc: |corner| < 0.8).
            const double cx = -1.0 + (x + 0.5) * kPixel, cy = 1.0 - (y + 0.5) * kPixel;
            if (expect == 0.0 &&
                std::hypot(std::fabs(cx) + kPixel / 2, std::fabs(cy) + kPixel / 2) < 0.8) {
                EXPECT_EQ(a, 0.f) << "pixel " << x << ", " << y;
                ++lit;
            }
        }
    }
    EXPECT_GT(partial, 8);  // the shadow's edge crosses pixels: the test sees fractions
    EXPECT_GT(full, 2);
    EXPECT_GT(lit, 60);
    EXPECT_GT(worst_control, 0.5);
    std::printf(
        "catcher alpha vs shadowed fraction: worst pixel %.4f (tolerance %.4f; without "
        "the flag: %.4f); %d partial, %d fully shadowed, %d lit pixels\n",
        worst, tol, worst_control, partial, full, lit);
}

// In an opaque film the catcher shows the environment behind it darkened by the shadow:
// colour = environment x (1 - alpha of the transparent film's render), pixel for pixel (the
// same samples give the same ratio; the environment is constant, so "behind" is exact), to
// float rounding (relative 1e-5). The environment seen directly stays as it is, and no alpha
// channel is made. Control: the disc without the flag shows its own lit colour instead.
TEST(ShadowCatcher, OpaqueFilmShowsTheDarkenedEnvironment) {
    const std::string env = R"(, {"type": "environment", "radiance": [0.2, 0.3, 0.5]})";
    const Rgb e(0.2f, 0.3f, 0.5f);
    const auto opts = fr::testing::test_options("path", 64, 5);
    const fr::Image transparent = fr::render(scene_of(scene_text(true, true, env)), opts);
    const fr::Image opaque = fr::render(scene_of(scene_text(true, false, env)), opts);
    const fr::Image control = fr::render(scene_of(scene_text(false, false, env)), opts);
    ASSERT_TRUE(transparent.has_alpha());
    EXPECT_FALSE(opaque.has_alpha());
    EXPECT_EQ(opaque.at(0, 0), e);  // a corner: the environment only
    int checked = 0, darker = 0;
    double worst_control = 0.0;
    for (int y = 0; y < kSide; ++y) {
        for (int x = 0; x < kSide; ++x) {
            const double cx = -1.0 + (x + 0.5) * kPixel, cy = 1.0 - (y + 0.5) * kPixel;
            const bool on_disc =
                std::hypot(std::fabs(cx) + kPixel / 2, std::fabs(cy) + kPixel / 2) < 0.8;
            if (!on_disc || sphere_coverage(x, y) > 0.0) continue;
            const std::size_t i = std::size_t(y * kSide + x);
            const float a = transparent.alpha()[i];
            EXPECT_EQ(transparent.pixels()[i], Rgb(0.f));
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(opaque.pixels()[i][c], e[c] * (1.f - a), 1e-5 * e[c])
                    << "pixel " << x << ", " << y;
                worst_control = std::max(
                    worst_control, std::fabs(double(control.pixels()[i][c]) - e[c] * (1.0 - a)));
            }
            ++checked;
            darker += a > 0.5f;
        }
    }
    EXPECT_GT(checked, 80);
    EXPECT_GT(darker, 2);  // the shadow is there, and darkens the environment
    EXPECT_GT(worst_control, 0.1);
}

// An emitting shape lights the catcher-only run only if it is a catcher itself, as in Cycles
// 3.4 (measured there: a Mesh Light over a catcher leaves alpha 0 in its cube's shadow unless
// the emitter's own Shadow Catcher is on). The scene's only light is an emissive quad outside
// the view: not a catcher, the catcher-only radiance is 0, the ratio counts as 1 and no pixel
// wholly on the catcher gets alpha (exactly 0); flagged, its shadow is caught (alpha > 0.5
// somewhere on the disc). Both are exact statements about the estimator, not noisy bounds.
TEST(ShadowCatcher, EmittersLightTheCatcherOnlyRunWhenCatchersThemselves) {
    auto scene = [](bool emitter_catches) {
        return std::string(
                   R"("camera": {"type": "orthographic", "position": [0, 0, 5],
                                 "look_at": [0, 0, 0], "up": [0, 1, 0], "scale": 2,
                                 "width": 16, "height": 16},
                      "shapes": [{"type": "disc", "center": [0, 0, 0], "normal": [0, 0, 1],
                                  "radius": 0.8, "shadow_catcher": true,
                                  "material": {"model": "lambert", "reflectance": 0.8}},
                                 {"type": "sphere", "center": [0.4, 0, 0.6], "radius": 0.2,
                                  "material": {"model": "lambert", "reflectance": 0}},
                                 {"type": "quad", "vertices": [[1.2, -0.3, 2], [1.2, 0.3, 2],
                                                               [1.8, 0.3, 2], [1.8, -0.3, 2]],
                                  "emission": 20, "shadow_catcher": )") +
               (emitter_catches ? "true" : "false") +
               R"(}], "render": {"max_depth": 4, "film_transparent": true})";
    };
    const auto opts = fr::testing::test_options("path", 64, 7);
    const fr::Image plain = fr::render(scene_of(scene(false)), opts);
    const fr::Image caught = fr::render(scene_of(scene(true)), opts);
    ASSERT_TRUE(plain.has_alpha() && caught.has_alpha());
    float most = 0.f;
    int checked = 0;
    for (int y = 0; y < kSide; ++y) {
        for (int x = 0; x < kSide; ++x) {
            const double cx = -1.0 + (x + 0.5) * kPixel, cy = 1.0 - (y + 0.5) * kPixel;
            if (std::hypot(std::fabs(cx) + kPixel / 2, std::fabs(cy) + kPixel / 2) >= 0.8 ||
                sphere_coverage(x, y) > 0.0)
                continue;
            const std::size_t i = std::size_t(y * kSide + x);
            EXPECT_EQ(plain.alpha()[i], 0.f) << "pixel " << x << ", " << y;
            most = std::max(most, caught.alpha()[i]);
            ++checked;
        }
    }
    EXPECT_GT(checked, 80);
    EXPECT_GT(most, 0.5f);
}

// The flag's errors name their place; an instance cannot carry it (its prototype's shapes do).
TEST(ShadowCatcher, JsonErrorsNameThePlace) {
    auto message = [](const std::string& body) {
        try {
            scene_of(body);
        } catch (const fr::SceneError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string cam =
        R"("camera": {"type": "orthographic", "position": [0, 0, 5], "look_at": [0, 0, 0],
                      "up": [0, 1, 0], "scale": 2, "width": 4, "height": 4},
           "lights": [{"type": "environment", "radiance": 1}],)";
    const std::string bad =
        message(cam + R"("shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                                     "material": {"model": "lambert", "reflectance": 0.5},
                                     "shadow_catcher": 1}])");
    EXPECT_NE(bad.find("/shapes/0/shadow_catcher"), std::string::npos) << bad;
    const std::string inst =
        message(cam + R"("prototypes": {"p": [{"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1],
                                       "material": {"model": "lambert", "reflectance": 0.5}}]},
                 "shapes": [{"type": "instance", "of": "p", "shadow_catcher": true}])");
    EXPECT_NE(inst.find("/shapes/0/shadow_catcher"), std::string::npos) << inst;
    EXPECT_NE(inst.find("prototype"), std::string::npos) << inst;
    // POV-Ray has no shadow catcher: its export refuses one, naming it.
    const std::string body = scene_text(true, false);
    std::string pov = "no error";
    try {
        fr::export_pov(fr::parse_scene_description(
                           R"({"format": "facet-scene", "version": 1, )" + body + "}", "a"),
                       "a.json");
    } catch (const fr::SceneError& e) {
        pov = e.what();
    }
    EXPECT_NE(pov.find("/shapes/0/shadow_catcher"), std::string::npos) << pov;
}

// A catcher's film keeps its sums beside the colour; parts cannot carry them: a session refuses
// to make one, and a part file is not written (errors, never a part that would merge into a
// different image).
TEST(ShadowCatcher, PartsAreRefused) {
    const fr::Scene scene = scene_of(scene_text(true, true));
    fr::RenderSession session(scene, fr::testing::test_options("path", 2, 1));
    session.render();
    try {
        (void)session.part();
        FAIL() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("shadow catcher"), std::string::npos) << e.what();
    }
    fr::RenderPart part;
    part.info.width = part.info.height = 2;
    part.info.region = {0, 0, 2, 2};
    part.info.sample_end = 1;
    part.film = fr::Film(part.info.region, true, true);
    EXPECT_TRUE(part.film.has_catcher());
    try {
        fr::write_part(part, "/nonexistent/catcher.fpart");
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("shadow catcher"), std::string::npos) << e.what();
    }
}
