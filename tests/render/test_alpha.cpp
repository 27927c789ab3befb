// Film transparency and holdouts (scenes/FORMAT.md "Film transparency and holdouts";
// integrator.h "Alpha"): a sphere's alpha is its analytic coverage of each pixel, the background
// leaves the colour, holdouts (the model, inside a mix, and the shape flag) are holes, straight
// pass-throughs keep the background's transparency and mirrors do not, split renders merge
// alpha bit for bit, and EXR/PNG/part files carry it. Without the switch nothing changes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include <unistd.h>

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
                                      "alpha.json");
}

// A 16 x 16 orthographic camera looking down -z, seeing [-1, 1]^2 of the plane z = 0: pixel
// (x, y) covers [-1 + x/8, -1 + (x+1)/8] x [1 - (y+1)/8, 1 - y/8].
constexpr int kSide = 16;
constexpr double kPixel = 2.0 / kSide;
const char* const kOrtho =
    R"("camera": {"type": "orthographic", "position": [0, 0, 5], "look_at": [0, 0, 0],
                  "up": [0, 1, 0], "scale": 2, "width": 16, "height": 16},)";

// The area of pixel (x, y) inside the disc of radius r about the origin, as a fraction of the
// pixel: the integral over the pixel's columns of the chord clipped to its rows (midpoint rule,
// 4000 steps: error below 1e-6 of the pixel).
double disc_coverage(int x, int y, double r) {
    const double x0 = -1.0 + x * kPixel, y1 = 1.0 - y * kPixel, y0 = y1 - kPixel;
    constexpr int kSteps = 4000;
    double area = 0.0;
    for (int i = 0; i < kSteps; ++i) {
        const double u = x0 + (i + 0.5) * kPixel / kSteps;
        if (std::fabs(u) >= r) continue;
        const double h = std::sqrt(r * r - u * u);
        area += std::max(0.0, std::min(y1, h) - std::max(y0, -h));
    }
    return area * (kPixel / kSteps) / (kPixel * kPixel);
}

// A Lambertian sphere of radius 0.7 lit by a point light, nothing behind it.
std::string sphere_scene(const std::string& render, const std::string& extra_lights = "") {
    return std::string(kOrtho) +
           R"("shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.7,
                          "material": {"model": "lambert", "reflectance": 0.8}}],
             "lights": [{"type": "point", "position": [0, 0, 6], "power": 400})" +
           extra_lights + R"(], "render": )" + render;
}

}  // namespace

// Alpha is the covered fraction of each pixel. Each sample's coverage is 0 or 1; the film
// positions of 256 samples are a scrambled Sobol (0, 2)-sequence, stratified on the 16 x 16
// grid of the pixel, so only the ~2 sqrt(N) = 32 strata the silhouette crosses are random, each
// a Bernoulli of variance <= 1/4: sigma <= sqrt(32 / 4) / 256 = 0.011 per pixel. The tolerance
// is 5 sigma per pixel (0.055) and, for the image mean, 5 sigma of a mean over the ~60 edge
// pixels (0.0017). Control: the same comparison against a sphere of radius 0.69 (edge pixels
// move by up to 0.08, the mean by 0.011) must fail; so must alpha inverted.
TEST(Alpha, SphereCoverageIsTheAnalyticFraction) {
    const int spp = 256;
    const fr::Scene scene = scene_of(sphere_scene(R"({"film_transparent": true})"));
    EXPECT_TRUE(scene.features().needs_alpha);
    fr::RenderStats st;
    const fr::Image img = fr::render(scene, fr::testing::test_options("path", spp, 3), &st);
    ASSERT_TRUE(img.has_alpha());
    EXPECT_NE(st.kernel.name.find("alpha"), std::string::npos) << st.kernel.name;
    const double sigma = std::sqrt(2.0 * std::sqrt(double(spp)) * 0.25) / spp;
    const double tol = 5.0 * sigma + 1e-6;
    double worst = 0.0, worst_control = 0.0, sum_a = 0.0, sum_c = 0.0, sum_control = 0.0;
    int edge = 0;
    for (int y = 0; y < kSide; ++y) {
        for (int x = 0; x < kSide; ++x) {
            const double c = disc_coverage(x, y, 0.7);
            const double a = img.alpha()[std::size_t(y * kSide + x)];
            EXPECT_NEAR(a, c, tol) << "pixel " << x << ", " << y;
            worst = std::max(worst, std::fabs(a - c));
            const double control = disc_coverage(x, y, 0.69);
            worst_control = std::max(worst_control, std::fabs(a - control));
            sum_a += a;
            sum_c += c;
            sum_control += control;
            edge += c > 0.0 && c < 1.0;
            // Outside the sphere: no colour at all (nothing behind it, no environment).
            if (c == 0.0) {
                EXPECT_EQ(img.at(x, y), Rgb(0.f));
            }
        }
    }
    EXPECT_GT(edge, 20);  // the silhouette crosses many pixels: the test sees fractions
    const double n = kSide * kSide, mean_tol = 5.0 * sigma * std::sqrt(double(edge)) / n;
    EXPECT_NEAR(sum_a / n, sum_c / n, mean_tol);
    // The control fails both bounds.
    EXPECT_GT(worst_control, tol);
    EXPECT_GT(std::fabs(sum_a - sum_control) / n, mean_tol);
    std::printf(
        "alpha vs analytic coverage: worst pixel %.4f (tolerance %.4f; radius 0.69: "
        "%.4f), mean %.5f vs %.5f (tolerance %.5f; radius 0.69: %.5f)\n",
        worst, tol, worst_control, sum_a / n, sum_c / n, mean_tol, sum_control / n);
}

// The environment seen directly leaves the colour (alpha 0 there); off, it stays and the image
// has no alpha channel and the kernel is the ordinary one.
TEST(Alpha, BackgroundLeavesTheColour) {
    const std::string env = R"(, {"type": "environment", "radiance": 0.5})";
    const fr::Image on = fr::render(scene_of(sphere_scene(R"({"film_transparent": true})", env)),
                                    fr::testing::test_options("path", 4, 3));
    fr::RenderStats st;
    const fr::Image off = fr::render(scene_of(sphere_scene(R"({})", env)),
                                     fr::testing::test_options("path", 4, 3), &st);
    EXPECT_FALSE(off.has_alpha());
    EXPECT_EQ(st.kernel.name.find("alpha"), std::string::npos) << st.kernel.name;
    ASSERT_TRUE(on.has_alpha());
    // The corner pixel sees only the environment.
    EXPECT_EQ(on.at(0, 0), Rgb(0.f));
    EXPECT_EQ(on.alpha()[0], 0.f);
    EXPECT_FLOAT_EQ(off.at(0, 0).r, 0.5f);
    // The centre sees only the sphere: alpha 1.
    EXPECT_EQ(on.alpha()[std::size_t(8 * kSide + 8)], 1.f);
}

// Holdouts. A quad fills the view in front of a constant environment; a sphere in front of
// it is a holdout: the `holdout` model, or a Lambertian shape with "holdout": true. Where the
// sphere covers a whole pixel, alpha and colour are 0; where only the quad is seen, alpha is 1
// and the colour is the quad's. With an opaque film the hole is black and there is no alpha.
TEST(Alpha, HoldoutMakesAHole) {
    auto scene = [](const std::string& sphere, bool transparent = true) {
        return std::string(kOrtho) +
               R"("shapes": [{"type": "quad", "vertices": [[-2, -2, -1], [2, -2, -1], [2, 2, -1],
                                                          [-2, 2, -1]],
                              "material": {"model": "lambert", "reflectance": 0.5}},
                             {"type": "sphere", "center": [0, 0, 0], "radius": 0.7, )" +
               sphere + R"(}],
                 "lights": [{"type": "environment", "radiance": 1}],
                 "render": {"max_depth": 1, "film_transparent": )" +
               (transparent ? "true" : "false") + "}";
    };
    for (const std::string& s :
         {std::string(R"("material": {"model": "holdout"})"),
          std::string(
              R"("material": {"model": "lambert", "reflectance": 0.8}, "holdout": true)")}) {
        SCOPED_TRACE(s);
        const fr::Scene sc = scene_of(scene(s));
        EXPECT_TRUE(sc.features().has_holdout);
        const fr::Image img = fr::render(sc, fr::testing::test_options("path", 16, 3));
        ASSERT_TRUE(img.has_alpha());
        const std::size_t centre = std::size_t(8 * kSide + 8);
        EXPECT_EQ(img.alpha()[centre], 0.f);
        EXPECT_EQ(img.pixels()[centre], Rgb(0.f));
        EXPECT_EQ(img.alpha()[0], 1.f);
        EXPECT_GT(img.pixels()[0].r, 0.1f);
        const fr::Image opaque =
            fr::render(scene_of(scene(s, false)), fr::testing::test_options("path", 16, 3));
        EXPECT_FALSE(opaque.has_alpha());
        EXPECT_EQ(opaque.pixels()[centre], Rgb(0.f));
        EXPECT_EQ(opaque.pixels()[0], img.pixels()[0]);
    }
    // Control: the same sphere without holdout is opaque and lit.
    const fr::Image plain =
        fr::render(scene_of(scene(R"("material": {"model": "lambert", "reflectance": 0.8})")),
                   fr::testing::test_options("path", 16, 3));
    ASSERT_TRUE(plain.has_alpha());
    EXPECT_EQ(plain.alpha()[std::size_t(8 * kSide + 8)], 1.f);
    EXPECT_GT(plain.pixels()[std::size_t(8 * kSide + 8)].r, 0.1f);
}

// A holdout inside a mix is a hole of its share: weight 0.3 on a quad that fills the view
// makes every camera sample 30% transparent (the weight is constant: alpha 0.7 up to float
// rounding) and leaves 70% of the Lambertian colour: under a constant environment of radiance
// 1 with max_depth 1 the Lambertian of reflectance 0.5 alone is 0.5, the mix 0.35 in the mean.
// The tolerance is 5 sigma of the noisiest estimator the mix could be (0 or 0.5 per sample,
// sigma 0.229 per sample) over 256 pixels x 64 samples; alpha 1 or 0.3 (the weight read the
// wrong way round) fails.
TEST(Alpha, HoldoutInAMixIsItsShare) {
    const fr::Scene sc = scene_of(
        std::string(kOrtho) +
        R"("shapes": [{"type": "quad", "vertices": [[-2, -2, 0], [2, -2, 0], [2, 2, 0], [-2, 2, 0]],
                       "material": {"model": "mix", "weight": 0.3, "materials": [
                           {"model": "lambert", "reflectance": 0.5}, {"model": "holdout"}]}}],
             "lights": [{"type": "environment", "radiance": 1}],
             "render": {"max_depth": 1, "film_transparent": true})");
    const int spp = 64;
    const fr::Image img = fr::render(sc, fr::testing::test_options("path", spp, 3));
    ASSERT_TRUE(img.has_alpha());
    double mean = 0.0;
    for (std::size_t i = 0; i < img.pixels().size(); ++i) {
        EXPECT_NEAR(img.alpha()[i], 0.7f, 1e-6f);
        mean += img.pixels()[i].r;
    }
    mean /= double(img.pixels().size());
    EXPECT_NEAR(mean, 0.35, 5.0 * 0.229 / std::sqrt(256.0 * spp));
}

// Straight pass-throughs keep the background's transparency (a `null` quad in front of the
// camera: alpha stays 0 behind it); a mirror does not (Cycles counts only transparent
// bounces): the environment seen in a mirror is colour with alpha 1.
TEST(Alpha, TransparentSurfacesLetAlphaThroughMirrorsDoNot) {
    auto scene = [](const std::string& material) {
        return std::string(kOrtho) +
               R"("shapes": [{"type": "quad", "vertices": [[-2, -2, 0], [2, -2, 0], [2, 2, 0],
                                                          [-2, 2, 0]],
                              "material": )" +
               material + R"(}],
                 "lights": [{"type": "environment", "radiance": 1}],
                 "render": {"film_transparent": true})";
    };
    const fr::Image through = fr::render(scene_of(scene(R"({"model": "null"})")),
                                         fr::testing::test_options("path", 4, 3));
    ASSERT_TRUE(through.has_alpha());
    for (std::size_t i = 0; i < through.alpha().size(); ++i) {
        EXPECT_EQ(through.alpha()[i], 0.f);
        EXPECT_EQ(through.pixels()[i], Rgb(0.f));
    }
    const fr::Image mirror = fr::render(scene_of(scene(R"({"model": "mirror"})")),
                                        fr::testing::test_options("path", 4, 3));
    for (std::size_t i = 0; i < mirror.alpha().size(); ++i) {
        EXPECT_EQ(mirror.alpha()[i], 1.f);
        EXPECT_GT(mirror.pixels()[i].r, 0.5f);
    }
}

// The direct integrator agrees with path on alpha (the same see-through rule).
TEST(Alpha, DirectIntegratorHasTheSameAlpha) {
    const fr::Scene scene = scene_of(sphere_scene(R"({"film_transparent": true})"));
    const fr::Image p = fr::render(scene, fr::testing::test_options("path", 16, 3));
    const fr::Image d = fr::render(scene, fr::testing::test_options("direct", 16, 3));
    ASSERT_TRUE(d.has_alpha());
    EXPECT_EQ(p.alpha(), d.alpha());  // same film positions, and alpha depends only on them
}

// Split by region and by sample range, the parts (through their files) merge into the single
// render's colour and alpha bit for bit; a part without alpha does not merge with them.
TEST(Alpha, PartsMergeAlphaExactly) {
    const fr::Scene scene = scene_of(sphere_scene(R"({"film_transparent": true})"));
    fr::RenderOptions o = fr::testing::test_options("path", 8, 3);
    const fr::Image whole = fr::render(scene, o);
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("facet_alpha_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::vector<fr::RenderPart> parts;
    std::vector<std::string> names;
    for (const auto& [region, s0, s1] :
         {std::tuple{fr::Region{0, 0, 16, 8}, 0, 8}, std::tuple{fr::Region{0, 8, 16, 16}, 0, 3},
          std::tuple{fr::Region{0, 8, 16, 16}, 3, 8}}) {
        fr::RenderOptions po = o;
        po.region = region;
        po.sample_begin = s0;
        po.sample_end = s1;
        fr::RenderSession session(scene, po);
        session.render();
        const std::string path = (dir / ("p" + std::to_string(parts.size()) + ".fpart")).string();
        fr::write_part(session.part(), path);
        parts.push_back(fr::read_part(path));
        names.push_back(path);
    }
    const fr::Image merged = fr::merge_parts(parts, names).resolve();
    ASSERT_TRUE(merged.has_alpha());
    EXPECT_EQ(merged.pixels(), whole.pixels());
    EXPECT_EQ(merged.alpha(), whole.alpha());
    // A part of the same scene without alpha: refused, naming it.
    fr::RenderPart opaque = parts[0];
    opaque.film = fr::Film(opaque.info.region);
    try {
        fr::merge_parts({parts[1], opaque}, {"a", "opaque"});
        ADD_FAILURE() << "merged a part without alpha";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("opaque"), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(dir);
}

// EXR keeps alpha exactly (channel A); PNG writes RGBA.
TEST(Alpha, ExrAndPngCarryAlpha) {
    fr::Image img(3, 2);
    img.add_alpha(0.f);
    for (int i = 0; i < 6; ++i) {
        img.pixels()[std::size_t(i)] = Rgb(0.1f * float(i));
        img.alpha()[std::size_t(i)] = 0.2f * float(i) - 0.05f * float(i == 0);
    }
    const std::filesystem::path dir = std::filesystem::temp_directory_path();
    const std::string exr = (dir / ("facet_alpha_" + std::to_string(::getpid()) + ".exr")).string();
    fr::write_image(img, exr);
    const fr::Image back = fr::read_image(exr);
    ASSERT_TRUE(back.has_alpha());
    EXPECT_EQ(back.alpha(), img.alpha());
    EXPECT_EQ(back.pixels(), img.pixels());
    std::filesystem::remove(exr);
    fr::Image opaque(3, 2);
    fr::write_image(opaque, exr);
    EXPECT_FALSE(fr::read_image(exr).has_alpha());
    std::filesystem::remove(exr);
    const std::string png = (dir / ("facet_alpha_" + std::to_string(::getpid()) + ".png")).string();
    fr::write_image(img, png);
    EXPECT_GT(std::filesystem::file_size(png), 0u);
    std::filesystem::remove(png);
}

// The JSON keys round-trip, and bad values name their place.
TEST(Alpha, JsonKeysRoundTripAndErrorsNameThePlace) {
    const fr::SceneDescription d =
        fr::parse_scene_description(R"({"format": "facet-scene", "version": 1, )" +
                                        sphere_scene(R"({"film_transparent": true})") + "}",
                                    "alpha.json");
    EXPECT_TRUE(d.render.film_transparent);
    const fr::SceneDescription again =
        fr::parse_scene_description(fr::write_scene_json(d), "again.json");
    EXPECT_EQ(again, d);
    try {
        scene_of(sphere_scene(R"({"film_transparent": 1})"));
        ADD_FAILURE() << "accepted a number";
    } catch (const fr::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("/render/film_transparent"), std::string::npos)
            << e.what();
    }
    try {
        scene_of(std::string(kOrtho) +
                 R"("shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                                "material": {"model": "lambert"}, "holdout": "yes"}],
                   "lights": [{"type": "point", "position": [0, 0, 6], "power": 1}])");
        ADD_FAILURE() << "accepted a string";
    } catch (const fr::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("/shapes/0/holdout"), std::string::npos) << e.what();
    }
}

// export-pov refuses what POV-Ray cannot render, naming the place (never a silent drop).
TEST(Alpha, ExportPovRefusesTransparencyAndHoldouts) {
    auto error_of = [](const std::string& body) {
        try {
            fr::export_pov(fr::parse_scene_description(
                               R"({"format": "facet-scene", "version": 1, )" + body + "}", "a"),
                           "a.json");
        } catch (const fr::SceneError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(
        error_of(sphere_scene(R"({"film_transparent": true})")).find("/render/film_transparent"),
        std::string::npos);
    const std::string holdout_shape =
        std::string(kOrtho) +
        R"("shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "holdout": true,
                       "material": {"model": "lambert"}}],
           "lights": [{"type": "point", "position": [0, 0, 6], "power": 1}])";
    EXPECT_NE(error_of(holdout_shape).find("/shapes/0/holdout"), std::string::npos);
    const std::string holdout_material =
        std::string(kOrtho) +
        R"("shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                       "material": {"model": "holdout"}}],
           "lights": [{"type": "point", "position": [0, 0, 6], "power": 1}])";
    EXPECT_NE(error_of(holdout_material).find("holdout cannot be exported"), std::string::npos)
        << error_of(holdout_material);
    // Control: the same scene with an ordinary material exports.
    EXPECT_EQ(error_of(sphere_scene(R"({})")), "");
}

// Media: a camera ray crossing a `null`-bounded box of scattering fog (sigma_s 1, depth 1)
// without scattering stays see-through; one that scatters covers. Alpha is then the
// probability of scattering, 1 - exp(-1) = 0.632, each sample a Bernoulli of it: over the 8 x 8
// central pixels x 64 samples, sigma 0.0075; the tolerance is 5 of those. No fog (alpha 0) or
// the box opaque (alpha 1) fails.
TEST(Alpha, FogCoversByItsScatteringProbability) {
    const fr::Scene sc = scene_of(
        R"("camera": {"type": "orthographic", "position": [0, 0, 5], "look_at": [0, 0, 0],
                      "up": [0, 1, 0], "scale": 2, "width": 32, "height": 32},
           "materials": {"fogbox": {"model": "null", "interior": "fog"}},
           "media": {"fog": {"kind": "homogeneous", "sigma_a": 0, "sigma_s": 1}},
           "shapes": [{"type": "box", "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5],
                       "material": "fogbox"}],
           "lights": [{"type": "environment", "radiance": 1}],
           "render": {"film_transparent": true})");
    fr::RenderStats st;
    const fr::Image img = fr::render(sc, fr::testing::test_options("path", 64, 3), &st);
    EXPECT_NE(st.kernel.name.find("media"), std::string::npos) << st.kernel.name;
    ASSERT_TRUE(img.has_alpha());
    double sum = 0.0;
    for (int y = 12; y < 20; ++y)
        for (int x = 12; x < 20; ++x) sum += img.alpha()[std::size_t(y * 32 + x)];
    const double p = 1.0 - std::exp(-1.0);
    EXPECT_NEAR(sum / 64.0, p, 5.0 * std::sqrt(p * (1.0 - p) / (64.0 * 64.0)));
    EXPECT_EQ(img.alpha()[0], 0.f);  // outside the box: the background
}
