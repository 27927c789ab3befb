// The light tree (facet/render/light_tree.h): its choice has exactly the probabilities pmf()
// reports, at every shaded point; it never chooses a light that cannot light the point, nor
// refuses one that can; and renders with it converge to the same image as the power choice.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "facet/render/light.h"
#include "facet/render/light_tree.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"
#include "facet/testsupport/render_test_util.h"

namespace fr = facet::render;
using facet::Rgb;
using facet::Vec3;

namespace {

// 40 point lights of powers 1..40 W on a 8 x 5 grid above z = 0, a spot, two one-sided quads
// (one facing down, one facing up), an emissive sphere, a disc, a sun and an environment.
std::vector<fr::Light> tree_test_lights() {
    std::vector<fr::Light> l;
    for (int i = 0; i < 40; ++i)
        l.push_back(
            fr::Light::point({float(i % 8) - 3.5f, float(i / 8) - 2.f, 1.5f}, Rgb(float(i + 1))));
    l.push_back(fr::Light::spot({0, 0, 3}, {0, 0, -1}, Rgb(50.f), 20.f, 30.f));
    const std::vector<Vec3> down = {{-1, -1, 2}, {-1, 1, 2}, {1, 1, 2},
                                    {-1, -1, 2}, {1, 1, 2},  {1, -1, 2}};
    l.push_back(fr::Light::area_triangles(down, Rgb(3.f), 0));
    const std::vector<Vec3> up = {{3, 3, 0.5f}, {4, 3, 0.5f}, {4, 4, 0.5f}};
    l.push_back(fr::Light::area_triangles(up, Rgb(6.f), 1));
    l.push_back(fr::Light::area_sphere({-3, 3, 1}, 0.3f, Rgb(4.f), 2));
    l.push_back(fr::Light::area_disc({2, -3, 1}, {0.4f, 0, 0}, {0, 0.4f, 0}, Rgb(2.f), 3));
    l.push_back(fr::Light::directional({0.2f, 0.1f, -1.f}, Rgb(1.f)));
    l.push_back(fr::Light::environment(Rgb(0.1f)));  // BSDF sampling's: not a candidate
    return l;
}

}  // namespace

// At random shaded points (above, between and below the lights; with a normal, and with none
// as in media), a fine stratified grid of u over [0, 1) picks each light with the frequency
// pmf() gives (to two grid cells: each light's set of u is one interval per leaf of the
// walk), sample() reports pmf() of what it chose bit for bit, and the pmfs sum to 1 unless no
// light can reach the point.
TEST(LightTree, SamplesWithThePmfItReports) {
    const std::vector<fr::Light> lights = tree_test_lights();
    const fr::LightDistribution d = fr::LightDistribution::tree(lights, 10.f);
    ASSERT_TRUE(d.has_tree());
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-5.f, 5.f), z(-1.f, 4.f), s(-1.f, 1.f);
    const int n = 1 << 15;
    for (int trial = 0; trial < 24; ++trial) {
        fr::LightSampleContext ctx;
        ctx.p = Vec3(pos(rng), pos(rng), z(rng));
        if (trial % 3 != 0) ctx.n = glm::normalize(Vec3(s(rng), s(rng), s(rng) + 1.2f));
        std::vector<double> f(lights.size(), 0.0);
        for (int k = 0; k < n; ++k) {
            float pmf = 0.f;
            const std::uint32_t i = d.sample(ctx, (float(k) + 0.5f) / float(n), pmf);
            if (pmf == 0.f) continue;
            ASSERT_EQ(pmf, d.pmf(ctx, i)) << "trial " << trial << " light " << i;
            f[i] += 1.0 / n;
        }
        double total = 0.0;
        for (std::size_t i = 0; i < lights.size(); ++i) {
            EXPECT_NEAR(f[i], d.pmf(ctx, i), 2.0 / n) << "trial " << trial << " light " << i;
            total += d.pmf(ctx, i);
        }
        EXPECT_NEAR(total, 1.0, 1e-5) << "trial " << trial;  // every point here sees a light
        EXPECT_EQ(d.pmf(ctx, lights.size() - 1), 0.f);       // the environment
    }
}

// A light the tree gives probability 0 at a point cannot light it: for each light with bounds
// and random points, importance 0 implies that a one-sample estimate of its irradiance is 0
// for 64 light samples (sample_li with the normal's hemisphere test); and a point in front of
// a quad facing it, close to it, gets a positive importance.
TEST(LightTree, ZeroImportanceOnlyWhereTheLightIsDark) {
    const std::vector<fr::Light> lights = tree_test_lights();
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> pos(-5.f, 5.f), z(-1.f, 4.f), s(-1.f, 1.f), u(0.f, 1.f);
    int zeros = 0;
    for (std::size_t li = 0; li < lights.size(); ++li) {
        const auto b = lights[li].bounds();
        if (!b) continue;
        for (int trial = 0; trial < 400; ++trial) {
            fr::LightSampleContext ctx;
            ctx.p = Vec3(pos(rng), pos(rng), z(rng));
            ctx.n = glm::normalize(Vec3(s(rng), s(rng), s(rng)));
            if (fr::light_importance(*b, ctx.p, ctx.n) > 0.f) continue;
            ++zeros;
            for (int k = 0; k < 64; ++k) {
                const auto ls = lights[li].sample_li(ctx, {u(rng), u(rng)});
                const double c = ls ? double(glm::dot(ls->wi, ctx.n)) * double(ls->li.g) : 0.0;
                ASSERT_LE(c, 0.0) << "light " << li << " lights a point of importance 0";
            }
        }
    }
    EXPECT_GT(zeros, 100);  // the check above ran
    // Under the downward quad, facing it: lit.
    const auto quad = lights[41].bounds();
    ASSERT_TRUE(quad);
    EXPECT_GT(fr::light_importance(*quad, {0, 0, 1}, {0, 0, 1}), 0.f);
    // Above it (behind the one-sided quad, outside the sphere around its box): dark.
    EXPECT_EQ(fr::light_importance(*quad, {0, 0, 6}, {0, 0, -1}), 0.f);
    // A hard-edged spot (inner = outer): lit inside its cone, dark outside.
    const auto spot = lights[40].bounds();
    ASSERT_TRUE(spot);
    EXPECT_GT(fr::light_importance(*spot, {0, 0, 0}, {0, 0, 1}), 0.f);
    const fr::Light hard = fr::Light::spot({0, 0, 3}, {0, 0, -1}, Rgb(50.f), 25.f, 25.f);
    EXPECT_GT(fr::light_importance(*hard.bounds(), {0.5f, 0, 0}, {0, 0, 1}), 0.f);
    EXPECT_EQ(fr::light_importance(*hard.bounds(), {3, 0, 0}, {0, 0, 1}), 0.f);
}

// A room of 24 point lights, a spot and two quad emitters over a floor with a box: the path
// integrator with the tree converges to the power choice's image (the image means differ by
// less than 5 standard errors of the difference, from per-pixel differences), and with 24
// lights the tree's image is less noisy than the power choice's at equal samples.
TEST(LightTree, RendersTheSameImageAsThePowerChoice) {
    std::string lights;
    for (int i = 0; i < 24; ++i)
        lights += "{\"type\": \"point\", \"position\": [" + std::to_string(i % 6 - 2.5) + ", " +
                  std::to_string(i / 6 - 1.5) + ", 0.6], \"power\": " + std::to_string(2 + i % 5) +
                  "},";
    const fr::Scene scene = fr::testing::scene_from(R"(
        "camera": {"position": [0, -6, 5], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 50,
                   "width": 32, "height": 24},
        "materials": {"white": {"model": "lambert", "reflectance": 0.6}},
        "shapes": [
          {"type": "quad", "material": "white",
           "vertices": [[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]]},
          {"type": "box", "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 1], "material": "white"},
          {"type": "quad", "emission": 4,
           "vertices": [[2, 2, 1.5], [2, 3, 1.5], [3, 3, 1.5], [3, 2, 1.5]]},
          {"type": "quad", "emission": 2,
           "vertices": [[-3, -3, 1.2], [-3, -2, 1.2], [-2, -2, 1.2], [-2, -3, 1.2]]}],
        "lights": [)" + lights + R"(
          {"type": "spot", "position": [0, 0, 3], "direction": [0, 0, -1], "power": 30,
           "outer_angle": 25, "inner_angle": 25}],
        "render": {"max_depth": 3})");
    const int spp = int(64 * fr::testing::stress_scale()) + 8;
    fr::RenderOptions o = fr::testing::test_options("path", spp, 5);
    o.light_selection = fr::LightSelection::Tree;
    const fr::Image tree = fr::render(scene, o);
    o.light_selection = fr::LightSelection::Power;
    const fr::Image power = fr::render(scene, o);
    o.seed = 6;
    const fr::Image power2 = fr::render(scene, o);
    double s = 0.0, s2 = 0.0, noise_power = 0.0, mean = 0.0;
    const double n = double(tree.pixels().size());
    for (std::size_t i = 0; i < tree.pixels().size(); ++i) {
        const double d = double(tree.pixels()[i].g) - double(power.pixels()[i].g);
        s += d;
        s2 += d * d;
        const double e = double(power.pixels()[i].g) - double(power2.pixels()[i].g);
        noise_power += 0.5 * e * e;
        mean += double(power.pixels()[i].g) / n;
    }
    const double md = s / n;
    const double se = std::sqrt(std::max(0.0, s2 / n - md * md) / (n - 1));
    EXPECT_LT(std::fabs(md), 5.0 * se)
        << "tree - power image mean " << md << " (se " << se << ", image mean " << mean << ")";
    EXPECT_GT(mean, 0.01);
    // The difference's variance is the sum of both images' variances: the tree's is below the
    // power choice's when var(tree - power) < 2 var(power).
    const double var_diff = s2 / n - md * md, var_power = noise_power / n;
    EXPECT_LT(var_diff, 2.0 * var_power)
        << "tree variance " << var_diff - var_power << " vs power " << var_power;
}

// Auto (the default) is the tree from kTreeMinLocalLights local lights on and View below: an
// environment and a sun do not count, an emitting quad does; an Auto render is the resolved
// selection's image bit for bit.
TEST(LightTree, AutoSelectionCountsLocalLights) {
    auto scene_with = [](int points, bool quad) {
        std::string lights = R"({"type": "directional", "direction": [0, 0.3, -1],
                                 "irradiance": 0.5}, {"type": "environment", "radiance": 0.1},)";
        for (int i = 0; i < points; ++i)
            lights += "{\"type\": \"point\", \"position\": [" + std::to_string(i % 4 - 1.5) + ", " +
                      std::to_string(i / 4 - 1) + ", 1], \"power\": 3},";
        lights.pop_back();
        return fr::testing::scene_from(R"(
            "camera": {"position": [0, -4, 3], "look_at": [0, 0, 0], "up": [0, 0, 1],
                       "fov": 50, "width": 16, "height": 12},
            "materials": {"white": {"model": "lambert", "reflectance": 0.6}},
            "shapes": [
              {"type": "quad", "material": "white",
               "vertices": [[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]]})" +
                                       std::string(quad ? R"(,
              {"type": "quad", "emission": 2,
               "vertices": [[2, 2, 1.5], [2, 3, 1.5], [3, 3, 1.5], [3, 2, 1.5]]})"
                                                        : "") +
                                       R"(],
            "lights": [)" + lights + "]");
    };
    using fr::LightSelection;
    ASSERT_EQ(fr::kTreeMinLocalLights, 12);
    EXPECT_EQ(fr::resolve_light_selection(scene_with(11, false), LightSelection::Auto),
              LightSelection::View);
    EXPECT_EQ(fr::resolve_light_selection(scene_with(12, false), LightSelection::Auto),
              LightSelection::Tree);
    const fr::Scene eleven_and_quad = scene_with(11, true);
    EXPECT_EQ(fr::resolve_light_selection(eleven_and_quad, LightSelection::Auto),
              LightSelection::Tree);
    EXPECT_EQ(fr::resolve_light_selection(eleven_and_quad, LightSelection::Power),
              LightSelection::Power);
    fr::RenderOptions o = fr::testing::test_options("path", 8, 3);
    EXPECT_EQ(o.light_selection, LightSelection::Auto) << "the default";
    const fr::Image autos = fr::render(eleven_and_quad, o);
    o.light_selection = LightSelection::Tree;
    const fr::Image tree = fr::render(eleven_and_quad, o);
    o.light_selection = LightSelection::View;
    const fr::Image view = fr::render(eleven_and_quad, o);
    EXPECT_TRUE(autos.pixels() == tree.pixels());
    EXPECT_FALSE(autos.pixels() == view.pixels());
}
