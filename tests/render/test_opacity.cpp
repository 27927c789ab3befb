// Opacity (cut-outs; scene.h, Opacity): what camera rays see through a partly opaque surface,
// what shadow rays let through, exact holes of a 0/1 texture, that opacity 1 changes nothing,
// and the errors for bad values. Monte Carlo counts scale with FACET_STRESS_SCALE.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

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
                                      "opacity.json");
}

std::string error_of(const std::string& body) {
    try {
        scene_of(body);
    } catch (const fr::SceneError& e) {
        return e.what();
    }
    return "";
}

double mean_red(const fr::Image& img) {
    double s = 0.0;
    for (const Rgb& p : img.pixels()) s += double(p.r);
    return s / double(img.pixels().size());
}

// A 16 x 16 camera looking down -z at the quad [-1, 1]^2 in z = 0, which fills the film.
const char* const kCamera =
    R"("camera": {"position": [0, 0, 2], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 50,
                  "width": 16, "height": 16},)";

// The quad in front of a constant environment of radiance 1 (max_depth 1): where it is there,
// the Lambertian quad of reflectance 0.5 has radiance rho * E / pi = 0.5 exactly (every
// cosine-sampled estimate is rho); where it lets the ray through, the camera sees 1.
// `opacity`: the material's opacity key and value (or nothing).
std::string quad_in_front(const std::string& opacity) {
    return std::string(kCamera) +
           R"("shapes": [{"type": "quad", "vertices": [[-1.5, -1.5, 0], [1.5, -1.5, 0],
                                                       [1.5, 1.5, 0], [-1.5, 1.5, 0]],
                          "material": {"model": "lambert", "reflectance": 0.5)" +
           opacity + R"(}}],
             "lights": [{"type": "environment", "radiance": 1}],
             "render": {"max_depth": 1})";
}

}  // namespace

// Opacity 0.3: each camera ray stops with probability 0.3 (sees 0.5) and passes with 0.7 (sees
// 1), so the expected pixel is 0.7 * 1 + 0.3 * 0.5 = 0.85. Each sample is 0.5 or 1, a Bernoulli
// of standard deviation 0.5 sqrt(0.21) = 0.229; over N = 256 pixels x spp samples the mean's is
// 0.229 / sqrt(N): the tolerance is 5 of those (4e-3 at 256 spp). A wrong decision rule (u > a,
// alpha read as 1 - alpha: 0.65) or a correlated hash (all samples alike: 0.5 or 1) fails.
TEST(Opacity, CameraRaysSeeThroughInProportion) {
    const int spp = std::max(16, int(256 * fr::testing::stress_scale()));
    const fr::Scene scene = scene_of(quad_in_front(R"(, "opacity": 0.3)"));
    const fr::Image img = fr::render(scene, fr::testing::test_options("path", spp, 5));
    const double n = 256.0 * spp;
    EXPECT_NEAR(mean_red(img), 0.85, 5.0 * 0.229 / std::sqrt(n));
    // Both outcomes occur in one image (the numbers are not one per pixel or per image).
    int seen = 0, through = 0;
    const fr::Image one = fr::render(scene, fr::testing::test_options("path", 1, 5));
    for (const Rgb& p : one.pixels()) {
        seen += std::fabs(p.r - 0.5f) < 1e-5f;
        through += std::fabs(p.r - 1.f) < 1e-6f;
    }
    EXPECT_EQ(seen + through, 256);
    EXPECT_GT(seen, 40);
    EXPECT_GT(through, 120);
}

// A plane of opacity 0.5 between a directional light and a Lambertian floor halves the floor's
// irradiance: the direct integrator (no indirect light) gives rho E cos / pi * V with V = 1 for
// half of the shadow rays. Floor rho = 0.5, E = pi, light straight down: 0.5 unshadowed, 0.25
// expected. Samples are 0 or 0.5 (standard deviation 0.25); tolerance 5 sigma of the mean. The
// camera hangs between the floor and the screen, so it sees only the floor. Opacity 1 gives
// exactly 0 and no screen exactly 0.5 (the test can tell them apart).
TEST(Opacity, ShadowRaysPassInProportion) {
    const int spp = std::max(16, int(256 * fr::testing::stress_scale()));
    auto scene = [](const std::string& screen) {
        return scene_of(std::string(R"("camera": {"position": [0, 0, 0.5], "look_at": [0, 0, 0],
                                       "up": [0, 1, 0], "fov": 40, "width": 16, "height": 16},
            "shapes": [{"type": "quad", "vertices": [[-9, -9, 0], [9, -9, 0], [9, 9, 0], [-9, 9, 0]],
                        "material": {"model": "lambert", "reflectance": 0.5}})") +
                        screen + R"(],
            "lights": [{"type": "directional", "direction": [0, 0, -1], "irradiance": 3.14159265358979}],
            "render": {"max_depth": 1})");
    };
    const std::string screen =
        R"(, {"type": "quad", "vertices": [[-9, -9, 1], [9, -9, 1], [9, 9, 1], [-9, 9, 1]],
              "material": {"model": "lambert", "reflectance": 0.5, "opacity": )";
    const double n = 256.0 * spp;
    const fr::Image half =
        fr::render(scene(screen + "0.5}}"), fr::testing::test_options("direct", spp, 3));
    EXPECT_NEAR(mean_red(half), 0.25, 5.0 * 0.25 / std::sqrt(n));
    const fr::Image full =
        fr::render(scene(screen + "1}}"), fr::testing::test_options("direct", 4, 3));
    EXPECT_EQ(mean_red(full), 0.0);
    const fr::Image none = fr::render(scene(""), fr::testing::test_options("direct", 4, 3));
    EXPECT_NEAR(mean_red(none), 0.5, 1e-6);
    // The path integrator's shadow rays (packets) honour it as well.
    const fr::Image path =
        fr::render(scene(screen + "0.5}}"), fr::testing::test_options("path", spp, 3));
    EXPECT_NEAR(mean_red(path), 0.25, 5.0 * 0.25 / std::sqrt(n));
}

// A 0/1 checker as opacity cuts exact holes: 2 x 2 cells over the quad's uv square, the cell at
// the uv origin (bottom-left) with opacity 0. The 16 x 16 pixels lie inside the quad's
// central [-1, 1]^2 ... so the cells are 8 x 8 pixels; every sample of a pixel stays in its
// cell. Holes see the environment (exactly 1), the rest the quad (0.5 to float rounding).
TEST(Opacity, CheckerOpacityCutsExactHoles) {
    const fr::Scene scene = scene_of(std::string(kCamera) + R"(
        "shapes": [{"type": "quad", "vertices": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]],
                    "material": {"model": "lambert", "reflectance": 0.5,
                                 "opacity": {"checker": {"colors": [0, 1], "scale": 2}}}}],
        "lights": [{"type": "environment", "radiance": 1}],
        "render": {"max_depth": 1})");
    // fov 50 from distance 2: the film spans 2 tan 25 * 2 = 1.865 < 2, inside the quad.
    const fr::Image img = fr::render(scene, fr::testing::test_options("path", 8, 1));
    for (int y = 0; y < 16; ++y) {
        for (int x = 0; x < 16; ++x) {
            const bool left = x < 8, bottom = y >= 8;  // image row 0 at the top
            const bool hole = left == bottom;          // cells (0,0) and (1,1): colour 0
            const float want = hole ? 1.f : 0.5f;
            EXPECT_NEAR(img.at(x, y).r, want, 1e-6f) << x << "," << y;
        }
    }
}

// Invisible analytic shapes: a sphere and a plane of opacity 0 let every ray through (both of
// the sphere's roots are tested), so the camera sees the environment exactly.
TEST(Opacity, OpacityZeroSphereAndPlaneAreInvisible) {
    const fr::Scene scene = scene_of(std::string(kCamera) + R"(
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5,
                    "material": {"model": "lambert", "reflectance": 0.5, "opacity": 0}},
                   {"type": "plane", "point": [0, 0, -1], "normal": [0, 0, 1],
                    "material": {"model": "lambert", "reflectance": 0.5, "opacity": 0}}],
        "lights": [{"type": "environment", "radiance": 1}],
        "render": {"max_depth": 2})");
    const fr::Image img = fr::render(scene, fr::testing::test_options("path", 2, 1));
    for (const Rgb& p : img.pixels()) EXPECT_EQ(p.r, 1.f);
}

// Opacity 1 is the opaque fast path: the same image bit for bit as without the key.
TEST(Opacity, OpacityOneChangesNothing) {
    const fr::Image with = fr::render(scene_of(quad_in_front(R"(, "opacity": 1)")),
                                      fr::testing::test_options("path", 4, 9));
    const fr::Image without =
        fr::render(scene_of(quad_in_front("")), fr::testing::test_options("path", 4, 9));
    ASSERT_EQ(with.pixels().size(), without.pixels().size());
    for (std::size_t i = 0; i < with.pixels().size(); ++i)
        EXPECT_EQ(with.pixels()[i], without.pixels()[i]);
}

TEST(Opacity, BadValuesNameThePointer) {
    auto named = [](const std::string& body) {
        return scene_of(std::string(kCamera) +
                        R"("materials": {"leaf": {"model": "lambert", "reflectance": 0.5, )" +
                        body + R"(}},
             "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "leaf"}],
             "lights": [{"type": "environment", "radiance": 1}])");
    };
    auto err = [&](const std::string& body) {
        try {
            named(body);
        } catch (const fr::SceneError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(err(R"("opacity": 1.5)").find("/materials/leaf/opacity"), std::string::npos);
    EXPECT_NE(err(R"("opacity": -0.1)").find("/materials/leaf/opacity"), std::string::npos);
    EXPECT_NE(err(R"("opacity": "half")").find("/materials/leaf/opacity"), std::string::npos);
    EXPECT_NE(err(R"("opacity": {"checker": {"colors": [0, 2]}})").find("/materials/leaf/opacity"),
              std::string::npos);
    EXPECT_NE(err(R"("alpha_cutoff": 0)").find("/materials/leaf/alpha_cutoff"), std::string::npos);
    // NaN cannot be written in JSON: through the description, as Python would pass it.
    fr::SceneDescription d = fr::parse_scene_description(
        std::string(R"({"format": "facet-scene", "version": 1, )") + kCamera +
            R"("materials": {"leaf": {"model": "lambert", "reflectance": 0.5, "opacity": 0.5}},
               "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "leaf"}],
               "lights": [{"type": "environment", "radiance": 1}]})",
        "nan.json");
    d.materials[0].second.params.set("opacity", std::numeric_limits<double>::quiet_NaN());
    try {
        fr::build_scene(d, "nan.json");
        ADD_FAILURE() << "NaN opacity accepted";
    } catch (const fr::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("/materials/leaf/opacity"), std::string::npos)
            << e.what();
    }
    // An emitter with opacity would be sampled in full by next-event estimation: refused.
    EXPECT_NE(error_of(std::string(kCamera) + R"(
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "emission": 1,
                    "material": {"model": "lambert", "reflectance": 0.5, "opacity": 0.5}}],
        "lights": [])")
                  .find("/shapes/0/material"),
              std::string::npos);
    // A valid material still loads (the lambdas above can tell success from failure).
    EXPECT_EQ(err(R"("opacity": 0.5, "alpha_cutoff": 0.5)"), "");
}

// export-pov cannot express opacity exactly yet: an error naming the key, never a dropped key.
TEST(Opacity, PovExportNamesTheOpacity) {
    std::string e;
    try {
        (void)fr::export_pov(
            fr::parse_scene_description(
                std::string(R"({"format": "facet-scene", "version": 1, )") + kCamera +
                    R"("materials": {"leaf": {"model": "lambert", "reflectance": 0.5,
                                               "opacity": 0.5}},
                       "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "leaf"}],
                       "lights": [{"type": "point", "position": [0, 0, 5], "power": 10}]})",
                "p.json"),
            "p.json");
    } catch (const fr::SceneError& x) {
        e = x.what();
    }
    EXPECT_NE(e.find("p.json: /materials/leaf/opacity:"), std::string::npos) << e;
}
