// Random-walk subsurface scattering in the renderer (integrator.h, "Subsurface"): a white SSS
// sphere in a white furnace renders the environment's radiance; the kernel with walks runs only
// for scenes with subsurface materials; threads and regions give the same pixels.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "facet/render/integrator.h"
#include "facet/render/pov_export.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/render/scene_description.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;

namespace {

std::string sss_sphere(const std::string& material, int size = 24) {
    return R"("camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 35, "width": )" +
           std::to_string(size) + R"(, "height": )" + std::to_string(size) + R"(},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": )" +
           material + R"(}],
        "lights": [{"type": "environment", "radiance": 0.5}],
        "render": {"max_depth": 1000})";
}

}  // namespace

// Energy: colour 1 (alpha 0.999999: loss ~1e-5 per walk) with a mean free path of 0.8
// (fixed radius 10 / (4 pi)) so that the 256-step cut is never reached; the exit lobe is
// Lambert (albedo 1), so every sphere pixel converges to the environment's 0.5. Mean within 5
// standard errors (pixels as independent estimates) plus 1e-4.
TEST(SubsurfaceFurnace, WhiteSphereRendersTheEnvironment) {
    const int spp = std::max(16, int(64 * fr::testing::stress_scale()));
    for (const char* g : {"0", "0.6"}) {
        const fr::Scene scene = fr::testing::scene_from(sss_sphere(
            R"({"model": "subsurface", "color": 1, "radius": 10,
                "method": "random_walk_fixed_radius", "anisotropy": )" +
            std::string(g) + "}"));
        const fr::Image img = fr::render(scene, fr::testing::test_options("path", spp, 3));
        std::vector<double> v;
        for (const Rgb& p : img.pixels())
            if (p != Rgb(0.5f)) v.push_back(p.g);
        ASSERT_GT(v.size(), img.pixels().size() / 4);
        double s = 0.0, s2 = 0.0;
        for (double x : v) s += x, s2 += x * x;
        const double n = double(v.size()), m = s / n;
        const double se = std::sqrt(std::max(0.0, s2 / n - m * m) / n);
        EXPECT_NEAR(m, 0.5, 5.0 * se + 1e-4) << "g " << g;
    }
    // Control: colour 0.3 (alpha 0.83 per event) absorbs visibly.
    const fr::Scene grey = fr::testing::scene_from(sss_sphere(
        R"({"model": "subsurface", "color": 0.3, "radius": 10,
            "method": "random_walk_fixed_radius"})"));
    const fr::Image img = fr::render(grey, fr::testing::test_options("path", spp, 3));
    double s = 0.0;
    int n = 0;
    for (const Rgb& p : img.pixels())
        if (p != Rgb(0.5f)) s += p.g, ++n;
    EXPECT_LT(s / n, 0.45);
}

TEST(SubsurfaceKernel, ChosenOnlyForScenesWithSubsurface) {
    const fr::Scene cornell = fr::load_scene(std::string(FACET_SCENES_DIR) + "/cornell_box.json");
    EXPECT_FALSE(cornell.features().has_subsurface);
    const fr::KernelChoice k =
        fr::choose_kernel(cornell.features(), fr::IntegratorKind::Path, 8, false);
    EXPECT_EQ(k.features & fr::kFeatMedia, 0u);
    const fr::Scene sss = fr::testing::scene_from(sss_sphere(R"({"model": "subsurface"})"));
    EXPECT_TRUE(sss.features().has_subsurface);
    const fr::KernelChoice ks =
        fr::choose_kernel(sss.features(), fr::IntegratorKind::Path, 8, false);
    EXPECT_NE(ks.features & fr::kFeatMedia, 0u);
    const fr::Scene p = fr::testing::scene_from(sss_sphere(R"({"model": "principled"})"));
    EXPECT_FALSE(p.features().has_subsurface);
}

// A subsurface material inside a combination renders its diffuse fallback: the scene says so
// (a warning naming the child's pointer), and says nothing for the same material used directly.
TEST(SubsurfaceWarnings, InsideAMixIsNamed) {
    const fr::Scene mixed = fr::testing::scene_from(sss_sphere(
        R"({"model": "mix", "weight": 0.5, "materials": [{"model": "lambert"},
            {"model": "subsurface"}]})"));
    bool named = false;
    for (const std::string& w : mixed.warnings())
        named = named ||
                (w.find("/materials/1: a subsurface material inside 'mix'") != std::string::npos);
    EXPECT_TRUE(named) << "warnings: " << ::testing::PrintToString(mixed.warnings());
    const fr::Scene direct = fr::testing::scene_from(sss_sphere(R"({"model": "subsurface"})"));
    for (const std::string& w : direct.warnings())
        EXPECT_EQ(w.find("subsurface material inside"), std::string::npos) << w;
}

TEST(SubsurfaceKernel, ThreadsAndRegionsGiveTheSamePixels) {
    const fr::Scene scene = fr::testing::scene_from(sss_sphere(
        R"({"model": "principled", "subsurface": 1, "subsurface_radius": [0.5, 0.2, 0.1],
            "base_color": [0.8, 0.5, 0.4]})",
        40));
    fr::RenderOptions o = fr::testing::test_options("path", 4, 2, 2);
    const fr::Image two = fr::render(scene, o);
    o.threads = 1;
    const fr::Image one = fr::render(scene, o);
    EXPECT_TRUE(one.pixels() == two.pixels());
    o.region = fr::Region{7, 9, 30, 33};
    const fr::Image part = fr::render(scene, o);
    int differ = 0;
    for (int y = 9; y < 33; ++y)
        for (int x = 7; x < 30; ++x) differ += part.at(x - 7, y - 9) != two.at(x, y);
    EXPECT_EQ(differ, 0);
    // Not black: the walk ran and its exits were lit.
    double s = 0.0;
    for (const Rgb& px : two.pixels()) s += px.r;
    EXPECT_GT(s, 0.0);
}

// The walk's entry direction and first step and its exit's light sample and direction take the
// path's stratified sample dimensions (integrator.cpp, kMediaDimsPerSegment): a sphere of the
// Subsurface Scattering node (no surface closures: every camera path walks) with short walks
// under a uniform environment is less noisy with Sobol samples than with independent ones.
// Noise: sigma = RMS(seed 1 - seed 2) / sqrt(2) over the sphere's pixels and channels. Measured
// (32 x 32, 64 spp): Sobol / independent 0.87; 1.03 when the walk and the exit drew from the
// segment's generator. Bound 0.95: about 4 standard errors of the ratio (about 2000 values per
// estimate, ~1.5% each) from either.
TEST(SubsurfaceNoise, WalkAndExitAreStratified) {
    const fr::Scene scene = fr::testing::scene_from(
        R"("camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 35, "width": 32,
                      "height": 32},
           "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material":
                       {"model": "subsurface", "color": [0.8, 0.5, 0.4],
                        "radius": [0.3, 0.1, 0.05]}}],
           "lights": [{"type": "environment", "radiance": 0.5}],
           "render": {"max_depth": 8})");
    auto sigma = [&](bool independent) {
        fr::RenderOptions o = fr::testing::test_options("path", 64, 1);
        o.independent_samples = independent;
        const fr::Image a = fr::render(scene, o);
        o.seed = 2;
        const fr::Image b = fr::render(scene, o);
        double s2 = 0.0;
        int n = 0;
        for (std::size_t i = 0; i < a.pixels().size(); ++i) {
            const Rgb &p = a.pixels()[i], &q = b.pixels()[i];
            if (p.g == 0.5f || q.g == 0.5f) continue;  // the environment
            for (int c = 0; c < 3; ++c) s2 += double(p[c] - q[c]) * double(p[c] - q[c]), ++n;
        }
        EXPECT_GT(n, 1500);
        return std::sqrt(s2 / (2.0 * n));
    };
    const double sobol = sigma(false), independent = sigma(true);
    EXPECT_LT(sobol / independent, 0.95)
        << "sigma Sobol " << sobol << ", independent " << independent;
}

// export-pov: a walk has no POV-Ray equivalent; the error names the JSON pointer (principled:
// its subsurface parameter). Principled with subsurface 0 exports.
TEST(SubsurfaceErrors, PovExportNamesThePointer) {
    const std::string head =
        R"({"format": "facet-scene", "version": 1,
            "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30, "width": 8,
                       "height": 8},
            "lights": [{"type": "point", "position": [0, 3, 3], "power": 10}],)";
    auto pov_error = [&](const std::string& material) {
        try {
            fr::export_pov(
                fr::parse_scene_description(head + R"("materials": {"m": )" + material + R"(},
                   "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                               "material": "m"}]})",
                                            "pov.json"),
                "pov.json");
        } catch (const fr::SceneError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(pov_error(R"({"model": "principled", "subsurface": 0.5})")
                  .find("pov.json: /materials/m/subsurface: random-walk subsurface"),
              std::string::npos);
    EXPECT_NE(pov_error(R"({"model": "subsurface"})")
                  .find("pov.json: /materials/m/model: random-walk subsurface"),
              std::string::npos);
    EXPECT_EQ(pov_error(R"({"model": "principled"})"), "");
}
