// Shadow catchers (scenes/FORMAT.md "Shadow catchers"; integrator.h "Shadow catcher"; film.h):
// over a transparent film a catcher keeps only the shadow the other objects cast on it, as
// alpha, with no colour; in an opaque film it shows the environment darkened by the same
// amount; scenes with a catcher run the alpha media kernel; the flag's JSON errors name their
// place.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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

// The Shadow Catcher pass (film.h; Cycles 3.4's film_calculate_shadow_catcher) on an analytic
// case: the scene's disc and sphere, its directional light A (irradiance 2 along -(1, 0, 1) /
// sqrt 2: E_A = sqrt 2 on the disc) that casts the sphere's shadow, and a light B straight down
// (E_B = (0.5, 1, 1.5): its shadow lies under the sphere, hidden from the camera above). Only
// direct light reaches the disc (black sphere and world), so per channel the pass is
// E_B / (E_A + E_B) = (0.261, 0.414, 0.515) in pixels wholly in A's shadow, and exactly 1 in
// pixels wholly lit (the full and catcher-only runs take the same light sample, bit for bit),
// on the sphere and off the disc (no catcher seen). Lights are chosen uniformly from one
// stratified sample dimension: in A's shadow a sample gives 2 E_B / pi rho or 0, the
// catcher-only run 2 E_A or 2 E_B (times rho / pi), so the pass is n_B E_B / (n_A E_A + n_B E_B),
// which is the ratio when the pixel's n = 256 samples split n_A = n_B; a split off by k moves it
// by about k / n relative: tolerance 2 / 256 = 0.8% relative. With the pass the image is
// Cycles' Combined of such a render (measured in Cycles 3.4: tests/blender/
// test_cycles_shadow_catcher.py): the matte alone, with an alpha channel also over an opaque
// film, colourless and transparent where the camera sees the catcher, the sphere opaque.
// Control: the pass of the disc without the flag is 1 everywhere, which fails in the shadow.
TEST(ShadowCatcher, PassIsTheLightTheCatcherKept) {
    const std::string b =
        R"(, {"type": "directional", "direction": [0, 0, -1], "irradiance": [0.5, 1, 1.5]})";
    const double ea = std::sqrt(2.0), eb[3] = {0.5, 1.0, 1.5};
    auto opts = fr::testing::test_options("path", 256, 3);
    opts.light_selection = fr::LightSelection::Uniform;
    for (const bool transparent : {false, true}) {
        SCOPED_TRACE(transparent ? "transparent film" : "opaque film");
        const fr::Scene scene = scene_of(scene_text(true, transparent, b));
        opts.shadow_catcher_pass = true;
        fr::RenderSession session(scene, opts);
        session.render();
        const fr::Image pass = session.shadow_catcher_pass();
        const fr::Image combined = session.image();
        ASSERT_FALSE(pass.has_alpha());
        ASSERT_TRUE(combined.has_alpha());
        int lit = 0, umbra = 0, off = 0;
        double worst = 0.0;
        for (int y = 0; y < kSide; ++y) {
            for (int x = 0; x < kSide; ++x) {
                const std::size_t i = std::size_t(y * kSide + x);
                const double cx = -1.0 + (x + 0.5) * kPixel, cy = 1.0 - (y + 0.5) * kPixel;
                const double far =
                    std::hypot(std::fabs(cx) + kPixel / 2, std::fabs(cy) + kPixel / 2);
                const double near = std::hypot(std::max(0.0, std::fabs(cx) - kPixel / 2),
                                               std::max(0.0, std::fabs(cy) - kPixel / 2));
                const double sphere = sphere_coverage(x, y), shadow = shadow_coverage(x, y);
                const Rgb& p = pass.pixels()[i];
                if (near > 0.8 || sphere > 1.0 - 1e-9) {  // no catcher seen
                    EXPECT_EQ(p, Rgb(1.f)) << x << ", " << y;
                    EXPECT_EQ(combined.alpha()[i], near > 0.8 && transparent ? 0.f : 1.f);
                    ++off;
                }
                if (far >= 0.8 || sphere > 0.0) continue;  // wholly on the disc from here
                EXPECT_EQ(combined.pixels()[i], Rgb(0.f)) << x << ", " << y;
                EXPECT_EQ(combined.alpha()[i], 0.f) << x << ", " << y;
                if (shadow < 1e-9) {
                    EXPECT_EQ(p, Rgb(1.f)) << x << ", " << y;
                    ++lit;
                } else if (shadow > 1.0 - 1e-9) {
                    for (int c = 0; c < 3; ++c) {
                        const double want = eb[c] / (ea + eb[c]);
                        worst = std::max(worst, std::fabs(p[c] / want - 1.0));
                        EXPECT_NEAR(p[c], want, want * 2.0 / 256) << x << ", " << y << " " << c;
                    }
                    ++umbra;
                }
            }
        }
        EXPECT_GT(lit, 60);
        EXPECT_GE(umbra, 3);
        EXPECT_GT(off, 40);
        std::printf("pass in the umbra: worst relative error %.2e over %d pixels (lit %d)\n", worst,
                    umbra, lit);
        // Control: no catcher, no pass (1 everywhere), which the umbra's expectation fails.
        const fr::Scene plain = scene_of(scene_text(false, transparent, b));
        fr::RenderSession control(plain, opts);
        control.render();
        const fr::Image none = control.shadow_catcher_pass();
        int wrong = 0;
        for (int y = 0; y < kSide; ++y)
            for (int x = 0; x < kSide; ++x)
                wrong += shadow_coverage(x, y) > 1.0 - 1e-9 && sphere_coverage(x, y) == 0.0 &&
                         none.pixels()[std::size_t(y * kSide + x)] == Rgb(1.f);
        EXPECT_GE(wrong, 3);
    }
}

// A catcher's film keeps its sums beside the colour, and parts carry them (film.h, part files
// version 3): regions and sample ranges rendered apart, through part files, merge into the
// whole render's Combined pass (approximate and with the pass) and Shadow Catcher pass, bit for
// bit, over a transparent and an opaque film. Merging a part without the sums is an error
// naming it. Control: a part whose catcher sums are left out of the merge (its colour kept)
// gives a different image.
TEST(ShadowCatcher, PartsMergeBitForBit) {
    const std::string env = R"(, {"type": "environment", "radiance": [0.2, 0.3, 0.5]})";
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("facet_catcher_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    for (const bool transparent : {false, true}) {
        SCOPED_TRACE(transparent ? "transparent film" : "opaque film");
        const fr::Scene scene = scene_of(scene_text(true, transparent, env));
        const auto opts = fr::testing::test_options("path", 8, 7);
        fr::RenderSession whole(scene, opts);
        whole.render();
        std::vector<fr::RenderPart> parts;
        std::vector<std::string> names;
        for (const fr::Region& r : {fr::Region{0, 0, 16, 5}, fr::Region{0, 5, 16, 16}}) {
            for (const auto& [s0, s1] : {std::pair{0, 3}, std::pair{3, 8}}) {
                auto o = opts;
                o.region = r;
                o.sample_begin = s0;
                o.sample_end = s1;
                fr::RenderSession s(scene, o);
                s.render();
                const std::string path =
                    (dir / ("p" + std::to_string(parts.size()) + ".fpart")).string();
                fr::write_part(s.part(), path);
                parts.push_back(fr::read_part(path));
                names.push_back(path);
                EXPECT_TRUE(parts.back().film.has_catcher());
            }
        }
        const fr::Film merged = fr::merge_parts(parts, names);
        const fr::Film& film = whole.film();
        auto same = [](const fr::Image& a, const fr::Image& b) {
            return a.pixels() == b.pixels() && a.alpha() == b.alpha();
        };
        EXPECT_TRUE(same(merged.resolve(), film.resolve()));
        EXPECT_TRUE(same(merged.resolve(true), film.resolve(true)));
        EXPECT_TRUE(same(merged.resolve_shadow_catcher_pass(), whole.shadow_catcher_pass()));
        EXPECT_TRUE(same(merged.resolve(), whole.image()));
        // A part without catcher sums: an error naming it.
        std::vector<fr::RenderPart> bad = parts;
        bad[1].film = fr::Film(bad[1].info.region, bad[1].film.has_alpha(), false);
        try {
            (void)fr::merge_parts(bad, names);
            ADD_FAILURE() << "no error";
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find(names[1]), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("shadow-catcher"), std::string::npos) << e.what();
        }
        // Control: part 0's catcher sums zeroed (as a part file without them would leave them).
        std::vector<fr::RenderPart> lost = parts;
        fr::Film zeroed(lost[0].info.region, lost[0].film.has_alpha(), true);
        std::copy(lost[0].film.sum_values().begin(), lost[0].film.sum_values().end(),
                  zeroed.sums());
        std::copy(lost[0].film.count_values().begin(), lost[0].film.count_values().end(),
                  zeroed.counts());
        if (transparent)
            std::copy(lost[0].film.alpha_values().begin(), lost[0].film.alpha_values().end(),
                      zeroed.alpha_sums());
        lost[0].film = zeroed;
        EXPECT_FALSE(same(fr::merge_parts(lost, names).resolve(), film.resolve()));
    }
    std::filesystem::remove_all(dir);
}
