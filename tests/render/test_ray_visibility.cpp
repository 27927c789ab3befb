// Per-shape ray visibility (scenes/FORMAT.md "Ray visibility"; integrator.h "Ray visibility"):
// each flag on its own in a scene whose answer is known exactly, each with a control render
// that changes (the flag ignored, or the same shape without it), JSON errors naming the pointer,
// the round trip, and the kernel choice (scenes without the key run the kernels they ran).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "facet/render/aov.h"
#include "facet/render/image.h"
#include "facet/render/pov_export.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
namespace ft = facet::render::testing;
using facet::Rgb;
using facet::Vec3;

namespace {

constexpr int kVisSide = 16;

// A 16 x 16 orthographic camera at height h looking straight down at the floor y = 0 (which it
// sees over [-1, 1]^2 in x and z).
std::string camera_down(double h) {
    return R"("camera": {"type": "orthographic", "position": [0, )" + std::to_string(h) +
           R"(, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "scale": 2, "width": 16,
               "height": 16},)";
}

// A quad at height y over [x0, x1] x [-z, z], facing up (+y) or down.
std::string quad(double y, double x0, double x1, double z, bool up) {
    auto p = [&](double x, double zz) {
        return "[" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(zz) + "]";
    };
    // Counter-clockwise seen from +y: (x0, -z) -> (x0, z) -> (x1, z) -> (x1, -z).
    return up ? "[" + p(x0, -z) + ", " + p(x0, z) + ", " + p(x1, z) + ", " + p(x1, -z) + "]"
              : "[" + p(x0, -z) + ", " + p(x1, -z) + ", " + p(x1, z) + ", " + p(x0, z) + "]";
}

fr::Image render(const fr::Scene& scene, int spp, fr::RenderStats* st = nullptr) {
    fr::RenderOptions o = ft::test_options("path", spp, 7);
    return fr::render(scene, o, st);
}

// A white Lambertian floor (reflectance 0.5) under a point light of power 300 at (0, 4, 0).
constexpr double kRho = 0.5, kPower = 300.0;
const Vec3 kLight(0.f, 4.f, 0.f);
const char* const kFloorAndLamp = R"(
    "materials": {"floor": {"model": "lambert", "reflectance": 0.5},
                  "grey": {"model": "lambert", "reflectance": 0.8}},
    "lights": [{"type": "point", "position": [0, 4, 0], "power": 300}],
    "render": {"max_depth": 1},)";
const char* const kFloor =
    R"({"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"})";

// The largest relative difference of the image from the analytic point-lit floor over the
// pixels `use` selects (and the number of them).
template <class Use>
double worst_vs_floor(const fr::Scene& scene, const fr::Image& img, Use use, int& count) {
    double worst = 0.0;
    count = 0;
    for (int y = 0; y < kVisSide; ++y) {
        for (int x = 0; x < kVisSide; ++x) {
            if (!use(x, y)) continue;
            const double want =
                *ft::point_light_on_plane(scene.camera(), x, y, kLight, kPower, kRho);
            const Rgb got = img.at(x, y);
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::fabs(double(got[c]) - want) / want);
            ++count;
        }
    }
    return worst;
}

}  // namespace

// An occluder between the lamp and the floor that shadow rays do not see lets the light through
// exactly: every pixel is the unoccluded analytic irradiance of the point light (deterministic:
// a delta light, 1 spp, max_depth 1), to float rounding (relative 1e-5). The camera lies below
// the occluder. Controls: the same occluder casting shadows leaves the floor black, and one
// that only the camera does not see too.
TEST(RayVisibility, ShadowOffOccluderLetsTheLightThroughExactly) {
    auto scene_with = [&](const std::string& vis) {
        return ft::scene_from(camera_down(1.0) + kFloorAndLamp + R"("shapes": [)" + kFloor +
                              R"(, {"type": "quad", "material": "grey", "vertices": )" +
                              quad(2.0, -3, 3, 3, true) + vis + "}]");
    };
    fr::RenderStats st;
    const fr::Scene scene = scene_with(R"(, "visibility": {"shadow": false})");
    EXPECT_TRUE(scene.features().has_ray_visibility);
    const fr::Image img = render(scene, 1, &st);
    EXPECT_NE(st.kernel.name.find("media"), std::string::npos) << st.kernel.name;
    int n = 0;
    const double worst = worst_vs_floor(
        scene, img, [](int, int) { return true; }, n);
    EXPECT_EQ(n, kVisSide * kVisSide);
    EXPECT_LT(worst, 1e-5);
    for (const char* control : {"", R"(, "visibility": {"camera": false})"}) {
        const fr::Scene c = scene_with(control);
        const fr::Image ci = render(c, 1);
        for (int y = 0; y < kVisSide; ++y)
            for (int x = 0; x < kVisSide; ++x) EXPECT_EQ(ci.at(x, y), Rgb(0.f)) << control;
    }
    std::printf("shadow-invisible occluder: worst relative difference %.2e (tolerance 1e-5)\n",
                worst);
}

// An occluder the camera does not see still casts its shadow: seen from above, the floor under
// it (x < 0: the occluder covers x in [-3, 0] at height 2, its shadow x in [-6, 0]) is black and
// the rest is the analytic floor (relative 1e-5). Control: seen by the camera, the occluder's
// lit top shows where the shadow was.
TEST(RayVisibility, CameraOffOccluderStillCastsItsShadow) {
    auto scene_with = [&](const std::string& vis) {
        return ft::scene_from(camera_down(5.0) + kFloorAndLamp + R"("shapes": [)" + kFloor +
                              R"(, {"type": "quad", "material": "grey", "vertices": )" +
                              quad(2.0, -3, 0, 3, true) + vis + "}]");
    };
    const fr::Scene scene = scene_with(R"(, "visibility": {"camera": false})");
    const fr::Image img = render(scene, 1);
    int n = 0;
    const double worst = worst_vs_floor(
        scene, img, [](int x, int) { return x >= kVisSide / 2; }, n);
    EXPECT_EQ(n, kVisSide * kVisSide / 2);
    EXPECT_LT(worst, 1e-5);
    for (int y = 0; y < kVisSide; ++y)
        for (int x = 0; x < kVisSide / 2; ++x) EXPECT_EQ(img.at(x, y), Rgb(0.f)) << x << ", " << y;
    const fr::Image control = render(scene_with(""), 1);
    EXPECT_GT(control.at(2, 8).r, 0.05f);  // the occluder's top: 0.8/pi 300/(4 pi 4) = 1.5
}

// A mirror shows an emitter that the camera does not see. The emitter (radiance 2, facing down,
// at height 1 over a mirror floor, covering the view): camera rays cross it from its back
// (invisible to them) and its front shines in the mirror: every pixel is exactly 2 (a delta
// bounce, full weight). Controls: glossy rays not seeing it either gives 0, and the emitter seen
// by the camera (its black back) gives 0.
TEST(RayVisibility, MirrorSeesWhatTheCameraDoesNot) {
    auto scene_with = [&](const std::string& vis) {
        return ft::scene_from(
            camera_down(5.0) +
            R"("shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0],
                           "material": {"model": "mirror"}},
                          {"type": "quad", "emission": 2, "vertices": )" +
            quad(1.0, -3, 3, 3, false) + vis + "}]");
    };
    const fr::Image img = render(scene_with(R"(, "visibility": {"camera": false})"), 1);
    for (int y = 0; y < kVisSide; ++y)
        for (int x = 0; x < kVisSide; ++x) EXPECT_EQ(img.at(x, y), Rgb(2.f)) << x << ", " << y;
    for (const char* control : {R"(, "visibility": {"camera": false, "glossy": false})", ""}) {
        const fr::Image ci = render(scene_with(control), 1);
        for (int y = 0; y < kVisSide; ++y)
            for (int x = 0; x < kVisSide; ++x) EXPECT_EQ(ci.at(x, y), Rgb(0.f)) << control;
    }
}

// Diffuse rays pass a shape they do not see: a black occluder over a white-furnace floor
// (reflectance 0.6 under a constant environment of radiance 1), invisible to camera, diffuse and
// shadow rays, leaves the floor at 0.6: each cosine-sampled BSDF ray escapes to the environment
// (f cos / pdf = 0.6 exactly); light samples of the environment (if any) are unblocked too. The
// mean over the image must be within 1e-3 of 0.6 (16 spp: the estimate of a constant integrand,
// exact up to the MIS split between the two estimators). Control: the occluder seen by diffuse
// rays darkens the floor below 0.3.
TEST(RayVisibility, DiffuseRaysPassWhatTheyDoNotSee) {
    auto scene_with = [&](const std::string& vis) {
        return ft::scene_from(camera_down(5.0) +
                              R"("lights": [{"type": "environment", "radiance": 1}],
               "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0],
                           "material": {"model": "lambert", "reflectance": 0.6}},
                          {"type": "quad", "material": {"model": "lambert", "reflectance": 0},
                           "vertices": )" +
                              quad(1.0, -50, 50, 50, true) + vis + "}]");
    };
    auto mean = [](const fr::Image& img) {
        double s = 0.0;
        for (int y = 0; y < kVisSide; ++y)
            for (int x = 0; x < kVisSide; ++x) s += img.at(x, y).g;
        return s / (kVisSide * kVisSide);
    };
    const double m = mean(render(scene_with(R"(, "visibility": {"camera": false, "diffuse": false,
                                                   "shadow": false})"),
                                 16));
    EXPECT_NEAR(m, 0.6, 1e-3);
    const double control =
        mean(render(scene_with(R"(, "visibility": {"camera": false, "shadow": false})"), 16));
    EXPECT_LT(control, 0.3);
    std::printf("diffuse-invisible occluder: floor %.6f (0.6), seen by diffuse rays %.4f\n", m,
                control);
}

// Transmitted rays see what the camera does not: an emitter under a smooth glass pane (seen
// obliquely, so that refraction bends the rays) with camera rays off renders bit for bit as with
// every kind of ray on (the camera reaches it only through the glass; the reference turns off a
// flag no ray here exercises, volume scatter, so that both run the same kernel); with
// transmission off too, no light reaches the camera at all.
TEST(RayVisibility, TransmittedRaysSeeWhatTheCameraDoesNot) {
    auto scene_with = [&](const std::string& vis) {
        return ft::scene_from(
            R"("camera": {"type": "orthographic", "position": [0, 5, 3], "look_at": [0, 0, 0],
                          "up": [0, 1, 0], "scale": 1, "width": 16, "height": 16},
               "shapes": [{"type": "quad", "material": {"model": "dielectric", "ior": 1.5},
                           "vertices": )" +
            quad(1.0, -20, 20, 20, true) +
            R"(}, {"type": "quad", "emission": [1, 2, 3], "vertices": )" +
            quad(0.5, -20, 20, 20, true) + vis + "}]");
    };
    const fr::Image seen = render(scene_with(R"(, "visibility": {"camera": false})"), 4);
    const fr::Image ref = render(scene_with(R"(, "visibility": {"volume_scatter": false})"), 4);
    const fr::Image none =
        render(scene_with(R"(, "visibility": {"camera": false, "transmission": false})"), 4);
    double sum = 0.0;
    for (int y = 0; y < kVisSide; ++y) {
        for (int x = 0; x < kVisSide; ++x) {
            EXPECT_EQ(seen.at(x, y), ref.at(x, y)) << x << ", " << y;
            EXPECT_EQ(none.at(x, y), Rgb(0.f)) << x << ", " << y;
            sum += seen.at(x, y).b;
        }
    }
    EXPECT_GT(sum / (kVisSide * kVisSide), 0.5);  // mostly transmitted: 3 (1 - F) / 1.5^2 or so
}

// An emitter that no diffuse, glossy or transmission ray sees is no light source (Cycles 3.4's
// object_usable_as_light): the camera sees its radiance (3, at full weight: no light sample can
// find it) and it still casts its shadow; the floor it would have lit shows only the lamp's
// light (analytic, relative 1e-5, outside the shadow). Control: as a light source (diffuse rays
// on) it is one of the scene's lights.
TEST(RayVisibility, EmitterNoRayOfLightSeesIsNoLightSource) {
    auto scene_with = [&](const std::string& vis) {
        return ft::scene_from(camera_down(5.0) + kFloorAndLamp + R"("shapes": [)" + kFloor +
                              R"(, {"type": "quad", "emission": 3, "vertices": )" +
                              quad(1.0, -0.5, 0.5, 0.5, true) + vis + "}]");
    };
    const fr::Scene scene =
        scene_with(R"(, "visibility": {"diffuse": false, "glossy": false, "transmission": false})");
    EXPECT_EQ(scene.lights().size(), 1u);
    const fr::Image img = render(scene, 1);
    EXPECT_EQ(img.at(7, 7), Rgb(3.f));
    EXPECT_EQ(img.at(8, 8), Rgb(3.f));
    int n = 0;
    // Outside the shadow (|x|, |z| < 2/3 on the floor: pixel centres beyond 0.6875).
    auto lit = [](int x, int y) {
        auto out = [](int i) { return std::fabs(-1.0 + (i + 0.5) * 2.0 / kVisSide) > 0.68; };
        return out(x) || out(y);
    };
    const double worst = worst_vs_floor(scene, img, lit, n);
    EXPECT_GT(n, 20);
    EXPECT_LT(worst, 1e-5);
    EXPECT_EQ(scene_with(R"(, "visibility": {"glossy": false})").lights().size(), 2u);
}

// An emitter that diffuse rays do not see lights no diffuse surface, through light samples
// either (Cycles 3.4's SHADER_EXCLUDE_DIFFUSE of a mesh light): a Lambertian floor under it
// (and under nothing else) is exactly black. Control: a glossy floor (GGX, alpha 0.3) under the
// same emitter is lit (its glossy rays and light samples see it), and with diffuse rays on the
// Lambertian floor is lit.
TEST(RayVisibility, EmitterDiffuseRaysDoNotSeeLightsNoDiffuseSurface) {
    auto scene_with = [&](const std::string& floor, const std::string& vis) {
        return ft::scene_from(camera_down(5.0) + R"("shapes": [{"type": "plane", "point": [0, 0, 0],
                                              "normal": [0, 1, 0], "material": )" +
                              floor + R"(}, {"type": "quad", "emission": 2, "vertices": )" +
                              quad(1.0, -3, 3, 3, false) + R"(, "visibility": {"camera": false)" +
                              vis + "}}]");
    };
    const std::string lambert = R"({"model": "lambert", "reflectance": 0.5})";
    const std::string ggx = R"({"model": "ggx", "alpha": 0.3, "fresnel": "none"})";
    auto sum = [](const fr::Image& im) {
        double t = 0.0;
        for (int y = 0; y < kVisSide; ++y)
            for (int x = 0; x < kVisSide; ++x) t += im.at(x, y).g;
        return t;
    };
    EXPECT_EQ(sum(render(scene_with(lambert, R"(, "diffuse": false)"), 4)), 0.0);
    EXPECT_GT(sum(render(scene_with(ggx, R"(, "diffuse": false)"), 4)), 1.0);
    EXPECT_GT(sum(render(scene_with(lambert, ""), 4)), 1.0);
}

// Errors name the pointer; the description round-trips; all flags true is no feature at all.
TEST(RayVisibility, JsonErrorsRoundTripAndNoCostWithoutIt) {
    const std::string base = camera_down(5.0) + kFloorAndLamp;
    auto error = [&](const std::string& shapes) {
        try {
            ft::scene_from(base + R"("shapes": )" + shapes);
        } catch (const fr::SceneError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    std::string e = error(std::string("[") + kFloor +
                          R"(, {"type": "sphere", "center": [0, 1, 0], "radius": 0.5,
                                "material": "grey", "visibility": {"camra": false}}])");
    EXPECT_NE(e.find("/shapes/1/visibility/camra"), std::string::npos) << e;
    EXPECT_NE(e.find("did you mean 'camera'"), std::string::npos) << e;
    e = error(std::string("[") + kFloor +
              R"(, {"type": "sphere", "center": [0, 1, 0], "radius": 0.5,
                    "material": "grey", "visibility": {"shadow": 0}}])");
    EXPECT_NE(e.find("/shapes/1/visibility/shadow"), std::string::npos) << e;
    e = error(std::string("[") + kFloor +
              R"(, {"type": "sphere", "center": [0, 1, 0], "radius": 0.5,
                    "material": "grey", "visibility": false}])");
    EXPECT_NE(e.find("/shapes/1/visibility"), std::string::npos) << e;
    // An instance takes its prototype's visibility.
    e = error(R"([{"type": "instance", "of": "p", "visibility": {"camera": false}}],
                 "prototypes": {"p": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, 1],
                                       "material": "grey"}]})");
    EXPECT_NE(e.find("/shapes/0/visibility"), std::string::npos) << e;

    const std::string doc = R"({"format": "facet-scene", "version": 1, )" + base +
                            R"("shapes": [)" + kFloor +
                            R"(, {"type": "sphere", "center": [0, 1, 0], "radius": 0.5,
                                  "material": "grey",
                                  "visibility": {"camera": false, "volume_scatter": false}}]})";
    const fr::SceneDescription d = fr::parse_scene_description(doc, "v.json");
    ASSERT_EQ(d.shapes.size(), 2u);
    EXPECT_EQ(d.shapes[0].visibility, fr::kRayAll);
    EXPECT_EQ(d.shapes[1].visibility, fr::kRayAll & ~(fr::kRayCamera | fr::kRayVolumeScatter));
    const fr::SceneDescription again =
        fr::parse_scene_description(fr::write_scene_json(d), "again.json");
    EXPECT_EQ(again.shapes[1].visibility, d.shapes[1].visibility);

    // Every flag given as true: nothing changes (the ordinary kernel).
    fr::RenderStats st;
    const fr::Scene all = ft::scene_from(
        base + R"("shapes": [)" + kFloor +
        R"(, {"type": "sphere", "center": [0, 1, 0], "radius": 0.5, "material": "grey",
              "visibility": {"camera": true, "diffuse": true, "glossy": true,
                             "transmission": true, "volume_scatter": true, "shadow": true}}])");
    EXPECT_FALSE(all.features().has_ray_visibility);
    render(all, 1, &st);
    EXPECT_EQ(st.kernel.name.find("media"), std::string::npos) << st.kernel.name;
}

// Light Path switches (FORMAT.md "Light Path switches"): Blender's Mix Shader(X, Transparent,
// Is Shadow Ray) as a `shadow` switch to the `null` model lets the lamp's light through the
// occluder exactly as a shadow-invisible occluder does (the analytic floor, relative 1e-5);
// without the switch the floor is black, and a `camera` switch to `null` (shadow rays see the
// occluder's own material) leaves it black too.
TEST(LightPath, ShadowSwitchToNullCastsNoShadow) {
    auto scene_with = [&](const std::string& sw) {
        return ft::scene_from(camera_down(1.0) + kFloorAndLamp + R"("shapes": [)" + kFloor +
                              R"(, {"type": "quad", "material": "grey", "vertices": )" +
                              quad(2.0, -3, 3, 3, true) + sw + "}]");
    };
    const fr::Scene scene =
        scene_with(R"(, "light_path": [{"ray": "shadow", "material": {"model": "null"}}])");
    EXPECT_TRUE(scene.features().has_ray_visibility);
    const fr::Image img = render(scene, 1);
    int n = 0;
    const double worst = worst_vs_floor(
        scene, img, [](int, int) { return true; }, n);
    EXPECT_LT(worst, 1e-5);
    for (const char* control :
         {"", R"(, "light_path": [{"ray": "camera", "material": {"model": "null"}}])"}) {
        const fr::Image ci = render(scene_with(control), 1);
        for (int y = 0; y < kVisSide; ++y)
            for (int x = 0; x < kVisSide; ++x) EXPECT_EQ(ci.at(x, y), Rgb(0.f)) << control;
    }
}

// Mix Shader(Emission A, Emission B, Is Camera Ray): the camera sees B, the lighting is A's.
// An emitter tilted toward the camera (front normal (-0.8, 0.6, 0), own radiance A = 2, a
// `camera` switch to B = [0, 5, 1]) over a Lambertian floor (1 spp: pixel-centre rays, so each
// pixel sees the emitter or the floor): its pixels are exactly B, and the floor is bit for bit
// the floor of the same scene without the switch (both renders run the same kernel: the
// reference turns off a flag no ray here exercises), since light samples and diffuse rays read
// A. Control: a switch on `diffuse` rays instead (to [0, 500, 0]) changes the lit floor (its
// BSDF rays read it: over 64 samples more than 20 pixels are greener) and the camera sees A.
TEST(LightPath, CameraSwitchShowsOneEmissionAndLightsWithTheOther) {
    // Centre (0, 0.5, 0), half size 0.3 along x' = (0.6, 0.8, 0) and z; counter-clockwise
    // about (p1 - p0) x (p2 - p0) ~ (-0.8, 0.6, 0), which faces the camera (and x < -0.375 of
    // the floor).
    const std::string tilted = R"([[-0.18, 0.26, 0.3], [0.18, 0.74, 0.3], [0.18, 0.74, -0.3],
                                   [-0.18, 0.26, -0.3]])";
    auto scene_with = [&](const std::string& extra) {
        return ft::scene_from(camera_down(5.0) +
                              R"("materials": {"floor": {"model": "lambert", "reflectance": 0.5}},
               "render": {"max_depth": 2},
               "shapes": [)" + std::string(kFloor) +
                              R"(, {"type": "quad", "emission": 2, "vertices": )" + tilted + extra +
                              "}]");
    };
    const fr::Image img =
        render(scene_with(R"(, "light_path": [{"ray": "camera", "emission": [0, 5, 1]}])"), 1);
    const fr::Image ref = render(scene_with(R"(, "visibility": {"volume_scatter": false})"), 1);
    int on_emitter = 0, on_floor = 0;
    for (int y = 0; y < kVisSide; ++y) {
        for (int x = 0; x < kVisSide; ++x) {
            if (ref.at(x, y) == Rgb(2.f)) {  // the emitter's front, A = 2
                EXPECT_EQ(img.at(x, y), Rgb(0.f, 5.f, 1.f)) << x << ", " << y;
                ++on_emitter;
            } else {
                EXPECT_EQ(img.at(x, y), ref.at(x, y)) << x << ", " << y;
                on_floor += ref.at(x, y).r > 0.f;
            }
        }
    }
    EXPECT_GT(on_emitter, 4);
    EXPECT_GT(on_floor, 40);
    // The control: pixel-centre rays see A on the emitter; over 64 samples the floor, whose
    // diffuse rays read B' = [0, 500, 0] where they find the emitter (a bright B': BSDF samples
    // of a small lamp have a small MIS weight), is greener than the reference's in more than
    // 20 pixels (the same samples: only the switch differs).
    const fr::Image control =
        render(scene_with(R"(, "light_path": [{"ray": "diffuse", "emission": [0, 5, 1]}])"), 1);
    int shows_a = 0;
    for (int y = 0; y < kVisSide; ++y)
        for (int x = 0; x < kVisSide; ++x)
            if (ref.at(x, y) == Rgb(2.f)) shows_a += control.at(x, y) == Rgb(2.f);
    EXPECT_EQ(shows_a, on_emitter);
    const fr::Image ref64 = render(scene_with(R"(, "visibility": {"volume_scatter": false})"), 64);
    const fr::Image ctl64 =
        render(scene_with(R"(, "light_path": [{"ray": "diffuse", "emission": [0, 500, 0]}])"), 64);
    int greener = 0;
    double sum_ref = 0.0, sum_ctl = 0.0;
    for (int y = 0; y < kVisSide; ++y) {
        for (int x = 0; x < kVisSide; ++x) {
            greener += ctl64.at(x, y).g > ref64.at(x, y).g;
            sum_ref += ref64.at(x, y).g;
            sum_ctl += ctl64.at(x, y).g;
        }
    }
    EXPECT_GT(greener, 20);
    EXPECT_GT(sum_ctl, sum_ref);
    std::printf(
        "camera switch: %d emitter pixels show B, %d lit floor pixels as without it; "
        "a diffuse switch makes %d pixels greener (mean green %.4f -> %.4f)\n",
        on_emitter, on_floor, greener, sum_ref / (kVisSide * kVisSide),
        sum_ctl / (kVisSide * kVisSide));
}

// Light Path errors name the pointer; the description round-trips.
TEST(LightPath, JsonErrorsAndRoundTrip) {
    const std::string base = camera_down(5.0) + kFloorAndLamp;
    auto error = [&](const std::string& sw) {
        try {
            ft::scene_from(base + R"("shapes": [)" + kFloor +
                           R"(, {"type": "sphere", "center": [0, 1, 0], "radius": 0.5,
                                 "material": "grey", "light_path": )" +
                           sw + "}]");
        } catch (const fr::SceneError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    std::string e = error(R"([{"ray": "camra"}])");
    EXPECT_NE(e.find("/shapes/1/light_path/0/ray"), std::string::npos) << e;
    EXPECT_NE(e.find("did you mean 'camera'"), std::string::npos) << e;
    e = error(R"([{"ray": "camera", "colour": 1}])");
    EXPECT_NE(e.find("/shapes/1/light_path/0/colour"), std::string::npos) << e;
    e = error(R"([{"material": "grey"}])");
    EXPECT_NE(e.find("/shapes/1/light_path/0"), std::string::npos) << e;
    e = error(R"([{"ray": "camera", "material": "nope"}])");
    EXPECT_NE(e.find("/shapes/1/light_path/0/material"), std::string::npos) << e;
    e = error(R"([{"ray": "camera", "material": {"model": "lambert",
                   "reflectance": {"checker": {"scale": 4, "colors": [0, 1]}}}}])");
    EXPECT_NE(e.find("/shapes/1/light_path/0/material"), std::string::npos) << e;
    e = error(R"([{"ray": "camera", "material": {"model": "lambert", "opacity": 0.5}}])");
    EXPECT_NE(e.find("/shapes/1/light_path/0/material"), std::string::npos) << e;
    e = error(R"({"ray": "camera"})");
    EXPECT_NE(e.find("/shapes/1/light_path"), std::string::npos) << e;

    const std::string doc = R"({"format": "facet-scene", "version": 1, )" + base +
                            R"("shapes": [)" + kFloor +
                            R"(, {"type": "sphere", "center": [0, 1, 0], "radius": 0.5,
                                  "material": "grey",
                                  "light_path": [{"ray": "shadow", "material": {"model": "null"}},
                                                 {"ray": "camera", "material": "floor",
                                                  "emission": [1, 2, 3]}]}]})";
    const fr::SceneDescription d = fr::parse_scene_description(doc, "lp.json");
    ASSERT_EQ(d.shapes[1].light_path.size(), 2u);
    EXPECT_EQ(d.shapes[1].light_path[0].ray, fr::kLpShadow);
    EXPECT_EQ(d.shapes[1].light_path[1].material->ref, "floor");
    EXPECT_EQ(d.shapes[1].light_path[1].emission, Rgb(1.f, 2.f, 3.f));
    const fr::SceneDescription again =
        fr::parse_scene_description(fr::write_scene_json(d), "again.json");
    EXPECT_EQ(again.shapes[1].light_path, d.shapes[1].light_path);
}

// export-pov refuses ray visibility and Light Path switches, naming the place (never a silent
// drop); the same scene without them exports.
TEST(RayVisibility, ExportPovRefusesVisibilityAndSwitches) {
    auto error_of = [](const std::string& extra) {
        try {
            fr::export_pov(fr::parse_scene_description(
                               R"({"format": "facet-scene", "version": 1, )" + camera_down(5.0) +
                                   kFloorAndLamp + R"("shapes": [)" + kFloor + extra + "]}",
                               "a"),
                           "a.json");
        } catch (const fr::SceneError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(error_of(""), "");
    EXPECT_NE(error_of(R"(, {"type": "sphere", "center": [0, 1, 0], "radius": 0.5,
                             "material": "grey", "visibility": {"shadow": false}})")
                  .find("/shapes/1/visibility"),
              std::string::npos);
    EXPECT_NE(error_of(R"(, {"type": "sphere", "center": [0, 1, 0], "radius": 0.5,
                             "material": "grey", "light_path": [{"ray": "camera"}]})")
                  .find("/shapes/1/light_path"),
              std::string::npos);
}

// The AOV pass sees what camera rays see: a camera-invisible quad over the floor leaves the
// floor's albedo (0.5, the Lambertian's exactly) and depth (5); a Light Path switch gives a
// camera-visible emitter its camera emission. Control: seen by the camera, the quad (albedo
// 0.8) covers them.
TEST(RayVisibility, AovsSeeWhatCameraRaysSee) {
    auto scene_with = [&](const std::string& vis) {
        return ft::scene_from(camera_down(5.0) + kFloorAndLamp + R"("shapes": [)" + kFloor +
                              R"(, {"type": "quad", "material": "grey", "vertices": )" +
                              quad(1.0, -3, 3, 3, true) + vis +
                              R"(}, {"type": "quad", "emission": 2, "vertices": )" +
                              quad(3.0, -0.2, 0.2, 0.2, true) +
                              R"(, "light_path": [{"ray": "camera", "emission": [0, 4, 0]}]}])");
    };
    fr::AovOptions ao;
    ao.which = fr::kAovAlbedo | fr::kAovDepth | fr::kAovEmission;
    ao.spp = 1;
    ao.threads = 1;
    const fr::Aovs a = fr::render_aovs(scene_with(R"(, "visibility": {"camera": false})"), ao);
    EXPECT_NEAR(a.albedo.at(0, 0).g, 0.5f, 1e-6f);
    EXPECT_NEAR(a.depth.at(0, 0).r, 5.f, 1e-4f);
    EXPECT_EQ(a.emission.at(8, 8), Rgb(0.f, 4.f, 0.f));  // the switch's camera emission
    const fr::Aovs c = fr::render_aovs(scene_with(""), ao);
    EXPECT_NEAR(c.albedo.at(0, 0).g, 0.8f, 1e-6f);
    EXPECT_NEAR(c.depth.at(0, 0).r, 4.f, 1e-4f);
}
