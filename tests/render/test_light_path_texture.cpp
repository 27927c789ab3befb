// The light_path texture kind (scenes/FORMAT.md "Light Path outputs"; texture.h RayState):
// Blender's Light Path outputs for the ray that reached a hit, read by material parameters and
// combination weights. Each output in a scene whose answer is known exactly (delta light, delta
// or no bounce, 1 spp), with controls that change; JSON errors naming the pointer; the kernel
// choice (scenes that read the ray run the media kernel, others the one they ran).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
namespace ft = facet::render::testing;
using facet::Rgb;
using facet::Vec3;

namespace {

constexpr int kLpSide = 16;

// A 16 x 16 orthographic camera at height h looking straight down (it sees [-1, 1]^2 in x, z).
std::string lp_camera_down(double h) {
    return R"("camera": {"type": "orthographic", "position": [0, )" + std::to_string(h) +
           R"(, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "scale": 2, "width": 16,
               "height": 16},)";
}

fr::Image lp_render(const fr::Scene& scene, fr::RenderStats* st = nullptr) {
    return fr::render(scene, ft::test_options("path", 1, 7), st);
}

// A light_path texture of `output` times b, clamped to [0, 1].
std::string lp_scaled(const std::string& output, double b) {
    return R"({"math": {"operation": "multiply", "use_clamp": true, "b": )" + std::to_string(b) +
           R"(, "a": {"light_path": {"output": ")" + output + R"("}}}})";
}

constexpr double kLpPower = 300.0;
const Vec3 kLpLight(0.f, 4.f, 0.f);

// The floor y = 0 with material `m`, seen from height 3 under a point light at (0, 4, 0).
fr::Scene lp_floor_scene(const std::string& m) {
    return ft::scene_from(lp_camera_down(3.0) +
                          R"("lights": [{"type": "point", "position": [0, 4, 0], "power": 300}],
                             "render": {"max_depth": 1},
                             "shapes": [{"type": "plane", "point": [0, 0, 0],
                                         "normal": [0, 1, 0], "material": )" +
                          m + "}]");
}

// The largest relative difference of the image from the analytic floor of reflectance rho.
double lp_worst_vs_floor(const fr::Scene& scene, const fr::Image& img, double rho) {
    double worst = 0.0;
    for (int y = 0; y < kLpSide; ++y)
        for (int x = 0; x < kLpSide; ++x) {
            const double want =
                *ft::point_light_on_plane(scene.camera(), x, y, kLpLight, kLpPower, rho);
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::fabs(double(img.at(x, y)[c]) - want) / want);
        }
    return worst;
}

}  // namespace

// Camera rays: Is Camera Ray is 1 (a mix by it shows its second material) and Ray Length is the
// distance from the orthographic camera's plane, 3: a reflectance of 0.1 x Ray Length is 0.3.
// Each against the analytic point-lit floor to float rounding (relative 1e-5: the length is 3 to
// an ulp). Controls: a mix by Is Diffuse Ray shows its first material, Ray Depth is 0.
TEST(LightPathTexture, CameraRaysReadCameraAndLength) {
    struct Case {
        std::string material;
        double rho;
    };
    const Case cases[] = {
        {R"({"model": "mix", "materials": [{"model": "lambert", "reflectance": 0.5},
                                           {"model": "lambert", "reflectance": 0.2}],
             "weight": {"light_path": {"output": "is_camera_ray"}}})",
         0.2},
        {R"({"model": "mix", "materials": [{"model": "lambert", "reflectance": 0.5},
                                           {"model": "lambert", "reflectance": 0.2}],
             "weight": {"light_path": {"output": "is_diffuse_ray"}}})",
         0.5},
        {R"({"model": "lambert", "reflectance": )" + lp_scaled("ray_length", 0.1) + "}", 0.3},
        {R"({"model": "lambert", "reflectance": {"math": {"operation": "add", "b": 0.4, "use_clamp": true,
             "a": {"light_path": {"output": "ray_depth"}}}}})",
         0.4},
    };
    for (const Case& c : cases) {
        fr::RenderStats st;
        const fr::Scene scene = lp_floor_scene(c.material);
        EXPECT_TRUE(scene.features().has_ray_visibility);
        const fr::Image img = lp_render(scene, &st);
        EXPECT_NE(st.kernel.name.find("media"), std::string::npos) << st.kernel.name;
        const double worst = lp_worst_vs_floor(scene, img, c.rho);
        EXPECT_LT(worst, 1e-5) << c.material;
        std::printf("rho %.2f: worst relative difference %.2e (tolerance 1e-5)\n", c.rho, worst);
    }
    // Without a light_path texture the scene runs the kernel it ran before.
    fr::RenderStats st;
    const fr::Scene plain = lp_floor_scene(R"({"model": "lambert", "reflectance": 0.3})");
    EXPECT_FALSE(plain.features().has_ray_visibility);
    lp_render(plain, &st);
    EXPECT_EQ(st.kernel.name.find("media"), std::string::npos) << st.kernel.name;
}

// A ray after a mirror: the camera looks down at a 45-degree mirror that sends its rays along
// +x to a wall at x = 3 lit by a point light. The wall's reflectance is 0.5 x an output, so each
// pixel is the output's value times the same wall with reflectance 0.5 (relative 1e-5: the same
// arithmetic but for the texture path). After one delta reflection the ray is glossy, singular
// and a reflection, at depth 1 and glossy depth 1; it is no camera, diffuse or transmission ray
// and its diffuse and transmission depths are 0 (those wrongly 1 would light the wall).
TEST(LightPathTexture, RayAfterAMirrorIsGlossySingularReflectionAtDepthOne) {
    auto scene_with = [](const std::string& reflectance) {
        return ft::scene_from(
            lp_camera_down(5.0) +
            R"("lights": [{"type": "point", "position": [2, 0, 0], "power": 100}],
               "render": {"max_depth": 2},
               "shapes": [{"type": "quad", "material": {"model": "mirror"},
                           "vertices": [[-1.5, 1.5, -1.5], [-1.5, 1.5, 1.5], [1.5, -1.5, 1.5],
                                        [1.5, -1.5, -1.5]]},
                          {"type": "quad", "material": {"model": "lambert", "reflectance": )" +
            reflectance + R"(}, "vertices": [[3, -3, -3], [3, -3, 3], [3, 3, 3], [3, 3, -3]]}])");
    };
    const fr::Image ref = lp_render(scene_with("0.5"));
    double lit = 0.0;
    for (int y = 0; y < kLpSide; ++y)
        for (int x = 0; x < kLpSide; ++x) lit += ref.at(x, y).g;
    ASSERT_GT(lit / (kLpSide * kLpSide), 0.01);  // the wall is seen lit in the mirror
    const std::pair<const char*, double> outputs[] = {
        {"is_camera_ray", 0},     {"is_diffuse_ray", 0},    {"is_glossy_ray", 1},
        {"is_singular_ray", 1},   {"is_reflection_ray", 1}, {"is_transmission_ray", 0},
        {"ray_depth", 1},         {"diffuse_depth", 0},     {"glossy_depth", 1},
        {"transmission_depth", 0}};
    for (const auto& [output, v] : outputs) {
        const fr::Image img = lp_render(scene_with(lp_scaled(output, 0.5)));
        double worst = 0.0;
        for (int y = 0; y < kLpSide; ++y)
            for (int x = 0; x < kLpSide; ++x) {
                const double want = v * ref.at(x, y).g, got = img.at(x, y).g;
                worst = std::max(worst, std::fabs(got - want) / std::max(ref.at(x, y).g, 1e-6f));
            }
        EXPECT_LT(worst, 1e-5) << output;
    }
}

// Errors name the pointer: a light_path texture where no ray reads it (an emission, an opacity,
// a normal or bump map), an unknown output, and a length into a reflectance unclamped (its
// range is unbounded above).
TEST(LightPathTexture, JsonErrorsNameThePlace) {
    auto error = [](const std::string& doc) {
        try {
            ft::scene_from(doc);
        } catch (const fr::SceneError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const std::string lp = R"({"light_path": {"output": "is_camera_ray"}})";
    const std::string head = lp_camera_down(3.0) +
                             R"("lights": [{"type": "point", "position": [0, 4, 0], "power": 1}],)";
    std::string e = error(
        head + R"("shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "emission": )" +
        lp + "}]");
    EXPECT_NE(e.find("/shapes/0/emission"), std::string::npos) << e;
    e = error(head +
              R"("shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material":
                          {"model": "lambert", "opacity": )" +
              lp + "}}]");
    EXPECT_NE(e.find("opacity"), std::string::npos) << e;
    e = error(head +
              R"("shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material":
                          {"model": "lambert", "bump": {"light_path":
                           {"output": "is_camera_ray"}}}}])");
    EXPECT_NE(e.find("bump"), std::string::npos) << e;
    e = error(head +
              R"("shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material":
                          {"model": "lambert", "reflectance": {"light_path":
                           {"output": "ray_lenght"}}}}])");
    EXPECT_NE(e.find("/shapes/0/material/reflectance/light_path/output"), std::string::npos) << e;
    EXPECT_NE(e.find("ray_length"), std::string::npos) << e;
    e = error(head +
              R"("shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material":
                          {"model": "lambert", "reflectance": {"light_path":
                           {"output": "ray_length"}}}}])");
    EXPECT_NE(e.find("/shapes/0/material/reflectance"), std::string::npos) << e;
    EXPECT_NE(e.find("largest"), std::string::npos) << e;
}
